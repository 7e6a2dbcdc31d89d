/* Per-frame plans (vn_plan_*): against vn_triangle_normals and the other
 * entry points, bit for bit where the arithmetic is the same, within the
 * stated bounds in float32; thread counts, strides, types, polygons,
 * corners, degenerate input, errors, and no allocation per frame. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vn.h"
#include "test_util.h"
#include "fastmath.h" /* internal: the corner angles of MWA */

/* ---------------------------------------------------------------- helpers */

/* Plan normals of a triangle mesh in one call (create, normals, destroy). */
static vn_result plan_tri(const vn_positions* p, const uint32_t* idx, size_t nf, vn_method m, const vn_options* o,
                          const vn_vectors* out, vn_stats* st)
{
	vn_plan* plan = NULL;
	vn_result r = vn_plan_create(idx, NULL, nf, p->count, o, &plan);
	if (r != vn_result_success)
		return r;
	r = vn_plan_normals(plan, p, m, out, st);
	vn_plan_destroy(plan);
	return r;
}

static vn_options threads_options(unsigned threads, vn_simd simd)
{
	vn_options o;
	memset(&o, 0, sizeof(o));
	o.threads = threads;
	o.simd = simd;
	return o;
}

/* test_grid's n x n mesh, a float32 copy of its positions times scale, and
 * two work arrays of 3 doubles a vertex. */
typedef struct grid {
	size_t nv, ni;
	double* pos;
	float* pos32;
	uint32_t* idx;
	double *a, *b;
} grid;

static grid make_grid(size_t n, double scale)
{
	grid g;
	g.nv = n * n;
	g.pos = (double*)malloc(sizeof(double) * 3 * g.nv);
	g.pos32 = (float*)malloc(sizeof(float) * 3 * g.nv);
	g.a = (double*)malloc(sizeof(double) * 3 * g.nv);
	g.b = (double*)malloc(sizeof(double) * 3 * g.nv);
	g.idx = test_grid(n, g.pos, &g.ni);
	for (size_t i = 0; i < 3 * g.nv; ++i)
		g.pos32[i] = (float)(g.pos[i] * scale);
	return g;
}

static void free_grid(grid* g)
{
	free(g->idx);
	free(g->b);
	free(g->a);
	free(g->pos32);
	free(g->pos);
}

/* The largest angle in degrees between unit vectors a[i] and b[i]; zero
 * vectors must match exactly. */
static double worst_degrees(const double* a, const double* b, size_t n)
{
	double worst = 0.0;
	for (size_t i = 0; i < n; ++i) {
		const double* u = a + 3 * i;
		const double* v = b + 3 * i;
		const int zu = u[0] == 0 && u[1] == 0 && u[2] == 0, zv = v[0] == 0 && v[1] == 0 && v[2] == 0;
		if (zu || zv) {
			if (zu != zv)
				return 180.0;
			continue;
		}
		double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
		const double deg = atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) *
		                   (180.0 / 3.14159265358979323846);
		worst = deg > worst ? deg : worst;
	}
	return worst;
}

/* ---------------------------------------------------------------- literal fan
 *
 * test_core.c's hand-computed fan: vertex 0 with T1 = (0, 1, 2), N = +z,
 * and T2 = (0, 3, 4), N = +x; each weighted scheme gives normalize(w2, 0, w1). */
static const double fan_pos[] = {0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 1, 0, 0, 3, 4};
static const uint32_t fan_idx[] = {0, 1, 2, 0, 3, 4};

static void fan_literal_values(void** state)
{
	(void)state;
	static const double expect[6][3] = {
	    {0.70710678118654746, 0, 0.70710678118654746}, {0.50836250043097309, 0, 0.86114317517795425},
	    {0.30477572710378376, 0, 0.95242414719932422}, {0.89442719099991586, 0, 0.44721359549995793},
	    {0.37139067635410367, 0, 0.92847669088525919}, {0.53452248382484879, 0, 0.84515425472851657},
	};
	float fpos[15];
	for (int i = 0; i < 15; ++i)
		fpos[i] = (float)fan_pos[i];
	for (unsigned m = 0; m < 6; ++m) {
		double d[15], f[15];
		const vn_positions pd = {fan_pos, 5, 0, vn_scalar_float64}, pf = {fpos, 5, 0, vn_scalar_float32};
		const vn_vectors od = {d, 0, vn_scalar_float64}, of = {f, 0, vn_scalar_float64};
		assert_int_equal(plan_tri(&pd, fan_idx, 2, (vn_method)m, NULL, &od, NULL), vn_result_success);
		assert_int_equal(plan_tri(&pf, fan_idx, 2, (vn_method)m, NULL, &of, NULL), vn_result_success);
		for (int k = 0; k < 3; ++k) {
			/* MWA's angles in double from vn_atan2_poly, within 1e-13 rad */
			assert_true(fabs(d[k] - expect[m][k]) <= (m == vn_method_mwa ? 1e-13 : 1e-15));
			assert_true(fabs(f[k] - expect[m][k]) <= 1e-6);
		}
	}
}

