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

/* What libvnio.so exports (vn_convert.h's entry points and what a binding
 * needs besides); the rest of vn_io is internal to vn's programs. */
#if defined(__GNUC__) || defined(__clang__)
#  define VN_IO_API __attribute__((visibility("default")))
#else
#  define VN_IO_API
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
	vn_io_error_option,      /* an option value out of range, or not applying to the conversion */
	vn_io_result_count_
} vn_io_result;

/* A short English description of r; never NULL. */
VN_IO_API const char* vn_io_result_string(vn_io_result r);

/* One human-readable line: "<file>:<line>: <what>" or "<file>: <what>". */
typedef struct vn_io_error {
	char message[512];
} vn_io_error;

/* What an attribute beyond positions, normals, `colors` and `texcoords`
 * means; the values are Draco's GeometryAttribute::Type. */
typedef enum vn_io_semantic {
	vn_io_semantic_color = 2,
	vn_io_semantic_texcoord = 3,
	vn_io_semantic_generic = 4 /* application-specific */
} vn_io_semantic;

/* One more per-vertex attribute: a second texture coordinate or colour set,
 * or application-specific data (glTF `_NAME`, Draco GENERIC). */
typedef struct vn_io_attribute {
	/* As glTF names it: "TEXCOORD_1", "COLOR_1", or "_NAME" (application-
	 * specific: an underscore, then upper case letters, digits and '_'). */
	char name[64];
	int semantic;       /* a vn_io_semantic */
	int component_type; /* glTF numbering: 5120 int8, 5121 uint8, 5122 int16, 5123 uint16,
	                       5124 int32 (Draco only), 5125 uint32, 5126 float32; and
	                       5130 float64 (OpenGL's number: PLY double, Draco
	                       float64; glTF has none) */
	int components;     /* 1 to 4 */
	int normalized;     /* integers stand for [0, 1] (unsigned) or [-1, 1] (signed) */
	void* data;         /* vertex_count * components values, packed, vertex by vertex */
	/* The property it was read from, as the file names it (PLY: "my-prop",
	 * where name is "_MY_PROP"), or NULL: the PLY writer writes it back
	 * under that name. Freed with the mesh. */
	char* source_name;
} vn_io_attribute;

/* Names given to sets of faces: OBJ's materials (`usemtl`), objects (`o`),
 * groups (`g`) and smoothing groups (`s`). */
typedef struct vn_io_face_names {
	size_t count;
	char** names;      /* count NUL-terminated names */
	uint32_t* of_face; /* NULL, or face_count entries: an index into names, or VN_IO_NO_NAME */
} vn_io_face_names;

/* A face that belongs to no named set (faces before an OBJ's first `usemtl`,
 * `o`, `g` or `s`). */
#define VN_IO_NO_NAME UINT32_MAX

/* The images of a material (vn_io_material.textures): its base colour's
 * (map_Kd), its normal map's (map_Bump, bump or norm) and its emission's
 * (map_Ke). */
enum { vn_io_texture_base, vn_io_texture_normal, vn_io_texture_emissive, vn_io_texture_kinds };

/* What an OBJ's material library (.mtl) says of one material, as far as
 * glTF's metallic-roughness material carries it (vn_io_mtl_read). */
typedef struct vn_io_material {
	double color[4];    /* Kd and d, clamped to [0, 1]: diffuse colour and opacity, 1 where not given */
	double emissive[3]; /* Ke, clamped to [0, 1]; 0 where not given */
	double roughness;   /* Pr, else 1 - sqrt(Ns / 1000) (Blender's reading of Ns); -1 where neither is given */
	double metallic;    /* Pm (the PBR extension of MTL); 0 where not given, as the Phong model has no metal */
	double normal_scale; /* the normal map's -bm; 1 where not given */
	/* NULL, or each kind's image (PNG or JPEG): a path from the working
	 * folder, or absolute; jpeg: it is JPEG (else PNG). */
	char* textures[vn_io_texture_kinds];
	int jpeg[vn_io_texture_kinds];
	int defined; /* the library has a newmtl of its name (else it is a name only) */
} vn_io_material;

/* What a PLY file holds besides what vn_io_mesh describes (comments,
 * other face properties, other elements), for the PLY writer to write
 * back; opaque outside ply.c. */
typedef struct vn_io_ply_extras vn_io_ply_extras;

/* What a binary STL holds besides its triangles: the 80-byte header and
 * each triangle's 2 attribute bytes (colours, or whatever the writer put
 * there), for the STL writer to write back. */
