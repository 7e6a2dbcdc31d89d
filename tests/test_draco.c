/*
 * The Draco geometry API (draco.h) that glTF's KHR_draco_mesh_compression
 * uses: encode/decode round trips keeping unique ids, types, point and
 * triangle counts, quantization bits and grids (no generation loss); errors
 * on bad streams and input (non-finite values); each bitstream version's
 * counts; hostile counts; every attribute through the vn_io reader and
 * writer.
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "draco.h"

/* ------------------------------------------------------------------ helpers */

/* A unit octahedron: 6 points, 8 triangles, with a float POSITION (uid 7),
 * NORMAL (uid 3), normalized uint8 COLOR (uid 0) and a uint16 GENERIC (uid 12). */
static float positions[6 * 3] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
static float normals[6 * 3] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
static uint8_t colors[6 * 4] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255,
                                9, 9, 9, 255, 1, 2, 3, 4, 200, 100, 50, 25};
static uint16_t generic[6] = {0, 1000, 2000, 3000, 4000, 65535};
static uint32_t indices[8 * 3] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};

static vn_drc_attribute attributes[4] = {
    {7, vn_drc_position, vn_drc_float32, 3, 0, 11, positions, {0}},
    {3, vn_drc_normal, vn_drc_float32, 3, 0, 9, normals, {0}},
    {0, vn_drc_color, vn_drc_uint8, 4, 1, 0, colors, {0}},
    {12, vn_drc_generic, vn_drc_uint16, 1, 0, 0, generic, {0}},
};

static vn_drc_geometry octahedron(void)
{
	vn_drc_geometry g = {6, 8, indices, 4, attributes, NULL, 0};
	return g;
}

static const vn_drc_attribute* by_id(const vn_drc_geometry* g, uint32_t id)
{
	for (size_t i = 0; i < g->attribute_count; ++i)
		if (g->attributes[i].unique_id == id)
			return &g->attributes[i];
	return NULL;
}

/* Encodes the octahedron at `level` and decodes it into *out. */
static void round_trip_order(int level, int keep_order, vn_drc_geometry* out)
{
	vn_drc_geometry g = octahedron();
	void* data;
	size_t size;
	vn_io_error e;
	assert_int_equal(vn_drc_encode(&g, level, keep_order, "mem", &data, &size, &e), vn_io_success);
	assert_true(size > 0);
	assert_int_equal(vn_drc_decode(data, size, "mem", out, &e), vn_io_success);
	free(data);
}

static void round_trip(int level, vn_drc_geometry* out)
{
	round_trip_order(level, 0, out);
}

/* Decoded point p's position, to find the point the input had there. */
static int input_point(const vn_drc_geometry* g, size_t p)
{
	const float* q = (const float*)by_id(g, 7)->data + 3 * p;
	for (int i = 0; i < 6; ++i)
		if (fabsf(q[0] - positions[3 * i]) < 1e-3f && fabsf(q[1] - positions[3 * i + 1]) < 1e-3f &&
		    fabsf(q[2] - positions[3 * i + 2]) < 1e-3f)
			return i;
	return -1;
}

/* ------------------------------------------------------------------ tests */

static void check_round_trip(int level)
{
	vn_drc_geometry d;
	round_trip(level, &d);
	assert_int_equal(d.point_count, 6);
	assert_int_equal(d.triangle_count, 8);
	assert_int_equal(d.attribute_count, 4);
	const vn_drc_attribute* p = by_id(&d, 7);
	const vn_drc_attribute* n = by_id(&d, 3);
	const vn_drc_attribute* c = by_id(&d, 0);
	const vn_drc_attribute* x = by_id(&d, 12);
	assert_non_null(p);
	assert_non_null(n);
	assert_non_null(c);
	assert_non_null(x);
	assert_int_equal(p->semantic, vn_drc_position);
	assert_int_equal(p->component_type, vn_drc_float32);
	assert_int_equal(p->quantization_bits, 11);
	assert_int_equal(n->semantic, vn_drc_normal);
	assert_int_equal(n->quantization_bits, 9);
	assert_int_equal(c->component_type, vn_drc_uint8);
	assert_int_equal(c->components, 4);
	assert_true(c->normalized);
	assert_int_equal(c->quantization_bits, 0);
	assert_int_equal(x->semantic, vn_drc_generic);
	assert_int_equal(x->component_type, vn_drc_uint16);
	assert_int_equal(x->components, 1);
	/* Integer attributes are lossless, whatever the point order. */
	for (size_t i = 0; i < d.point_count; ++i) {
		const int k = input_point(&d, i);
		assert_true(k >= 0);
		assert_memory_equal((const uint8_t*)c->data + 4 * i, colors + 4 * k, 4);
		assert_int_equal(((const uint16_t*)x->data)[i], generic[k]);
		assert_true(fabsf(((const float*)n->data)[3 * i + k / 2] - normals[3 * k + k / 2]) < 1e-2f);
	}
	vn_drc_geometry_free(&d);
	assert_null(d.attributes);
}

static void test_round_trip_edgebreaker(void** state)
{
	(void)state;
	check_round_trip(7);
}

static void test_round_trip_sequential(void** state)
{
	(void)state;
	check_round_trip(10);
	/* The sequential method keeps the triangles as given. */
	vn_drc_geometry d;
	round_trip(10, &d);
	for (size_t i = 0; i < 3 * d.triangle_count; ++i)
		assert_int_equal(input_point(&d, d.indices[i]), indices[i]);
	vn_drc_geometry_free(&d);
}

/* keep_order: points and triangles come back as given at any level (what
 * glTF morph targets need); edgebreaker at level 7 renumbers the points. */
static void test_keep_order(void** state)
{
	(void)state;
	vn_drc_geometry d;
	round_trip_order(7, 1, &d);
	for (size_t i = 0; i < d.point_count; ++i)
		assert_int_equal(input_point(&d, i), (int)i);
	for (size_t i = 0; i < 3 * d.triangle_count; ++i)
		assert_int_equal(d.indices[i], indices[i]);
	vn_drc_geometry_free(&d);
	round_trip_order(7, 0, &d);
	int moved = 0;
	for (size_t i = 0; i < d.point_count; ++i)
		moved += input_point(&d, i) != (int)i;
	assert_true(moved > 0);
	vn_drc_geometry_free(&d);
}

/* Points no triangle uses (a glTF primitive drawing part of a shared
 * accessor): Draco 1.5.5's decoder refuses a mesh with more points than 3
 * per triangle, so encoding one is an error; up to that they come back at
 * every level (6 points, 2 triangles on 4 of them), in order with keep_order. */
