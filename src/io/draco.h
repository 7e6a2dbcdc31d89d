/*
 * Draco (.drc) for vn_io, on Debian's libdraco (Draco 1.5.5). Four layers:
 *
 *  - A geometry API in plain C structs (vn_drc_decode, vn_drc_encode):
 *    triangles plus any attributes, each keeping its Draco unique id and the
 *    quantization grid it was decoded from, and the stream's metadata, so
 *    that glTF's KHR_draco_mesh_compression (which names attributes by
 *    unique id) can be built on it and encoding decoded data again does not
 *    move them.
 *
 *  - The format-table entries ("drc"): a Draco mesh to and from vn_io_mesh
 *    (positions, normals, the first 2-component float TEX_COORD in
 *    `texcoords`, the first RGB(A) COLOR in `colors`, every other attribute
 *    in `attributes`; polygons fan-triangulated on writing). A point cloud
 *    is read (a mesh without faces), not written.
 *
 *  - vn_drc_convert: .drc to .drc keeping everything but NORMAL (every
 *    attribute with its type, unique id, grid and metadata).
 *
 *  - vn_drc_read_file, which also reports the stream's quantization bits;
 *    writing with settings goes through vn_io_write_file with a
 *    vn_drc_options* as its settings; vn_drc_normal_error for --stats.
 *
 * Implemented in C++ (draco.cpp, draco_mesh.cpp) behind this C interface.
 */
#ifndef VN_IO_DRACO_H
#define VN_IO_DRACO_H

#include "vn_io.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ geometry */

/* Attribute meaning; the values are Draco's GeometryAttribute::Type. */
typedef enum vn_drc_semantic {
	vn_drc_position = 0,
	vn_drc_normal = 1,
	vn_drc_color = 2,
	vn_drc_texcoord = 3,
	vn_drc_generic = 4,
	/* Debian's libdraco is built with DRACO_TRANSCODER_SUPPORTED, whose
	 * streams may also carry these. */
	vn_drc_tangent = 5,
	vn_drc_material = 6,
	vn_drc_joints = 7,
	vn_drc_weights = 8,
	vn_drc_semantic_count = 9
} vn_drc_semantic;

/* Component types as glTF (and OpenGL) number them; float64 (OpenGL's
 * number, not a glTF type) is Draco's DT_FLOAT64, as PDAL writes
 * coordinates. */
enum {
	vn_drc_int8 = 5120,
	vn_drc_uint8 = 5121,
	vn_drc_int16 = 5122,
	vn_drc_uint16 = 5123,
	vn_drc_int32 = 5124,
	vn_drc_uint32 = 5125,
	vn_drc_float32 = 5126,
	vn_drc_float64 = 5130
};

/* A float attribute's quantization grid, as Draco stores it: quantized
 * integer q of component c stands for origin[c] + q * (range / (2^bits - 1)). */
typedef struct vn_drc_grid {
	int bits; /* 0: none */
	float origin[4];
	float range;
} vn_drc_grid;

typedef struct vn_drc_attribute {
	uint32_t unique_id;    /* Draco's id (what KHR_draco_mesh_compression refers to) */
	int semantic;          /* a vn_drc_semantic (int: a stream may carry other values) */
	int component_type;    /* vn_drc_int8 ... vn_drc_float32 */
	int components;        /* 1 to 4 */
	int normalized;        /* integer values stand for [0, 1] or [-1, 1] */
	/* Decoding: the bits the stream was quantized with, 0 when it was not
	 * (integer attributes are always lossless). Encoding: the bits to
	 * quantize a float32 attribute with, 0 for lossless; ignored for
	 * integer attributes. */
	int quantization_bits;
	void* data;            /* point_count * components values, packed, point by point */
	/* Decoding: the grid a quantized float attribute was decoded from (bits
	 * 0 for lossless and integer attributes and for normals, which Draco
	 * codes octahedrally; a kd-tree point cloud's NORMAL, which it quantizes
	 * per component, has its grid with quantization_bits 0). Encoding: a
	 * float attribute other than NORMAL whose quantization_bits equal
	 * grid.bits, and whose values all lie on the grid's box, is quantized
	 * on this grid, so that values decoded from it decode again to the same
	 * values (no generation loss); otherwise a new grid spans the values
	 * (Draco's default). A point cloud's NORMAL with quantization_bits 0 and
	 * its values on its grid is quantized on it where the cloud is written
	 * by kd-tree (levels 1 to 9, every other attribute quantized or
	 * integer), and stored unquantized otherwise. Zero it for new data. */
	vn_drc_grid grid;
} vn_drc_attribute;