typedef struct vn_io_stl_extras {
	unsigned char header[80];
	uint16_t* attributes; /* one per triangle, in the file's order */
	size_t count;
} vn_io_stl_extras;

/* A polygon mesh as files carry it. Arrays are owned by the mesh and freed by
 * vn_io_mesh_free; optional arrays are NULL when the file has none. Readers
 * put the first colour set in `colors`, the first 2-component texture
 * coordinate set in `texcoords` and every other per-vertex attribute in
 * `attributes`; writers keep what their format can hold
 * (vn_io_format.holds). */
typedef struct vn_io_mesh {
	size_t vertex_count;
	double* positions; /* 3 per vertex */
	double* normals;   /* NULL or 3 per vertex */
	float* colors;     /* NULL or RGBA per vertex, each in [0, 1] */
	float* texcoords;  /* NULL or 2 per vertex, (0, 0) the image's bottom left (OBJ's `vt`) */
	/* NULL or per vertex, from an OBJ: the v line (0-based) of its
	 * position. Vertices split from one v line (for their texture
	 * coordinates or normals) share it; equal v lines stay apart, as every
	 * other OBJ reader keeps them. The OBJ writer writes a v line per line
	 * (else per distinct position). */
	uint32_t* position_lines;

	size_t face_count;
	uint32_t* face_offsets; /* face_count + 1 entries; face f is indices[face_offsets[f] .. face_offsets[f+1]) */
	uint32_t* indices;
	float* face_colors; /* NULL or RGBA per face, each in [0, 1] */

	/* Colours were written as integers 0..255 in the source file (OFF allows
	 * both); writers that have the choice reproduce the source's style. */
	int colors_are_bytes;
	int face_colors_are_bytes;

	size_t attribute_count;
	vn_io_attribute* attributes; /* NULL or attribute_count entries, each owning its data */

	/* The material, object, group and smoothing group of each face, and the
	 * files defining the materials (an OBJ's `mtllib` arguments as written:
	 * "model.mtl", or NULL), as an OBJ names them (a group or smoothing
	 * group by its line's arguments as written: "1", "off"; "" for a bare
	 * `g`); only the OBJ writer keeps them (vn_io_holds_face_names). Faces
	 * are never reordered, so of_face stays valid through vn. */
	vn_io_face_names materials;
	vn_io_face_names objects;
	vn_io_face_names groups;
	vn_io_face_names smoothing;
	/* NULL, or per face: 1 where the file gave none of its corners a texture
	 * coordinate though others have them (an OBJ "f 1//1 2//2 3//3" beside
	 * textured faces; the texcoords of its vertices are the first vt, as
	 * Draco fills them); only the OBJ writer keeps it, writing no vt there. */
	unsigned char* face_untextured;
	char* material_library;
	/* The folder of the file read (absolute, links resolved: realpath), that
	 * material_library's relative names are relative to; NULL when read from
	 * memory. The OBJ writer writes each relative name from its output's
	 * folder to that one ("../assets/model.mtl"; as written when the folder
	 * is the same or this is NULL); absolute names stay. */
	char* material_folder;
	/* NULL, or materials.count entries: each material as the library
	 * defines it (vn_io_mtl_read, for writers of materials: glTF). */
	vn_io_material* material_defs;

	/* NULL, or what a PLY file held besides the above; only the PLY writer
	 * keeps it (vn_io_holds_ply_extras). Faces are never reordered, and
	 * vertices only appended, so its face properties and the indices in
	 * its elements (an edge's vertex1) stay valid through vn. */
	vn_io_ply_extras* ply_extras;

	/* An OBJ's polylines (`l`): line_count + 1 offsets into line_indices,
	 * each point a vertex (one of its v line's); only the OBJ writer keeps
	 * them (vn_io_holds_lines). Vertices are only appended, so the indices
	 * stay valid through vn. */
	size_t line_count;
	uint32_t* line_offsets;
	uint32_t* line_indices;

	/* NULL, or what a binary STL held besides the above; only the STL
	 * writer keeps it (vn_io_holds_stl_extras), when the mesh has as many
	 * triangles as it has attributes (faces are never reordered). */
	vn_io_stl_extras* stl_extras;

	/* NULL, or the comment lines of an OFF's header (before the counts) or
	 * at the top of an OBJ (before any other line), which carry exporters'
	 * credits and licences: each as written after its '#', "\n"-separated;
	 * the OFF, OBJ and PLY writers put them back (vn_io_holds_comments). */
	char* comments;

	/* NULL, or what the reader read anyway but the file should not have
	 * (bytes after a GLB's declared length): one line each, "\n"-separated,
	 * not naming the file. */
	char* warnings;
} vn_io_mesh;

