/*
 * vn_io_mesh_normals, the normals plan every vnconvert conversion follows
 * (split_normals.h): welding, hard edges from input normals, crease
 * splitting, on triangles and polygons. Small meshes with hand-computed
 * normals: a cube split per face, the same cube smooth, a quad strip with a
 * seam, a folded quad strip.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vn_io.h"

#define PI 3.14159265358979323846

/* ------------------------------------------------------------------ helpers */

/* A mesh owning copies of the literals: n vertices, faces of sizes[f]
 * corners (indices in order), normals optional (NULL). */
static vn_io_mesh make_mesh(const double* positions, size_t n, const uint32_t* sizes, size_t faces,
                            const uint32_t* indices, const double* normals)
{
	vn_io_mesh m;
	memset(&m, 0, sizeof m);
	m.vertex_count = n;
	m.positions = malloc(3 * sizeof(double) * n);
	memcpy(m.positions, positions, 3 * sizeof(double) * n);
	if (normals) {
		m.normals = malloc(3 * sizeof(double) * n);
		memcpy(m.normals, normals, 3 * sizeof(double) * n);
	}
	m.face_count = faces;
	m.face_offsets = malloc(sizeof(uint32_t) * (faces + 1));
	m.face_offsets[0] = 0;
	for (size_t f = 0; f < faces; ++f)
		m.face_offsets[f + 1] = m.face_offsets[f] + sizes[f];
	m.indices = malloc(sizeof(uint32_t) * m.face_offsets[faces]);
	memcpy(m.indices, indices, sizeof(uint32_t) * m.face_offsets[faces]);
	return m;
}

static vn_io_normals_options options(vn_method method)
{
	vn_io_normals_options o;
	memset(&o, 0, sizeof o);
	o.method = method;
	o.threads = 1;
	return o;
}

static vn_io_normals_stats compute(vn_io_mesh* m, const vn_io_normals_options* o)
{
	vn_io_normals_stats st;
	vn_io_error e;
	assert_int_equal(vn_io_mesh_normals(m, "test", o, &st, &e), vn_io_success);
	return st;
}

/* Normal of vertex i is (x, y, z) to 1e-15. */
static void assert_normal(const vn_io_mesh* m, size_t i, double x, double y, double z)
{
	const double* n = m->normals + 3 * i;
	if (fabs(n[0] - x) > 1e-15 || fabs(n[1] - y) > 1e-15 || fabs(n[2] - z) > 1e-15)
		fail_msg("vertex %zu: normal (%.17g, %.17g, %.17g), expected (%.17g, %.17g, %.17g)", i, n[0], n[1], n[2], x, y,
		         z);
}

/* ------------------------------------------------------------------ a point cloud */

/* No faces: normals stay as the input has them, none made up; every vertex
 * counts as without one. */
static void test_point_cloud(void** state)
{
	(void)state;
	static const double p[6] = {0, 0, 0, 1, 2, 3};
	static const double given[6] = {0, 0, 1, 0.6, 0, 0.8};
	const vn_io_normals_options o = options(vn_method_mwa);
	static const uint32_t none[1] = {0};
	vn_io_mesh m = make_mesh(p, 2, NULL, 0, none, NULL);
	vn_io_normals_stats st = compute(&m, &o);
	assert_null(m.normals);
	assert_int_equal(st.zero_normals, 2);
	assert_int_equal(st.vertices, 2);
	vn_io_mesh_free(&m);
	m = make_mesh(p, 2, NULL, 0, none, given);
	st = compute(&m, &o);
	assert_memory_equal(m.normals, given, sizeof given);
	assert_int_equal(st.zero_normals, 2);
	vn_io_mesh_free(&m);
}

/* vn_io_mesh_append_vertices: every per-vertex array, attributes in their
 * own type, grows by the copies, in order; absent arrays stay absent. */
