/* Core library: hand-computed cases per scheme, the degenerate-input matrix,
 * argument checks, names, version and allocator. Literal inputs, literal
 * expected values. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vn.h"
#include "test_util.h"
#include "fastmath.h" /* internal: the corner-angle atan2 of MWA */

/* ---------------------------------------------------------------- helpers */

static vn_result tri(const double* pos, size_t nv, const uint32_t* idx, size_t ni, vn_method m, double* out,
                     vn_stats* st)
{
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	return vn_triangle_normals(&o, &p, idx, ni, m, NULL, st);
}

static vn_result poly(const double* pos, size_t nv, const uint32_t* idx, const uint32_t* off, size_t nf,
                      vn_method m, double* out, vn_stats* st)
{
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	return vn_polygon_normals(&o, &p, idx, off, nf, m, NULL, st);
}

static void assert_vec(const double* got, double x, double y, double z, double tol)
{
	if (fabs(got[0] - x) > tol || fabs(got[1] - y) > tol || fabs(got[2] - z) > tol)
		fail_msg("got (%.17g, %.17g, %.17g), expected (%.17g, %.17g, %.17g)", got[0], got[1], got[2], x, y, z);
}

static int all_finite(const double* v, size_t n)
{
	for (size_t i = 0; i < n; ++i)
		if (!isfinite(v[i]))
			return 0;
	return 1;
}

/* ---------------------------------------------------------------- hand-computed fan
 *
 * Vertex 0 at the origin with two faces:
 *   T1 = (0, 1, 2), p1 = (2,0,0), p2 = (0,1,0): N = +z, angle pi/2,
 *        |E| = 1 (to p2), |E'| = 2 (to p1), |E x E'| = 2.
 *   T2 = (0, 3, 4), p3 = (0,1,0), p4 = (0,3,4): N = +x, angle atan2(4,3),
 *        |E| = 5 (to p4), |E'| = 1 (to p3), |E x E'| = 4.
 * Each scheme gives normalize(w2, 0, w1) for its weights w1 (T1), w2 (T2). */
static const double fan_pos[] = {0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 1, 0, 0, 3, 4};
static const uint32_t fan_idx[] = {0, 1, 2, 0, 3, 4};
static const uint32_t fan_off[] = {0, 3, 6};

static void check_fan(vn_method m, double x, double y, double z)
{
	double out[15], out2[15];
	assert_int_equal(tri(fan_pos, 5, fan_idx, 6, m, out, NULL), vn_result_success);
	assert_vec(out, x, y, z, 1e-12);
	/* The polygon entry point agrees on triangles. */
	assert_int_equal(poly(fan_pos, 5, fan_idx, fan_off, 2, m, out2, NULL), vn_result_success);
	assert_vec(out2, x, y, z, 1e-12);
}

static void fan_mwe(void** state)
{
	(void)state;
	check_fan(vn_method_mwe, 0.70710678118654746, 0, 0.70710678118654746); /* w = 1, 1 */
}

static void fan_mwa(void** state)
{
	(void)state;
	/* w1 = pi/2, w2 = atan2(4, 3) = 0.92729521800161224 */
	check_fan(vn_method_mwa, 0.50836250043097309, 0, 0.86114317517795425);
}

static void fan_mwselr(void** state)
{
	(void)state;
	check_fan(vn_method_mwselr, 0.30477572710378376, 0, 0.95242414719932422); /* w = 1/2, 0.8/5 */
}

static void fan_mwaat(void** state)
{
	(void)state;
	check_fan(vn_method_mwaat, 0.89442719099991586, 0, 0.44721359549995793); /* w = 2, 4: (2,0,1)/sqrt 5 */
}

static void fan_mwelr(void** state)
{
	(void)state;
	check_fan(vn_method_mwelr, 0.37139067635410367, 0, 0.92847669088525919); /* w = 1/2, 1/5: (2,0,5)/sqrt 29 */
}

static void fan_mwrelr(void** state)
{
	(void)state;
	/* w = 1/sqrt 2, 1/sqrt 5: (sqrt 2, 0, sqrt 5) / sqrt 7 */
	check_fan(vn_method_mwrelr, 0.53452248382484879, 0, 0.84515425472851657);
}

static void fan_mewcsa(void** state)
{
	(void)state;
	/* (p1 - p2) x z = (-1,-2,0); (p3 - p4) x x = (0,-4,2); sum (-1,-6,2)/sqrt 41 */
	check_fan(vn_method_mewcsa, -0.15617376188860607, -0.93704257133163638, 0.31234752377721214);
}