/* Frees every array and zeroes the struct; NULL or a zeroed mesh is fine. */
void vn_io_mesh_free(vn_io_mesh* mesh);

/* True when every face has exactly 3 corners (a mesh with no faces is not). */
int vn_io_mesh_is_triangles(const vn_io_mesh* mesh);

/* The triangles of mesh once its polygons are fan-triangulated (a face of
 * k >= 3 corners makes k - 2; faces of fewer make none). */
uint64_t vn_io_mesh_triangle_count(const vn_io_mesh* mesh);

/* Whether each component of `count` RGBA colours is a byte over 255, as
 * a float holds k / 255 or as 6 decimals print it (MeshLab's and Open3D's
 * "%f": within 2e-4 of k): a reader of colours in another form (OBJ text,
 * glTF float or unsigned short, Draco float) then sets colors_are_bytes,
 * so that PLY, OFF and glTF write the bytes, which is how MeshLab (float
 * PLY colours read as white) and Open3D (divided by 255 again) read them. */
int vn_io_colors_are_bytes(const float* rgba, size_t count);

/* Makes a zeroed mesh the empty one (no vertices, no faces, face_offsets
 * {0}), which a reader gives for a file that holds no geometry (an OBJ of
 * comments, an STL of no triangles); 0 when out of memory. */
int vn_io_mesh_set_empty(vn_io_mesh* mesh);

/* Appends a copy of vertex source[e], for each e < count, to every
 * per-vertex array (positions, normals, colors, texcoords, attributes), so
 * that vertex_count grows by count; 0 when out of memory (vertex_count then
 * as it was, each array holding at least its first vertex_count vertices). */
int vn_io_mesh_append_vertices(vn_io_mesh* mesh, const uint32_t* source, size_t count);

/* Appends an attribute with room for vertex_count * components values of
 * component_type (zeroed) and returns it, or NULL when out of memory or the
 * type is unknown. name is copied (truncated to fit). */
vn_io_attribute* vn_io_mesh_add_attribute(vn_io_mesh* mesh, const char* name, int semantic, int component_type,
                                          int components, int normalized);

/* Bytes of one component of an attribute's component type (5120 ... 5126,
 * 5130); 0 when unknown. */
size_t vn_io_component_size(int component_type);

/* How many of a float64 attribute's values (vertex_count * components)
 * change when written as float32 (glTF has no double); *beyond: how many of
 * them become infinite or 0. */
size_t vn_io_attribute_rounded(const vn_io_mesh* mesh, const vn_io_attribute* a, size_t* beyond);

/* The first vertex with a non-finite position coordinate, or vertex_count
 * when every position is finite. Every writer refuses such a mesh: no file
 * format vn writes can hold NaN or infinite positions. */
size_t vn_io_mesh_first_nonfinite(const vn_io_mesh* mesh);

/* ------------------------------------------------------------------ normals
 *
 * The normals of a vn_io_mesh as vnconvert computes them for every format
 * (mesh_normals.cpp; glTF to glTF follows the same plan on its primitives):
 * vertices at one position are welded so that the copies a file splits
 * along UV seams get one normal; welded copies whose input normals differ
 * by more than 0.1 degree (with a crease angle: by more than it) keep a
 * hard edge between them, each copy the normal of its own side; with a
 * crease angle, faces meeting at more than it are hard too and a vertex
 * whose corners need different normals is split. */

typedef struct vn_io_normals_options {
	vn_method method;
	unsigned threads;    /* results do not depend on it */
	int no_weld;         /* compute on the vertices as the file splits them */
	double weld_epsilon; /* vn_weld_positions' epsilon; 0: exactly equal positions */
	int crease;          /* hard edges at crease_angle (radians), vertices split */
	double crease_angle;
} vn_io_normals_options;

typedef struct vn_io_normals_stats {
	size_t vertices;         /* input vertices */
	size_t faces;
	size_t welded_vertices;  /* vertices merged into another one by position */
	size_t hard_edges;       /* edges kept hard because the input normals of their welded copies differ */
	size_t split_vertices;   /* vertices appended by crease splitting */
	size_t zero_normals;     /* output vertices whose normal sums to zero (isolated, only degenerate faces, or faces that cancel) */
	size_t degenerate_faces; /* faces that contributed nothing (vn_stats) */
} vn_io_normals_stats;