static void test_isolated_points(void** state)
{
	(void)state;
	float p[7 * 3], q[7 * 3];
	for (size_t i = 0; i < 7 * 3; ++i)
		p[i] = (float)(i * 7 % 11), q[i] = i % 3 == 2 ? 1.0f : 0.0f;
	const uint32_t t[6] = {0, 1, 2, 2, 1, 3};
	vn_drc_attribute a[2] = {{0, vn_drc_position, vn_drc_float32, 3, 0, 14, p, {0}}, {1, vn_drc_normal, vn_drc_float32, 3, 0, 10, q, {0}}};
	vn_drc_geometry g = {7, 2, (uint32_t*)t, 2, a, NULL, 0};
	void* data;
	size_t size;
	vn_io_error e;
	vn_drc_geometry d;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "iso", &data, &size, &e), vn_io_error_unsupported);
	assert_non_null(strstr(e.message, "iso: 7 points"));
	g.point_count = 6;
	for (int level = 0; level <= 10; level += 5)
		for (int keep = 0; keep < 2; ++keep) {
			assert_int_equal(vn_drc_encode(&g, level, keep, "iso", &data, &size, &e), vn_io_success);
			assert_int_equal(vn_drc_decode(data, size, "iso", &d, &e), vn_io_success);
			assert_int_equal(d.point_count, 6);
			assert_int_equal(d.triangle_count, 2);
			if (keep)
				assert_memory_equal(d.indices, t, sizeof t);
			vn_drc_geometry_free(&d);
			free(data);
		}
}

static void test_lossless_float(void** state)
{
	(void)state;
	vn_drc_geometry g = octahedron();
	vn_drc_attribute a[1] = {attributes[0]};
	a[0].quantization_bits = 0;
	g.attributes = a;
	g.attribute_count = 1;
	void* data;
	size_t size;
	vn_io_error e;
	vn_drc_geometry d;
	assert_int_equal(vn_drc_encode(&g, 10, 0, "mem", &data, &size, &e), vn_io_success);
	assert_int_equal(vn_drc_decode(data, size, "mem", &d, &e), vn_io_success);
	assert_int_equal(d.attributes[0].quantization_bits, 0);
	assert_memory_equal(d.attributes[0].data, positions, sizeof positions);
	vn_drc_geometry_free(&d);
	free(data);
}

/* Peak resident memory of this process so far, in MB. */
static long peak_mb(void)
{
	struct rusage u;
	assert_int_equal(getrusage(RUSAGE_SELF, &u), 0);
	return u.ru_maxrss / 1024;
}

/* Ascending order, for comparing values that edgebreaker renumbered. */
static int ascending(const void* a, const void* b)
{
	const double x = *(const double*)a, y = *(const double*)b;
	return (x > y) - (x < y);
}

/* The n values of a 1-component float32 or uint32 attribute, sorted. */
static void sorted_values(const vn_drc_attribute* a, size_t n, double* out)
{
	for (size_t i = 0; i < n; ++i)
		out[i] = a->component_type == vn_drc_uint32 ? ((const uint32_t*)a->data)[i] : ((const float*)a->data)[i];
	qsort(out, n, sizeof *out, ascending);
}

/* Values of a wide span: Draco's entropy coder takes 4 bytes per symbol up
 * to the largest, so floats quantized to 30 bits spread over their range (a
 * fuzzed point cloud of 1,065 points took 4 GB) and integers spanning 2^30
 * are stored without it, losslessly, by each method. 32-bit integers of
 * magnitude 2^30 and more, which Draco's prediction overflows on, are
 * refused by name. */
static void test_wide_values(void** state)
{
	(void)state;
	static float wide[6] = {-1e22f, 6e21f, -2e21f, 1e22f, 2e21f, -6e21f};
	static uint32_t ids[6] = {0, 700000000u, 1073741823u, 300000000u, 1, 900000000u};
	vn_drc_geometry g = octahedron();
	vn_drc_attribute a[3] = {attributes[0], {4, vn_drc_generic, vn_drc_float32, 1, 0, 30, wide, {0}},
	                         {8, vn_drc_generic, vn_drc_uint32, 1, 0, 0, ids, {0}}};
	g.attributes = a;
	void* data;
	size_t size;
	vn_io_error e;
	vn_drc_geometry d;
	double expected[6], got[6];
	/* edgebreaker, sequential, a point cloud (kd-tree) */
	for (int method = 0; method < 3; ++method)
		for (size_t n = 2; n <= 3; ++n) {
			g.attribute_count = n;
			g.triangle_count = method < 2 ? 8 : 0;
			g.point_cloud = method == 2;
			assert_int_equal(vn_drc_encode(&g, 7, method == 1, "wide", &data, &size, &e), vn_io_success);
			assert_true(peak_mb() < 512);
			assert_int_equal(vn_drc_decode_any(data, size, "wide", &d, &e), vn_io_success);
			free(data);
			assert_int_equal(d.point_count, 6);
			assert_int_equal(d.attribute_count, n);
			const vn_drc_attribute* w = by_id(&d, 4);
			assert_int_equal(w->quantization_bits, 30);
			sorted_values(&a[1], 6, expected);
			sorted_values(w, 6, got);
			for (int i = 0; i < 6; ++i) /* Draco quantizes in float: 2^-21 of the range */
				assert_float_equal(got[i], expected[i], 1e16);
			if (n == 3) {
				sorted_values(&a[2], 6, expected);
				sorted_values(by_id(&d, 8), 6, got);
				assert_memory_equal(got, expected, sizeof got);
			}
			vn_drc_geometry_free(&d);
		}
	g.triangle_count = 8, g.point_cloud = 0;
	ids[2] = 1073741824u;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "wide", &data, &size, &e), vn_io_error_unsupported);
	assert_string_equal(e.message, "wide: attribute 8 (GENERIC) has 1073741824 at point 2, and Draco codes 32-bit "
	                               "integers only of magnitude below 2^30 (1073741824)");
	ids[2] = 1073741823u;
}

/* float64 attributes (PDAL writes coordinates so) come back as float64,
 * exactly, at every level, as a mesh and as a point cloud: Draco stores
 * them losslessly (it quantizes float32 only). */