/* ---------------------------------------------------------------- against vn_triangle_normals */

/* Every method on a 101 x 101 jittered grid (a degenerate triangle, one on
 * the last vertex, an odd count): float64 positions give vn_triangle_normals'
 * bits and stats, with and without AVX2; MWA (its polynomial atan2) within
 * 1e-9 degrees, the same bits with and without AVX2. */
static void double_equals_triangle_normals(void** state)
{
	(void)state;
	grid g = make_grid(101, 1.0);
	const size_t nv = g.nv, ni = g.ni;
	double *a = g.a, *b = g.b;
	double* mwa = (double*)malloc(sizeof(double) * 3 * nv);
	const uint32_t* idx = g.idx;
	const vn_positions p = {g.pos, nv, 0, vn_scalar_float64};
	const vn_vectors oa = {a, 0, vn_scalar_float64}, ob = {b, 0, vn_scalar_float64};
	for (int simd = 0; simd < 2; ++simd) {
		const vn_options o = threads_options(1, simd ? vn_simd_off : vn_simd_auto);
		for (unsigned m = 0; m < vn_method_count; ++m) {
			vn_stats sa, sb;
			assert_int_equal(vn_triangle_normals(&oa, &p, idx, ni, (vn_method)m, &o, &sa), vn_result_success);
			memset(b, 0xff, sizeof(double) * 3 * nv);
			assert_int_equal(plan_tri(&p, idx, ni / 3, (vn_method)m, &o, &ob, &sb), vn_result_success);
			if (m == vn_method_mwa) {
				const double worst = worst_degrees(a, b, nv);
				if (worst > 1e-9 || worst == 0.0)
					fail_msg("MWA: %.3g degrees from vn_triangle_normals", worst);
				if (simd)
					assert_memory_equal(mwa, b, sizeof(double) * 3 * nv);
				memcpy(mwa, b, sizeof(double) * 3 * nv);
			} else {
				assert_memory_equal(a, b, sizeof(double) * 3 * nv);
			}
			assert_memory_equal(&sa, &sb, sizeof(sa));
			assert_int_equal(sb.degenerate_faces, 1);
			assert_int_equal(sb.faces, 20002);
		}
	}
	free(mwa);
	free_grid(&g);
}

/* The float64 corner angle of the plans' MWA: within 1e-13 rad of atan2
 * over [0, pi], exact where the reduction is, 0 for (0, 0). */
static void double_atan2_bound(void** state)
{
	(void)state;
	double worst = 0.0;
	for (int i = 0; i <= 1000000; ++i) {
		const double t = 3.14159265358979323846 * i / 1000000.0;
		const double y = sin(t), x = cos(t);
		const double err = fabs(vn_atan2_poly(y, x) - atan2(y, x));
		worst = err > worst ? err : worst;
	}
	if (worst > 1e-13)
		fail_msg("double atan2 off by %.3g rad", worst);
	assert_true(vn_atan2_poly(0.0, 0.0) == 0.0);
	assert_true(vn_atan2_poly(0.0, 1.0) == 0.0);
	assert_true(vn_atan2_poly(0.0, -1.0) == VN_PI);
	assert_true(vn_atan2_poly(1.0, 0.0) == VN_PI_2);
	assert_true(fabs(vn_atan2_poly(1e300, 1e-300) - VN_PI_2) < 1e-15);
}

/* float32 positions: float arithmetic within 1e-4 degrees of the double
 * computation on the same positions, AVX2 and scalar bit-identical. */
static void float_within_bound(void** state)
{
	(void)state;
	grid g = make_grid(101, 100.0); /* in centimetres: no exact binary fractions */
	const size_t nv = g.nv, ni = g.ni;
	double *ref = g.pos, *a = g.a, *b = g.b; /* the double positions are not needed */
	const uint32_t* idx = g.idx;
	const vn_positions p = {g.pos32, nv, 0, vn_scalar_float32};
	const vn_vectors oref = {ref, 0, vn_scalar_float64}, oa = {a, 0, vn_scalar_float64},
	                 ob = {b, 0, vn_scalar_float64};
	const vn_options on = threads_options(1, vn_simd_auto), off = threads_options(1, vn_simd_off);
	for (unsigned m = 0; m < 6; ++m) {
		vn_stats sr, sa, sb;
		assert_int_equal(vn_triangle_normals(&oref, &p, idx, ni, (vn_method)m, NULL, &sr), vn_result_success);
		assert_int_equal(plan_tri(&p, idx, ni / 3, (vn_method)m, &on, &oa, &sa), vn_result_success);
		assert_int_equal(plan_tri(&p, idx, ni / 3, (vn_method)m, &off, &ob, &sb), vn_result_success);
		assert_memory_equal(a, b, sizeof(double) * 3 * nv);
		assert_memory_equal(&sr, &sa, sizeof(sr));
		const double worst = worst_degrees(ref, a, nv);
		if (worst > 1e-4)
			fail_msg("%s: %.3g degrees from the double computation", vn_method_name((vn_method)m), worst);
		assert_true(worst > 0.0); /* float arithmetic indeed */
	}
	free_grid(&g);
}

