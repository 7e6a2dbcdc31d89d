/*
 * Draco (.drc) for vn_io, on Debian's libdraco (Draco 1.5.5). Three layers:
 *
 *  - A geometry API in plain C structs (vn_drc_decode, vn_drc_encode):
 *    triangles plus any attributes, each keeping its Draco unique id, so
 *    that glTF's KHR_draco_mesh_compression (which names attributes by
 *    unique id) can be built on it.
 *
 *  - The format-table entries ("drc"): a Draco mesh to and from vn_io_mesh
 *    (positions, normals, the first 2-component TEX_COORD, the first COLOR;
 *    polygons fan-triangulated on writing). A point cloud is refused as
 *    unsupported.
 *
 *  - vn_drc_read_file, which also reports the stream's quantization bits;
 *    writing with settings goes through vn_io_write_file with a
 *    vn_drc_options* as its settings; vn_drc_normal_error for --stats.
 *
 * Implemented in C++ (draco.cpp) behind this C interface.
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
	vn_drc_generic = 4
} vn_drc_semantic;

/* Component types as glTF (and OpenGL) number them. */
enum {
	vn_drc_int8 = 5120,
	vn_drc_uint8 = 5121,
	vn_drc_int16 = 5122,
	vn_drc_uint16 = 5123,
	vn_drc_int32 = 5124,
	vn_drc_uint32 = 5125,
	vn_drc_float32 = 5126
};

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
} vn_drc_attribute;

typedef struct vn_drc_geometry {
	size_t point_count;
	size_t triangle_count;
	uint32_t* indices; /* 3 per triangle, each < point_count */
	size_t attribute_count;
	vn_drc_attribute* attributes;
} vn_drc_geometry;

/* Frees what vn_drc_decode allocated and zeroes *g; NULL is fine. */
void vn_drc_geometry_free(vn_drc_geometry* g);

/* Decodes a Draco mesh bitstream into *g (zeroed first and on failure).
 * Float attributes come out dequantized as float32 (so POSITION is always
 * float32), integer ones in their own type. `name` starts error messages. */
vn_io_result vn_drc_decode(const void* data, size_t size, const char* name, vn_drc_geometry* g, vn_io_error* error);

/* Encodes g as a Draco mesh at compression level 0..10 (draco_encoder's -cl:
 * 10 - level is Draco's speed) into a malloc'ed *data the caller frees.
 * Unique ids must differ. Decoding gives back as many points and triangles,
 * in another order below level 10 (edgebreaker) unless keep_order; where
 * edgebreaker would change a count (non-manifold vertices, degenerate
 * triangles), at level 10, and with keep_order (what data kept outside the
 * stream, such as glTF morph targets, need) the sequential method, which
 * keeps points and triangles in order, is used. Draco 1.5.5's decoder refuses
 * more points than 3 per triangle: such g is unsupported. `name` starts
 * error messages. */
vn_io_result vn_drc_encode(const vn_drc_geometry* g, int compression_level, int keep_order, const char* name,
                           void** data, size_t* size, vn_io_error* error);

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

#ifdef __cplusplus
}
#endif

#endif /* VN_IO_DRACO_H */