static void test_float64(void** state)
{
	(void)state;
	double xyz[6 * 3], time[6];
	for (int i = 0; i < 18; ++i)
		xyz[i] = 637012.24 + positions[i] * 0.01 + i * 1e-7; /* not floats */
	for (int i = 0; i < 6; ++i)
		time[i] = 245000000.123456 + i;
	vn_drc_attribute a[2] = {{7, vn_drc_position, vn_drc_float64, 3, 0, 0, xyz, {0}},
	                         {12, vn_drc_generic, vn_drc_float64, 1, 0, 0, time, {0}}};
	for (int cloud = 0; cloud < 2; ++cloud)
		for (int level = 0; level <= 10; level += 5) {
			vn_drc_geometry g = octahedron();
			g.attributes = a;
			g.attribute_count = 2;
			g.point_cloud = cloud;
			g.triangle_count = cloud ? 0 : g.triangle_count;
			void* data;
			size_t size;
			vn_io_error e;
			vn_drc_geometry d;
			assert_int_equal(vn_drc_encode(&g, level, 0, "f64", &data, &size, &e), vn_io_success);
			assert_int_equal(vn_drc_decode_any(data, size, "f64", &d, &e), vn_io_success);
			assert_int_equal(d.point_count, 6);
			const vn_drc_attribute *p = by_id(&d, 7), *t = by_id(&d, 12);
			assert_non_null(p);
			assert_non_null(t);
			assert_int_equal(p->component_type, vn_drc_float64);
			assert_int_equal(t->component_type, vn_drc_float64);
			/* Edgebreaker (mesh, below 10) renumbers the points: the
			 * generic attribute follows each position. */
			for (size_t i = 0; i < 6; ++i) {
				const double* q = (const double*)p->data + 3 * i;
				size_t k = 0;
				while (k < 6 && memcmp(q, xyz + 3 * k, 3 * sizeof(double)))
					++k;
				assert_true(k < 6);
				assert_memory_equal((const double*)t->data + i, time + k, sizeof(double));
			}
			vn_drc_geometry_free(&d);
			free(data);
		}
}

/* KHR_mesh_quantization's integers (int16 positions, int8 normals) come
 * back exactly at every level, through the two-step encoder whose input is
 * freed before it encodes. Draco 1.5.5 predicts a NORMAL from the
 * positions below speed 4 (levels 7 to 9) in a way only float normals
 * survive: an int8 (0, 0, 127) came back as (4, 4, 5). */
static void test_integer_normals(void** state)
{
	(void)state;
	for (int level = 0; level <= 10; ++level) {
		int16_t* p = malloc(sizeof(int16_t) * 18);
		int8_t* n = malloc(18);
		uint32_t* t = malloc(sizeof indices);
		assert_non_null(p);
		assert_non_null(n);
		assert_non_null(t);
		for (int k = 0; k < 18; ++k)
			p[k] = (int16_t)(positions[k] * 1000), n[k] = (int8_t)(normals[k] * 127);
		memcpy(t, indices, sizeof indices);
		vn_drc_attribute a[2] = {{7, vn_drc_position, vn_drc_int16, 3, 0, 0, p, {0}},
		                         {3, vn_drc_normal, vn_drc_int8, 3, 1, 0, n, {0}}};
		vn_drc_geometry g = {6, 8, t, 2, a, NULL, 0};
		vn_drc_encoder* encoder;
		vn_io_error e;
		assert_int_equal(vn_drc_encoder_new(&g, "int", &encoder, &e), vn_io_success);
		free(p);
		free(n);
		free(t);
		void* data;
		size_t size;
		assert_int_equal(vn_drc_encoder_encode(encoder, level, 0, "int", &data, &size, &e), vn_io_success);
		vn_drc_encoder_free(encoder);
		vn_drc_geometry d;
		assert_int_equal(vn_drc_decode(data, size, "int", &d, &e), vn_io_success);
		free(data);
		assert_int_equal(d.point_count, 6);
		const int16_t* q = by_id(&d, 7)->data;
		const int8_t* m = by_id(&d, 3)->data;
		assert_int_equal(by_id(&d, 3)->component_type, vn_drc_int8);
		for (size_t i = 0; i < 6; ++i)
			for (int c = 0; c < 3; ++c)
				assert_int_equal(m[3 * i + c], (int)(q[3 * i + c] / 1000 * 127));
		vn_drc_geometry_free(&d);
	}
}

static void test_corrupt_streams(void** state)
{
	(void)state;
	vn_drc_geometry g = octahedron();
	void* data;
	size_t size;
	vn_io_error e;
	vn_drc_geometry d;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "mem", &data, &size, &e), vn_io_success);
	assert_int_equal(vn_drc_decode(data, 4, "short.drc", &d, &e), vn_io_error_parse);
	assert_non_null(strstr(e.message, "short.drc: "));
	assert_null(d.attributes);
	assert_int_equal(vn_drc_decode(data, size / 2, "half.drc", &d, &e), vn_io_error_parse);
	assert_non_null(strstr(e.message, "half.drc: "));
	assert_int_equal(vn_drc_decode("not draco at all", 16, "text.drc", &d, &e), vn_io_error_parse);
	free(data);
}

static void test_bad_input(void** state)
{
	(void)state;
	vn_drc_geometry g = octahedron();
	vn_drc_attribute a[4];
	memcpy(a, attributes, sizeof a);
	g.attributes = a;
	void* data;
	size_t size;
	vn_io_error e;
	a[3].unique_id = 7;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "dup", &data, &size, &e), vn_io_error_unsupported);
	assert_non_null(strstr(e.message, "unique id 7"));
	a[3].unique_id = 12;
	a[0].quantization_bits = VN_DRC_MAX_BITS + 1;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "bits", &data, &size, &e), vn_io_error_unsupported);
	a[0].quantization_bits = 11;
	a[1].quantization_bits = 1;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "qn", &data, &size, &e), vn_io_error_unsupported);
	assert_non_null(strstr(e.message, "normals need 2 to 30"));
	a[1].quantization_bits = 9;
	assert_int_equal(vn_drc_encode(&g, 11, 0, "level", &data, &size, &e), vn_io_error_unsupported);
	uint32_t bad[3] = {0, 1, 6};
	g.indices = bad;
	g.triangle_count = 1;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "index", &data, &size, &e), vn_io_error_unsupported);
	assert_null(data);
}

static void test_format_table(void** state)
{
	(void)state;
	const vn_io_format* f = vn_io_format_for_path("Bunny.DRC");
	assert_non_null(f);
	assert_string_equal(f->name, "drc");
	vn_drc_options o;
	vn_drc_default_options(&o);
	assert_int_equal(o.position_bits, 14);
	assert_int_equal(o.normal_bits, 10);
	assert_int_equal(o.texcoord_bits, 12);
	assert_int_equal(o.color_bits, 8);
	assert_int_equal(o.compression_level, 7);
}