/* Vertex 482098 of the 1M-triangle torus (genmesh.py 1e6) and its five
 * triangles, two of them thin (smallest angles 0.06 and 0.13 rad): float
 * arithmetic there put MWA 1.29e-4 degrees off the double computation until
 * such triangles took the fallback; every scheme is within 1e-4 now. */
static void float_thin_triangles(void** state)
{
	(void)state;
	static const float pos[] = {0.585754991f, -0.141064003f, -0.042394001f,  0.586126029f, -0.139807999f, -0.046151001f,
	                            0.586407006f, -0.137327999f, -0.0407879986f, 0.586844027f, -0.138558f,    -0.0492639989f,
	                            0.587710977f, -0.136741996f, -0.0515879989f, 0.587750018f, -0.133726001f, -0.0460040011f};
	static const uint32_t idx[] = {0, 2, 3, 0, 3, 1, 1, 3, 4, 2, 5, 3, 3, 5, 4};
	const vn_positions p = {pos, 6, 0, vn_scalar_float32};
	double ref[18], got[18];
	const vn_vectors oref = {ref, 0, vn_scalar_float64}, ogot = {got, 0, vn_scalar_float64};
	for (unsigned m = 0; m < 6; ++m) {
		assert_int_equal(vn_triangle_normals(&oref, &p, idx, 15, (vn_method)m, NULL, NULL), vn_result_success);
		assert_int_equal(plan_tri(&p, idx, 5, (vn_method)m, NULL, &ogot, NULL), vn_result_success);
		const double worst = worst_degrees(ref, got, 6);
		if (worst > 1e-4)
			fail_msg("%s: %.3g degrees from the double computation", vn_method_name((vn_method)m), worst);
	}
}

/* The float32 corner angle of MWA: within 3e-7 rad of atan2 over [0, pi],
 * exact at the ends, 0 for (0, 0). */
static void float_atan2_bound(void** state)
{
	(void)state;
	double worst = 0.0;
	for (int i = 0; i <= 200000; ++i) {
		const double t = 3.14159265358979323846 * i / 200000.0;
		const float y = (float)sin(t), x = (float)cos(t);
		const double err = fabs((double)vn_atan2f_nonneg(y, x) - atan2((double)y, (double)x));
		worst = err > worst ? err : worst;
	}
	if (worst > 3e-7)
		fail_msg("float atan2 off by %.3g rad", worst);
	assert_true(vn_atan2f_nonneg(0.0f, 0.0f) == 0.0f);
	assert_true(vn_atan2f_nonneg(0.0f, 1.0f) == 0.0f);
	assert_true(vn_atan2f_nonneg(0.0f, -1.0f) == (float)VN_PI);
	assert_true(vn_atan2f_nonneg(1.0f, 0.0f) == (float)VN_PI_2);
	assert_true(fabs(vn_atan2f_nonneg(1e30f, 1e-30f) - VN_PI_2) < 1e-7);
}

/* 1, 2, 3 and 7 threads on a mesh large enough for 7 workers (340 x 340
 * vertices): the same bits, float32 and float64, every fast method. */
static void threads_bit_identical(void** state)
{
	(void)state;
	grid g = make_grid(340, 1.0);
	const size_t nv = g.nv, ni = g.ni;
	float *a = (float*)g.a, *b = (float*)g.b;
	const uint32_t* idx = g.idx;
	static const unsigned counts[] = {2, 3, 7};
	for (int type = 0; type < 2; ++type) {
		const vn_positions p = {type ? (const void*)g.pos : (const void*)g.pos32, nv, 0, (vn_scalar)type};
		const vn_vectors oa = {a, 0, vn_scalar_float32}, ob = {b, 0, vn_scalar_float32};
		for (unsigned m = 0; m < 6; ++m) {
			vn_stats sa, sb;
			const vn_options one = threads_options(1, vn_simd_auto);
			assert_int_equal(plan_tri(&p, idx, ni / 3, (vn_method)m, &one, &oa, &sa), vn_result_success);
			for (int c = 0; c < 3; ++c) {
				const vn_options o = threads_options(counts[c], vn_simd_auto);
				memset(b, 0, sizeof(float) * 3 * nv);
				assert_int_equal(plan_tri(&p, idx, ni / 3, (vn_method)m, &o, &ob, &sb), vn_result_success);
				assert_memory_equal(a, b, sizeof(float) * 3 * nv);
				assert_memory_equal(&sa, &sb, sizeof(sa));
			}
		}
	}
	free_grid(&g);
}