static void test_append_vertices(void** state)
{
	(void)state;
	static const double p[6] = {0, 0, 0, 1, 2, 3};
	static const double n[6] = {0, 0, 1, 0.6, 0, 0.8};
	static const uint32_t three[1] = {3}, corners[3] = {0, 1, 1};
	vn_io_mesh m = make_mesh(p, 2, three, 1, corners, n);
	m.texcoords = malloc(4 * sizeof(float));
	memcpy(m.texcoords, (const float[4]){0.25f, 0.5f, 0.75f, 1}, 4 * sizeof(float));
	vn_io_attribute* a = vn_io_mesh_add_attribute(&m, "_ID", vn_io_semantic_generic, 5123, 1, 0);
	memcpy(a->data, (const uint16_t[2]){7, 65535}, 2 * sizeof(uint16_t));
	static const uint32_t source[3] = {1, 0, 1};
	assert_true(vn_io_mesh_append_vertices(&m, source, 3));
	assert_int_equal(m.vertex_count, 5);
	assert_memory_equal(m.positions, ((const double[15]){0, 0, 0, 1, 2, 3, 1, 2, 3, 0, 0, 0, 1, 2, 3}),
	                    15 * sizeof(double));
	assert_memory_equal(m.normals, ((const double[15]){0, 0, 1, 0.6, 0, 0.8, 0.6, 0, 0.8, 0, 0, 1, 0.6, 0, 0.8}),
	                    15 * sizeof(double));
	assert_memory_equal(m.texcoords, ((const float[10]){0.25f, 0.5f, 0.75f, 1, 0.75f, 1, 0.25f, 0.5f, 0.75f, 1}),
	                    10 * sizeof(float));
	assert_memory_equal(m.attributes[0].data, ((const uint16_t[5]){7, 65535, 65535, 7, 65535}), 5 * sizeof(uint16_t));
	assert_null(m.colors);
	vn_io_mesh_free(&m);
}

/* ------------------------------------------------------------------ the cube */

