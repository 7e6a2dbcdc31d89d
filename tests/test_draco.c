/*
 * The Draco geometry API (draco.h) that glTF's KHR_draco_mesh_compression
 * will use: encode/decode round trips keeping unique ids, types, point and
 * triangle counts and quantization bits; errors on bad streams and input.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

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
    {7, vn_drc_position, vn_drc_float32, 3, 0, 11, positions},
    {3, vn_drc_normal, vn_drc_float32, 3, 0, 9, normals},
    {0, vn_drc_color, vn_drc_uint8, 4, 1, 0, colors},
    {12, vn_drc_generic, vn_drc_uint16, 1, 0, 0, generic},
};

static vn_drc_geometry octahedron(void)
{
	vn_drc_geometry g = {6, 8, indices, 4, attributes};
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
	vn_drc_attribute a[2] = {{0, vn_drc_position, vn_drc_float32, 3, 0, 14, p}, {1, vn_drc_normal, vn_drc_float32, 3, 0, 10, q}};
	vn_drc_geometry g = {7, 2, (uint32_t*)t, 2, a};
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

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_round_trip_edgebreaker),
	    cmocka_unit_test(test_round_trip_sequential),
	    cmocka_unit_test(test_keep_order),
	    cmocka_unit_test(test_isolated_points),
	    cmocka_unit_test(test_lossless_float),
	    cmocka_unit_test(test_corrupt_streams),
	    cmocka_unit_test(test_bad_input),
	    cmocka_unit_test(test_format_table),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
