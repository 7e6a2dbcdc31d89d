/*
 * vn_io: the importer/exporter layer around libvn.
 *
 * A format-neutral polygon mesh (vn_io_mesh) that every format reads into and
 * writes from, a table of formats chosen by file extension, and an atomic
 * writer (temporary file in the output's folder, then rename) so that an
 * output is either complete or absent.
 *
 * Errors: every call returns a vn_io_result and, on failure, fills the
 * caller's vn_io_error with one line naming the file and, for parse errors,
 * the line ("in.off:12: face 3 has index 99, but the file has 8 vertices").
 */
#ifndef VN_IO_H
#define VN_IO_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "vn.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vn_io_result {
	vn_io_success = 0,
	vn_io_error_open,        /* cannot open or read the input file */
	vn_io_error_write,       /* cannot create, write or rename the output */
	vn_io_error_parse,       /* malformed content */
	vn_io_error_unsupported, /* a valid file using a feature vn does not handle */
	vn_io_error_format,      /* unknown extension or format name */
	vn_io_error_memory,      /* out of memory */
	vn_io_error_same_file,   /* output is the input and in-place was not asked for */
	vn_io_result_count_
} vn_io_result;

/* A short English description of r; never NULL. */
const char* vn_io_result_string(vn_io_result r);

/* One human-readable line: "<file>:<line>: <what>" or "<file>: <what>". */
typedef struct vn_io_error {
	char message[512];
} vn_io_error;

/* A polygon mesh as files carry it. Arrays are owned by the mesh and freed by
 * vn_io_mesh_free; optional arrays are NULL when the file has none. */
typedef struct vn_io_mesh {
	size_t vertex_count;
	double* positions; /* 3 per vertex */
	double* normals;   /* NULL or 3 per vertex */
	float* colors;     /* NULL or RGBA per vertex, each in [0, 1] */
	float* texcoords;  /* NULL or 2 per vertex */

	size_t face_count;
	uint32_t* face_offsets; /* face_count + 1 entries; face f is indices[face_offsets[f] .. face_offsets[f+1]) */
	uint32_t* indices;
	float* face_colors; /* NULL or RGBA per face, each in [0, 1] */

	/* Colours were written as integers 0..255 in the source file (OFF allows
	 * both); writers that have the choice reproduce the source's style. */
	int colors_are_bytes;
	int face_colors_are_bytes;
} vn_io_mesh;

/* Frees every array and zeroes the struct; NULL or a zeroed mesh is fine. */
void vn_io_mesh_free(vn_io_mesh* mesh);

/* True when every face has exactly 3 corners (a mesh with no faces is not). */
int vn_io_mesh_is_triangles(const vn_io_mesh* mesh);

/* ------------------------------------------------------------------ formats */

typedef struct vn_io_format {
	const char* name;       /* "off" */
	const char* extensions; /* space-separated, lower case, with dot: ".off" */
	const char* description;
	/* Reads `path` into *mesh (zeroed on entry). */
	vn_io_result (*read)(const char* path, vn_io_mesh* mesh, vn_io_error* error);
	/* Writes mesh to the open stream; `path` is only for messages. settings
	 * are the format's own write settings (NULL: its defaults; the drc
	 * format takes a vn_drc_options*, the others none). The caller
	 * (vn_io_write_file) takes care of atomicity. */
	vn_io_result (*write)(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings,
	                      vn_io_error* error);
} vn_io_format;

/* The format whose extension `path` ends with (case-insensitive), or NULL. */
const vn_io_format* vn_io_format_for_path(const char* path);
/* The format called `name` (case-insensitive), or NULL. */
const vn_io_format* vn_io_format_by_name(const char* name);
/* The i-th known format, or NULL past the end (for --help listings). */
const vn_io_format* vn_io_format_at(size_t i);

/* Reads path with `format`, or the format its extension names when NULL. */
vn_io_result vn_io_read_file(const char* path, const vn_io_format* format, vn_io_mesh* mesh, vn_io_error* error);

/* Writes mesh to path atomically: a temporary file in the same folder is
 * written, flushed, synced and renamed over path; on any failure the
 * temporary file is removed and path is untouched. format NULL: the one
 * path's extension names; settings go to its writer (NULL: defaults). */
vn_io_result vn_io_write_file(const char* path, const vn_io_format* format, const vn_io_mesh* mesh,
                              const void* settings, vn_io_error* error);

/* Reads a whole file into a NUL-terminated buffer the caller frees. */
vn_io_result vn_io_read_all(const char* path, char** data, size_t* size, vn_io_error* error);

/* True when a and b name the same existing file (same device and inode). */
int vn_io_same_file(const char* a, const char* b);

/* Fills error with printf-style text; returns r, for `return vn_io_fail(...)`. */
vn_io_result vn_io_fail(vn_io_error* error, vn_io_result r, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#ifdef __cplusplus
}
#endif

#endif /* VN_IO_H */