typedef struct vn_drc_geometry {
	size_t point_count;
	size_t triangle_count;
	uint32_t* indices; /* 3 per triangle, each < point_count */
	size_t attribute_count;
	vn_drc_attribute* attributes;
	/* Opaque: the stream's metadata (Draco's GeometryMetadata: its entries
	 * and each attribute's, by unique id), or NULL. Decoding allocates it
	 * (vn_drc_geometry_free frees it); encoding writes it, with the
	 * attribute metadata of the unique ids g has (others are left out). */
	void* metadata;
	/* A point cloud stream (no triangles): decoded from one by
	 * vn_drc_decode_any; encoded as one (Draco's sequential or kd-tree point
	 * cloud method) where set, else as a mesh. */
	int point_cloud;
} vn_drc_geometry;

/* Frees what vn_drc_decode allocated and zeroes *g; NULL is fine. */
void vn_drc_geometry_free(vn_drc_geometry* g);

/* Decodes a Draco mesh bitstream into *g (zeroed first and on failure).
 * Float attributes come out dequantized as float32 (so POSITION is always
 * float32), integer ones in their own type, with their grid; the metadata
 * too. A stream declaring more faces or points than could fit in its bytes
 * and than Draco could allocate room for under a cap is refused before
 * Draco sizes tables from them (vn_drc_declared_counts). `name` starts
 * error messages. */
vn_io_result vn_drc_decode(const void* data, size_t size, const char* name, vn_drc_geometry* g, vn_io_error* error);
/* As vn_drc_decode, and a point cloud stream too (Draco's sequential or
 * kd-tree point cloud methods): its points and attributes, triangle_count
 * 0, point_cloud set. */
vn_io_result vn_drc_decode_any(const void* data, size_t size, const char* name, vn_drc_geometry* g,
                               vn_io_error* error);

/* Encodes g as a Draco mesh (a point cloud where g->point_cloud) at
 * compression level 0..10 (draco_encoder's -cl: 10 - level is Draco's
 * speed) into a malloc'ed *data the caller frees. Unique ids must differ.
 * Decoding gives back as many points and triangles, in another order below
 * level 10 (edgebreaker; kd-tree for a point cloud whose attributes allow
 * it) unless keep_order; where edgebreaker would change a count
 * (non-manifold vertices, degenerate triangles), at level 10, and with
 * keep_order (what data kept outside the stream, such as glTF morph
 * targets, need) the sequential method, which keeps points and triangles in
 * order, is used. Draco 1.5.5's decoder refuses more points than 3 per
 * triangle: such a mesh is unsupported, as is a non-finite value in a float
 * attribute to be quantized (the error names the attribute and the point).
 * `name` starts error messages. */
vn_io_result vn_drc_encode(const vn_drc_geometry* g, int compression_level, int keep_order, const char* name,
                           void** data, size_t* size, vn_io_error* error);

/* vn_drc_encode in two steps, so that the caller can free g's data before
 * Draco's encoder allocates its tables (several times the geometry's size):
 * vn_drc_encoder_new checks g (as vn_drc_encode) and copies it; g is not
 * used after it returns. vn_drc_encoder_encode encodes that copy as
 * vn_drc_encode does. vn_drc_encoder_free frees it; NULL is fine. */
typedef struct vn_drc_encoder vn_drc_encoder;
vn_io_result vn_drc_encoder_new(const vn_drc_geometry* g, const char* name, vn_drc_encoder** encoder, vn_io_error* error);
vn_io_result vn_drc_encoder_encode(const vn_drc_encoder* encoder, int compression_level, int keep_order, const char* name,
                                   void** data, size_t* size, vn_io_error* error);
void vn_drc_encoder_free(vn_drc_encoder* encoder);

/* The face and point counts a Draco stream's connectivity header declares,
 * read as Draco 1.5.5's decoders read them for each bitstream version they
 * accept (meshes 1.0 to 2.2, edgebreaker and sequential; point clouds to
 * 2.3, sequential and kd-tree, with no faces): *faces and *vertices
 * (edgebreaker: encoded vertices plus split symbols, what it sizes its
 * tables with). Returns 0 when the header cannot be read that far (neither
 * a mesh nor a point cloud, unknown method or version, truncated): Draco
 * then says why. */
int vn_drc_declared_counts(const void* data, size_t size, uint32_t* faces, uint64_t* vertices);

/* ------------------------------------------------------------------ vn_io */

