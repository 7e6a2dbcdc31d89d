/*
 * glTF 2.0 (.gltf and .glb) for vn_io. Two ways in:
 *
 *  - As a vn_io format ("gltf", "glb" in the format table): the reader
 *    merges every triangle primitive (TRIANGLES, TRIANGLE_STRIP,
 *    TRIANGLE_FAN) of every mesh into one vn_io_mesh, in mesh-local
 *    coordinates (node transforms are not applied; vn_io_gltf_read_scene
 *    applies them); the writers produce a minimal glTF (one mesh, one
 *    primitive: POSITION with min/max, NORMAL, uint32 indices; polygons
 *    fan-triangulated; asset.generator "vn"). A .gltf written this way
 *    carries its buffer as a data URI. Given a vn_drc_options* as their
 *    settings (fields -1: vn_drc_default_options'), the writers compress
 *    each triangle primitive as vn_gltf_draco_on does (vnconvert --draco
 *    on from another format).
 *
 *  - As a document (vn_gltf_convert): glTF in, glTF out, recomputing the
 *    NORMAL of every triangle primitive and of its morph targets, and
 *    changing nothing else (unless crease splitting adds vertices). The
 *    original JSON is edited (key order, extras and unknown extensions
 *    survive) and only NORMAL bytes are rewritten: in place when the NORMAL
 *    accessor is plain (float32, or normalized byte/short under
 *    KHR_mesh_quantization, not sparse), otherwise in a new bufferView and
 *    accessor appended at the end of the arrays. Draco-compressed
 *    primitives (KHR_draco_mesh_compression) are decoded with draco.h and
 *    encoded again, written uncompressed, or (with every other triangle
 *    primitive) compressed: vn_gltf_options.draco. bufferViews compressed
 *    with EXT_meshopt_compression or KHR_meshopt_compression are decoded
 *    with meshoptimizer, and those the normals change encoded again, or
 *    all written plain: vn_gltf_options.meshopt. What these changes leave
 *    unused is removed. See README.md, "glTF".
 *
 * Implemented in C++ (gltf*.cpp, one file per stage: see gltf.cpp; on
 * nlohmann json) behind this C interface.
 */
#ifndef VN_IO_GLTF_H
#define VN_IO_GLTF_H

#include "draco.h"
#include "vn_io.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vn_gltf_draco { vn_gltf_draco_keep, vn_gltf_draco_off, vn_gltf_draco_on } vn_gltf_draco;
typedef enum vn_gltf_meshopt { vn_gltf_meshopt_keep, vn_gltf_meshopt_off } vn_gltf_meshopt;

typedef struct vn_gltf_options {
	vn_method method;
	unsigned threads;     /* as vn_options.threads */
	int no_weld;          /* compute on the vertices as split in the file */
	double weld_epsilon;  /* vn_weld_positions' epsilon; 0: exactly equal positions */
	int weld_mesh;        /* weld across all triangle primitives of a mesh, not per primitive */
	int drop_tangents;    /* remove TANGENT from primitives (otherwise left as is) */
	/* Per-corner normals within smooth fans (vn_corner_normals): edges
	 * whose faces meet at more than crease_angle (radians) are hard, and
	 * vertices whose corners get different normals are split. Without it,
	 * hard edges already in the file (split copies whose input normals
	 * differ by more than 0.1 degree) are kept, and nothing is split; with
	 * it, copies whose input normals differ by more than crease_angle. */
	int crease;
	double crease_angle;
	/* KHR_draco_mesh_compression on output: keep (a compressed primitive
	 * is re-encoded with its own attributes, unique ids and bits), off
	 * (every primitive written uncompressed) or on (every triangle
	 * primitive compressed). */
	vn_gltf_draco draco;
	/* Draco bits and level; -1 fields: not given. keep uses the input's
	 * bits except normal_bits, and compression_level (the stream does not
	 * record it); on uses all, else vn_drc_default_options'. */
	vn_drc_options draco_options;
	int draco_normal_error; /* fill vn_gltf_stats.draco_normal_error (an extra encoding) */
	/* EXT_/KHR_meshopt_compression bufferViews on output: keep (compressed
	 * as they were; those whose data the normals change encoded again) or
	 * off (every view written plain, the extensions removed). */
	vn_gltf_meshopt meshopt;
	/* External images copied into the output's folder (another one than
	 * the input's) are named OUTSTEM_NAME rather than NAME, so that models
	 * converted into one folder never share a name for different images
	 * (vnconvert --out-dir). */
	int image_names_from_output;
} vn_gltf_options;