/* A 90 x 90 grid's faces in a random order, and isolated vertices up to
 * 33000 (2 workers when asked): on 1 worker every face is in its ring and
 * the order stays; on 2 most vertices span both, so the plan takes faces
 * in a locality order (one more allocation at create). Each vertex still
 * sums its corners in input order: the same bits. */
static void locality_order_same_bits(void** state)
{
	(void)state;
	grid g = make_grid(90, 1.0);
	const size_t nf = g.ni / 3, nv = 33000;
	float* pos = (float*)calloc(3 * nv, sizeof(float));
	memcpy(pos, g.pos32, sizeof(float) * 3 * g.nv);
	uint32_t seed = 2463534242u;
	for (size_t f = nf; f > 1; --f) {
		seed ^= seed << 13, seed ^= seed >> 17, seed ^= seed << 5;
		const size_t j = seed % f;
		uint32_t t[3];
		memcpy(t, g.idx + 3 * (f - 1), sizeof(t));
		memcpy(g.idx + 3 * (f - 1), g.idx + 3 * j, sizeof(t));
		memcpy(g.idx + 3 * j, t, sizeof(t));
	}
	float* a = (float*)malloc(sizeof(float) * 3 * nv);
	float* b = (float*)malloc(sizeof(float) * 3 * nv);
	const vn_positions p = {pos, nv, 0, vn_scalar_float32};
	const vn_vectors oa = {a, 0, vn_scalar_float32}, ob = {b, 0, vn_scalar_float32};
	counting c1 = {0, 0, -1}, c2 = {0, 0, -1};
	vn_options o1 = counting_options(&c1), o2 = counting_options(&c2);
	o2.threads = 2;
	vn_plan *kept = NULL, *sorted = NULL;
	assert_int_equal(vn_plan_create(g.idx, NULL, nf, nv, &o1, &kept), vn_result_success);
	assert_int_equal(vn_plan_create(g.idx, NULL, nf, nv, &o2, &sorted), vn_result_success);
	assert_int_equal(c1.allocations, 2);
	assert_int_equal(c2.allocations, 3);
	for (unsigned m = 0; m < 6; ++m) {
		vn_stats sa, sb;
		assert_int_equal(vn_plan_normals(kept, &p, (vn_method)m, &oa, &sa), vn_result_success);
		assert_int_equal(vn_plan_normals(sorted, &p, (vn_method)m, &ob, &sb), vn_result_success);
		assert_memory_equal(a, b, sizeof(float) * 3 * nv);
		assert_memory_equal(&sa, &sb, sizeof(sa));
		assert_int_equal(sb.zero_normals, nv - g.nv);
	}
	vn_plan_destroy(sorted);
	vn_plan_destroy(kept);
	assert_int_equal(c2.frees, 3);
	free(b);
	free(a);
	free(pos);
	free_grid(&g);
}

/* A vertex with 20 triangles (12 beyond the 8 slots), one with 9, in both
 * arithmetics: the overflow list keeps face order. */