/* Quantization bits per semantic (1 to VN_DRC_MAX_BITS, Draco's limit;
 * normals 2 to VN_DRC_MAX_BITS: octahedral coding) and compression level
 * (0 to 10). */
#define VN_DRC_MAX_BITS 30
typedef struct vn_drc_options {
	int position_bits, normal_bits, texcoord_bits, color_bits;
	int compression_level;
} vn_drc_options;

/* Position 14, normal 10, texcoord 12, colour 8 bits (glTF-Transform's
 * defaults, finer than draco_encoder's 11/8/10: vn's point is the normals),
 * compression level 7 (draco_encoder's default). */
void vn_drc_default_options(vn_drc_options* options);

/* The format-table entries; the writer's settings are a vn_drc_options*
 * (NULL: vn_drc_default_options). */
vn_io_result vn_io_drc_read(const char* path, vn_io_mesh* mesh, vn_io_error* error);
vn_io_result vn_io_drc_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error);

/* As vn_io_drc_read, and sets each field of *found (may be NULL) for which
 * the stream has a quantized attribute to the bits it was quantized with;
 * other fields are left as they are. */
vn_io_result vn_drc_read_file(const char* path, vn_io_mesh* mesh, vn_drc_options* found, vn_io_error* error);

/* The angle between mesh's normals and what a decoder gets back from them
 * after encoding with `options`, over the vertices with a nonzero normal that
 * the encoding keeps: median and maximum in degrees (0 when none). */
typedef struct vn_drc_normal_error {
	size_t compared;
	double median_degrees, max_degrees;
} vn_drc_normal_error;
vn_io_result vn_drc_normal_error_of(const vn_io_mesh* mesh, const vn_drc_options* options, const char* name,
                                    vn_drc_normal_error* out, vn_io_error* error);

/* As vn_drc_normal_error_of, for a triangle mesh given as `points` positions
 * and normals (3 doubles each) and 3 * triangles indices. */
vn_io_result vn_drc_triangle_normal_error(const double* positions, const double* normals, size_t points,
                                          const uint32_t* indices, size_t triangles, const vn_drc_options* options,
                                          const char* name, vn_drc_normal_error* out, vn_io_error* error);

/* The bits `given` sets for a float32 attribute of `semantic` (its position,
 * normal, texcoord or colour bits; -1 there: not given), else -1: integer
 * attributes are lossless, other semantics have no setting. */
int vn_drc_given_bits(const vn_drc_options* given, int semantic, int component_type);

/* ------------------------------------------------------------------ .drc to .drc */

typedef struct vn_drc_convert_options {
	vn_method method;
	unsigned threads;
	/* Each field -1 to keep the input's: an attribute's own bits (and grid),
	 * NORMAL's bits or 10, level 7; else the bits for every float attribute
	 * of that semantic (a new grid where they differ) and the level. */
	vn_drc_options given;
	int normal_error; /* fill vn_drc_convert_stats.normal_error (--stats) */
} vn_drc_convert_options;

typedef struct vn_drc_convert_stats {
	size_t points, triangles, attributes;
	vn_stats normals;      /* what libvn reported */
	vn_drc_options used;   /* the bits of POSITION, NORMAL, the first TEX_COORD and
	                          COLOR (else the defaults) and the level */
	vn_drc_normal_error normal_error;
	double read_seconds, normals_seconds, write_seconds;
	int input_normals; /* the input has a NORMAL of 3 floats or signed integers: a
	                      point no face gives a normal keeps its own (an integer
	                      one as the unit vector it stands for), else it gets
	                      the zero vector */
	int point_cloud;   /* the input is a point cloud: its NORMAL (if any) is kept as
	                      it is, and it is written as a point cloud */
} vn_drc_convert_stats;

/* Reads the Draco mesh `in`, recomputes its normals with options->method
 * and writes it to `out` (atomically, as vn_io_write_file) with everything
 * else kept: every attribute with its type, unique id, bits, grid (so its
 * decoded values are the input's) and metadata, the geometry metadata. Only
 * NORMAL (the first) is replaced, or added with the next free unique id.
 * Points and triangles may come out in another order (edgebreaker, or
 * kd-tree for a point cloud), as from any Draco encoder. A point cloud has
 * no faces to compute normals from: it is written as a point cloud with
 * every attribute kept, NORMAL too. A non-finite position is refused before
 * anything is written. stats may be NULL. */
vn_io_result vn_drc_convert(const char* in, const char* out, const vn_drc_convert_options* options,
                            vn_drc_convert_stats* stats, vn_io_error* error);

#ifdef __cplusplus
}
#endif

#endif /* VN_IO_DRACO_H */