/* ------------------------------------------------------------------ bitstream versions */

/* A hand-built mesh stream header: "DRACO", version, mesh, method, flags. */
static size_t header(uint8_t* b, int major, int minor, int method, int flags)
{
	memcpy(b, "DRACO", 5);
	b[5] = (uint8_t)major, b[6] = (uint8_t)minor, b[7] = 1, b[8] = (uint8_t)method;
	b[9] = (uint8_t)(flags & 0xFF), b[10] = (uint8_t)(flags >> 8);
	return 11;
}

/* A point cloud stream's header (geometry type 0). */
static size_t cloud_header(uint8_t* b, int major, int minor, int method, int flags)
{
	const size_t n = header(b, major, minor, method, flags);
	b[7] = 0;
	return n;
}

static size_t u32(uint8_t* b, uint32_t v)
{
	for (int i = 0; i < 4; ++i)
		b[i] = (uint8_t)(v >> 8 * i);
	return 4;
}

static size_t varint(uint8_t* b, uint32_t v)
{
	size_t n = 0;
	for (; v >= 0x80; v >>= 7)
		b[n++] = (uint8_t)(v | 0x80);
	b[n++] = (uint8_t)v;
	return n;
}

/* An edgebreaker connectivity header as Draco 1.5.5 reads it for version
 * major.minor: traversal type, new vertices (before 2.2), encoded vertices,
 * faces, attribute data, symbols, split symbols; uint32 before 2.0, varints
 * from 2.0; then filler. */
static size_t edgebreaker(uint8_t* b, int major, int minor, int flags, uint32_t vertices, uint32_t faces, uint32_t split)
{
	const int version = major << 8 | minor, wide = version < 0x0200;
	size_t n = header(b, major, minor, 1, flags);
	if (flags && version >= 0x0103)
		b[n++] = 0, b[n++] = 0, b[n++] = 0; /* empty metadata: no attribute metadata, entries, sub-metadata */
	b[n++] = 2;                              /* valence traversal */
	if (version < 0x0202)
		n += wide ? u32(b + n, 7) : varint(b + n, 7);
	n += wide ? u32(b + n, vertices) : varint(b + n, vertices);
	n += wide ? u32(b + n, faces) : varint(b + n, faces);
	b[n++] = 1;
	n += wide ? u32(b + n, faces) : varint(b + n, faces);
	n += wide ? u32(b + n, split) : varint(b + n, split);
	memset(b + n, 0x11, 16);
	return n + 16;
}

/* Each bitstream version's layout: the counts are read where Draco reads them. */
static void test_declared_counts(void** state)
{
	(void)state;
	static const int versions[][2] = {{1, 0}, {1, 1}, {1, 2}, {1, 3}, {2, 0}, {2, 1}, {2, 2}};
	uint8_t b[128];
	uint32_t faces;
	uint64_t vertices;
	for (size_t i = 0; i < sizeof versions / sizeof versions[0]; ++i)
		for (int flags = 0; flags <= 0x8000; flags += 0x8000) {
			/* 170 faces, 99 vertices, 17 split symbols (test_nm.obj's): 300 and 200 do not fit in a byte. */
			const size_t n = edgebreaker(b, versions[i][0], versions[i][1], flags, 99, 170 + 130, 17 + 200);
			assert_true(vn_drc_declared_counts(b, n, &faces, &vertices));
			assert_int_equal(faces, 300);
			assert_int_equal(vertices, 99 + 217);
			/* Cut inside the counts: unreadable, Draco decides. */
			assert_false(vn_drc_declared_counts(b, 14, &faces, &vertices));
		}
	/* Sequential: faces and points, uint32 before 2.2, varints from 2.2. */
	for (int minor = 1; minor <= 2; ++minor) {
		size_t n = header(b, 2, minor, 0, 0);
		n += minor < 2 ? u32(b + n, 1000) : varint(b + n, 1000);
		n += minor < 2 ? u32(b + n, 700) : varint(b + n, 700);
		b[n++] = 1;
		assert_true(vn_drc_declared_counts(b, n, &faces, &vertices));
		assert_int_equal(faces, 1000);
		assert_int_equal(vertices, 700);
	}
	/* Point clouds, sequential (0) and kd-tree (1), up to 2.3: an int32
	 * point count, no faces (a negative count is a huge one to Draco). */
	for (int method = 0; method <= 1; ++method) {
		size_t n = cloud_header(b, 2, 3, method, 0);
		n += u32(b + n, 123456);
		assert_true(vn_drc_declared_counts(b, n, &faces, &vertices));
		assert_int_equal(faces, 0);
		assert_int_equal(vertices, 123456);
		n = cloud_header(b, 2, 3, method, 0);
		n += u32(b + n, (uint32_t)-5);
		assert_true(vn_drc_declared_counts(b, n, &faces, &vertices));
		assert_int_equal(vertices, 0xFFFFFFFBu);
		assert_false(vn_drc_declared_counts(b, n - 1, &faces, &vertices));
	}
	/* Neither a mesh nor a point cloud, an unknown method or version: left
	 * to Draco. */
	size_t n = edgebreaker(b, 2, 2, 0, 99, 170, 17);
	b[7] = 2;
	assert_false(vn_drc_declared_counts(b, n, &faces, &vertices));
	n = edgebreaker(b, 2, 3, 0, 99, 170, 17);
	assert_false(vn_drc_declared_counts(b, n, &faces, &vertices));
	n = cloud_header(b, 2, 3, 2, 0);
	n += u32(b + n, 10);
	assert_false(vn_drc_declared_counts(b, n, &faces, &vertices));
	n = cloud_header(b, 2, 4, 0, 0);
	n += u32(b + n, 10);
	assert_false(vn_drc_declared_counts(b, n, &faces, &vertices));
	/* A real 2.2 stream. */
	vn_drc_geometry g = octahedron();
	void* data;
	size_t size;
	vn_io_error e;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "mem", &data, &size, &e), vn_io_success);
	assert_true(vn_drc_declared_counts(data, size, &faces, &vertices));
	assert_int_equal(faces, 8);
	assert_true(vertices >= 6);
	free(data);
}

/* Hostile counts are refused before Draco allocates for them; counts a
 * stream might hold, even improbable for its size, are left to Draco. */