/* Corners of the cube [-1, 1]^3, and its faces counter-clockwise from outside. */
static const double corner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
static const uint32_t cube_quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                          {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
static const double face_normal[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};

/* The cube as files split it for flat shading: vertex 4f + k is corner k of
 * face f, with the face's normal when with_normals; quads, or two
 * triangles a face. */
static vn_io_mesh split_cube(int triangles, int with_normals)
{
	double positions[24][3], normals[24][3];
	uint32_t sizes[12], indices[36];
	for (size_t f = 0; f < 6; ++f)
		for (size_t k = 0; k < 4; ++k) {
			memcpy(positions[4 * f + k], corner[cube_quads[f][k]], sizeof positions[0]);
			memcpy(normals[4 * f + k], face_normal[f], sizeof normals[0]);
		}
	size_t faces = 0, used = 0;
	for (uint32_t f = 0; f < 6; ++f) {
		const uint32_t v = 4 * f;
		const uint32_t quad[4] = {v, v + 1, v + 2, v + 3}, pair[6] = {v, v + 1, v + 2, v, v + 2, v + 3};
		if (triangles) {
			memcpy(indices + used, pair, sizeof pair), used += 6;
			sizes[faces++] = 3, sizes[faces++] = 3;
		} else {
			memcpy(indices + used, quad, sizeof quad), used += 4;
			sizes[faces++] = 4;
		}
	}
	return make_mesh(&positions[0][0], 24, sizes, faces, indices, with_normals ? &normals[0][0] : NULL);
}

/* Split copies whose input normals differ keep the hard edge between them:
 * every vertex keeps its face's normal (nothing split). */
static void test_cube_hard_edges(void** state)
{
	(void)state;
	for (int triangles = 0; triangles < 2; ++triangles)
		for (int method = vn_method_mwe; method <= vn_method_mwselr; ++method) {
			vn_io_mesh m = split_cube(triangles, 1);
			const vn_io_normals_options o = options((vn_method)method);
			const vn_io_normals_stats st = compute(&m, &o);
			assert_int_equal(st.vertices, 24);
			assert_int_equal(st.faces, triangles ? 12 : 6);
			assert_int_equal(st.welded_vertices, 16);
			assert_int_equal(st.hard_edges, 12);
			assert_int_equal(st.split_vertices, 0);
			assert_int_equal(st.zero_normals, 0);
			assert_int_equal(m.vertex_count, 24);
			for (size_t i = 0; i < 24; ++i)
				assert_normal(&m, i, face_normal[i / 4][0], face_normal[i / 4][1], face_normal[i / 4][2]);
			vn_io_mesh_free(&m);
		}
}

/* Without input normals the welded cube is smooth: with MWE, three equal
 * faces at each corner give the corner's direction, (+-1, +-1, +-1)/sqrt 3,
 * to all three of its copies. */
static void test_cube_welded_smooth(void** state)
{
	(void)state;
	vn_io_mesh m = split_cube(0, 0);
	const vn_io_normals_options o = options(vn_method_mwe);
	const vn_io_normals_stats st = compute(&m, &o);
	assert_int_equal(st.welded_vertices, 16);
	assert_int_equal(st.hard_edges, 0);
	assert_int_equal(st.split_vertices, 0);
	const double s = 1 / sqrt(3.0);
	for (size_t i = 0; i < 24; ++i) {
		const double* p = m.positions + 3 * i;
		assert_normal(&m, i, s * p[0], s * p[1], s * p[2]);
	}
	vn_io_mesh_free(&m);

	/* --no-weld: each copy sees its own face only. */
	m = split_cube(0, 0);
	vn_io_normals_options unwelded = options(vn_method_mwe);
	unwelded.no_weld = 1;
	assert_int_equal(compute(&m, &unwelded).welded_vertices, 0);
	for (size_t i = 0; i < 24; ++i)
		assert_normal(&m, i, face_normal[i / 4][0], face_normal[i / 4][1], face_normal[i / 4][2]);
	vn_io_mesh_free(&m);
}

/* --crease-angle 30 on the smooth 8-vertex cube: every corner's three faces
 * meet at 90 degrees, so each corner becomes three vertices (16 appended),
 * each with its face's normal; every per-vertex array is copied along. */
static void test_cube_crease_split(void** state)
{
	(void)state;
	const uint32_t sizes[6] = {4, 4, 4, 4, 4, 4};
	for (unsigned threads = 1; threads <= 4; threads += 3) {
		vn_io_mesh m = make_mesh(&corner[0][0], 8, sizes, 6, &cube_quads[0][0], NULL);
		m.texcoords = malloc(2 * sizeof(float) * 8);
		m.colors = malloc(4 * sizeof(float) * 8);
		for (size_t i = 0; i < 8; ++i) {
			m.texcoords[2 * i] = (float)i, m.texcoords[2 * i + 1] = (float)(10 * i);
			for (size_t c = 0; c < 4; ++c)
				m.colors[4 * i + c] = (float)(i + c) / 16;
		}
		vn_io_attribute* a = vn_io_mesh_add_attribute(&m, "_ID", vn_io_semantic_generic, 5123, 1, 0);
		assert_non_null(a);
		for (size_t i = 0; i < 8; ++i)
			((uint16_t*)a->data)[i] = (uint16_t)(1000 + i);
		vn_io_normals_options o = options(vn_method_mwa);
		o.threads = threads;
		o.crease = 1;
		o.crease_angle = 30 * PI / 180;
		const vn_io_normals_stats st = compute(&m, &o);
		assert_int_equal(st.vertices, 8);
		assert_int_equal(st.welded_vertices, 0);
		assert_int_equal(st.hard_edges, 0);
		assert_int_equal(st.split_vertices, 16);
		assert_int_equal(m.vertex_count, 24);
		uint32_t uses[24] = {0};
		for (size_t f = 0; f < 6; ++f)
			for (size_t k = 0; k < 4; ++k) {
				const uint32_t v = m.indices[4 * f + k], source = cube_quads[f][k];
				assert_true(v < 24);
				++uses[v];
				assert_normal(&m, v, face_normal[f][0], face_normal[f][1], face_normal[f][2]);
				assert_memory_equal(m.positions + 3 * v, corner[source], 3 * sizeof(double));
				assert_true(m.texcoords[2 * v] == (float)source && m.texcoords[2 * v + 1] == (float)(10 * source));
				assert_true(m.colors[4 * v + 3] == (float)(source + 3) / 16);
				assert_int_equal(((uint16_t*)m.attributes[0].data)[v], 1000 + source);
			}
		for (size_t v = 0; v < 24; ++v)
			assert_int_equal(uses[v], 1);
		vn_io_mesh_free(&m);
	}
}

/* ------------------------------------------------------------------ quad strips */

/* Two unit quads meeting at x = 0, the left one flat (normal +Z), the right
 * one rising at 45 degrees (normal (-1, 0, 1)/sqrt 2); the seam's vertices
 * are split: 1 and 4 at (0, 0, 0), 2 and 7 at (0, 1, 0). */
static const double seam_positions[8][3] = {{-1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0},
                                            {0, 0, 0},  {1, 0, 1}, {1, 1, 1}, {0, 1, 0}};
static const uint32_t seam_sizes[2] = {4, 4};
static const uint32_t seam_quads[8] = {0, 1, 2, 3, 4, 5, 6, 7};
#define R 0.70710678118654752 /* 1/sqrt 2 */
static const double seam_normals[8][3] = {{0, 0, 1},  {0, 0, 1},  {0, 0, 1},  {0, 0, 1},
                                          {-R, 0, R}, {-R, 0, R}, {-R, 0, R}, {-R, 0, R}};

/* Welded, the seam's copies get one normal: with MWE the sum of the two
 * faces', (-sin 22.5, 0, cos 22.5); --no-weld leaves each its own face's. */
static void test_seam_welded(void** state)
{
	(void)state;
	const double sx = -0.38268343236508977, cz = 0.92387953251128676;
	vn_io_mesh m = make_mesh(&seam_positions[0][0], 8, seam_sizes, 2, seam_quads, NULL);
	vn_io_normals_options o = options(vn_method_mwe);
	vn_io_normals_stats st = compute(&m, &o);
	assert_int_equal(st.welded_vertices, 2);
	assert_int_equal(st.hard_edges, 0);
	const size_t seam[4] = {1, 4, 2, 7};
	for (size_t k = 0; k < 4; ++k)
		assert_normal(&m, seam[k], sx, 0, cz);
	assert_normal(&m, 0, 0, 0, 1);
	assert_normal(&m, 3, 0, 0, 1);
	assert_normal(&m, 5, -R, 0, R);
	assert_normal(&m, 6, -R, 0, R);
	vn_io_mesh_free(&m);

	m = make_mesh(&seam_positions[0][0], 8, seam_sizes, 2, seam_quads, NULL);
	o.no_weld = 1;
	st = compute(&m, &o);
	assert_int_equal(st.welded_vertices, 0);
	for (size_t i = 0; i < 8; ++i)
		assert_normal(&m, i, seam_normals[i][0], seam_normals[i][1], seam_normals[i][2]);
	vn_io_mesh_free(&m);
}

/* The seam's copies 1e-9 apart weld only with an epsilon that covers it. */
static void test_seam_epsilon(void** state)
{
	(void)state;
	double moved[8][3];
	memcpy(moved, seam_positions, sizeof moved);
	moved[4][0] = moved[7][0] = 1e-9;
	vn_io_mesh m = make_mesh(&moved[0][0], 8, seam_sizes, 2, seam_quads, NULL);
	vn_io_normals_options o = options(vn_method_mwe);
	assert_int_equal(compute(&m, &o).welded_vertices, 0);
	vn_io_mesh_free(&m);
	m = make_mesh(&moved[0][0], 8, seam_sizes, 2, seam_quads, NULL);
	o.weld_epsilon = 1e-6;
	assert_int_equal(compute(&m, &o).welded_vertices, 2);
	assert_memory_equal(m.normals + 3 * 1, m.normals + 3 * 4, 3 * sizeof(double));
	vn_io_mesh_free(&m);
}

/* Input normals that differ across the seam make it a hard edge: each copy
 * keeps its face's normal, though welded. */
static void test_seam_hard_edge(void** state)
{
	(void)state;
	for (int method = 0; method < vn_method_count; ++method) {
		if (method == vn_method_mewcsa)
			continue; /* its boundary corners point along the surface */
		vn_io_mesh m = make_mesh(&seam_positions[0][0], 8, seam_sizes, 2, seam_quads, &seam_normals[0][0]);
		const vn_io_normals_options o = options((vn_method)method);
		const vn_io_normals_stats st = compute(&m, &o);
		assert_int_equal(st.welded_vertices, 2);
		assert_int_equal(st.hard_edges, 1);
		assert_int_equal(st.split_vertices, 0);
		for (size_t i = 0; i < 8; ++i)
			assert_normal(&m, i, seam_normals[i][0], seam_normals[i][1], seam_normals[i][2]);
		vn_io_mesh_free(&m);
	}
}

/* A double-sided surface as exporters write it: each side on its own
 * copies of the vertices, the back's faces reversed and its input normals
 * negated. Welding would make every edge four faces and each sum cancel
 * (noise: half the normals 87 degrees off before); the two sides are not
 * welded, and each keeps its own normals. A flat 3 x 3 sheet in z = 0
 * (triangles) and the split cube made a box seen from inside too
 * (quads; each side welded at its hard edges as test_cube_hard_edges). */
static void test_two_sided(void** state)
{
	(void)state;
	double positions[48][3], normals[48][3];
	uint32_t sizes[16], indices[96];
	for (size_t v = 0; v < 9; ++v) {
		const double p[3] = {(double)(v % 3), (double)(v / 3), 0}, up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
		memcpy(positions[v], p, sizeof p), memcpy(positions[9 + v], p, sizeof p);
		memcpy(normals[v], up, sizeof up), memcpy(normals[9 + v], down, sizeof down);
	}
	for (uint32_t q = 0; q < 4; ++q) {
		const uint32_t a = q % 2 + 3 * (q / 2), t[6] = {a, a + 1, a + 4, a, a + 4, a + 3};
		for (int k = 0; k < 6; ++k)
			indices[6 * q + k] = t[k], indices[24 + 6 * q + k] = 9 + t[5 - k];
	}
	for (size_t f = 0; f < 16; ++f)
		sizes[f] = 3;
	for (int method = 0; method < vn_method_count; ++method) {
		if (method == vn_method_mewcsa)
			continue; /* its boundary corners point along the surface */
		vn_io_mesh m = make_mesh(&positions[0][0], 18, sizes, 16, indices, &normals[0][0]);
		const vn_io_normals_options o = options((vn_method)method);
		const vn_io_normals_stats st = compute(&m, &o);
		assert_int_equal(st.welded_vertices, 0);
		assert_int_equal(st.hard_edges, 0);
		for (size_t i = 0; i < 18; ++i)
			assert_normal(&m, i, 0, 0, i < 9 ? 1 : -1);
		vn_io_mesh_free(&m);
	}
	vn_io_mesh outside = split_cube(0, 1);
	memcpy(positions, outside.positions, 24 * sizeof positions[0]);
	memcpy(positions + 24, outside.positions, 24 * sizeof positions[0]);
	for (size_t i = 0; i < 24; ++i)
		for (int d = 0; d < 3; ++d)
			normals[i][d] = outside.normals[3 * i + d], normals[24 + i][d] = -outside.normals[3 * i + d];
	for (uint32_t f = 0; f < 6; ++f)
		for (uint32_t k = 0; k < 4; ++k)
			indices[4 * f + k] = outside.indices[4 * f + k], indices[24 + 4 * f + k] = 24 + outside.indices[4 * f + 3 - k];
	for (size_t f = 0; f < 12; ++f)
		sizes[f] = 4;
	vn_io_mesh_free(&outside);
	vn_io_mesh m = make_mesh(&positions[0][0], 48, sizes, 12, indices, &normals[0][0]);
	const vn_io_normals_options o = options(vn_method_mwa);
	const vn_io_normals_stats st = compute(&m, &o);
	assert_int_equal(st.welded_vertices, 32);
	assert_int_equal(st.hard_edges, 24);
	for (size_t i = 0; i < 48; ++i)
		assert_normal(&m, i, normals[i][0], normals[i][1], normals[i][2]);
	vn_io_mesh_free(&m);
}

/* The flat 3 x 3 sheet of test_two_sided with both sides on the same 9
 * vertices (every face followed, 8 faces later, by its reverse) or on 18
 * without input normals (welded into 9): each face and its reverse summed
 * at one vertex cancelled to rounding noise (+-z or in the plane). The
 * backs are computed apart: every corner of a front face gets (0, 0, 1),
 * of a back face (0, 0, -1), and a vertex both sides use is split. quads:
 * the sheet as 4 quads a side, with a crease angle. */
static void two_sided_sheet(int shared, int quads, vn_method method)
{
	double positions[18][3];
	uint32_t sizes[16], indices[48];
	const uint32_t faces = quads ? 8 : 16, corners = quads ? 32 : 48, per = quads ? 4 : 3, cell = quads ? 4 : 6;
	for (size_t v = 0; v < 18; ++v) {
		const double p[3] = {(double)(v % 9 % 3), (double)(v % 9 / 3), 0};
		memcpy(positions[v], p, sizeof p);
	}
	for (uint32_t q = 0; q < 4; ++q) {
		const uint32_t a = q % 2 + 3 * (q / 2), t[6] = {a, a + 1, a + 4, a, a + 4, a + 3}, r[4] = {a, a + 1, a + 4, a + 3};
		for (uint32_t k = 0; k < cell; ++k) {
			indices[cell * q + k] = quads ? r[k] : t[k];
			indices[corners / 2 + cell * q + k] = (shared ? 0 : 9) + (quads ? r[3 - k] : t[5 - k]);
		}
	}
	for (size_t f = 0; f < faces; ++f)
		sizes[f] = per;
	vn_io_mesh m = make_mesh(&positions[0][0], shared ? 9 : 18, sizes, faces, indices, NULL);
	vn_io_normals_options o = options(method);
	if (quads)
		o.crease = 1, o.crease_angle = 30 * PI / 180;
	const vn_io_normals_stats st = compute(&m, &o);
	assert_int_equal(st.welded_vertices, shared ? 0 : 9);
	assert_int_equal(st.split_vertices, shared ? 9 : 0);
	assert_int_equal(st.zero_normals, 0);
	assert_int_equal(m.vertex_count, 18);
	for (uint32_t k = 0; k < corners; ++k)
		assert_normal(&m, m.indices[k], 0, 0, k < corners / 2 ? 1 : -1);
	vn_io_mesh_free(&m);
}

static void test_two_sided_shared(void** state)
{
	(void)state;
	for (int method = 0; method < vn_method_count; ++method)
		if (method != vn_method_mewcsa) { /* its boundary corners point along the surface */
			two_sided_sheet(1, 0, (vn_method)method);
			two_sided_sheet(0, 0, (vn_method)method);
		}
	two_sided_sheet(1, 1, vn_method_mwa);
	two_sided_sheet(0, 1, vn_method_mwa);
}

/* Two cubes sharing a wall (x = 1), each closed and facing out, so the wall
 * is a face and its reverse on the same vertices. Its vertices also have
 * faces without a reverse: nothing is split there, the pair cancels and
 * every normal is the one without the wall (to rounding). */
static void test_shared_wall(void** state)
{
	(void)state;
	double positions[12][3];
	for (size_t v = 0; v < 12; ++v) {
		const double p[3] = {-1.0 + 2.0 * (double)(v / 4), v % 4 == 1 || v % 4 == 2 ? 1.0 : -1.0, v % 4 >= 2 ? 1.0 : -1.0};
		memcpy(positions[v], p, sizeof p);
	}
	/* Layers at x = -1 (0-3), 1 (4-7), 3 (8-11), each (y, z) = (-1, -1),
	 * (1, -1), (1, 1), (-1, 1); the walls last. */
	const uint32_t quads[12][4] = {{0, 3, 2, 1}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7},
	                               {4, 5, 9, 8}, {5, 6, 10, 9}, {6, 7, 11, 10}, {7, 4, 8, 11}, {8, 9, 10, 11},
	                               {4, 5, 6, 7}, {4, 7, 6, 5}};
	const uint32_t sizes[12] = {4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4};
	for (int method = 0; method < vn_method_count; ++method) {
		vn_io_mesh with = make_mesh(&positions[0][0], 12, sizes, 12, &quads[0][0], NULL);
		vn_io_mesh without = make_mesh(&positions[0][0], 12, sizes, 10, &quads[0][0], NULL);
		const vn_io_normals_options o = options((vn_method)method);
		const vn_io_normals_stats st = compute(&with, &o);
		compute(&without, &o);
		assert_int_equal(st.split_vertices, 0);
		assert_int_equal(with.vertex_count, 12);
		for (size_t i = 0; i < 36; ++i)
			if (fabs(with.normals[i] - without.normals[i]) > 1e-12)
				fail_msg("%s, vertex %zu: %.17g, without the wall %.17g", vn_method_name((vn_method)method), i / 3,
				         with.normals[i], without.normals[i]);
		vn_io_mesh_free(&with);
		vn_io_mesh_free(&without);
	}
}