static void overflow_beyond_eight_corners(void** state)
{
	(void)state;
	/* vertex 0 at the centre of a 20-gon of vertices 1..20 on a wavy rim;
	 * vertices 21..29 add 9 triangles around vertex 1. */
	double pos[3 * 30];
	float pos32[3 * 30];
	uint32_t idx[3 * 29];
	pos[0] = pos[1] = 0.0, pos[2] = 0.25;
	for (int i = 0; i < 20; ++i) {
		const double t = 2 * 3.14159265358979323846 * i / 20.0;
		pos[3 + 3 * i] = cos(t), pos[4 + 3 * i] = sin(t), pos[5 + 3 * i] = 0.1 * (i % 3);
		idx[3 * i] = 0, idx[3 * i + 1] = 1 + (uint32_t)i, idx[3 * i + 2] = 1 + (uint32_t)(i + 1) % 20;
	}
	for (int i = 0; i < 9; ++i) {
		const double t = 0.3 + 0.25 * i;
		pos[63 + 3 * i] = 1.0 + 0.5 * cos(t), pos[64 + 3 * i] = 0.5 * sin(t), pos[65 + 3 * i] = 0.05 * i;
		idx[60 + 3 * i] = 1, idx[61 + 3 * i] = 21 + (uint32_t)i, idx[62 + 3 * i] = i < 8 ? 22 + (uint32_t)i : 2;
	}
	for (int i = 0; i < 90; ++i)
		pos32[i] = (float)pos[i];
	for (int simd = 0; simd < 2; ++simd) {
		const vn_options o = threads_options(1, simd ? vn_simd_off : vn_simd_auto);
		for (unsigned m = 0; m < 6; ++m) {
			double a[90], b[90], fa[90];
			const vn_positions p = {pos, 30, 0, vn_scalar_float64}, pf = {pos32, 30, 0, vn_scalar_float32};
			const vn_vectors oa = {a, 0, vn_scalar_float64}, ob = {b, 0, vn_scalar_float64},
			                 of = {fa, 0, vn_scalar_float64};
			assert_int_equal(vn_triangle_normals(&oa, &p, idx, 87, (vn_method)m, &o, NULL), vn_result_success);
			assert_int_equal(plan_tri(&p, idx, 29, (vn_method)m, &o, &ob, NULL), vn_result_success);
			if (m == vn_method_mwa)
				assert_true(worst_degrees(a, b, 30) <= 1e-9);
			else
				assert_memory_equal(a, b, sizeof(a));
			assert_int_equal(vn_triangle_normals(&oa, &pf, idx, 87, (vn_method)m, &o, NULL), vn_result_success);
			assert_int_equal(plan_tri(&pf, idx, 29, (vn_method)m, &o, &of, NULL), vn_result_success);
			assert_true(worst_degrees(a, fa, 30) <= 1e-4);
		}
	}
}

/* ---------------------------------------------------------------- layouts */

/* Interleaved float32 vertex buffers (position, uv, colour: 36 bytes; and
 * 38, whose positions are not 4-byte aligned) in, normals into an
 * interleaved 28-byte output, and float64 in / float32 out: the same values
 * as packed arrays, also from one plan that sees the strides in turn. */
static void strides_and_types(void** state)
{
	(void)state;
	grid g = make_grid(30, 1.0);
	const size_t nv = g.nv, ni = g.ni;
	const uint32_t* idx = g.idx;
	const double* pos = g.pos;
	const float* packed = g.pos32;
	float* a = (float*)g.a;
	double* d = g.b;
	unsigned char* inter = (unsigned char*)malloc(38 * nv);
	unsigned char* b = (unsigned char*)malloc(28 * nv);
	const vn_positions pp = {packed, nv, 0, vn_scalar_float32}, pd = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors oa = {a, 0, vn_scalar_float32}, ob = {b, 28, vn_scalar_float32}, od = {d, 0, vn_scalar_float64};
	vn_plan* plan = NULL;
	assert_int_equal(vn_plan_create(idx, NULL, ni / 3, nv, NULL, &plan), vn_result_success);
	for (size_t stride = 36; stride <= 38; stride += 2) {
		memset(inter, 0x7f, 38 * nv);
		for (size_t v = 0; v < nv; ++v)
			memcpy(inter + stride * v, packed + 3 * v, 12);
		const vn_positions pi = {inter, nv, stride, vn_scalar_float32};
		for (unsigned m = 0; m < 6; ++m) {
			assert_int_equal(plan_tri(&pp, idx, ni / 3, (vn_method)m, NULL, &oa, NULL), vn_result_success);
			for (int again = 0; again < 2; ++again) {
				memset(b, 0x55, 28 * nv);
				assert_int_equal(again ? vn_plan_normals(plan, &pi, (vn_method)m, &ob, NULL)
				                       : plan_tri(&pi, idx, ni / 3, (vn_method)m, NULL, &ob, NULL),
				                 vn_result_success);
				for (size_t v = 0; v < nv; ++v) {
					assert_memory_equal(b + 28 * v, a + 3 * v, 12);
					assert_int_equal(b[28 * v + 12], 0x55); /* the rest of the element untouched */
				}
			}
			memset(d, 0, sizeof(float) * 3 * nv);
			assert_int_equal(vn_plan_normals(plan, &pp, (vn_method)m, &(vn_vectors){d, 0, vn_scalar_float32}, NULL),
			                 vn_result_success);
			assert_memory_equal(d, a, sizeof(float) * 3 * nv);
			/* float32 positions, float64 output: the float results widened */
			assert_int_equal(plan_tri(&pi, idx, ni / 3, (vn_method)m, NULL, &od, NULL), vn_result_success);
			for (size_t i = 0; i < 3 * nv; ++i)
				assert_true(d[i] == (double)a[i]);
			/* float64 positions, float32 output: vn_triangle_normals' bits */
			assert_int_equal(vn_triangle_normals(&oa, &pd, idx, ni, (vn_method)m, NULL, NULL), vn_result_success);
			assert_int_equal(plan_tri(&pd, idx, ni / 3, (vn_method)m, NULL, &ob, NULL), vn_result_success);
			for (size_t v = 0; v < nv; ++v)
				assert_memory_equal(b + 28 * v, a + 3 * v, 12);
		}
	}
	vn_plan_destroy(plan);
	free(b);
	free(inter);
	free_grid(&g);
}