static void test_hostile_counts(void** state)
{
	(void)state;
	uint8_t b[128];
	vn_drc_geometry d;
	vn_io_error e;
	for (int minor = 0; minor <= 2; ++minor) {
		size_t n = edgebreaker(b, 2, minor, 0, 3, 100000000, 0);
		assert_int_equal(vn_drc_decode(b, n, "hostile.drc", &d, &e), vn_io_error_parse);
		assert_non_null(strstr(e.message, "hostile.drc: the stream declares 100000000 faces and 3 points in"));
		/* 1.6 million faces in 40 bytes: implausible but within the cap; Draco says it is corrupt. */
		n = edgebreaker(b, 2, minor, 0, 3, 1600000, 0);
		assert_int_equal(vn_drc_decode(b, n, "dense.drc", &d, &e), vn_io_error_parse);
		assert_null(strstr(e.message, "declares"));
	}
	/* A point cloud declaring 2^31 points in 16 bytes, or 65537 (more than
	 * 4096 a byte: a point cloud's attributes, read after the counts, are
	 * bounded by no cap), refused before Draco sizes its attributes from
	 * them; 65536 are left to Draco (which finds no attribute data). */
	for (int method = 0; method <= 1; ++method) {
		size_t n = cloud_header(b, 2, 3, method, 0);
		n += u32(b + n, 0x80000000u);
		b[n++] = 1;
		assert_int_equal(vn_drc_decode_any(b, n, "hostile.drc", &d, &e), vn_io_error_parse);
		assert_non_null(strstr(e.message, "hostile.drc: the stream declares 2147483648 points in 16 bytes: corrupt"));
		n = cloud_header(b, 2, 3, method, 0);
		n += u32(b + n, 65537);
		b[n++] = 1;
		assert_int_equal(vn_drc_decode_any(b, n, "dense.drc", &d, &e), vn_io_error_parse);
		assert_non_null(strstr(e.message, "dense.drc: the stream declares 65537 points in 16 bytes: corrupt"));
		n = cloud_header(b, 2, 3, method, 0);
		n += u32(b + n, 65536);
		b[n++] = 1;
		assert_int_equal(vn_drc_decode_any(b, n, "dense.drc", &d, &e), vn_io_error_parse);
		assert_null(strstr(e.message, "declares"));
	}
	/* A kd-tree point cloud before bitstream 2.3 (a point count libdraco
	 * reads unchecked inside its attribute data): refused, saying so. */
	size_t n = cloud_header(b, 2, 2, 1, 0);
	n += u32(b + n, 4);
	b[n++] = 1;
	assert_int_equal(vn_drc_decode_any(b, n, "old.drc", &d, &e), vn_io_error_unsupported);
	assert_string_equal(e.message, "old.drc: a kd-tree point cloud of bitstream 2.2, which vn does not read (libdraco "
	                               "would size it from counts vn cannot check): encode it again with Draco 1.4 or later");
}

/* A point cloud stream (points.drc: a unit cube's 8 corners with normals):
 * vn_drc_decode refuses it, vn_drc_decode_any gives its points in Draco's
 * order and no triangles. */
static void test_point_cloud(void** state)
{
	(void)state;
	char* data;
	size_t size;
	vn_io_error e;
	assert_int_equal(vn_io_read_all("data/draco/points.drc", &data, &size, &e), vn_io_success);
	vn_drc_geometry d;
	assert_int_equal(vn_drc_decode(data, size, "points.drc", &d, &e), vn_io_error_unsupported);
	assert_string_equal(e.message, "points.drc: a Draco point cloud, not a mesh");
	assert_int_equal(vn_drc_decode_any(data, size, "points.drc", &d, &e), vn_io_success);
	assert_int_equal(d.point_count, 8);
	assert_int_equal(d.triangle_count, 0);
	assert_int_equal(d.attribute_count, 2);
	assert_int_equal(d.attributes[0].semantic, vn_drc_position);
	assert_int_equal(d.attributes[1].semantic, vn_drc_normal);
	static const float expected[24] = {1, 1, 1, 1, 1, 0, 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 0, 1};
	const float* p = (const float*)d.attributes[0].data;
	for (int i = 0; i < 24; ++i)
		assert_float_equal(p[i], expected[i], 0.0);
	vn_drc_geometry_free(&d);
	free(data);
}

/* ------------------------------------------------------------------ generation loss */

/* A 10 x 20 grid of points with uneven coordinates, 342 triangles, float
 * POSITION (14 bits) and TEX_COORD (12 bits). */
#define GRID_POINTS 200
static float grid_positions[3 * GRID_POINTS], grid_uv[2 * GRID_POINTS];
static uint32_t grid_indices[3 * 342];

static vn_drc_geometry grid_mesh(vn_drc_attribute* a)
{
	size_t t = 0;
	for (uint32_t i = 0; i < 10; ++i)
		for (uint32_t j = 0; j < 20; ++j) {
			const uint32_t p = 20 * i + j;
			grid_positions[3 * p] = 3.7f + 0.123457f * (float)i + 0.001f * (float)(j % 7);
			grid_positions[3 * p + 1] = -11.3f + 0.0987f * (float)j;
			grid_positions[3 * p + 2] = 0.25f * sinf((float)p);
			grid_uv[2 * p] = 0.1f + 0.031f * (float)i, grid_uv[2 * p + 1] = 0.77f - 0.0171f * (float)j;
			if (i < 9 && j < 19) {
				const uint32_t q[6] = {p, p + 20, p + 1, p + 1, p + 20, p + 21};
				memcpy(grid_indices + t, q, sizeof q);
				t += 6;
			}
		}
	const vn_drc_attribute init[2] = {{5, vn_drc_position, vn_drc_float32, 3, 0, 14, grid_positions, {0}},
	                                  {9, vn_drc_texcoord, vn_drc_float32, 2, 0, 12, grid_uv, {0}}};
	memcpy(a, init, sizeof init);
	vn_drc_geometry g = {GRID_POINTS, t / 3, grid_indices, 2, a, NULL, 0};
	return g;
}

static void encode_decode(const vn_drc_geometry* g, vn_drc_geometry* out)
{
	void* data;
	size_t size;
	vn_io_error e;
	assert_int_equal(vn_drc_encode(g, 7, 1, "grid", &data, &size, &e), vn_io_success);
	assert_int_equal(vn_drc_decode(data, size, "grid", out, &e), vn_io_success);
	free(data);
}

/* Encodes g (a point cloud too) at `level`, checks the stream's method
 * (header byte 8: 0 sequential, 1 kd-tree or edgebreaker) and decodes it
 * into *out. */