/* Computes mesh->normals (allocated when the mesh has none). A vertex no
 * face contributes to keeps the input's normal bit for bit, else gets
 * (0, 0, 0); a mesh without faces (a point cloud) keeps its normals, or
 * stays without (zero_normals: every vertex). Split vertices are appended
 * after the mesh's, copying every per-vertex array (positions, colors,
 * texcoords, attributes: vn_io_mesh_append_vertices), and the indices
 * rewritten; polygons stay polygons. stats may be NULL; path only
 * names the mesh in errors. On failure the mesh is as it was. */
vn_io_result vn_io_mesh_normals(vn_io_mesh* mesh, const char* path, const vn_io_normals_options* options,
                                vn_io_normals_stats* stats, vn_io_error* error);

/* ------------------------------------------------------------------ formats
 *
 * One table (format.c) holds every fact about a file format: its names and
 * extensions, its reader and writer, what each keeps, and which conversion
 * path two formats of one family take. vnconvert's dispatch, --help, its
 * messages about formats and the README's "What vnconvert keeps" table
 * (vn_io_conversions_table) are made from it. A new format is its own
 * source file plus one row. */

/* What a format's writer keeps of a vn_io_mesh besides positions, normals
 * and triangles (vn_io_format.holds), and what a read item needs. */
enum {
	vn_io_holds_colors = 1,        /* `colors` (RGB: see vn_io_holds_color_alpha) */
	vn_io_holds_texcoords = 2,     /* `texcoords` */
	vn_io_holds_attributes = 4,    /* `attributes` */
	vn_io_holds_face_colors = 8,   /* `face_colors` */
	vn_io_holds_polygons = 16,     /* faces of more than 3 corners (else fan-triangulated) */
	vn_io_holds_loose_vertices = 32, /* vertices no face uses (else only the vertices faces use are written) */
	vn_io_holds_face_names = 64,     /* `objects`, `groups`, `smoothing`, `material_library` and its folder */
	vn_io_holds_color_alpha = 128,   /* the alpha of `colors` (OBJ's `v x y z r g b` has none) */
	vn_io_holds_no_faces = 256,      /* a mesh without faces but with vertices: a point cloud */
	vn_io_holds_nothing = 512,       /* a mesh without vertices: an empty file vn reads back */
	vn_io_holds_ply_extras = 1024,   /* `ply_extras` */
	vn_io_holds_materials = 2048,    /* each face's material (`materials`), with `material_defs` or the `mtllib` line */
	vn_io_holds_stl_extras = 4096,   /* `stl_extras` */
	vn_io_holds_lines = 8192,        /* `line_count`, `line_offsets`, `line_indices` */
	vn_io_holds_comments = 16384     /* `comments` */
};

/* How vnconvert converts between two formats of one family (both ends with
 * the same path); any other pair goes through a vn_io_mesh. */
typedef enum vn_io_path {
	vn_io_path_mesh = 0, /* read into a vn_io_mesh, compute, write */
	vn_io_path_gltf,     /* the glTF document is edited, only normals change (vn_gltf_convert);
	                        the glTF-only options apply */
	vn_io_path_drc       /* the Draco stream is kept but NORMAL (vn_drc_convert) */
} vn_io_path;

/* Where the Draco options (--draco-qp ... --draco-cl) apply (vn_io_format.draco). */
enum {
	vn_io_draco_output = 1,  /* whenever this format is written */
	vn_io_draco_document = 2 /* in conversions on its document path */
};

/* One thing a reader brings into a vn_io_mesh besides positions and faces:
 * a writer keeps it when its holds has every bit of `needs` (0: no writer
 * does). Named as the README's "What vnconvert keeps" table names it;
 * `lost` names it where it is left out (NULL: `text`), unless an item
 * needing part of its bits is left out too ("their alpha" after "vertex
 * colours"). */
typedef struct vn_io_item {
	unsigned needs;
	const char* text;
	const char* lost;
} vn_io_item;

#define VN_IO_MAX_ITEMS 9