/* A strip of four unit quads folded along y: the bends between them are
 * 20, 45 and 10 degrees. A crease angle splits the vertices of the bends
 * sharper than it, two a bend; the input is smooth (nothing welded). */
static size_t folded_strip_splits(double degrees)
{
	const double turn[4] = {0, 20, 65, 75}; /* each quad's slope, degrees */
	double positions[10][3], x = 0, z = 0;
	for (size_t i = 0; i < 5; ++i) {
		positions[2 * i][0] = positions[2 * i + 1][0] = x;
		positions[2 * i][1] = 0, positions[2 * i + 1][1] = 1;
		positions[2 * i][2] = positions[2 * i + 1][2] = z;
		if (i < 4)
			x += cos(turn[i] * PI / 180), z += sin(turn[i] * PI / 180);
	}
	const uint32_t sizes[4] = {4, 4, 4, 4};
	const uint32_t quads[16] = {0, 2, 3, 1, 2, 4, 5, 3, 4, 6, 7, 5, 6, 8, 9, 7};
	vn_io_mesh m = make_mesh(&positions[0][0], 10, sizes, 4, quads, NULL);
	vn_io_normals_options o = options(vn_method_mwa);
	o.crease = 1;
	o.crease_angle = degrees * PI / 180;
	const vn_io_normals_stats st = compute(&m, &o);
	assert_int_equal(st.welded_vertices, 0);
	assert_int_equal(m.vertex_count, 10 + st.split_vertices);
	assert_int_equal(m.face_offsets[4], 16); /* still quads */
	vn_io_mesh_free(&m);
	return st.split_vertices;
}