static void encode_method(const vn_drc_geometry* g, int level, int method, vn_drc_geometry* out)
{
	void* data;
	size_t size;
	vn_io_error e;
	assert_int_equal(vn_drc_encode(g, level, 0, "cloud", &data, &size, &e), vn_io_success);
	assert_int_equal(((const unsigned char*)data)[8], method);
	assert_int_equal(vn_drc_decode_any(data, size, "cloud", out, &e), vn_io_success);
	free(data);
}

/* A point cloud at level 7 (kd-tree), three generations: the bits and grids
 * read back, the same floats. The kd-tree decoder leaves the unique ids of
 * its quantized attributes 0, and vn matched them by id: the bits read 0,
 * and the next generation stored the floats unquantized. */
static void test_point_cloud_grid_kept(void** state)
{
	(void)state;
	vn_drc_attribute a[2];
	vn_drc_geometry g = grid_mesh(a);
	g.triangle_count = 0, g.point_cloud = 1;
	vn_drc_geometry d[3];
	for (int i = 0; i < 3; ++i) {
		encode_method(i ? &d[i - 1] : &g, 7, 1, &d[i]); /* kd-tree */
		assert_int_equal(by_id(&d[i], 5)->quantization_bits, 14);
		assert_int_equal(by_id(&d[i], 9)->quantization_bits, 12);
	}
	for (uint32_t id = 5; id <= 9; id += 4) {
		assert_int_equal(by_id(&d[0], id)->grid.bits, id == 5 ? 14 : 12);
		assert_memory_equal(by_id(&d[0], id)->data, by_id(&d[2], id)->data, GRID_POINTS * by_id(&d[0], id)->components * 4);
		assert_memory_equal(&by_id(&d[0], id)->grid, &by_id(&d[2], id)->grid, sizeof(vn_drc_grid));
	}
	for (int i = 0; i < 3; ++i)
		vn_drc_geometry_free(&d[i]);
}

/* Lexicographic order of 6 floats. */
static int row_order(const void* a, const void* b)
{
	const float *x = a, *y = b;
	for (int k = 0; k < 6; ++k)
		if (x[k] != y[k])
			return x[k] < y[k] ? -1 : 1;
	return 0;
}

/* Cloud g's points (at most 8) as rows of POSITION (id 0) and NORMAL (id 1),
 * sorted. */
static void sorted_points(const vn_drc_geometry* g, float rows[8][6])
{
	assert_true(g->point_count <= 8);
	const float *p = by_id(g, 0)->data, *n = by_id(g, 1)->data;
	for (size_t i = 0; i < g->point_count; ++i)
		for (int k = 0; k < 3; ++k)
			rows[i][k] = p[3 * i + k], rows[i][3 + k] = n[3 * i + k];
	qsort(rows, g->point_count, sizeof rows[0], row_order);
}

/* A kd-tree point cloud's NORMAL (quantized per component there;
 * draco_encoder -point_cloud's points.drc) reads back with its grid and
 * bits 0: written again by kd-tree it is quantized on that grid (the
 * stream stays kd-tree, the same values); at level 10 it is stored
 * unquantized, the same values too. Before, it was read without its grid,
 * and any unquantized float keeps Draco from kd-tree: the cloud was
 * rewritten sequential, 4 times the size for 100k points. */
static void test_point_cloud_kd_normals(void** state)
{
	(void)state;
	char* bytes;
	size_t n;
	vn_io_error e;
	assert_int_equal(vn_io_read_all("data/draco/points.drc", &bytes, &n, &e), vn_io_success);
	assert_int_equal(bytes[8], 1); /* kd-tree */
	vn_drc_geometry d[3];
	assert_int_equal(vn_drc_decode_any(bytes, n, "points.drc", &d[0], &e), vn_io_success);
	free(bytes);
	assert_int_equal(by_id(&d[0], 1)->quantization_bits, 0);
	assert_int_equal(by_id(&d[0], 1)->grid.bits, 8);
	float p0[8][6], pi[8][6];
	sorted_points(&d[0], p0);
	const int levels[3] = {0, 7, 10}, methods[3] = {0, 1, 0}; /* -, kd-tree, sequential */
	for (int i = 1; i < 3; ++i) {
		encode_method(&d[0], levels[i], methods[i], &d[i]);
		assert_int_equal(by_id(&d[i], 1)->grid.bits, i == 1 ? 8 : 0);
		sorted_points(&d[i], pi); /* kd-tree sorts the points */
		assert_memory_equal(pi, p0, d[0].point_count * sizeof pi[0]);
	}
	for (int i = 0; i < 3; ++i)
		vn_drc_geometry_free(&d[i]);
}

/* A point cloud with quantized float normals is written by the sequential
 * method, which codes them octahedrally: kd-tree quantized them per
 * component, so an octahedral (0, 0, -1) came back as (0.001, 0.001, -1)
 * and every generation moved them (google/draco's cube_pc.drc). The cube's
 * axis normals come back exactly, twice. */
static void test_point_cloud_octahedral_normals(void** state)
{
	(void)state;
	static float p[8 * 3], nrm[8 * 3];
	for (int i = 0; i < 8; ++i) {
		p[3 * i] = (float)(i & 1), p[3 * i + 1] = (float)(i >> 1 & 1), p[3 * i + 2] = (float)(i >> 2 & 1);
		nrm[3 * i + i % 3] = i % 2 ? 1.0f : -1.0f;
	}
	vn_drc_attribute a[2] = {{0, vn_drc_position, vn_drc_float32, 3, 0, 11, p, {0}},
	                         {1, vn_drc_normal, vn_drc_float32, 3, 0, 10, nrm, {0}}};
	vn_drc_geometry g = {8, 0, NULL, 2, a, NULL, 1};
	vn_drc_geometry d[2];
	for (int i = 0; i < 2; ++i) {
		encode_method(i ? &d[0] : &g, 7, 0, &d[i]); /* sequential */
		assert_int_equal(by_id(&d[i], 1)->quantization_bits, 10);
		assert_memory_equal(by_id(&d[i], 1)->data, nrm, sizeof nrm);
	}
	vn_drc_geometry_free(&d[0]);
	vn_drc_geometry_free(&d[1]);
}

/* Decoded float attributes come with the grid they were quantized on, and
 * encoding them again at the same bits decodes to the same values; without
 * the grid (or with other bits) Draco fits a new one and they move. */