typedef struct vn_io_format {
	const char* name;       /* "glb": as --format and --input-format take it */
	const char* title;      /* "GLB": as messages name the format */
	const char* family;     /* "glTF": formats of one family share a reader and a conversion path */
	const char* extensions; /* space-separated, lower case, with dot: ".off" */
	const char* description;
	/* Reads `path` into *mesh (zeroed on entry). */
	vn_io_result (*read)(const char* path, vn_io_mesh* mesh, vn_io_error* error);
	/* Writes mesh to the open stream; `path` is only for messages. settings
	 * are the format's own write settings (NULL: its defaults; the drc
	 * format takes a vn_drc_options*, and gltf and glb one to
	 * Draco-compress their triangle primitives; the others none). The caller
	 * (vn_io_write_file) takes care of atomicity. */
	vn_io_result (*write)(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings,
	                      vn_io_error* error);
	unsigned holds;        /* vn_io_holds_* bits */
	vn_io_path path;       /* between two formats of this path */
	unsigned draco;        /* vn_io_draco_* bits */
	/* What the writer gives a vertex without a normal: "the zero vector";
	 * NULL when the format holds no vertex normals at all (STL: one normal
	 * per facet, made from positions). */
	const char* no_normal;
	/* What the reader brings (text NULL ends the list), and what reading
	 * always leaves out (NULL: nothing). */
	vn_io_item reads[VN_IO_MAX_ITEMS];
	const char* never_read;
	/* Between two formats of the family on its document path (path !=
	 * vn_io_path_mesh): what is kept and what is left out. */
	const char* document_keeps;
	const char* document_loses;
	/* NULL when a file of this format is all there is to it, so that it can
	 * be read from a pipe or written to one (vnconvert's `-`); else what
	 * other files it may come with ("buffers and images"). */
	const char* companions;
} vn_io_format;

/* Names what writing mesh as `format` leaves out ("vertex normals, face
 * colours, TEXCOORD_1, _ID"; "vertex colour alpha" only when an alpha is
 * not 1), comma-separated, into text (truncated to size); returns how many
 * things that is (0: nothing is lost, text ""). */
size_t vn_io_mesh_losses(const vn_io_mesh* mesh, const vn_io_format* format, char* text, size_t size);

/* The format whose extension `path` ends with (case-insensitive), or NULL. */
const vn_io_format* vn_io_format_for_path(const char* path);
/* The format called `name` (case-insensitive), or NULL. */
const vn_io_format* vn_io_format_by_name(const char* name);
/* The i-th known format, or NULL past the end (for --help listings). */
const vn_io_format* vn_io_format_at(size_t i);

/* The conversion path from `in` to `out`: theirs when both have the same,
 * else vn_io_path_mesh. */
vn_io_path vn_io_conversion_path(const vn_io_format* in, const vn_io_format* out);

/* Lists the known formats into text (truncated to size) in one of these
 * styles, for messages: */
typedef enum vn_io_listing {
	vn_io_list_names,      /* "off, gltf, glb, drc" */
	vn_io_list_titles,     /* "OFF, glTF, GLB and Draco" */
	vn_io_list_families,   /* "OFF (.off), glTF (.gltf, .glb) and Draco (.drc)" */
	vn_io_list_extensions, /* ".off .gltf .glb .drc" */
	vn_io_list_draco       /* where the Draco options apply: "Draco (.drc) output, to glTF to glTF conversions
	                          and to glTF output with --draco on" */
} vn_io_listing;
VN_IO_API void vn_io_format_list(vn_io_listing style, char* text, size_t size);

/* The families (with their extensions) of path `p`: "glTF to glTF
 * conversions (.gltf or .glb in and out)", into text. */
void vn_io_path_description(vn_io_path p, char* text, size_t size);

/* One line telling why `path`, whose extension names no format vn knows,
 * cannot be read (input) or written, and what to do: a known foreign
 * format's name ("an OBJ file") and the formats vn has, into text. */
void vn_io_unknown_format(const char* path, int input, char* text, size_t size);

/* Writes the README's "What vnconvert keeps" table, in Markdown, to out: a
 * row for every pair of families, made from each format's reads, holds and
 * document_keeps/loses. */
void vn_io_conversions_table(FILE* out);

/* Reads path with `format`, or the format its extension names when NULL. */
vn_io_result vn_io_read_file(const char* path, const vn_io_format* format, vn_io_mesh* mesh, vn_io_error* error);

/* Writes mesh to path atomically, through vn_io_output: on any failure
 * path is untouched and no temporary file is left. format NULL: the one
 * path's extension names; settings go to its writer (NULL: defaults). */
vn_io_result vn_io_write_file(const char* path, const vn_io_format* format, const vn_io_mesh* mesh,
                              const void* settings, vn_io_error* error);