typedef struct vn_gltf_stats {
	size_t primitives;         /* triangle primitives whose normals were recomputed */
	size_t skipped_points;     /* POINTS primitives, left untouched */
	size_t skipped_lines;      /* LINES, LINE_LOOP, LINE_STRIP primitives, left untouched */
	size_t skipped_no_position; /* primitives without POSITION, left untouched */
	size_t vertices;           /* vertices of the processed primitives */
	size_t triangles;          /* triangles after strip and fan conversion */
	size_t welded_vertices;    /* vertices merged into another one by position */
	size_t hard_edges;         /* edges kept hard because the input's normals of
	                              the split copies along them differ */
	size_t split_vertices;     /* vertices added by --crease-angle splitting */
	size_t zero_normals;       /* vertices no face contributed to: written as the
	                              input's unit normal, or (0, 0, 1) */
	size_t tangent_primitives; /* processed primitives with TANGENT */
	size_t tangents_needed;    /* --tangents drop: primitives whose TANGENT stays, as their
	                              material needs a tangent space and has no normal map to
	                              generate one from */
	size_t appended_accessors; /* NORMAL accessors added (none before, sparse,
	                              unusual type, or shared with differing result) */
	size_t draco_primitives;   /* primitives written Draco-compressed */
	size_t draco_uncompressed; /* --draco on: primitives left uncompressed (morph
	                              targets on more than 3 vertices per triangle) */
	size_t meshopt_views;      /* meshopt-compressed bufferViews read */
	size_t meshopt_encoded;    /* of those, encoded again with new normals (keep) */
	/* Accessors and bufferViews the input used and vn's changes left unused
	 * (old NORMAL data, re-encoded or newly compressed Draco primitives):
	 * removed, with their bytes, and every reference renumbered; unless the
	 * document uses an extension vn does not know (it may hold indices),
	 * whose name is then in unpruned_extension ("" otherwise). */
	size_t pruned_accessors, pruned_views;
	char unpruned_extension[64];
	/* What vn read anyway but the input should not have (GLB_EXTRA_DATA):
	 * one line each, "\n"-separated, not naming the file; "" for none. */
	char warnings[1024];
	/* The angle normal quantization adds to the new normals of those, per
	 * normal bits (index: bits; compared 0 when no primitive has them). */
	vn_drc_normal_error draco_normal_error[VN_DRC_MAX_BITS + 1];
} vn_gltf_stats;

/* Reads the glTF or GLB file `in` (told apart by content), recomputes its
 * normals and writes `out` as GLB when out_glb, else as .gltf with its
 * buffers in files beside it (OUTSTEM.bin, OUTSTEM_1.bin, ...; data-URI
 * buffers stay data URIs) and its external images copied next to it when
 * the folder differs (as OUTSTEM_NAME with image_names_from_output). Every output file is written to a temporary file
 * first and renamed once all are complete. stats may be NULL. */
vn_io_result vn_gltf_convert(const char* in, const char* out, int out_glb, const vn_gltf_options* options,
                             vn_gltf_stats* stats, vn_io_error* error);

/* The format-table entry points described above. */
vn_io_result vn_io_gltf_read(const char* path, vn_io_mesh* mesh, vn_io_error* error);
/* As vn_io_gltf_read, but the default scene as it is drawn (vnconvert
 * --apply-transforms): each triangle primitive once per node of the scene
 * (scene, else scenes[0], else every root node) that instances its mesh,
 * with the node's world transform (matrix, or translation, rotation and
 * scale, down the hierarchy) applied to POSITION, and its inverse
 * transpose to NORMAL (normalized); a mirroring transform (negative
 * determinant) turns the triangles' winding over, as glTF draws them.
 * Meshes no node of the scene instances are left out; other attributes
 * (TANGENT too) are copied as they are. */
vn_io_result vn_io_gltf_read_scene(const char* path, vn_io_mesh* mesh, vn_io_error* error);
vn_io_result vn_io_gltf_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error);
vn_io_result vn_io_glb_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error);

#ifdef __cplusplus
}
#endif

#endif /* VN_IO_GLTF_H */