static void test_folded_strip_crease(void** state)
{
	(void)state;
	assert_int_equal(folded_strip_splits(50), 0);
	assert_int_equal(folded_strip_splits(30), 2);
	assert_int_equal(folded_strip_splits(15), 4);
	assert_int_equal(folded_strip_splits(5), 6);
}

/* A vertex no face contributes to keeps its input normal bit for bit (any
 * length), or gets (0, 0, 0) without one; a degenerate face is counted. */
static void test_zero_normals(void** state)
{
	(void)state;
	double positions[9][3], normals[9][3];
	memcpy(positions, seam_positions, sizeof seam_positions);
	memcpy(normals, seam_normals, sizeof seam_normals);
	const double isolated[3] = {5, 5, 5}, own[3] = {0.3, 0.4, 12.000000000000002};
	memcpy(positions[8], isolated, sizeof isolated);
	memcpy(normals[8], own, sizeof own);
	const uint32_t sizes[3] = {4, 4, 3};
	const uint32_t indices[11] = {0, 1, 2, 3, 4, 5, 6, 7, 0, 0, 3};
	for (int with = 0; with < 2; ++with) {
		vn_io_mesh m = make_mesh(&positions[0][0], 9, sizes, 3, indices, with ? &normals[0][0] : NULL);
		const vn_io_normals_options o = options(vn_method_mwa);
		const vn_io_normals_stats st = compute(&m, &o);
		assert_int_equal(st.zero_normals, 1);
		assert_int_equal(st.degenerate_faces, 1);
		if (with)
			assert_memory_equal(m.normals + 3 * 8, own, sizeof own);
		else
			assert_normal(&m, 8, 0, 0, 0);
		vn_io_mesh_free(&m);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_cube_hard_edges),  cmocka_unit_test(test_cube_welded_smooth),
	    cmocka_unit_test(test_cube_crease_split), cmocka_unit_test(test_seam_welded),
	    cmocka_unit_test(test_seam_epsilon),      cmocka_unit_test(test_seam_hard_edge),
	    cmocka_unit_test(test_folded_strip_crease), cmocka_unit_test(test_zero_normals),
	    cmocka_unit_test(test_two_sided),         cmocka_unit_test(test_two_sided_shared),
	    cmocka_unit_test(test_shared_wall),       cmocka_unit_test(test_point_cloud),
	    cmocka_unit_test(test_append_vertices),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