/* ------------------------------------------------------------------ output files
 *
 * Every output file (vn_io_write_file, and each file of a glTF) is written as
 * a temporary in the folder of the file it replaces, synced, then put in its
 * place, so that the file is either complete or as it was. On Linux the
 * temporary is a file without a name (open(folder, O_TMPFILE)) until it is
 * complete: nothing is left when the process is killed, even by SIGKILL.
 * At the end it is linked under its final name when that is new (linkat),
 * else under ".NAME.XXXXXX" and renamed over it: only a SIGKILL between
 * those two calls can leave that complete file behind. Where O_TMPFILE or
 * /proc is missing, the temporary is ".NAME.XXXXXX" from the start, which a
 * fatal signal the process can catch removes (see below), SIGKILL not.
 * - A symbolic link is written through: its target (followed along a chain
 *   of links, relative ones from their own folder) is replaced and the link
 *   stays; a dangling link's target is created.
 * - Only regular files are written: a folder, device, FIFO or socket is
 *   refused (so are links to one, like /dev/stdout or /dev/null).
 * - A replaced file keeps its mode and, where permitted, its owner and
 *   group; a new file gets 0666 less the umask, like any created file. */

/* Checks that path can be written as an output: its folder exists and path
 * (through its links) is a regular file or absent. The error names path and
 * says what to do. When target is not NULL, *target is the file an output
 * replaces (path with its links followed; malloc'd, the caller frees it). */
vn_io_result vn_io_output_check(const char* path, char** target, vn_io_error* error);

/* An output being written: the temporary, open, beside `target`. */
typedef struct vn_io_output {
	char* path;      /* as the caller named it, for messages */
	char* target;    /* the file the temporary replaces (see vn_io_output_check) */
	char* temporary; /* registered for removal on a fatal signal until committed or discarded */
	int fd;          /* the temporary, open for writing; -1 once closed */
	int slot;        /* its entry in the temporary-file registry */
	int anonymous;   /* the temporary has no name yet (O_TMPFILE) */
} vn_io_output;

/* Checks path as vn_io_output_check does and creates the temporary with the
 * mode, owner and group described above. On failure nothing is created and
 * *output needs no discard. */
vn_io_result vn_io_output_open(vn_io_output* output, const char* path, vn_io_error* error);

/* Syncs the temporary to disk and closes it (fd becomes -1); commit does it
 * too. A temporary without a name gets its ".NAME.XXXXXX" name first (an
 * output kept open until commit never has one). On failure the caller
 * discards the output. */
vn_io_result vn_io_output_close(vn_io_output* output, vn_io_error* error);

/* Syncs and closes the temporary if open and puts it in place of the
 * target, then frees the output; on failure the temporary is removed
 * instead. */
vn_io_result vn_io_output_commit(vn_io_output* output, vn_io_error* error);

/* Removes the temporary and frees the output; nothing for an output already
 * committed or discarded. */
void vn_io_output_discard(vn_io_output* output);

/* Process-wide state, for programs (the vn tools call it first thing): makes
 * SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT (a crash, also in a library),
 * SIGINT, SIGTERM and SIGHUP remove every open output's temporary before the
 * signal takes the action it had before (the default: the process ends, with
 * a core dump where that applies; a sanitizer's report). Signals the process
 * ignores stay ignored; a second call changes nothing. The registry of
 * temporaries it uses is fixed-size (vn_io_output_open fails when 1024 are
 * open at once) and filled by every vn_io_output, with or without this
 * call; a library that installs its own handlers need not call it. */
void vn_io_remove_temporaries_on_signal(void);

/* Reads a whole file into a NUL-terminated buffer the caller frees. */
vn_io_result vn_io_read_all(const char* path, char** data, size_t* size, vn_io_error* error);

/* A format's reader of bytes in memory (data need not be NUL-terminated):
 * fills *mesh (zeroed first and again on failure); `name` starts messages. */
typedef vn_io_result (*vn_io_memory_reader)(const char* data, size_t size, const char* name, vn_io_mesh* mesh,
                                            vn_io_error* error);

/* Reads the whole file path and parses it with parse, named as path. */
vn_io_result vn_io_read_with(const char* path, vn_io_memory_reader parse, vn_io_mesh* mesh, vn_io_error* error);

/* True when a and b name the same existing file (same device and inode). */
int vn_io_same_file(const char* a, const char* b);

/* Parses a whole decimal number in [lo, hi] (the text of a command-line
 * value); false on anything else. */
int vn_io_parse_uint(const char* s, unsigned long lo, unsigned long hi, unsigned long* out);

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