/* A quad and a pentagon plus a non-planar quad: vn_polygon_normals' bits
 * for every method; the plane's normal for the flat ones. */
static void polygons_equal_polygon_normals(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 2, 0, 1, 3, 1, 1, 2, 2, 1, 0, 0, 0, 1, 0, 0, 1, 1, 1};
	const uint32_t idx[] = {0, 1, 2, 3, 1, 4, 5, 6, 2, 7, 8, 9, 3};
	const uint32_t off[] = {0, 4, 9, 13};
	vn_plan* plan = NULL;
	assert_int_equal(vn_plan_create(idx, off, 3, 10, NULL, &plan), vn_result_success);
	const vn_positions p = {pos, 10, 0, vn_scalar_float64};
	for (unsigned m = 0; m < vn_method_count; ++m) {
		double a[30], b[30];
		vn_stats sa, sb;
		const vn_vectors oa = {a, 0, vn_scalar_float64}, ob = {b, 0, vn_scalar_float64};
		assert_int_equal(vn_polygon_normals(&oa, &p, idx, off, 3, (vn_method)m, NULL, &sa), vn_result_success);
		assert_int_equal(vn_plan_normals(plan, &p, (vn_method)m, &ob, &sb), vn_result_success);
		assert_memory_equal(a, b, sizeof(a));
		assert_memory_equal(&sa, &sb, sizeof(sa));
		if (m != vn_method_mewcsa && m < vn_method_quadric)
			assert_true(b[3 * 5] == 0.0 && b[3 * 5 + 1] == 0.0 && b[3 * 5 + 2] == 1.0);
	}
	vn_plan_destroy(plan);
}

/* ---------------------------------------------------------------- corners */

/* vn_plan_corner_normals gives vn_corner_normals' and vn_polygon_corner_normals'
 * bits, with flagged and creased edges. */
static void corners_equal_corner_normals(void** state)
{
	(void)state;
	grid g = make_grid(12, 1.0);
	const size_t nv = g.nv, ni = g.ni;
	const uint32_t* idx = g.idx;
	uint8_t* sharp = (uint8_t*)calloc(ni, 1);
	for (size_t c = 0; c < ni; c += 7)
		sharp[c] = 1;
	double* a = (double*)malloc(sizeof(double) * 3 * ni);
	double* b = (double*)malloc(sizeof(double) * 3 * ni);
	uint32_t* off = (uint32_t*)malloc(sizeof(uint32_t) * (ni / 3 + 1));
	for (size_t f = 0; f <= ni / 3; ++f)
		off[f] = (uint32_t)(3 * f);
	const vn_positions p = {g.pos, nv, 0, vn_scalar_float64};
	const vn_vectors oa = {a, 0, vn_scalar_float64}, ob = {b, 0, vn_scalar_float64};
	vn_plan *tri = NULL, *poly = NULL;
	assert_int_equal(vn_plan_create(idx, NULL, ni / 3, nv, NULL, &tri), vn_result_success);
	assert_int_equal(vn_plan_create(idx, off, ni / 3, nv, NULL, &poly), vn_result_success);
	for (unsigned m = 0; m < vn_method_count; ++m) {
		vn_stats sa, sb;
		assert_int_equal(vn_corner_normals(&oa, &p, idx, ni, (vn_method)m, 0.5, sharp, NULL, &sa), vn_result_success);
		assert_int_equal(vn_plan_corner_normals(tri, &p, (vn_method)m, 0.5, sharp, &ob, &sb), vn_result_success);
		assert_memory_equal(a, b, sizeof(double) * 3 * ni);
		assert_memory_equal(&sa, &sb, sizeof(sa));
		assert_int_equal(vn_polygon_corner_normals(&oa, &p, idx, off, ni / 3, (vn_method)m, 0.5, sharp, NULL, &sa),
		                 vn_result_success);
		assert_int_equal(vn_plan_corner_normals(poly, &p, (vn_method)m, 0.5, sharp, &ob, &sb), vn_result_success);
		assert_memory_equal(a, b, sizeof(double) * 3 * ni);
	}
	vn_plan_destroy(poly);
	vn_plan_destroy(tri);
	free(off);
	free(b);
	free(a);
	free(sharp);
	free_grid(&g);
}