static void test_grid_kept(void** state)
{
	(void)state;
	vn_drc_attribute a[2];
	const vn_drc_geometry g = grid_mesh(a);
	vn_drc_geometry d1, d2, d3;
	encode_decode(&g, &d1);
	const vn_drc_attribute* p = by_id(&d1, 5);
	assert_int_equal(p->grid.bits, 14);
	assert_true(fabsf(p->grid.origin[0] - 3.7f) < 1e-6f && fabsf(p->grid.origin[1] + 11.3f) < 1e-5f);
	assert_true(fabsf(p->grid.range - 0.0987f * 19) < 1e-5f);
	assert_int_equal(by_id(&d1, 9)->grid.bits, 12);
	/* Three generations: the same floats. */
	encode_decode(&d1, &d2);
	encode_decode(&d2, &d3);
	for (uint32_t id = 5; id <= 9; id += 4) {
		assert_memory_equal(by_id(&d1, id)->data, by_id(&d3, id)->data, GRID_POINTS * by_id(&d1, id)->components * 4);
		assert_memory_equal(&by_id(&d1, id)->grid, &by_id(&d3, id)->grid, sizeof(vn_drc_grid));
	}
	vn_drc_geometry_free(&d1);
	vn_drc_geometry_free(&d2);
	vn_drc_geometry_free(&d3);
	/* A stream whose grid is larger than its values' box (other encoders',
	 * or data cut from a larger model): without the grid, Draco fits one
	 * to the decoded values and they move; with it they stay. */
	a[0].grid.bits = 14;
	a[0].grid.origin[0] = 3.1f, a[0].grid.origin[1] = -12.05f, a[0].grid.origin[2] = -0.3f;
	a[0].grid.range = 2.9f;
	encode_decode(&g, &d1);
	assert_true(by_id(&d1, 5)->grid.range == 2.9f && by_id(&d1, 5)->grid.origin[1] == -12.05f);
	encode_decode(&d1, &d2);
	assert_memory_equal(by_id(&d1, 5)->data, by_id(&d2, 5)->data, sizeof grid_positions);
	vn_drc_geometry_free(&d2);
	((vn_drc_attribute*)by_id(&d1, 5))->grid.bits = 0;
	encode_decode(&d1, &d2);
	assert_memory_not_equal(by_id(&d1, 5)->data, by_id(&d2, 5)->data, sizeof grid_positions);
	vn_drc_geometry_free(&d2);
	/* Values outside the grid's box: a new grid. */
	vn_drc_geometry_free(&d1);
	a[0].grid.range = 1.0f;
	encode_decode(&g, &d1);
	assert_true(fabsf(by_id(&d1, 5)->grid.range - 0.0987f * 19) < 1e-5f);
	/* Other bits: a new grid. */
	vn_drc_geometry_free(&d1);
	a[0].grid.bits = 0;
	encode_decode(&g, &d1);
	vn_drc_attribute* dp = (vn_drc_attribute*)by_id(&d1, 5);
	assert_int_equal(dp->quantization_bits, 14);
	dp->quantization_bits = 10;
	encode_decode(&d1, &d2);
	assert_int_equal(by_id(&d2, 5)->grid.bits, 10);
	vn_drc_geometry_free(&d1);
	vn_drc_geometry_free(&d2);
}

/* ------------------------------------------------------------------ non-finite values */

/* NaN or infinity in a float attribute to be quantized is refused, naming
 * the attribute and the point (Draco crashed in ComputeShannonEntropy);
 * a lossless float attribute keeps them. */
static void test_nonfinite(void** state)
{
	(void)state;
	vn_drc_geometry g = octahedron();
	vn_drc_attribute a[4];
	memcpy(a, attributes, sizeof a);
	float p[6 * 3];
	memcpy(p, positions, sizeof p);
	a[0].data = p;
	g.attributes = a;
	void* data = NULL;
	size_t size;
	vn_io_error e;
	p[3 * 2 + 1] = NAN;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "nan", &data, &size, &e), vn_io_error_unsupported);
	assert_non_null(strstr(e.message, "nan: attribute 7 (POSITION) has a non-finite value at point 2"));
	assert_null(data);
	p[3 * 2 + 1] = 0, p[3 * 4] = INFINITY;
	assert_int_equal(vn_drc_encode(&g, 10, 0, "inf", &data, &size, &e), vn_io_error_unsupported);
	assert_non_null(strstr(e.message, "point 4"));
	float n[6 * 3];
	memcpy(n, normals, sizeof n);
	a[1].data = n;
	p[3 * 4] = 0, n[5] = NAN;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "n", &data, &size, &e), vn_io_error_unsupported);
	assert_non_null(strstr(e.message, "attribute 3 (NORMAL) has a non-finite value at point 1"));
	n[5] = 0, p[0] = -3e38f, p[3] = 3e38f;
	assert_int_equal(vn_drc_encode(&g, 7, 0, "wide", &data, &size, &e), vn_io_error_unsupported);
	assert_non_null(strstr(e.message, "spans more than a float"));
	/* Lossless: kept as they are. */
	p[0] = NAN, p[3] = 1;
	a[0].quantization_bits = 0;
	vn_drc_geometry d;
	assert_int_equal(vn_drc_encode(&g, 10, 1, "lossless", &data, &size, &e), vn_io_success);
	assert_int_equal(vn_drc_decode(data, size, "lossless", &d, &e), vn_io_success);
	assert_true(isnan(((const float*)by_id(&d, 7)->data)[0]));
	vn_drc_geometry_free(&d);
	free(data);
	/* The format writer refuses too, without crashing. */
	double mp[9] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
	uint32_t offsets[2] = {0, 3}, corners[3] = {0, 1, 2};
	vn_io_mesh mesh;
	memset(&mesh, 0, sizeof mesh);
	mesh.vertex_count = 3, mesh.positions = mp, mesh.face_count = 1, mesh.face_offsets = offsets, mesh.indices = corners;
	FILE* f = tmpfile();
	assert_non_null(f);
	assert_int_equal(vn_io_drc_write(f, "w.drc", &mesh, NULL, &e), vn_io_error_unsupported);
	assert_non_null(strstr(e.message, "w.drc: attribute 0 (POSITION) has a non-finite value at point 2"));
	fclose(f);
}

/* ------------------------------------------------------------------ attributes and metadata */

/* Writes bytes to a temporary .drc and reads it with the vn_io reader. */
static void read_back(const void* data, size_t size, vn_io_mesh* mesh)
{
	char path[] = "/tmp/vn-test-drc-XXXXXX";
	const int fd = mkstemp(path);
	assert_true(fd >= 0);
	assert_int_equal(write(fd, data, size), (ssize_t)size);
	close(fd);
	vn_io_error e;
	assert_int_equal(vn_drc_read_file(path, mesh, NULL, &e), vn_io_success);
	unlink(path);
}