/* A planar quad and pentagon: every scheme gives the plane normal, and on a
 * non-planar quad Newell's normal is used (literal value below). */
static void polygons_planar_and_newell(void** state)
{
	(void)state;
	/* quad 0-1-2-3 in z = 1, pentagon 1-4-5-6-2 in z = 1 */
	const double pos[] = {0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 2, 0, 1, 3, 1, 1, 2, 2, 1};
	const uint32_t idx[] = {0, 1, 2, 3, 1, 4, 5, 6, 2};
	const uint32_t off[] = {0, 4, 9};
	for (unsigned m = 0; m < vn_method_count; ++m) {
		double out[21];
		assert_int_equal(poly(pos, 7, idx, off, 2, (vn_method)m, out, NULL), vn_result_success);
		if (m == vn_method_mewcsa)
			continue; /* the area gradient of a flat interior vertex is 0 */
		for (int v = 0; v < 7; ++v)
			assert_vec(out + 3 * v, 0, 0, 1, 1e-15);
	}
	/* Non-planar quad (0,0,0) (1,0,0) (1,1,1) (0,1,0): Newell's vector is
	 * (-1,-1,2)/2, so MWE at every corner is (-1,-1,2)/sqrt 6. */
	const double q[] = {0, 0, 0, 1, 0, 0, 1, 1, 1, 0, 1, 0};
	const uint32_t qi[] = {0, 1, 2, 3}, qo[] = {0, 4};
	double out[12];
	assert_int_equal(poly(q, 4, qi, qo, 1, vn_method_mwe, out, NULL), vn_result_success);
	for (int v = 0; v < 4; ++v)
		assert_vec(out + 3 * v, -0.40824829046386302, -0.40824829046386302, 0.81649658092772603, 1e-15);
}

/* ---------------------------------------------------------------- degenerate input */

/* A unit right triangle in z = 0 plus, sharing vertex 0, a zero-area face. */
static void zero_area_face_contributes_nothing(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0};
	const uint32_t idx[] = {0, 1, 2, 0, 3, 4}; /* 0, 3, 4 are collinear */
	for (unsigned m = 0; m < vn_method_count; ++m) {
		double out[15];
		vn_stats st;
		assert_int_equal(tri(pos, 5, idx, 6, (vn_method)m, out, &st), vn_result_success);
		assert_int_equal(st.faces, 2);
		assert_int_equal(st.degenerate_faces, 1);
		assert_true(all_finite(out, 15));
		if (m != vn_method_mewcsa)
			assert_vec(out, 0, 0, 1, 0);
		/* 3 and 4 touch only the degenerate face. */
		assert_vec(out + 9, 0, 0, 0, 0);
		assert_vec(out + 12, 0, 0, 0, 0);
		assert_int_equal(st.zero_normals, 2);
	}
}

static void repeated_index_and_zero_length_edge(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0};
	/* (0,0,1): repeated index; (0,3,1): vertex 3 coincides with 0. */
	const uint32_t idx[] = {0, 1, 2, 0, 0, 1, 0, 3, 1};
	double out[12];
	vn_stats st;
	assert_int_equal(tri(pos, 4, idx, 9, vn_method_mwselr, out, &st), vn_result_success);
	assert_int_equal(st.degenerate_faces, 2);
	assert_vec(out, 0, 0, 1, 0);
	assert_vec(out + 9, 0, 0, 0, 0);
	assert_int_equal(st.zero_normals, 1);
}

static void nonfinite_coordinates(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, NAN, 0, 0, 1, 1, INFINITY};
	/* a good triangle, one with a NaN vertex and one with an Inf vertex */
	const uint32_t idx[] = {0, 1, 2, 0, 3, 1, 1, 4, 2};
	for (unsigned m = 0; m < vn_method_count; ++m) {
		double out[15];
		vn_stats st;
		assert_int_equal(tri(pos, 5, idx, 9, (vn_method)m, out, &st), vn_result_success);
		assert_true(all_finite(out, 15));
		assert_int_equal(st.degenerate_faces, 2);
		assert_int_equal(st.nonfinite_vertices, 2);
		assert_vec(out + 9, 0, 0, 0, 0);
		assert_vec(out + 12, 0, 0, 0, 0);
		if (m != vn_method_mewcsa)
			assert_vec(out, 0, 0, 1, 0);
	}
}