/* ---------------------------------------------------------------- degenerate input */

/* A good triangle, a collinear one, a repeated index, a NaN and an Inf
 * vertex, an isolated vertex (6): literal counts and zero normals, in both
 * arithmetics; keep_existing leaves the zero ones alone. */
static void degenerate_nan_and_isolated(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, NAN, 0, 0, 1, 1, INFINITY, 2, 0, 0, 5, 5, 5, 3, 0, 0};
	const uint32_t idx[] = {0, 1, 2, 0, 3, 1, 1, 4, 2, 1, 5, 7, 0, 0, 2};
	float pos32[24];
	for (int i = 0; i < 24; ++i)
		pos32[i] = (float)pos[i];
	for (int type = 0; type < 2; ++type) {
		const vn_positions p = {type ? (const void*)pos : (const void*)pos32, 8, 0, (vn_scalar)type};
		for (unsigned m = 0; m < 6; ++m) {
			double out[24];
			vn_stats st;
			const vn_vectors o = {out, 0, vn_scalar_float64};
			assert_int_equal(plan_tri(&p, idx, 5, (vn_method)m, NULL, &o, &st), vn_result_success);
			assert_int_equal(st.faces, 5);
			assert_int_equal(st.degenerate_faces, 4);
			assert_int_equal(st.nonfinite_vertices, 2);
			assert_int_equal(st.zero_normals, 5); /* 3, 4, 5, 6, 7 */
			for (int v = 0; v < 3; ++v)
				assert_true(out[3 * v] == 0 && out[3 * v + 1] == 0 && fabs(out[3 * v + 2] - 1) <= (type ? 0 : 6e-8));
			for (int i = 9; i < 24; ++i)
				assert_true(out[i] == 0.0);
			vn_options keep;
			memset(&keep, 0, sizeof(keep));
			keep.keep_existing = 1;
			for (int i = 0; i < 24; ++i)
				out[i] = 7.0;
			assert_int_equal(plan_tri(&p, idx, 5, (vn_method)m, &keep, &o, NULL), vn_result_success);
			assert_true(fabs(out[2] - 1) <= 6e-8);
			for (int i = 9; i < 24; ++i)
				assert_true(out[i] == 7.0);
		}
	}
}

/* ---------------------------------------------------------------- errors */