static const vn_io_attribute* named(const vn_io_mesh* m, const char* name)
{
	for (size_t i = 0; i < m->attribute_count; ++i)
		if (!strcmp(m->attributes[i].name, name))
			return &m->attributes[i];
	return NULL;
}

/* The vn_io reader keeps every attribute: the first texture coordinates
 * and colours in texcoords and colors, the others as TEXCOORD_n, COLOR_n
 * and application-specific _NAMEs with their type; the writer writes them
 * back, GENERICs named in their metadata. */
static void test_attributes_to_mesh(void** state)
{
	(void)state;
	float uv0[6 * 2], uv1[6 * 2], c1[6 * 3], extra[6 * 2];
	uint8_t bytes3[6 * 3];
	int16_t ids[6];
	for (int i = 0; i < 12; ++i)
		uv0[i] = (float)i / 16, uv1[i] = 1 - (float)i / 16, extra[i] = (float)i * 3.5f;
	for (int i = 0; i < 18; ++i)
		c1[i] = (float)(i % 5) / 4, bytes3[i] = (uint8_t)(i * 13);
	for (int i = 0; i < 6; ++i)
		ids[i] = (int16_t)(100 * i - 250);
	vn_drc_attribute a[9] = {
	    attributes[0], attributes[2],
	    {20, vn_drc_texcoord, vn_drc_float32, 2, 0, 0, uv0, {0}},
	    {21, vn_drc_texcoord, vn_drc_float32, 2, 0, 0, uv1, {0}},
	    {22, vn_drc_color, vn_drc_float32, 3, 0, 0, c1, {0}},
	    {23, vn_drc_generic, vn_drc_float32, 2, 0, 0, extra, {0}},
	    {24, vn_drc_generic, vn_drc_int16, 1, 0, 0, ids, {0}},
	    {25, vn_drc_color, vn_drc_uint8, 3, 0, 0, bytes3, {0}}, /* not normalized: not a glTF colour */
	    {26, vn_drc_tangent, vn_drc_float32, 2, 0, 0, uv1, {0}},
	};
	vn_drc_geometry g = {6, 8, indices, 9, a, NULL, 0};
	void* data;
	size_t size;
	vn_io_error e;
	assert_int_equal(vn_drc_encode(&g, 10, 1, "mem", &data, &size, &e), vn_io_success);
	vn_io_mesh m;
	read_back(data, size, &m);
	free(data);
	assert_non_null(m.texcoords);
	assert_memory_equal(m.texcoords, uv0, sizeof uv0);
	assert_non_null(m.colors);
	assert_true(m.colors_are_bytes);
	assert_int_equal(m.attribute_count, 6);
	const vn_io_attribute* t1 = named(&m, "TEXCOORD_1");
	const vn_io_attribute* col1 = named(&m, "COLOR_1");
	const vn_io_attribute* x = named(&m, "_GENERIC_23");
	const vn_io_attribute* y = named(&m, "_GENERIC_24");
	const vn_io_attribute* z = named(&m, "_COLOR_25");
	/* Draco 1.5.5 writes TANGENT as GENERIC (its bitstream has no TANGENT). */
	const vn_io_attribute* w = named(&m, "_GENERIC_26");
	assert_non_null(t1), assert_non_null(col1), assert_non_null(x), assert_non_null(y), assert_non_null(z);
	assert_non_null(w);
	assert_int_equal(t1->semantic, vn_io_semantic_texcoord);
	assert_memory_equal(t1->data, uv1, sizeof uv1);
	assert_int_equal(col1->semantic, vn_io_semantic_color);
	assert_int_equal(col1->components, 3);
	assert_memory_equal(col1->data, c1, sizeof c1);
	assert_int_equal(x->semantic, vn_io_semantic_generic);
	assert_memory_equal(x->data, extra, sizeof extra);
	assert_int_equal(y->component_type, vn_drc_int16);
	assert_memory_equal(y->data, ids, sizeof ids);
	assert_int_equal(z->component_type, vn_drc_uint8);
	assert_false(z->normalized);

	/* Written back (the vn_io writer) and read again: the same names. */
	FILE* f = tmpfile();
	assert_non_null(f);
	vn_drc_options o;
	vn_drc_default_options(&o);
	o.texcoord_bits = o.color_bits = 0; /* lossless, and points in order (sequential), to compare */
	o.compression_level = 10;
	assert_int_equal(vn_io_drc_write(f, "w.drc", &m, &o, &e), vn_io_success);
	const long length = ftell(f);
	char* back = malloc((size_t)length);
	rewind(f);
	assert_int_equal(fread(back, 1, (size_t)length, f), (size_t)length);
	fclose(f);
	vn_io_mesh m2;
	read_back(back, (size_t)length, &m2);
	free(back);
	assert_int_equal(m2.attribute_count, 6);
	assert_non_null(named(&m2, "TEXCOORD_1"));
	assert_non_null(named(&m2, "COLOR_1"));
	assert_non_null(named(&m2, "_GENERIC_23")); /* the name its metadata now carries */
	assert_memory_equal(named(&m2, "_GENERIC_24")->data, ids, sizeof ids);
	vn_io_mesh_free(&m);
	vn_io_mesh_free(&m2);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_round_trip_edgebreaker),
	    cmocka_unit_test(test_round_trip_sequential),
	    cmocka_unit_test(test_keep_order),
	    cmocka_unit_test(test_isolated_points),
	    cmocka_unit_test(test_lossless_float),
	    cmocka_unit_test(test_wide_values),
	    cmocka_unit_test(test_float64),
	    cmocka_unit_test(test_integer_normals),
	    cmocka_unit_test(test_corrupt_streams),
	    cmocka_unit_test(test_bad_input),
	    cmocka_unit_test(test_format_table),
	    cmocka_unit_test(test_declared_counts),
	    cmocka_unit_test(test_hostile_counts),
	    cmocka_unit_test(test_point_cloud),
	    cmocka_unit_test(test_grid_kept),
	    cmocka_unit_test(test_point_cloud_grid_kept),
	    cmocka_unit_test(test_point_cloud_kd_normals),
	    cmocka_unit_test(test_point_cloud_octahedral_normals),
	    cmocka_unit_test(test_nonfinite),
	    cmocka_unit_test(test_attributes_to_mesh),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