static void isolated_vertex_and_empty_meshes(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5};
	const uint32_t idx[] = {0, 1, 2};
	double out[12];
	vn_stats st;
	assert_int_equal(tri(pos, 4, idx, 3, vn_method_mwa, out, &st), vn_result_success);
	assert_vec(out + 9, 0, 0, 0, 0);
	assert_int_equal(st.zero_normals, 1);

	/* vertices but no faces: every normal is zero */
	assert_int_equal(tri(pos, 4, NULL, 0, vn_method_mwa, out, &st), vn_result_success);
	assert_int_equal(st.zero_normals, 4);
	assert_int_equal(st.faces, 0);
	/* no vertices at all */
	assert_int_equal(tri(NULL, 0, NULL, 0, vn_method_mwa, NULL, &st), vn_result_success);
	const uint32_t off0[] = {0};
	assert_int_equal(poly(NULL, 0, NULL, off0, 0, vn_method_mwa, NULL, &st), vn_result_success);
}

/* keep_existing: a vertex whose normal is zero keeps what the output held.
 * Vertices 0-2 and 5-7: unit triangles facing +z and -x; 3 isolated; 4 only
 * in a zero-area face. Every scheme, SIMD on and off, triangles and the same
 * faces as polygons, float32 output with a stride. */
static void keep_existing_leaves_zero_normals(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 9, 9, 9, 2, 2, 2, 0, 0, 5, 0, 1, 5, 0, 0, 6};
	const uint32_t idx[] = {0, 1, 2, 0, 4, 4, 5, 7, 6};
	const uint32_t off[] = {0, 3, 6, 9};
	const vn_positions p = {pos, 8, 0, vn_scalar_float64};
	const float want[8][3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {7, 8, 9}, {7, 8, 9}, {-1, 0, 0}, {-1, 0, 0}, {-1, 0, 0}};
	for (int keep = 0; keep < 2; ++keep)
		for (int simd = 0; simd < 2; ++simd)
			for (int polygons = 0; polygons < 2; ++polygons)
				for (unsigned m = 0; m < vn_method_mewcsa; ++m) {
					float out[8][4];
					for (int v = 0; v < 8; ++v)
						out[v][0] = 7, out[v][1] = 8, out[v][2] = 9, out[v][3] = -1;
					const vn_vectors o = {out, 4 * sizeof(float), vn_scalar_float32};
					vn_options opt;
					memset(&opt, 0, sizeof(opt));
					opt.keep_existing = keep;
					opt.simd = simd ? vn_simd_auto : vn_simd_off;
					vn_stats st;
					const vn_result r = polygons ? vn_polygon_normals(&o, &p, idx, off, 3, (vn_method)m, &opt, &st)
					                             : vn_triangle_normals(&o, &p, idx, 9, (vn_method)m, &opt, &st);
					assert_int_equal(r, vn_result_success);
					assert_int_equal(st.zero_normals, 2);
					for (int v = 0; v < 8; ++v) {
						const int kept = v == 3 || v == 4;
						for (int k = 0; k < 3; ++k)
							assert_true(fabsf(out[v][k] - (kept && !keep ? 0.0f : want[v][k])) < 1e-6f);
						assert_true(out[v][3] == -1); /* padding untouched */
					}
				}
}

/* Three triangles on one edge (0,1): each contributes to both ends. */
static void nonmanifold_edge(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, 0, 1, 0.5, -1, 0};
	const uint32_t idx[] = {0, 1, 2, 0, 1, 3, 0, 1, 4};
	double out[15];
	assert_int_equal(tri(pos, 5, idx, 9, vn_method_mwe, out, NULL), vn_result_success);
	/* unit normals (0,0,1), (0,-1,0), (0,0,-1): sum (0,-1,0) */
	assert_vec(out, 0, -1, 0, 1e-15);
	assert_vec(out + 3, 0, -1, 0, 1e-15);
}

static void polygon_small_faces_and_repeated_corner(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
	/* faces of 0, 1 and 2 corners, then quad 0,1,1,2 with a repeated index */
	const uint32_t idx[] = {3, 2, 3, 0, 1, 1, 2};
	const uint32_t off[] = {0, 0, 1, 3, 7};
	double out[12];
	vn_stats st;
	assert_int_equal(poly(pos, 4, idx, off, 4, vn_method_mwa, out, &st), vn_result_success);
	assert_int_equal(st.degenerate_faces, 3);
	/* In the quad (the triangle 0, 1, 2 as files write it in a quad), the
	 * two corners at vertex 1 are one corner, with edges to 0 and 2: it
	 * contributes once (it contributed nothing before: zero). */
	assert_vec(out + 3, 0, 0, 1, 0);
	assert_vec(out, 0, 0, 1, 1e-15);
	assert_vec(out + 6, 0, 0, 1, 1e-15);
	assert_vec(out + 9, 0, 0, 0, 0); /* only in degenerate faces */
	assert_int_equal(st.zero_normals, 1);
}