static void errors_at_create(void** state)
{
	(void)state;
	const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
	const uint32_t bad_off[] = {0, 4, 3};
	vn_plan* plan = (vn_plan*)0x1; /* untouched on failure */
	assert_int_equal(vn_plan_create(idx, NULL, 2, 3, NULL, &plan), vn_result_index_out_of_range);
	assert_int_equal(vn_plan_create(idx, NULL, 2, 0, NULL, &plan), vn_result_index_out_of_range);
	assert_int_equal(vn_plan_create(idx, bad_off, 2, 4, NULL, &plan), vn_result_invalid_argument);
	assert_int_equal(vn_plan_create(NULL, NULL, 2, 4, NULL, &plan), vn_result_invalid_argument);
	assert_int_equal(vn_plan_create(idx, NULL, 2, 4, NULL, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_plan_create(idx, NULL, 2, (size_t)UINT32_MAX + 1, NULL, &plan), vn_result_invalid_argument);
	vn_options half;
	memset(&half, 0, sizeof(half));
	half.allocator.allocate = count_alloc;
	assert_int_equal(vn_plan_create(idx, NULL, 2, 4, &half, &plan), vn_result_invalid_argument);
	assert_ptr_equal(plan, (vn_plan*)0x1);
	/* A failing allocator: out_of_memory, nothing leaked. */
	for (int fail = 0; fail < 2; ++fail) {
		counting c = {0, 0, fail};
		const vn_options o = counting_options(&c);
		assert_int_equal(vn_plan_create(idx, NULL, 2, 4, &o, &plan), vn_result_out_of_memory);
		assert_int_equal(c.allocations, c.frees);
	}
	/* An empty mesh is a plan too. */
	assert_int_equal(vn_plan_create(NULL, NULL, 0, 0, NULL, &plan), vn_result_success);
	const vn_positions p = {NULL, 0, 0, vn_scalar_float32};
	const vn_vectors o = {NULL, 0, vn_scalar_float32};
	vn_stats st;
	assert_int_equal(vn_plan_normals(plan, &p, vn_method_mwe, &o, &st), vn_result_success);
	assert_int_equal(st.faces, 0);
	vn_plan_destroy(plan);
	vn_plan_destroy(NULL);
}

static void errors_at_normals(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
	const uint32_t idx[] = {0, 1, 2, 1, 3, 2};
	double out[12];
	vn_plan* plan = NULL;
	assert_int_equal(vn_plan_create(idx, NULL, 2, 4, NULL, &plan), vn_result_success);
	const vn_positions three = {pos, 3, 0, vn_scalar_float64}, four = {pos, 4, 0, vn_scalar_float64};
	const vn_positions short_stride = {pos, 4, 8, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64}, no_data = {NULL, 0, vn_scalar_float64};
	assert_int_equal(vn_plan_normals(plan, &three, vn_method_mwe, &o, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_plan_normals(plan, &short_stride, vn_method_mwe, &o, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_plan_normals(plan, &four, vn_method_mwe, &no_data, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_plan_normals(plan, &four, vn_method_count, &o, NULL), vn_result_unknown_method);
	assert_int_equal(vn_plan_normals(NULL, &four, vn_method_mwe, &o, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_plan_corner_normals(plan, &three, vn_method_mwe, 4.0, NULL, &o, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_plan_normals(plan, &four, vn_method_mwe, &o, NULL), vn_result_success);
	assert_true(out[2] == 1.0 && out[11] == 1.0);
	vn_plan_destroy(plan);
}

/* ---------------------------------------------------------------- memory */

/* vn_plan_create allocates (a scratch count and one block); vn_plan_normals
 * allocates nothing for the fast methods on 1 and 2 threads, nor for MEWCSA
 * and polygons (the plan's workspace), nor vn_plan_corner_normals; destroy
 * frees everything. */
static void no_allocation_per_frame(void** state)
{
	(void)state;
	grid g = make_grid(200, 1.0); /* 2 workers */
	const size_t nv = g.nv, ni = g.ni;
	const uint32_t* idx = g.idx;
	float* out = (float*)g.a;
	uint32_t* off = (uint32_t*)malloc(sizeof(uint32_t) * (ni / 3 + 1));
	for (size_t f = 0; f <= ni / 3; ++f)
		off[f] = (uint32_t)(3 * f);
	float* corners = (float*)malloc(sizeof(float) * 3 * ni);
	for (unsigned threads = 1; threads <= 2; ++threads) {
		counting c = {0, 0, -1};
		vn_options o = counting_options(&c);
		o.threads = threads;
		vn_plan *plan = NULL, *poly = NULL;
		assert_int_equal(vn_plan_create(idx, NULL, ni / 3, nv, &o, &plan), vn_result_success);
		assert_int_equal(c.allocations, 2);
		assert_int_equal(c.frees, 1);
		assert_int_equal(vn_plan_create(idx, off, ni / 3, nv, &o, &poly), vn_result_success);
		assert_int_equal(c.allocations, 3);
		const vn_vectors vo = {out, 0, vn_scalar_float32}, co = {corners, 0, vn_scalar_float32};
		for (int type = 0; type < 2; ++type) {
			const vn_positions p = {type ? (const void*)g.pos : (const void*)g.pos32, nv, 0, (vn_scalar)type};
			for (unsigned m = 0; m <= vn_method_mewcsa; ++m) {
				assert_int_equal(vn_plan_normals(plan, &p, (vn_method)m, &vo, NULL), vn_result_success);
				assert_int_equal(vn_plan_normals(poly, &p, (vn_method)m, &vo, NULL), vn_result_success);
			}
			assert_int_equal(vn_plan_corner_normals(plan, &p, vn_method_mwa, 0.5, NULL, &co, NULL), vn_result_success);
			assert_int_equal(vn_plan_corner_normals(poly, &p, vn_method_mwa, 0.5, NULL, &co, NULL), vn_result_success);
		}
		assert_int_equal(c.allocations, 3);
		vn_plan_destroy(poly);
		vn_plan_destroy(plan);
		assert_int_equal(c.frees, 3);
	}
	free(corners);
	free(off);
	free_grid(&g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(fan_literal_values),
	    cmocka_unit_test(double_equals_triangle_normals),
	    cmocka_unit_test(float_within_bound),
	    cmocka_unit_test(float_thin_triangles),
	    cmocka_unit_test(float_atan2_bound),
	    cmocka_unit_test(double_atan2_bound),
	    cmocka_unit_test(threads_bit_identical),
	    cmocka_unit_test(overflow_beyond_eight_corners),
	    cmocka_unit_test(locality_order_same_bits),
	    cmocka_unit_test(strides_and_types),
	    cmocka_unit_test(polygons_equal_polygon_normals),
	    cmocka_unit_test(corners_equal_corner_normals),
	    cmocka_unit_test(degenerate_nan_and_isolated),
	    cmocka_unit_test(errors_at_create),
	    cmocka_unit_test(errors_at_normals),
	    cmocka_unit_test(no_allocation_per_frame),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