static void index_out_of_range_writes_nothing(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
	double out[9];
	for (int i = 0; i < 9; ++i)
		out[i] = 42.0;
	assert_int_equal(tri(pos, 3, idx, 6, vn_method_mwe, out, NULL), vn_result_index_out_of_range);
	const uint32_t off[] = {0, 3, 6};
	assert_int_equal(poly(pos, 3, idx, off, 2, vn_method_mwe, out, NULL), vn_result_index_out_of_range);
	for (int i = 0; i < 9; ++i)
		assert_true(out[i] == 42.0);
}

/* ---------------------------------------------------------------- arguments and layout */

static void invalid_arguments(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	const uint32_t idx[] = {0, 1, 2};
	double out[9];
	const vn_positions p = {pos, 3, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	assert_int_equal(vn_triangle_normals(NULL, &p, idx, 3, vn_method_mwe, NULL, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_triangle_normals(&o, NULL, idx, 3, vn_method_mwe, NULL, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_triangle_normals(&o, &p, idx, 2, vn_method_mwe, NULL, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_triangle_normals(&o, &p, NULL, 3, vn_method_mwe, NULL, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_triangle_normals(&o, &p, idx, 3, vn_method_count, NULL, NULL), vn_result_unknown_method);
	const vn_positions narrow = {pos, 3, 16, vn_scalar_float64};
	assert_int_equal(vn_triangle_normals(&o, &narrow, idx, 3, vn_method_mwe, NULL, NULL),
	                 vn_result_invalid_argument);
	const vn_vectors bad_type = {out, 0, (vn_scalar)7};
	assert_int_equal(vn_triangle_normals(&bad_type, &p, idx, 3, vn_method_mwe, NULL, NULL),
	                 vn_result_invalid_argument);
	vn_options half;
	memset(&half, 0, sizeof(half));
	half.allocator.allocate = (void* (*)(void*, size_t))0x1;
	assert_int_equal(vn_triangle_normals(&o, &p, idx, 3, vn_method_mwe, &half, NULL), vn_result_invalid_argument);
	const uint32_t decreasing[] = {0, 3, 2};
	assert_int_equal(vn_polygon_normals(&o, &p, idx, decreasing, 2, vn_method_mwe, NULL, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_polygon_normals(&o, &p, idx, NULL, 1, vn_method_mwe, NULL, NULL),
	                 vn_result_invalid_argument);
}

/* Padded float32 positions in, strided float32 out; same values as packed doubles. */
static void strides_and_types(void** state)
{
	(void)state;
	float padded[3 * 5] = {0, 0, 0, 99, 99, 2, 0, 0, 99, 99, 0, 1, 0, 99, 99};
	const vn_positions p = {padded, 3, 5 * sizeof(float), vn_scalar_float32};
	float out[3 * 4];
	for (int i = 0; i < 12; ++i)
		out[i] = -7.0f;
	const vn_vectors o = {out, 4 * sizeof(float), vn_scalar_float32};
	const uint32_t idx[] = {0, 1, 2};
	assert_int_equal(vn_triangle_normals(&o, &p, idx, 3, vn_method_mwa, NULL, NULL), vn_result_success);
	for (int v = 0; v < 3; ++v) {
		assert_true(out[4 * v] == 0.0f && out[4 * v + 1] == 0.0f && out[4 * v + 2] == 1.0f);
		assert_true(out[4 * v + 3] == -7.0f); /* padding untouched */
	}
}

static void names_and_results(void** state)
{
	(void)state;
	static const char* names[] = {"mwe", "mwa", "mwselr", "mwaat", "mwelr", "mwrelr", "mewcsa", "smewcsa", "quadric", "jet", "adaptive"};
	for (unsigned m = 0; m < vn_method_count; ++m) {
		assert_string_equal(vn_method_name((vn_method)m), names[m]);
		assert_non_null(vn_method_description((vn_method)m));
		assert_non_null(vn_method_reference((vn_method)m));
		vn_method got = vn_method_count;
		assert_int_equal(vn_method_from_name(names[m], &got), vn_result_success);
		assert_int_equal(got, m);
	}
	vn_method got = vn_method_count;
	assert_int_equal(vn_method_from_name("MwSeLr", &got), vn_result_success);
	assert_int_equal(got, vn_method_mwselr);
	assert_int_equal(vn_method_from_name("mws", &got), vn_result_unknown_method);
	assert_int_equal(vn_method_from_name("mwselrx", &got), vn_result_unknown_method);
	assert_int_equal(vn_method_from_name(NULL, &got), vn_result_invalid_argument);
	assert_null(vn_method_name(vn_method_count));
	assert_string_equal(vn_result_string(vn_result_index_out_of_range), "index out of range");
	assert_string_equal(vn_result_string((vn_result)99), "unknown result");
	assert_int_equal(vn_version(), VN_VERSION);
	assert_string_equal(vn_version_string(), VN_VERSION_STRING);
	assert_int_equal(vn_version() >> 16, VN_VERSION_MAJOR);
	assert_int_equal(vn_version() >> 8, VN_VERSION >> 8);
}

/* ---------------------------------------------------------------- allocator */

static void custom_allocator(void** state)
{
	(void)state;
	counting c = {0, 0, -1};
	vn_options opt = counting_options(&c);
	const vn_positions p = {fan_pos, 5, 0, vn_scalar_float64};
	double out[15];
	const vn_vectors o = {out, 0, vn_scalar_float64};
	assert_int_equal(vn_triangle_normals(&o, &p, fan_idx, 6, vn_method_mwe, &opt, NULL), vn_result_success);
	assert_int_equal(c.allocations, 1);
	assert_int_equal(c.frees, 1);
	assert_vec(out, 0.70710678118654746, 0, 0.70710678118654746, 1e-15);

	c.fail_after = 0;
	out[0] = 42.0;
	assert_int_equal(vn_triangle_normals(&o, &p, fan_idx, 6, vn_method_mwe, &opt, NULL), vn_result_out_of_memory);
	assert_true(out[0] == 42.0);

	/* A large enough workspace: no allocation at all, same result. */
	const size_t need = vn_workspace_size(5, &opt);
	assert_true(need >= 5 * 32);
	assert_int_equal(vn_workspace_size((size_t)UINT32_MAX + 1, &opt), 0);
	unsigned char* ws = (unsigned char*)malloc(need + 1);
	opt.workspace = ws + 1; /* misaligned on purpose */
	opt.workspace_size = need;
	assert_int_equal(vn_triangle_normals(&o, &p, fan_idx, 6, vn_method_mwe, &opt, NULL), vn_result_success);
	assert_vec(out, 0.70710678118654746, 0, 0.70710678118654746, 1e-15);
	assert_int_equal(c.allocations, 1);
	/* One byte short: the allocator is used (and fails here). */
	opt.workspace_size = need - 1;
	assert_int_equal(vn_triangle_normals(&o, &p, fan_idx, 6, vn_method_mwe, &opt, NULL), vn_result_out_of_memory);
	free(ws);
}

/* ---------------------------------------------------------------- corner angles */

/* MWA's atan2 is within 2 ulp (relative) of libm's over angles from 1e-12 to
 * pi - 1e-12 and magnitudes from 1e-30 to 1e30, including both branches of
 * the reduction and the steep and obtuse cases. */
static void corner_angle_matches_libm(void** state)
{
	(void)state;
	double worst = 0.0;
	for (int e = -30; e <= 30; e += 3)
		for (int i = 0; i <= 20000; ++i) {
			const double a = 1e-12 + (VN_PI - 2e-12) * i / 20000.0;
			const double r = pow(10.0, e) * (1.0 + 0.37 * sin(i));
			const double y = r * sin(a), x = r * cos(a);
			const double want = atan2(y, x), got = vn_atan2_nonneg(y, x);
			const double rel = fabs(got - want) / want;
			worst = rel > worst ? rel : worst;
		}
	assert_true(worst <= 2 * DBL_EPSILON);
	assert_true(vn_atan2_nonneg(0.0, 0.0) == 0.0);
	assert_true(vn_atan2_nonneg(0.0, -1.0) == atan2(0.0, -1.0));
	assert_true(vn_atan2_nonneg(1.0, 0.0) == atan2(1.0, 0.0));
}

/* ---------------------------------------------------------------- SIMD == scalar */

static void simd_matches_scalar_bit_for_bit(void** state)
{
	(void)state;
	const size_t n = 101, nv = n * n;
	double* pos = (double*)malloc(sizeof(double) * 3 * nv);
	float* pos32 = (float*)malloc(sizeof(float) * 3 * nv);
	double* a = (double*)malloc(sizeof(double) * 3 * nv);
	double* b = (double*)malloc(sizeof(double) * 3 * nv);
	size_t ni;
	uint32_t* idx = test_grid(n, pos, &ni);
	for (size_t i = 0; i < 3 * nv; ++i)
		pos32[i] = (float)pos[i];
	vn_options on, off;
	memset(&on, 0, sizeof(on));
	off = on;
	off.simd = vn_simd_off;
	for (int type = 0; type < 2; ++type) {
		const vn_positions p = {type ? (const void*)pos : (const void*)pos32, nv, 0, (vn_scalar)type};
		const vn_vectors oa = {a, 0, vn_scalar_float64}, ob = {b, 0, vn_scalar_float64};
		for (unsigned m = 0; m < vn_method_count; ++m) {
			vn_stats sa, sb;
			assert_int_equal(vn_triangle_normals(&oa, &p, idx, ni, (vn_method)m, &on, &sa), vn_result_success);
			assert_int_equal(vn_triangle_normals(&ob, &p, idx, ni, (vn_method)m, &off, &sb), vn_result_success);
			assert_memory_equal(a, b, sizeof(double) * 3 * nv);
			assert_memory_equal(&sa, &sb, sizeof(sa));
			assert_int_equal(sa.degenerate_faces, 1);
		}
	}
	free(idx);
	free(b);
	free(a);
	free(pos32);
	free(pos);
}

/* A large mesh (6.5 MB of work memory): the default allocator and a caller's
 * workspace filled with garbage (which the computation must clear) give the
 * same bits. */
static void large_work_memory_paths_agree(void** state)
{
	(void)state;
	const size_t n = 450, nv = n * n; /* 6.5 MB of accumulators */
	double* pos = (double*)malloc(sizeof(double) * 3 * nv);
	double* a = (double*)malloc(sizeof(double) * 3 * nv);
	double* b = (double*)malloc(sizeof(double) * 3 * nv);
	size_t ni;
	uint32_t* idx = test_grid(n, pos, &ni);
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors oa = {a, 0, vn_scalar_float64}, ob = {b, 0, vn_scalar_float64};
	vn_options opt;
	memset(&opt, 0, sizeof(opt));
	assert_int_equal(vn_triangle_normals(&oa, &p, idx, ni, vn_method_mwselr, &opt, NULL), vn_result_success);
	opt.workspace_size = vn_workspace_size(nv, &opt);
	opt.workspace = malloc(opt.workspace_size);
	memset(opt.workspace, 0x7f, opt.workspace_size);
	assert_int_equal(vn_triangle_normals(&ob, &p, idx, ni, vn_method_mwselr, &opt, NULL), vn_result_success);
	assert_memory_equal(a, b, sizeof(double) * 3 * nv);
	assert_true(fabs(a[3 * (nv / 2) + 2]) > 0.5); /* a height field: normals point up */
	free(opt.workspace);
	free(idx);
	free(b);
	free(a);
	free(pos);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(fan_mwe),
	    cmocka_unit_test(fan_mwa),
	    cmocka_unit_test(fan_mwselr),
	    cmocka_unit_test(fan_mwaat),
	    cmocka_unit_test(fan_mwelr),
	    cmocka_unit_test(fan_mwrelr),
	    cmocka_unit_test(fan_mewcsa),
	    cmocka_unit_test(polygons_planar_and_newell),
	    cmocka_unit_test(zero_area_face_contributes_nothing),
	    cmocka_unit_test(repeated_index_and_zero_length_edge),
	    cmocka_unit_test(nonfinite_coordinates),
	    cmocka_unit_test(isolated_vertex_and_empty_meshes),
	    cmocka_unit_test(keep_existing_leaves_zero_normals),
	    cmocka_unit_test(nonmanifold_edge),
	    cmocka_unit_test(polygon_small_faces_and_repeated_corner),
	    cmocka_unit_test(index_out_of_range_writes_nothing),
	    cmocka_unit_test(invalid_arguments),
	    cmocka_unit_test(strides_and_types),
	    cmocka_unit_test(names_and_results),
	    cmocka_unit_test(custom_allocator),
	    cmocka_unit_test(corner_angle_matches_libm),
	    cmocka_unit_test(simd_matches_scalar_bit_for_bit),
	    cmocka_unit_test(large_work_memory_paths_agree),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
