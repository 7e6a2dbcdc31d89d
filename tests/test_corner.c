/* Welding and split normals: vn_weld_positions, vn_corner_normals and
 * vn_polygon_corner_normals.
 * Literal inputs, literal expected values (computed by hand or to 30
 * digits), plus bit-for-bit agreement with vn_triangle_normals where the
 * two must agree. */
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

/* The paper's seven schemes: the brute-force sums below are their definition
 * (the fits and SMEWCSA per corner are tested in test_fit.c). */
#define SEVEN (vn_method_mewcsa + 1)
#include "vn_paper.h" /* test meshes: vn_model_generate */
#include "test_util.h"

#define PI 3.141592653589793
#define DEG45 0.7853981633974483
#define DEG30 0.5235987755982988
#define DEG60 1.0471975511965976

/* ---------------------------------------------------------------- helpers */

static vn_result weld(const double* pos, size_t nv, double eps, uint32_t* remap)
{
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	return vn_weld_positions(remap, &p, eps, NULL);
}

static vn_result corners(const double* pos, size_t nv, const uint32_t* idx, size_t ni, vn_method m, double crease,
                         const uint8_t* sharp, double* out, vn_stats* st)
{
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	return vn_corner_normals(&o, &p, idx, ni, m, crease, sharp, NULL, st);
}

static void assert_vec(const double* got, double x, double y, double z, double tol)
{
	if (fabs(got[0] - x) > tol || fabs(got[1] - y) > tol || fabs(got[2] - z) > tol)
		fail_msg("got (%.17g, %.17g, %.17g), expected (%.17g, %.17g, %.17g)", got[0], got[1], got[2], x, y, z);
}

static void assert_same(const double* a, const double* b)
{
	assert_memory_equal(a, b, 3 * sizeof(double));
}

static void assert_remap(const uint32_t* got, const uint32_t* want, size_t n)
{
	for (size_t i = 0; i < n; ++i)
		if (got[i] != want[i])
			fail_msg("remap[%zu] = %u, expected %u", i, (unsigned)got[i], (unsigned)want[i]);
}

/* A UV sphere of radius 1 with R = 8 rings of faces and S = 12 segments.
 * split: every (ring, column) its own vertex, (R + 1)(S + 1) = 117 of them,
 * as files store UV spheres (column S repeats column 0 at angle 2 pi, and
 * each pole repeats S + 1 times). Closed: S (R - 1) + 2 = 86 vertices. The
 * triangles come in the same order and rotation either way; the closed
 * sphere leaves out the pole triangles that collapse. closed_id, when not
 * NULL, receives the closed vertex of each split vertex. */
enum { SPH_R = 8, SPH_S = 12, SPH_SPLIT = (SPH_R + 1) * (SPH_S + 1), SPH_CLOSED = SPH_S * (SPH_R - 1) + 2 };

static uint32_t sphere_closed_id(int r, int c)
{
	return r == 0 ? 0 : r == SPH_R ? (uint32_t)(1 + (SPH_R - 1) * SPH_S) : (uint32_t)(1 + (r - 1) * SPH_S + c % SPH_S);
}

static size_t uv_sphere(int split, double* pos, uint32_t* idx, uint32_t* closed_id)
{
	for (int r = 0; r <= SPH_R; ++r)
		for (int c = 0; c <= SPH_S; ++c) {
			const double th = PI * r / SPH_R, ph = 2 * PI * c / SPH_S;
			const uint32_t v = split ? (uint32_t)(r * (SPH_S + 1) + c) : sphere_closed_id(r, c);
			if (!split && (c == SPH_S || ((r == 0 || r == SPH_R) && c > 0)))
				continue; /* one closed vertex, at column 0 */
			pos[3 * v] = sin(th) * cos(ph), pos[3 * v + 1] = sin(th) * sin(ph), pos[3 * v + 2] = cos(th);
			if (closed_id)
				closed_id[v] = sphere_closed_id(r, c);
		}
	size_t k = 0;
	for (int r = 0; r < SPH_R; ++r)
		for (int c = 0; c < SPH_S; ++c) {
			const int rc[4][2] = {{r, c}, {r + 1, c}, {r + 1, c + 1}, {r, c + 1}};
			uint32_t q[4];
			for (int i = 0; i < 4; ++i)
				q[i] = split ? (uint32_t)(rc[i][0] * (SPH_S + 1) + rc[i][1]) : sphere_closed_id(rc[i][0], rc[i][1]);
			const uint32_t t[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
			for (int i = 0; i < 2; ++i) {
				if (!split && (t[i][0] == t[i][1] || t[i][1] == t[i][2] || t[i][2] == t[i][0]))
					continue;
				memcpy(idx + k, t[i], sizeof(t[i]));
				k += 3;
			}
		}
	return k;
}

static size_t distinct_groups(const uint32_t* remap, size_t n)
{
	size_t groups = 0;
	for (size_t i = 0; i < n; ++i) {
		assert_int_equal(remap[remap[i]], remap[i]);
		assert_true(remap[i] <= i);
		groups += remap[i] == i;
	}
	return groups;
}

/* ---------------------------------------------------------------- weld */

static void weld_exact_duplicates(void** state)
{
	(void)state;
	const double pos[] = {1, 2, 3, 4, 5, 6, 1, 2, 3, 4, 5, 6, 1, 2, 3.0000001, 1, 2, 3};
	uint32_t remap[6];
	assert_int_equal(weld(pos, 6, 0.0, remap), vn_result_success);
	const uint32_t want[] = {0, 1, 0, 1, 4, 0};
	assert_remap(remap, want, 6);
}

/* epsilon = 0.375 (cells of 0.25): 0 ~ 0.375 ~ 0.75 chain into one group
 * though 0 and 0.75 are 2 epsilon apart (cells 0, 1 and 3: a reach of 2
 * cells); 1.125 + 2^-20 is just beyond 0.75 + epsilon; (-0.375, -0.375,
 * 0.375) is within epsilon of the origin along a diagonal of cells;
 * (0.375, 0.375, 0.376) is within epsilon of nothing. */
static void weld_epsilon_chain(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 2, 0, 0, 0.75, 0, 0, 0.375, 0, 0, 1.12500095367431640625, 0, 0,
	                      -0.375, -0.375, 0.375, 0.375, 0.375, 0.376};
	uint32_t remap[7];
	assert_int_equal(weld(pos, 7, 0.375, remap), vn_result_success);
	const uint32_t want[] = {0, 1, 0, 0, 4, 0, 6};
	assert_remap(remap, want, 7);
	/* A hair less than the chain's links: nothing welds. */
	assert_int_equal(weld(pos, 7, 0.37499999999999994, remap), vn_result_success);
	const uint32_t alone[] = {0, 1, 2, 3, 4, 5, 6};
	assert_remap(remap, alone, 7);
}

static void weld_signed_zero(void** state)
{
	(void)state;
	const double pos[] = {0.0, 0.0, 0.0, -0.0, 0.0, -0.0, 0.0, -0.0, 1.0, -0.0, 0.0, 1.0};
	uint32_t remap[4];
	const uint32_t want[] = {0, 0, 2, 2};
	assert_int_equal(weld(pos, 4, 0.0, remap), vn_result_success);
	assert_remap(remap, want, 4);
	assert_int_equal(weld(pos, 4, 0.5, remap), vn_result_success);
	assert_remap(remap, want, 4);
}

static void weld_nan_never(void** state)
{
	(void)state;
	const double pos[] = {NAN, 0, 0, NAN, 0, 0, 0, 0, 0, 0, NAN, 0, 0.5, 0, 0};
	uint32_t remap[5];
	const uint32_t want[] = {0, 1, 2, 3, 2};
	assert_int_equal(weld(pos, 5, 1.0, remap), vn_result_success);
	assert_remap(remap, want, 5);
	const uint32_t exact[] = {0, 1, 2, 3, 4};
	assert_int_equal(weld(pos, 5, 0.0, remap), vn_result_success);
	assert_remap(remap, exact, 5);
}

/* Infinite coordinates, and coordinates so large that the doubles next to
 * them are more than epsilon away, weld only when equal; their other
 * coordinates still weld within epsilon (here from the next cell). */
static void weld_infinite_and_huge(void** state)
{
	(void)state;
	const double pos[] = {INFINITY, 0, 0, DBL_MAX, 0, 0, INFINITY, 1, 0, -INFINITY, 0, 0,
	                      1e300, 0, 0, 1e300, 0, 1, nextafter(1e300, INFINITY), 0, 0};
	uint32_t remap[7];
	assert_int_equal(weld(pos, 7, 1.0, remap), vn_result_success);
	const uint32_t want[] = {0, 1, 0, 3, 4, 4, 6};
	assert_remap(remap, want, 7);
}

/* The smallest epsilon, a subnormal: the grid is still exact, and normal
 * coordinates (far beyond 2^54 cells) are exact axes. */
static void weld_subnormal_epsilon(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 4.9406564584124654e-324, 0, 0, 1.4821969375237396e-323, 0, 0, 1, 1, 1, 1, 1, 1};
	uint32_t remap[5];
	assert_int_equal(weld(pos, 5, 4.9406564584124654e-324, remap), vn_result_success);
	const uint32_t want[] = {0, 0, 2, 3, 3};
	assert_remap(remap, want, 5);
}

/* float32 in a 5-float stride and float64 in a 4-double stride: the same
 * positions weld the same way. 1.005f is within 0.01 of 1, 3.02f is not of 3. */
static void weld_types_and_strides(void** state)
{
	(void)state;
	const float f[] = {1, 2, 3, 9, 9, 1.005f, 2, 3, 9, 9, 7, 7, 7, 9, 9, 1, 2, 3.02f, 9, 9};
	double d[16];
	for (int v = 0; v < 4; ++v)
		for (int a = 0; a < 4; ++a)
			d[4 * v + a] = a < 3 ? (double)f[5 * v + a] : 9.0;
	const vn_positions pf = {f, 4, 5 * sizeof(float), vn_scalar_float32};
	const vn_positions pd = {d, 4, 4 * sizeof(double), vn_scalar_float64};
	const uint32_t want[] = {0, 0, 2, 3};
	uint32_t remap[4];
	assert_int_equal(vn_weld_positions(remap, &pf, 0.01, NULL), vn_result_success);
	assert_remap(remap, want, 4);
	assert_int_equal(vn_weld_positions(remap, &pd, 0.01, NULL), vn_result_success);
	assert_remap(remap, want, 4);
}

static void weld_uv_sphere_seam(void** state)
{
	(void)state;
	double pos[3 * SPH_SPLIT];
	uint32_t idx[6 * SPH_R * SPH_S], remap[SPH_SPLIT], closed[SPH_SPLIT];
	uv_sphere(1, pos, idx, closed);
	assert_int_equal(weld(pos, SPH_SPLIT, 1e-9, remap), vn_result_success);
	assert_int_equal(distinct_groups(remap, SPH_SPLIT), 86);
	/* Each copy welds to the copy of lowest index: column 0, pole column 0. */
	for (int r = 1; r < SPH_R; ++r)
		assert_int_equal(remap[r * (SPH_S + 1) + SPH_S], r * (SPH_S + 1));
	assert_int_equal(remap[SPH_R * (SPH_S + 1) + 5], SPH_R * (SPH_S + 1));
	/* sin(2 pi) is not 0: without epsilon only the north pole (exact zeros) welds. */
	assert_int_equal(weld(pos, SPH_SPLIT, 0.0, remap), vn_result_success);
	assert_int_equal(distinct_groups(remap, SPH_SPLIT), SPH_SPLIT - SPH_S);
}

static void weld_invalid_arguments(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0};
	uint32_t remap[2] = {7, 7};
	const vn_positions p = {pos, 2, 0, vn_scalar_float64};
	assert_int_equal(vn_weld_positions(remap, NULL, 0.0, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_weld_positions(NULL, &p, 0.0, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_weld_positions(remap, &p, -1e-9, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_weld_positions(remap, &p, NAN, NULL), vn_result_invalid_argument);
	assert_int_equal(vn_weld_positions(remap, &p, INFINITY, NULL), vn_result_invalid_argument);
	const vn_positions narrow = {pos, 2, 16, vn_scalar_float64};
	assert_int_equal(vn_weld_positions(remap, &narrow, 0.0, NULL), vn_result_invalid_argument);
	const vn_positions bad_type = {pos, 2, 0, (vn_scalar)2};
	assert_int_equal(vn_weld_positions(remap, &bad_type, 0.0, NULL), vn_result_invalid_argument);
	const vn_positions no_data = {NULL, 2, 0, vn_scalar_float64};
	assert_int_equal(vn_weld_positions(remap, &no_data, 0.0, NULL), vn_result_invalid_argument);
	vn_options half;
	memset(&half, 0, sizeof(half));
	half.allocator.allocate = count_alloc;
	assert_int_equal(vn_weld_positions(remap, &p, 0.0, &half), vn_result_invalid_argument);
	assert_true(remap[0] == 7 && remap[1] == 7);
	/* No vertices: nothing to do, remap may be NULL. */
	const vn_positions none = {NULL, 0, 0, vn_scalar_float64};
	assert_int_equal(vn_weld_positions(NULL, &none, 0.0, NULL), vn_result_success);
}

static void weld_allocator(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 0, 0};
	const vn_positions p = {pos, 3, 0, vn_scalar_float64};
	counting c = {0, 0, -1};
	const vn_options o = counting_options(&c);
	uint32_t remap[3];
	assert_int_equal(vn_weld_positions(remap, &p, 0.0, &o), vn_result_success);
	assert_int_equal(c.allocations, 1);
	assert_int_equal(c.frees, 1);
	const uint32_t want[] = {0, 1, 0};
	assert_remap(remap, want, 3);

	counting none = {0, 0, 0};
	const vn_options fail = counting_options(&none);
	remap[0] = remap[1] = remap[2] = 42;
	assert_int_equal(vn_weld_positions(remap, &p, 0.0, &fail), vn_result_out_of_memory);
	assert_true(remap[0] == 42 && remap[1] == 42 && remap[2] == 42);
	assert_int_equal(none.frees, 0);
}

static uint32_t next_random(uint32_t* seed)
{
	*seed ^= *seed << 13, *seed ^= *seed >> 17, *seed ^= *seed << 5;
	return *seed;
}

/* Groups by brute force: every pair, union-find with the lowest index as root. */
static void weld_brute_force(const double* pos, size_t n, double eps, uint32_t* remap)
{
	for (size_t i = 0; i < n; ++i)
		remap[i] = (uint32_t)i;
	for (size_t i = 0; i < n; ++i)
		for (size_t j = i + 1; j < n; ++j) {
			int near = 1;
			for (int a = 0; a < 3; ++a)
				near &= pos[3 * i + a] == pos[3 * j + a] || fabs(pos[3 * i + a] - pos[3 * j + a]) <= eps;
			if (!near)
				continue;
			uint32_t ri = (uint32_t)i, rj = (uint32_t)j;
			while (remap[ri] != ri)
				ri = remap[ri];
			while (remap[rj] != rj)
				rj = remap[rj];
			if (ri < rj)
				remap[rj] = ri;
			else
				remap[ri] = rj;
		}
	for (size_t i = 0; i < n; ++i) {
		uint32_t r = (uint32_t)i;
		while (remap[r] != r)
			r = remap[r];
		remap[i] = r;
	}
}

/* Random clouds against the brute force: uniform doubles (many chains), and
 * coordinates on a 1/8 grid with epsilon 3/8 (pairs exactly epsilon apart,
 * duplicates, negative cells). */
static void weld_matches_brute_force(void** state)
{
	(void)state;
	enum { N = 3000 };
	double* pos = (double*)malloc(sizeof(double) * 3 * N);
	uint32_t* got = (uint32_t*)malloc(sizeof(uint32_t) * N);
	uint32_t* want = (uint32_t*)malloc(sizeof(uint32_t) * N);
	uint32_t seed = 2463534242u;
	for (int grid = 0; grid < 2; ++grid) {
		for (size_t i = 0; i < 3 * N; ++i)
			pos[i] = grid ? (double)(int)(next_random(&seed) % 128) / 8.0 - 8.0
			              : 10.0 * next_random(&seed) / 4294967296.0;
		const double eps = grid ? 0.375 : 0.4;
		weld_brute_force(pos, N, eps, want);
		assert_int_equal(weld(pos, N, eps, got), vn_result_success);
		assert_remap(got, want, N);
		assert_true(distinct_groups(got, N) < N - 100); /* many welds... */
		assert_true(distinct_groups(got, N) > 100);     /* ...but not one blob */
	}
	free(want);
	free(got);
	free(pos);
}

/* epsilon 0 (a hash table) against the brute force on points drawn from 12
 * values, signed zeros, infinities and NaNs of both signs among them, as
 * float32 in a 4-float stride and float64 in a 5-double stride whose padding
 * differs from vertex to vertex. The first six points are set by hand. */
static void weld_exact_matches_brute_force(void** state)
{
	(void)state;
	enum { N = 3000 };
	const float values[] = {0.0f, -0.0f, INFINITY, -INFINITY, NAN, -NAN, 1, -1, 0.1f, 1e-40f, FLT_MAX, 3};
	const float first[6][3] = {{-0.0f, INFINITY, 1}, {0, INFINITY, 1}, {NAN, 0, 0},
	                           {NAN, 0, 0},          {0, -INFINITY, 1}, {-0.0f, INFINITY, 1}};
	float* f = (float*)malloc(sizeof(float) * 4 * N);
	double* d = (double*)malloc(sizeof(double) * 5 * N);
	double* pos = (double*)malloc(sizeof(double) * 3 * N);
	uint32_t* got = (uint32_t*)malloc(sizeof(uint32_t) * N);
	uint32_t* want = (uint32_t*)malloc(sizeof(uint32_t) * N);
	uint32_t seed = 88675123u;
	for (size_t i = 0; i < N; ++i) {
		for (int a = 0; a < 3; ++a) {
			const float v = i < 6 ? first[i][a] : values[next_random(&seed) % 12];
			f[4 * i + a] = v, d[5 * i + a] = v, pos[3 * i + a] = v;
		}
		f[4 * i + 3] = (float)i, d[5 * i + 3] = d[5 * i + 4] = (double)i;
	}
	weld_brute_force(pos, N, 0.0, want);
	const uint32_t head[] = {0, 0, 2, 3, 4, 0};
	assert_remap(want, head, 6);
	const vn_positions pf = {f, N, 4 * sizeof(float), vn_scalar_float32};
	const vn_positions pd = {d, N, 5 * sizeof(double), vn_scalar_float64};
	assert_int_equal(vn_weld_positions(got, &pf, 0.0, NULL), vn_result_success);
	assert_remap(got, want, N);
	assert_true(distinct_groups(got, N) < N - 500); /* many welds... */
	assert_true(distinct_groups(got, N) > 1000);    /* ...and many NaN singletons */
	memset(got, 0, sizeof(uint32_t) * N);
	assert_int_equal(vn_weld_positions(got, &pd, 0.0, NULL), vn_result_success);
	assert_remap(got, want, N);
	free(want);
	free(got);
	free(pos);
	free(d);
	free(f);
}

/* A crowded table: 4096 distinct points fill half its slots, each point 0
 * but along one axis, so that a probe often meets a point equal to it in
 * two coordinates of three. None welds. */
static void weld_exact_crowded(void** state)
{
	(void)state;
	enum { N = 4096 };
	double* pos = (double*)calloc(3 * N, sizeof(double));
	uint32_t* remap = (uint32_t*)malloc(sizeof(uint32_t) * N);
	for (size_t i = 0; i < N; ++i)
		pos[3 * i + i % 3] = (double)(i / 3 + 1);
	assert_int_equal(weld(pos, N, 0.0, remap), vn_result_success);
	assert_int_equal(distinct_groups(remap, N), N);
	free(remap);
	free(pos);
}

/* The smallest epsilon, 2^-1074, also welds adjacent subnormals, but integer
 * coordinates are equal or 1 apart: there the grids must weld exactly what
 * epsilon 0 does. A G x G quad mesh stored quad by quad, corners (0, 0),
 * (1, 0), (1, 1), (0, 1), as files split it; z is +0 or -0. */
static void weld_exact_agrees_with_grid(void** state)
{
	(void)state;
	enum { G = 16, NV = 4 * G * G };
	double pos[3 * NV];
	for (int q = 0; q < G * G; ++q)
		for (int k = 0; k < 4; ++k) {
			double* p = pos + 3 * (4 * q + k);
			p[0] = q % G + (k == 1 || k == 2) - 8, p[1] = 3 * (q / G + (k >= 2)), p[2] = k & 1 ? -0.0 : 0.0;
		}
	uint32_t exact[NV], grid[NV];
	assert_int_equal(weld(pos, NV, 0.0, exact), vn_result_success);
	assert_int_equal(weld(pos, NV, 4.9406564584124654e-324, grid), vn_result_success);
	assert_remap(grid, exact, NV);
	assert_int_equal(distinct_groups(exact, NV), (G + 1) * (G + 1));
	/* Quad 1's first corner is quad 0's second; quad G + 1's is quad 0's third. */
	assert_int_equal(exact[4], 1);
	assert_int_equal(exact[4 * (G + 1)], 2);
}

/* ---------------------------------------------------------------- corner normals: a cube */

/* The unit cube, two outward triangles a face, faces -z, +z, -y, +y, -x, +x. */
static const double cube_pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t cube_idx[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                    3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
static const double cube_face[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}};

/* Crease 30 degrees: every edge is sharp, every corner gets its face's normal. */
static void cube_crease_30(void** state)
{
	(void)state;
	for (unsigned m = 0; m < vn_method_mewcsa; ++m) {
		double out[36 * 3];
		vn_stats st;
		assert_int_equal(corners(cube_pos, 8, cube_idx, 36, (vn_method)m, DEG30, NULL, out, &st), vn_result_success);
		for (int c = 0; c < 36; ++c) {
			const double* f = cube_face[c / 6];
			assert_vec(out + 3 * c, f[0], f[1], f[2], 0.0);
		}
		assert_int_equal(st.faces, 12);
		assert_int_equal(st.degenerate_faces, 0);
		assert_int_equal(st.zero_normals, 0);
	}
}

/* MEWCSA per wedge: the area gradient of the face's part around the vertex,
 * which lies in the face. At vertex 0 of face -z, triangles (0,2,1), (0,3,2):
 * (p2 - p1) x N + (p3 - p2) x N = (-1, 0, 0) + (0, -1, 0); at vertex 1,
 * only (0,2,1): (p0 - p2) x N = (1, -1, 0). */
static void cube_mewcsa_per_wedge(void** state)
{
	(void)state;
	double out[36 * 3];
	assert_int_equal(corners(cube_pos, 8, cube_idx, 36, vn_method_mewcsa, DEG30, NULL, out, NULL), vn_result_success);
	assert_vec(out + 0, -0.7071067811865476, -0.7071067811865476, 0, 1e-15); /* corner 0: vertex 0 */
	assert_vec(out + 3 * 3, -0.7071067811865476, -0.7071067811865476, 0, 1e-15);
	assert_vec(out + 3 * 2, 0.7071067811865476, -0.7071067811865476, 0, 1e-15); /* corner 2: vertex 1 */
	/* Vertex 0 on face -y, triangles (0,1,5), (0,5,4): (p1 - p4) x (0,-1,0) = (-1, 0, -1) summed. */
	assert_vec(out + 3 * 12, -0.7071067811865476, 0, -0.7071067811865476, 1e-15);
	assert_same(out + 3 * 12, out + 3 * 15);
}

/* Crease pi (or more) and no flags on a closed manifold mesh: every corner
 * gets its vertex's vn_triangle_normals normal, bit for bit. */
static void check_matches_vertex_normals(const double* pos, size_t nv, const uint32_t* idx, size_t ni, double crease)
{
	double* vert = (double*)malloc(sizeof(double) * 3 * nv);
	double* corner = (double*)malloc(sizeof(double) * 3 * ni);
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors ov = {vert, 0, vn_scalar_float64}, oc = {corner, 0, vn_scalar_float64};
	for (int simd = 0; simd < 2; ++simd) {
		vn_options o;
		memset(&o, 0, sizeof(o));
		o.simd = simd ? vn_simd_auto : vn_simd_off;
		for (unsigned m = 0; m < vn_method_count; ++m) {
			vn_stats sv, sc;
			assert_int_equal(vn_triangle_normals(&ov, &p, idx, ni, (vn_method)m, &o, &sv), vn_result_success);
			assert_int_equal(vn_corner_normals(&oc, &p, idx, ni, (vn_method)m, crease, NULL, &o, &sc),
			                 vn_result_success);
			for (size_t c = 0; c < ni; ++c)
				assert_same(corner + 3 * c, vert + 3 * (size_t)idx[c]);
			assert_int_equal(sc.faces, sv.faces);
			assert_int_equal(sc.degenerate_faces, sv.degenerate_faces);
		}
	}
	free(corner);
	free(vert);
}

static void cube_crease_pi(void** state)
{
	(void)state;
	check_matches_vertex_normals(cube_pos, 8, cube_idx, 36, PI);
	check_matches_vertex_normals(cube_pos, 8, cube_idx, 36, INFINITY);
}

/* A larger closed mesh (the paper's torus, 2304 triangles, float64). */
static void torus_crease_pi(void** state)
{
	(void)state;
	vn_model_mesh mesh;
	assert_int_equal(vn_model_generate(vn_model_torus_tp, vn_resolution_medium, NULL, &mesh), vn_result_success);
	check_matches_vertex_normals(mesh.positions, mesh.vertex_count, mesh.indices, 3 * mesh.triangle_count, PI);
	vn_model_free(&mesh, NULL);
}

/* ---------------------------------------------------------------- corner normals: a folded strip
 *
 * Cross-section (x, z) P0..P4 = (0, 0), (1, 0), (2, 0.125), (2.125, 1.125),
 * (2.375, 2.125), swept from y = 0 (vertices 0..4) to y = 1 (5..9). Segment
 * i is the quad (i, i+1, i+6, i+5) as triangles 2i = (i, i+1, i+6) and
 * 2i+1 = (i, i+6, i+5); unit normals
 *   u0 = (0, 0, 1), u1 ~ (-0.125, 0, 1), u2 ~ (-1, 0, 0.125), u3 ~ (-1, 0, 0.25).
 * Folds: 7.1 degrees at P1, 75.7 at P2, 7.0 at P3. */
static const double strip_pos[] = {0,    0, 0,     1,     0, 0,     2, 0, 0.125, 2.125, 0, 1.125, 2.375, 0, 2.125,
                                   0,    1, 0,     1,     1, 0,     2, 1, 0.125, 2.125, 1, 1.125, 2.375, 1, 2.125};
static const uint32_t strip_idx[] = {0, 1, 6, 0, 6, 5, 1, 2, 7, 1, 7, 6, 2, 3, 8, 2, 8, 7, 3, 4, 9, 3, 9, 8};
#define U1 -0.12403473458920845, 0.0, 0.9922778767136676
#define U2 -0.9922778767136676, 0.0, 0.12403473458920845

/* Crease 45 degrees: only the fold at P2 is hard. */
static void strip_smooth_and_hard(void** state)
{
	(void)state;
	double out[24 * 3];
	assert_int_equal(corners(strip_pos, 10, strip_idx, 24, vn_method_mwe, DEG45, NULL, out, NULL), vn_result_success);
	/* Vertex 1 (corners 1, 6, 9): one wedge, u0 + 2 u1. */
	assert_vec(out + 3 * 1, -0.08283208736036259, 0, 0.9965635179473135, 1e-15);
	assert_same(out + 3 * 6, out + 3 * 1);
	assert_same(out + 3 * 9, out + 3 * 1);
	/* Vertex 2: corner 7 on segment 1's side, corners 12 and 15 on segment 2's. */
	assert_vec(out + 3 * 7, U1, 1e-15);
	assert_vec(out + 3 * 12, U2, 1e-15);
	assert_same(out + 3 * 15, out + 3 * 12);
	/* Vertex 7 likewise: corners 8, 10 | 17. */
	assert_vec(out + 3 * 8, U1, 1e-15);
	assert_same(out + 3 * 10, out + 3 * 8);
	assert_vec(out + 3 * 17, U2, 1e-15);
	/* Vertex 3 (corners 13, 18, 21): one wedge, u2 + 2 u3. */
	assert_vec(out + 3 * 13, -0.9791032102184772, 0, 0.20336396863720066, 1e-15);
	assert_same(out + 3 * 18, out + 3 * 13);
	assert_same(out + 3 * 21, out + 3 * 13);
	/* Vertex 0, on segment 0 alone. */
	assert_vec(out + 0, 0, 0, 1, 0);
	assert_same(out + 3 * 3, out);
	/* Crease 0: the 7-degree folds split too; a quad's two coplanar triangles do not. */
	assert_int_equal(corners(strip_pos, 10, strip_idx, 24, vn_method_mwe, 0.0, NULL, out, NULL), vn_result_success);
	assert_vec(out + 3 * 1, 0, 0, 1, 0);
	assert_vec(out + 3 * 6, U1, 1e-15);
	assert_same(out + 3 * 9, out + 3 * 6);
}

/* MWA, no crease: vertex 1's faces weigh pi/2 on either side of the P1 fold,
 * so its normal is the bisector of u0 and u1. Flagging the edge 1-6 (from
 * either of its two corners) splits vertex 1 and vertex 6 into u0 | u1. */
static void strip_sharp_flags(void** state)
{
	(void)state;
	double out[24 * 3];
	assert_int_equal(corners(strip_pos, 10, strip_idx, 24, vn_method_mwa, PI, NULL, out, NULL), vn_result_success);
	for (int i = 0; i < 3; ++i) /* corners 1, 6, 9 */
		assert_vec(out + 3 * (i ? 3 * i + 3 : 1), -0.06213744155632878, 0, 0.9980676020975903, 1e-15);

	/* Corner 1 is vertex 1 of triangle 0, whose edge 1 -> 6 it is; corner
	 * 11 is vertex 6 of triangle 3, edge 6 -> 1. */
	for (int side = 0; side < 2; ++side) {
		uint8_t sharp[24] = {0};
		sharp[side ? 11 : 1] = 1;
		assert_int_equal(corners(strip_pos, 10, strip_idx, 24, vn_method_mwa, PI, sharp, out, NULL),
		                 vn_result_success);
		assert_vec(out + 3 * 1, 0, 0, 1, 1e-15);  /* vertex 1, triangle 0 */
		assert_vec(out + 3 * 6, U1, 1e-15);       /* vertex 1, triangles 2 and 3 */
		assert_same(out + 3 * 9, out + 3 * 6);
		assert_vec(out + 3 * 2, 0, 0, 1, 1e-15);  /* vertex 6, triangles 0 and 1 */
		assert_same(out + 3 * 4, out + 3 * 2);
		assert_vec(out + 3 * 11, U1, 1e-15);      /* vertex 6, triangle 3 */
		/* The flag splits nothing else: vertex 2 keeps both its segments. */
		assert_same(out + 3 * 7, out + 3 * 12);
	}
}

/* ---------------------------------------------------------------- corner normals: topology */

/* An open fan (three quarters of a ring around vertex 0, tilted faces): the
 * boundary edges end the fan but split nothing, so vertex 0 is one wedge
 * with vn_triangle_normals' normal. Two triangles that share only vertex 0
 * (a bow tie) are two wedges. */
static void boundary_edges(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0.5, 0, 1, 0, -1, 0, 0.25, 0, -1, 0};
	const uint32_t fan[] = {0, 1, 2, 0, 2, 3, 0, 3, 4};
	double out[9 * 3], vert[5 * 3];
	const vn_positions p = {pos, 5, 0, vn_scalar_float64};
	const vn_vectors ov = {vert, 0, vn_scalar_float64};
	assert_int_equal(vn_triangle_normals(&ov, &p, fan, 9, vn_method_mwa, NULL, NULL), vn_result_success);
	assert_int_equal(corners(pos, 5, fan, 9, vn_method_mwa, PI, NULL, out, NULL), vn_result_success);
	for (int t = 0; t < 3; ++t)
		assert_same(out + 9 * t, vert);

	const double bow_pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, 0, 1};
	const uint32_t bow[] = {0, 1, 2, 0, 3, 4};
	assert_int_equal(corners(bow_pos, 5, bow, 6, vn_method_mwe, PI, NULL, out, NULL), vn_result_success);
	assert_vec(out, 0, 0, 1, 0);
	assert_vec(out + 9, 0, 1, 0, 0);
}

/* Three triangles on edge 0-1 (normals (0,0,1), (0,1,2)/sqrt 5, (0,1,0)):
 * the edge is sharp, so each corner at vertex 0 keeps its face's normal.
 * Two triangles using 0 -> 1 in the same direction: sharp too. */
static void nonmanifold_edges(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0.5, 0.5, 0, 1, 0.5, -1, 0.5};
	const uint32_t three[] = {0, 1, 2, 1, 0, 3, 1, 0, 4};
	double out[9 * 3];
	assert_int_equal(corners(pos, 6, three, 9, vn_method_mwe, PI, NULL, out, NULL), vn_result_success);
	assert_vec(out + 0, 0, 0, 1, 1e-15);
	assert_vec(out + 3 * 4, 0, 0.4472135954999579, 0.8944271909999159, 1e-15);
	assert_vec(out + 3 * 7, 0, 1, 0, 1e-15);
	const uint32_t same_way[] = {0, 1, 2, 0, 1, 5};
	assert_int_equal(corners(pos, 6, same_way, 6, vn_method_mwe, PI, NULL, out, NULL), vn_result_success);
	assert_vec(out + 0, 0, 0, 1, 1e-15);
	assert_vec(out + 3 * 3, 0, -0.4472135954999579, -0.8944271909999159, 1e-15);
	/* Reversing the second makes the pair manifold: one wedge at vertex 0. */
	const uint32_t opposite[] = {0, 1, 2, 1, 0, 3};
	assert_int_equal(corners(pos, 6, opposite, 6, vn_method_mwe, PI, NULL, out, NULL), vn_result_success);
	assert_same(out, out + 3 * 4);
}

/* The cube plus (0, 1, 1), a triangle with a repeated index: its corners
 * get their vertex's normal over all its faces, (-1,-1,-1)/sqrt 3 at vertex
 * 0 and (2,-1,-1)/sqrt 6 at vertex 1 (MWE), although crease 30 splits the
 * real corners by face. It joins nothing: edge 0-1 stays manifold. */
static void repeated_index_gets_vertex_normal(void** state)
{
	(void)state;
	uint32_t idx[39];
	memcpy(idx, cube_idx, sizeof(cube_idx));
	idx[36] = 0, idx[37] = 1, idx[38] = 1;
	double out[39 * 3];
	vn_stats st;
	assert_int_equal(corners(cube_pos, 8, idx, 39, vn_method_mwe, DEG30, NULL, out, &st), vn_result_success);
	assert_vec(out + 3 * 36, -0.5773502691896257, -0.5773502691896257, -0.5773502691896257, 1e-15);
	assert_vec(out + 3 * 37, 0.816496580927726, -0.408248290463863, -0.408248290463863, 1e-15);
	assert_same(out + 3 * 38, out + 3 * 37);
	for (int c = 0; c < 36; ++c)
		assert_vec(out + 3 * c, cube_face[c / 6][0], cube_face[c / 6][1], cube_face[c / 6][2], 0.0);
	assert_int_equal(st.faces, 13);
	assert_int_equal(st.degenerate_faces, 1);
	assert_int_equal(st.zero_normals, 0);
}

/* A flat square (0,1,2), (0,2,3) with a zero-area sliver (0, 4, 1), 4 on
 * edge 0-1, and a triangle with a NaN vertex 5: both contribute nothing;
 * vertices 4 and 5 have no usable face, so their corners are zero. */
static void zero_area_and_nonfinite(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0, 0, NAN, 0, 0};
	const uint32_t idx[] = {0, 1, 2, 0, 2, 3, 0, 4, 1, 2, 5, 3};
	for (unsigned m = 0; m < vn_method_mewcsa; ++m) {
		double out[12 * 3];
		vn_stats st;
		assert_int_equal(corners(pos, 6, idx, 12, (vn_method)m, PI, NULL, out, &st), vn_result_success);
		for (int c = 0; c < 12; ++c)
			if (c == 7 || c == 10)
				assert_vec(out + 3 * c, 0, 0, 0, 0);
			else
				assert_vec(out + 3 * c, 0, 0, 1, 1e-15);
		assert_int_equal(st.faces, 4);
		assert_int_equal(st.degenerate_faces, 2);
		assert_int_equal(st.zero_normals, 2);
		assert_int_equal(st.nonfinite_vertices, 1);
	}
}

static void index_out_of_range_writes_nothing(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
	double out[6 * 3];
	for (int i = 0; i < 18; ++i)
		out[i] = 42.0;
	assert_int_equal(corners(pos, 3, idx, 6, vn_method_mwe, PI, NULL, out, NULL), vn_result_index_out_of_range);
	for (int i = 0; i < 18; ++i)
		assert_true(out[i] == 42.0);
	assert_int_equal(corners(NULL, 0, idx, 3, vn_method_mwe, PI, NULL, out, NULL), vn_result_index_out_of_range);
}

static void corner_invalid_arguments(void** state)
{
	(void)state;
	double out[9];
	const vn_positions p = {cube_pos, 8, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	assert_int_equal(vn_corner_normals(NULL, &p, cube_idx, 3, vn_method_mwe, PI, NULL, NULL, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_corner_normals(&o, NULL, cube_idx, 3, vn_method_mwe, PI, NULL, NULL, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_corner_normals(&o, &p, NULL, 3, vn_method_mwe, PI, NULL, NULL, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_corner_normals(&o, &p, cube_idx, 4, vn_method_mwe, PI, NULL, NULL, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_corner_normals(&o, &p, cube_idx, 3, vn_method_mwe, -0.1, NULL, NULL, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_corner_normals(&o, &p, cube_idx, 3, vn_method_mwe, NAN, NULL, NULL, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_corner_normals(&o, &p, cube_idx, 3, vn_method_count, PI, NULL, NULL, NULL),
	                 vn_result_unknown_method);
	const vn_vectors narrow = {out, 8, vn_scalar_float32};
	assert_int_equal(vn_corner_normals(&narrow, &p, cube_idx, 3, vn_method_mwe, PI, NULL, NULL, NULL),
	                 vn_result_invalid_argument);
	const vn_vectors no_data = {NULL, 0, vn_scalar_float64};
	assert_int_equal(vn_corner_normals(&no_data, &p, cube_idx, 3, vn_method_mwe, PI, NULL, NULL, NULL),
	                 vn_result_invalid_argument);
	vn_options bad;
	memset(&bad, 0, sizeof(bad));
	bad.simd = (vn_simd)5;
	assert_int_equal(vn_corner_normals(&o, &p, cube_idx, 3, vn_method_mwe, PI, NULL, &bad, NULL),
	                 vn_result_invalid_argument);
	/* No triangles: nothing to write, output may be NULL. */
	vn_stats st;
	assert_int_equal(vn_corner_normals(&no_data, &p, NULL, 0, vn_method_mwe, PI, NULL, NULL, &st),
	                 vn_result_success);
	assert_int_equal(st.faces, 0);
}

/* Padded float32 positions in, strided float32 out: the padding stays. */
static void corner_types_and_strides(void** state)
{
	(void)state;
	float pos[8 * 4];
	for (int v = 0; v < 8; ++v)
		for (int a = 0; a < 4; ++a)
			pos[4 * v + a] = a < 3 ? (float)cube_pos[3 * v + a] : 99.0f;
	float out[36 * 4];
	for (int i = 0; i < 36 * 4; ++i)
		out[i] = -7.0f;
	const vn_positions p = {pos, 8, 4 * sizeof(float), vn_scalar_float32};
	const vn_vectors o = {out, 4 * sizeof(float), vn_scalar_float32};
	assert_int_equal(vn_corner_normals(&o, &p, cube_idx, 36, vn_method_mwselr, DEG30, NULL, NULL, NULL),
	                 vn_result_success);
	for (int c = 0; c < 36; ++c) {
		for (int a = 0; a < 3; ++a)
			assert_true(out[4 * c + a] == (float)cube_face[c / 6][a]);
		assert_true(out[4 * c + 3] == -7.0f);
	}
}

static void corner_allocator(void** state)
{
	(void)state;
	double out[36 * 3];
	const vn_positions p = {cube_pos, 8, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	counting c = {0, 0, -1};
	const vn_options opt = counting_options(&c);
	assert_int_equal(vn_corner_normals(&o, &p, cube_idx, 36, vn_method_mwe, DEG30, NULL, &opt, NULL),
	                 vn_result_success);
	assert_true(c.allocations > 0);
	assert_int_equal(c.allocations, c.frees);
	/* Fail each allocation in turn: out of memory, nothing written, nothing leaked. */
	const int total = c.allocations;
	for (int k = 0; k < total; ++k) {
		counting f = {0, 0, k};
		const vn_options fail = counting_options(&f);
		out[0] = 42.0;
		assert_int_equal(vn_corner_normals(&o, &p, cube_idx, 36, vn_method_mwe, DEG30, NULL, &fail, NULL),
		                 vn_result_out_of_memory);
		assert_true(out[0] == 42.0);
		assert_int_equal(f.allocations, f.frees);
	}
}

/* ---------------------------------------------------------------- the intended use: a UV seam */

/* A UV sphere stored split along its seam and poles: welded, its corner
 * normals with crease 60 degrees give both copies of every seam vertex (and
 * every pole copy) one normal, the closed sphere's vertex normal, bit for
 * bit. Unwelded, the seam shows: the two copies differ. */
static void uv_seam_welded(void** state)
{
	(void)state;
	double pos[3 * SPH_SPLIT], closed_pos[3 * SPH_CLOSED];
	uint32_t idx[6 * SPH_R * SPH_S], closed_idx[6 * SPH_R * SPH_S], closed_id[SPH_SPLIT], remap[SPH_SPLIT];
	const size_t ni = uv_sphere(1, pos, idx, closed_id);
	const size_t closed_ni = uv_sphere(0, closed_pos, closed_idx, NULL);
	assert_int_equal(ni, 6 * SPH_R * SPH_S);
	assert_int_equal(closed_ni, 6 * SPH_S * (SPH_R - 1));
	assert_int_equal(weld(pos, SPH_SPLIT, 1e-9, remap), vn_result_success);
	uint32_t welded[6 * SPH_R * SPH_S];
	for (size_t i = 0; i < ni; ++i)
		welded[i] = remap[idx[i]];

	double out[6 * SPH_R * SPH_S * 3], vert[3 * SPH_CLOSED];
	const vn_positions cp = {closed_pos, SPH_CLOSED, 0, vn_scalar_float64};
	const vn_vectors ov = {vert, 0, vn_scalar_float64};
	for (unsigned m = 0; m < SEVEN; ++m) {
		vn_stats st;
		assert_int_equal(vn_triangle_normals(&ov, &cp, closed_idx, closed_ni, (vn_method)m, NULL, NULL),
		                 vn_result_success);
		assert_int_equal(corners(pos, SPH_SPLIT, welded, ni, (vn_method)m, DEG60, NULL, out, &st),
		                 vn_result_success);
		assert_int_equal(st.degenerate_faces, 2 * SPH_S); /* the collapsed pole triangles */
		for (size_t c = 0; c < ni; ++c)
			assert_same(out + 3 * c, vert + 3 * (size_t)closed_id[idx[c]]);
	}
	/* Unwelded: corner 1 is (1, 0) of triangle 0 (column 0), corner 68 is
	 * its seam copy (1, 12) of triangle 22 (column 11). */
	assert_int_equal(idx[1], SPH_S + 1);
	assert_int_equal(idx[68], 2 * (SPH_S + 1) - 1);
	assert_int_equal(corners(pos, SPH_SPLIT, idx, ni, vn_method_mwa, DEG60, NULL, out, NULL), vn_result_success);
	assert_true(fabs(out[3 * 1 + 1] - out[3 * 68 + 1]) > 0.1);
}

/* ---------------------------------------------------------------- polygon corner normals */

/* vn_polygon_corner_normals, or vn_corner_normals when off is NULL (nf
 * triangles), with face strengths (NULL: none). */
static vn_result scorners(const double* pos, size_t nv, const uint32_t* idx, const uint32_t* off, size_t nf,
                          vn_method m, double crease, const uint8_t* sharp, const int32_t* strength, unsigned threads,
                          double* out)
{
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	vn_options opt;
	memset(&opt, 0, sizeof(opt));
	opt.threads = threads;
	opt.face_strength = strength;
	return off ? vn_polygon_corner_normals(&o, &p, idx, off, nf, m, crease, sharp, &opt, NULL)
	           : vn_corner_normals(&o, &p, idx, 3 * nf, m, crease, sharp, &opt, NULL);
}

static vn_result pcorners(const double* pos, size_t nv, const uint32_t* idx, const uint32_t* off, size_t nf,
                          vn_method m, double crease, const uint8_t* sharp, unsigned threads, double* out,
                          vn_stats* st)
{
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	vn_options opt;
	memset(&opt, 0, sizeof(opt));
	opt.threads = threads;
	return vn_polygon_corner_normals(&o, &p, idx, off, nf, m, crease, sharp, &opt, st);
}

/* The unit cube as six outward quads: -z, +z, -y, +y, -x, +x. */
static const uint32_t qcube_idx[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 3, 7, 6, 2, 0, 4, 7, 3, 1, 2, 6, 5};
static const uint32_t qcube_off[] = {0, 4, 8, 12, 16, 20, 24};

/* Every edge flagged, or crease 30 degrees: each corner gets its face's
 * normal; with nothing sharp, the cube's vertex normal (+-1, +-1, +-1)/sqrt 3
 * for every face-normal scheme (all weights are equal on a cube). */
static void poly_cube(void** state)
{
	(void)state;
	uint8_t all[24];
	memset(all, 1, sizeof(all));
	for (unsigned m = 0; m < vn_method_mewcsa; ++m)
		for (int mode = 0; mode < 3; ++mode) {
			double out[24 * 3];
			vn_stats st;
			assert_int_equal(pcorners(cube_pos, 8, qcube_idx, qcube_off, 6, (vn_method)m, mode == 1 ? DEG30 : PI,
			                          mode == 0 ? all : NULL, 1, out, &st),
			                 vn_result_success);
			for (int c = 0; c < 24; ++c) {
				if (mode < 2) {
					const double* f = cube_face[c / 4];
					assert_vec(out + 3 * c, f[0], f[1], f[2], 1e-15);
				} else {
					const double* p = cube_pos + 3 * qcube_idx[c];
					const double k = 0.5773502691896258;
					assert_vec(out + 3 * c, p[0] ? k : -k, p[1] ? k : -k, p[2] ? k : -k, 1e-15);
				}
			}
			assert_int_equal(st.faces, 6);
			assert_int_equal(st.degenerate_faces, 0);
			assert_int_equal(st.zero_normals, 0);
		}
}

/* Two quads hinged at edge 1-2: A = (0,1,2,3) in z = 0 (normal +z), B =
 * (1,4,5,2) in x = 1 (normal -x), 90 degrees apart. MWE: vertices 1 and 2
 * get (-1, 0, 1)/sqrt 2 in both faces unless the edge is flagged (from
 * either side: corner 1 is A's 1 -> 2, corner 7 is B's 2 -> 1) or the crease
 * angle is below 90 degrees. */
static const double hinge_pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 1, 1, 1, 1};
static const uint32_t hinge_idx[] = {0, 1, 2, 3, 1, 4, 5, 2};
static const uint32_t hinge_off[] = {0, 4, 8};

static void poly_hinge(void** state)
{
	(void)state;
	const double h = 0.7071067811865475;
	double out[8 * 3];
	assert_int_equal(pcorners(hinge_pos, 6, hinge_idx, hinge_off, 2, vn_method_mwe, PI, NULL, 1, out, NULL),
	                 vn_result_success);
	for (int c = 0; c < 8; ++c) {
		const int joint = hinge_idx[c] == 1 || hinge_idx[c] == 2;
		if (joint)
			assert_vec(out + 3 * c, -h, 0, h, 1e-15);
		else if (c < 4)
			assert_vec(out + 3 * c, 0, 0, 1, 0);
		else
			assert_vec(out + 3 * c, -1, 0, 0, 0);
	}
	assert_int_equal(pcorners(hinge_pos, 6, hinge_idx, hinge_off, 2, vn_method_mwe, 1.6, NULL, 1, out, NULL),
	                 vn_result_success);
	assert_vec(out + 3 * 1, -h, 0, h, 1e-15);
	for (int mode = 0; mode < 3; ++mode) {
		uint8_t sharp[8] = {0};
		if (mode < 2)
			sharp[mode ? 7 : 1] = 1;
		assert_int_equal(pcorners(hinge_pos, 6, hinge_idx, hinge_off, 2, vn_method_mwe, mode == 2 ? 1.5 : PI,
		                          mode < 2 ? sharp : NULL, 1, out, NULL),
		                 vn_result_success);
		for (int c = 0; c < 8; ++c)
			if (c < 4)
				assert_vec(out + 3 * c, 0, 0, 1, 0);
			else
				assert_vec(out + 3 * c, -1, 0, 0, 0);
	}
	/* A flag on another edge (A's 0 -> 1, a boundary already) splits nothing. */
	uint8_t other[8] = {1, 0, 0, 0, 0, 0, 0, 0};
	assert_int_equal(pcorners(hinge_pos, 6, hinge_idx, hinge_off, 2, vn_method_mwe, PI, other, 1, out, NULL),
	                 vn_result_success);
	assert_vec(out + 3 * 2, -h, 0, h, 1e-15);
}

/* A closed torus of U x V cells: most quads, some split into two
 * triangles, and pairs of pentagons sharing an edge with a midpoint vertex
 * inserted. Positions jittered deterministically. Returns the face count;
 * pos needs 3 (U V + U V) doubles, idx 6 U V, off U V + ... (2 U V + 1). */
#define TU 12
#define TV 10
static size_t mixed_torus(int U, int V, uint32_t seed, double* pos, size_t* nv, uint32_t* idx, uint32_t* off)
{
	const double R = 1.0, r = 0.4;
	for (int i = 0; i < U; ++i)
		for (int j = 0; j < V; ++j) {
			const double ju = (double)(next_random(&seed) % 1000) / 1000.0 - 0.5;
			const double jv = (double)(next_random(&seed) % 1000) / 1000.0 - 0.5;
			const double u = 2 * PI * (i + 0.4 * ju) / U, v = 2 * PI * (j + 0.4 * jv) / V;
			double* p = pos + 3 * (size_t)(i * V + j);
			p[0] = (R + r * cos(v)) * cos(u), p[1] = (R + r * cos(v)) * sin(u), p[2] = r * sin(v);
		}
	/* Midpoint m(i, j) on the edge between cells (i, j) and (i, j + 1), for
	 * j % 4 == 0 and i % 3 == 0. */
	size_t n = (size_t)U * V;
	uint32_t* mid = (uint32_t*)malloc(sizeof(uint32_t) * (size_t)U * V);
#define VID(a, b) ((uint32_t)((((a) + U) % U) * V + (((b) + V) % V)))
	for (int i = 0; i < U; ++i)
		for (int j = 0; j < V; ++j) {
			mid[i * V + j] = UINT32_MAX;
			if (j % 4 == 0 && i % 3 == 0 && V % 4 == 2 - 2 + (V % 4)) {
				const double* a = pos + 3 * (size_t)VID(i, j + 1);
				const double* b = pos + 3 * (size_t)VID(i + 1, j + 1);
				for (int k = 0; k < 3; ++k)
					pos[3 * n + k] = 0.5 * (a[k] + b[k]) * (k == 2 ? 1.0 : 1.01);
				mid[i * V + j] = (uint32_t)n++;
			}
		}
	size_t f = 0, c = 0;
	off[0] = 0;
	for (int i = 0; i < U; ++i)
		for (int j = 0; j < V; ++j) {
			const uint32_t below = mid[i * V + (j + V - 1) % V], above = mid[i * V + j];
			const uint32_t v00 = VID(i, j), v10 = VID(i + 1, j), v11 = VID(i + 1, j + 1), v01 = VID(i, j + 1);
			if (below == UINT32_MAX && above == UINT32_MAX && (i + 2 * j) % 5 == 0) {
				const uint32_t t[6] = {v00, v10, v11, v00, v11, v01};
				memcpy(idx + c, t, sizeof(t));
				c += 6, off[++f] = (uint32_t)(c - 3), off[++f] = (uint32_t)c;
				continue;
			}
			idx[c++] = v00;
			if (below != UINT32_MAX)
				idx[c++] = below;
			idx[c++] = v10, idx[c++] = v11;
			if (above != UINT32_MAX)
				idx[c++] = above;
			idx[c++] = v01;
			off[++f] = (uint32_t)c;
		}
#undef VID
	free(mid);
	*nv = n;
	return f;
}

/* Nothing sharp on a closed mesh of triangles, quads and pentagons: every
 * corner gets its vertex's vn_polygon_normals normal, bit for bit. */
static void poly_matches_vertex_normals(void** state)
{
	(void)state;
	double pos[3 * 2 * TU * TV], vert[3 * 2 * TU * TV], out[3 * 6 * TU * TV];
	uint32_t idx[6 * TU * TV], off[2 * TU * TV + 1];
	size_t nv;
	const size_t nf = mixed_torus(TU, TV, 7, pos, &nv, idx, off);
	int sizes[6] = {0};
	for (size_t f = 0; f < nf; ++f)
		sizes[off[f + 1] - off[f]]++;
	assert_true(sizes[3] > 0 && sizes[4] > 0 && sizes[5] > 0);
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors ov = {vert, 0, vn_scalar_float64};
	for (unsigned m = 0; m < vn_method_count; ++m)
		for (unsigned threads = 1; threads <= 3; threads += 2) {
			vn_stats st;
			assert_int_equal(vn_polygon_normals(&ov, &p, idx, off, nf, (vn_method)m, NULL, NULL), vn_result_success);
			assert_int_equal(pcorners(pos, nv, idx, off, nf, (vn_method)m, PI, NULL, threads, out, &st),
			                 vn_result_success);
			for (size_t c = 0; c < off[nf]; ++c)
				assert_same(out + 3 * c, vert + 3 * (size_t)idx[c]);
			assert_int_equal(st.faces, nf);
			assert_int_equal(st.degenerate_faces, 0);
		}
}

/* An independent brute force: corners at one vertex are joined when some
 * edge of the vertex, found by scanning every corner of the mesh, has
 * exactly two uses in opposite directions, one the out edge of the one
 * corner and the other the in edge of the other, is not flagged and its
 * faces' normals are at most crease apart (acos), or when the two are
 * consecutive corners of one face at the same vertex. Contributions from
 * the paper's definitions, in long double; with strengths (not NULL), only
 * those of the group's strongest faces. */
static void brute_newell(const double* pos, const uint32_t* face, uint32_t k, long double n[3])
{
	n[0] = n[1] = n[2] = 0;
	for (uint32_t i = 0; i < k; ++i) {
		const double* a = pos + 3 * (size_t)face[i];
		const double* b = pos + 3 * (size_t)face[(i + 1) % k];
		n[0] += (long double)a[1] * b[2] - (long double)a[2] * b[1];
		n[1] += (long double)a[2] * b[0] - (long double)a[0] * b[2];
		n[2] += (long double)a[0] * b[1] - (long double)a[1] * b[0];
	}
	const long double l = sqrtl(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	n[0] /= l, n[1] /= l, n[2] /= l;
}

static void brute_corner_normals(const double* pos, const uint32_t* idx, const uint32_t* off, size_t nf, int method,
                                 double crease, const uint8_t* sharp, const int32_t* strength, double* out)
{
	const size_t n = off[nf];
	uint32_t* fof = (uint32_t*)malloc(sizeof(uint32_t) * n);
	uint32_t* nxt = (uint32_t*)malloc(sizeof(uint32_t) * n);
	uint32_t* prv = (uint32_t*)malloc(sizeof(uint32_t) * n);
	uint32_t* grp = (uint32_t*)malloc(sizeof(uint32_t) * n);
	long double* fn = (long double*)malloc(sizeof(long double) * 3 * nf);
	for (size_t f = 0; f < nf; ++f) {
		brute_newell(pos, idx + off[f], off[f + 1] - off[f], fn + 3 * f);
		for (uint32_t c = off[f]; c < off[f + 1]; ++c) {
			fof[c] = (uint32_t)f;
			nxt[c] = c + 1 == off[f + 1] ? off[f] : c + 1;
			prv[c] = c == off[f] ? off[f + 1] - 1 : c - 1;
		}
	}
	for (size_t c = 0; c < n; ++c)
		grp[c] = (uint32_t)c;
	for (size_t a = 0; a < n; ++a)
		for (size_t b = 0; b < n; ++b) {
			if (idx[a] != idx[b] || a == b)
				continue;
			int join = nxt[a] == b; /* consecutive corners at one vertex */
			const uint32_t v = idx[a], w = idx[nxt[a]];
			if (!join && w != v && idx[prv[b]] == w) {
				/* a: v -> w; b: w -> v. Count every use of edge {v, w}. */
				int uses = 0;
				for (size_t c = 0; c < n; ++c)
					uses += (idx[c] == v && idx[nxt[c]] == w) || (idx[c] == w && idx[nxt[c]] == v);
				const long double* na = fn + 3 * fof[a];
				const long double* nb = fn + 3 * fof[b];
				long double d = na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2];
				d = d > 1 ? 1 : d < -1 ? -1 : d;
				join = uses == 2 && !(sharp && (sharp[a] || sharp[prv[b]])) && acosl(d) <= crease;
			}
			if (join) { /* merge groups: relabel to the lower */
				const uint32_t ga = grp[a], gb = grp[b], lo = ga < gb ? ga : gb, hi = ga < gb ? gb : ga;
				for (size_t c = 0; c < n; ++c)
					if (grp[c] == hi)
						grp[c] = lo;
			}
		}
	for (size_t c = 0; c < n; ++c) {
		long double s[3] = {0, 0, 0};
		int32_t top = INT32_MIN;
		for (size_t d = 0; d < n; ++d)
			if (grp[d] == grp[c] && strength && strength[fof[d]] > top)
				top = strength[fof[d]];
		for (size_t d = 0; d < n; ++d) {
			if (grp[d] != grp[c] || (strength && strength[fof[d]] != top))
				continue;
			const double* p = pos + 3 * (size_t)idx[d];
			const double* pp = pos + 3 * (size_t)idx[prv[d]];
			const double* pn = pos + 3 * (size_t)idx[nxt[d]];
			long double e[3], e2[3], x[3];
			for (int i = 0; i < 3; ++i)
				e[i] = (long double)pp[i] - p[i], e2[i] = (long double)pn[i] - p[i];
			x[0] = e[1] * e2[2] - e[2] * e2[1], x[1] = e[2] * e2[0] - e[0] * e2[2], x[2] = e[0] * e2[1] - e[1] * e2[0];
			const long double le = sqrtl(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
			const long double le2 = sqrtl(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
			const long double lx = sqrtl(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
			const long double* N = fn + 3 * fof[d];
			if (le == 0 || le2 == 0)
				continue;
			if (method == vn_method_mewcsa) {
				const long double q[3] = {e2[0] - e[0], e2[1] - e[1], e2[2] - e[2]};
				s[0] += q[1] * N[2] - q[2] * N[1], s[1] += q[2] * N[0] - q[0] * N[2], s[2] += q[0] * N[1] - q[1] * N[0];
				continue;
			}
			const long double dot = e[0] * e2[0] + e[1] * e2[1] + e[2] * e2[2];
			const long double wts[6] = {1, atan2l(lx, dot), lx / (le * le * le2 * le2), lx, 1 / (le * le2),
			                            1 / sqrtl(le * le2)};
			for (int i = 0; i < 3; ++i)
				s[i] += wts[method] * N[i];
		}
		const long double l = sqrtl(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
		for (int i = 0; i < 3; ++i)
			out[3 * c + i] = l > 0 ? (double)(s[i] / l) : 0.0;
	}
	free(fn);
	free(grp);
	free(prv);
	free(nxt);
	free(fof);
}

/* The mixed torus with a few faces removed (boundaries), random flags and
 * crease angles: the library agrees with the brute force within 1e-12. */
static void poly_matches_brute_force(void** state)
{
	(void)state;
	double pos[3 * 2 * TU * TV];
	uint32_t idx[6 * TU * TV], off[2 * TU * TV + 1];
	size_t nv;
	size_t nf = mixed_torus(TU, TV, 11, pos, &nv, idx, off);
	/* Remove faces 5, 40 and 77: shift the rest down. */
	const size_t gone[3] = {77, 40, 5};
	for (int g = 0; g < 3; ++g) {
		const size_t f = gone[g], k = off[f + 1] - off[f];
		memmove(idx + off[f], idx + off[f + 1], sizeof(uint32_t) * (off[nf] - off[f + 1]));
		for (size_t h = f; h < nf; ++h)
			off[h] = off[h + 1] - (uint32_t)k;
		--nf;
	}
	const size_t n = off[nf];
	double* out = (double*)malloc(sizeof(double) * 3 * n);
	double* want = (double*)malloc(sizeof(double) * 3 * n);
	uint8_t* sharp = (uint8_t*)malloc(n);
	uint32_t seed = 99;
	const double creases[4] = {0.3, 0.8, 1.5, PI};
	for (unsigned m = 0; m < SEVEN; ++m)
		for (int t = 0; t < 4; ++t) {
			for (size_t c = 0; c < n; ++c)
				sharp[c] = next_random(&seed) % 5 == 0;
			assert_int_equal(pcorners(pos, nv, idx, off, nf, (vn_method)m, creases[t], sharp, 1, out, NULL),
			                 vn_result_success);
			brute_corner_normals(pos, idx, off, nf, (int)m, creases[t], sharp, NULL, want);
			for (size_t c = 0; c < n; ++c)
				assert_vec(out + 3 * c, want[3 * c], want[3 * c + 1], want[3 * c + 2], 1e-12);
		}
	free(sharp);
	free(want);
	free(out);
}

/* A vertex with many corners (a closed fan of N triangles and quads around
 * vertex 0, rim jittered in height, random flags): 12 and 40 corners take
 * the star paths that a mesh's usual vertices do not; the brute force
 * agrees within 1e-12. */
static void poly_high_valence(void** state)
{
	(void)state;
	for (int big = 0; big < 2; ++big) {
		const uint32_t N = big ? 40 : 12;
		double pos[3 * (2 * 40 + 1)];
		uint32_t idx[4 * 40], off[41];
		uint32_t seed = 23 + N;
		pos[0] = pos[1] = 0, pos[2] = 1;
		for (uint32_t i = 0; i < 2 * N; ++i) { /* rim i at even angles, outer ring at odd */
			const double a = 2 * PI * (double)(i / 2) / N, rr = i % 2 ? 2.0 : 1.0;
			pos[3 + 3 * i] = rr * cos(a), pos[4 + 3 * i] = rr * sin(a);
			pos[5 + 3 * i] = 0.3 * (double)(next_random(&seed) % 1000) / 1000.0;
		}
		size_t c = 0;
		for (uint32_t i = 0; i < N; ++i) {
			const uint32_t a = 1 + 2 * i, b = 1 + 2 * ((i + 1) % N);
			off[i] = (uint32_t)c;
			idx[c++] = 0, idx[c++] = a;
			if (i % 3 == 1) /* a quad now and then */
				idx[c++] = a + 1;
			idx[c++] = b;
		}
		off[N] = (uint32_t)c;
		double out[3 * 4 * 40], want[3 * 4 * 40];
		uint8_t sharp[4 * 40];
		for (unsigned m = 0; m < SEVEN; ++m)
			for (int t = 0; t < 3; ++t) {
				for (size_t k = 0; k < c; ++k)
					sharp[k] = t == 2 && next_random(&seed) % 4 == 0;
				const double crease = t == 1 ? 0.25 : PI;
				assert_int_equal(pcorners(pos, 2 * N + 1, idx, off, N, (vn_method)m, crease, sharp, 1, out, NULL),
				                 vn_result_success);
				brute_corner_normals(pos, idx, off, N, (int)m, crease, sharp, NULL, want);
				for (size_t k = 0; k < c; ++k)
					assert_vec(out + 3 * k, want[3 * k], want[3 * k + 1], want[3 * k + 2], 1e-12);
			}
	}
}

/* On triangles the polygon arithmetic (Newell normal, per-corner weights)
 * differs from vn_corner_normals' triangle arithmetic in the last bits
 * only, and the fans are the same: agreement within 1e-13. */
static void poly_matches_triangle_corners(void** state)
{
	(void)state;
	vn_model_mesh mesh;
	assert_int_equal(vn_model_generate(vn_model_perlin_hf, vn_resolution_low, NULL, &mesh), vn_result_success);
	const size_t ni = 3 * mesh.triangle_count;
	uint32_t* off = (uint32_t*)malloc(sizeof(uint32_t) * (mesh.triangle_count + 1));
	for (size_t f = 0; f <= mesh.triangle_count; ++f)
		off[f] = (uint32_t)(3 * f);
	double* a = (double*)malloc(sizeof(double) * 3 * ni);
	double* b = (double*)malloc(sizeof(double) * 3 * ni);
	uint8_t* sharp = (uint8_t*)malloc(ni);
	uint32_t seed = 5;
	for (size_t c = 0; c < ni; ++c)
		sharp[c] = next_random(&seed) % 7 == 0;
	const vn_positions p = {mesh.positions, mesh.vertex_count, 0, vn_scalar_float64};
	const vn_vectors oa = {a, 0, vn_scalar_float64};
	for (unsigned m = 0; m < SEVEN; ++m)
		for (int t = 0; t < 2; ++t) {
			const double crease = t ? 0.2 : PI;
			assert_int_equal(vn_corner_normals(&oa, &p, mesh.indices, ni, (vn_method)m, crease, sharp, NULL, NULL),
			                 vn_result_success);
			assert_int_equal(pcorners(mesh.positions, mesh.vertex_count, mesh.indices, off, mesh.triangle_count,
			                          (vn_method)m, crease, sharp, 2, b, NULL),
			                 vn_result_success);
			for (size_t c = 0; c < ni; ++c)
				assert_vec(b + 3 * c, a[3 * c], a[3 * c + 1], a[3 * c + 2], 1e-13);
		}
	free(sharp);
	free(b);
	free(a);
	free(off);
	vn_model_free(&mesh, NULL);
}

/* Results bit-identical for 1, 2, 3 and 7 threads on a mesh big enough for
 * 7 workers (more than 7 x 4096 vertices), polygons and triangles. */
static void poly_threads_bit_identical(void** state)
{
	(void)state;
	const int U = 220, V = 150;
	double* pos = (double*)malloc(sizeof(double) * 3 * 2 * U * V);
	uint32_t* idx = (uint32_t*)malloc(sizeof(uint32_t) * 6 * U * V);
	uint32_t* off = (uint32_t*)malloc(sizeof(uint32_t) * (2 * U * V + 1));
	size_t nv;
	const size_t nf = mixed_torus(U, V, 3, pos, &nv, idx, off), n = off[nf];
	assert_true(nv > 7 * 4096);
	uint8_t* sharp = (uint8_t*)malloc(n);
	uint32_t seed = 17;
	for (size_t c = 0; c < n; ++c)
		sharp[c] = next_random(&seed) % 9 == 0;
	double* one = (double*)malloc(sizeof(double) * 3 * n);
	double* many = (double*)malloc(sizeof(double) * 3 * n);
	const unsigned counts[3] = {2, 3, 7};
	for (unsigned m = 0; m < vn_method_count; m += 3) {
		vn_stats s1, sk;
		assert_int_equal(pcorners(pos, nv, idx, off, nf, (vn_method)m, 0.4, sharp, 1, one, &s1), vn_result_success);
		for (int t = 0; t < 3; ++t) {
			memset(many, 0xff, sizeof(double) * 3 * n);
			assert_int_equal(pcorners(pos, nv, idx, off, nf, (vn_method)m, 0.4, sharp, counts[t], many, &sk),
			                 vn_result_success);
			assert_memory_equal(one, many, sizeof(double) * 3 * n);
			assert_memory_equal(&s1, &sk, sizeof(s1));
		}
	}
	/* Triangles through vn_corner_normals: the faces as triangle fans. */
	uint32_t* tri = (uint32_t*)malloc(sizeof(uint32_t) * 3 * n);
	size_t ni = 0;
	for (size_t f = 0; f < nf; ++f)
		for (uint32_t c = off[f] + 1; c + 1 < off[f + 1]; ++c)
			tri[ni++] = idx[off[f]], tri[ni++] = idx[c], tri[ni++] = idx[c + 1];
	double* a = (double*)malloc(sizeof(double) * 3 * ni);
	double* b = (double*)malloc(sizeof(double) * 3 * ni);
	uint8_t* tri_sharp = (uint8_t*)malloc(ni);
	for (size_t c = 0; c < ni; ++c)
		tri_sharp[c] = next_random(&seed) % 9 == 0;
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors oa = {a, 0, vn_scalar_float64}, ob = {b, 0, vn_scalar_float64};
	vn_options o;
	memset(&o, 0, sizeof(o));
	assert_int_equal(vn_corner_normals(&oa, &p, tri, ni, vn_method_mwa, 0.3, tri_sharp, &o, NULL), vn_result_success);
	for (int t = 0; t < 3; ++t) {
		o.threads = counts[t];
		assert_int_equal(vn_corner_normals(&ob, &p, tri, ni, vn_method_mwa, 0.3, tri_sharp, &o, NULL), vn_result_success);
		assert_memory_equal(a, b, sizeof(double) * 3 * ni);
	}
	free(tri_sharp);
	free(b);
	free(a);
	free(tri);
	free(many);
	free(one);
	free(sharp);
	free(off);
	free(idx);
	free(pos);
}

/* The hinge with A given as (0, 1, 1, 2, 3), as files write a quad in a
 * pentagon: A's two corners at vertex 1 are one corner of the face (its
 * edges go to 0 and 2), which contributes once, and they are joined to B
 * across edge 1-2. Every method gives each corner what the plain hinge
 * gives its corner there, bit for bit (vertex 1's: (-h, 0, h) for MWE, as
 * in poly_hinge); before, A's corners at vertex 1 contributed nothing. */
static void poly_repeated_index(void** state)
{
	(void)state;
	const uint32_t idx[] = {0, 1, 1, 2, 3, 1, 4, 5, 2};
	const uint32_t off[] = {0, 5, 9};
	const int plain[9] = {0, 1, 1, 2, 3, 4, 5, 6, 7}; /* its corner in the plain hinge */
	for (unsigned m = 0; m < vn_method_count; ++m) {
		double out[9 * 3], want[8 * 3];
		vn_stats st;
		assert_int_equal(pcorners(hinge_pos, 6, idx, off, 2, (vn_method)m, PI, NULL, 1, out, &st), vn_result_success);
		assert_int_equal(pcorners(hinge_pos, 6, hinge_idx, hinge_off, 2, (vn_method)m, PI, NULL, 1, want, NULL),
		                 vn_result_success);
		for (int c = 0; c < 9; ++c)
			assert_memory_equal(out + 3 * c, want + 3 * plain[c], 3 * sizeof(double));
		assert_int_equal(st.degenerate_faces, 0);
	}
	double out[9 * 3];
	assert_int_equal(pcorners(hinge_pos, 6, idx, off, 2, vn_method_mwe, PI, NULL, 1, out, NULL), vn_result_success);
	assert_vec(out + 3 * 2, -0.7071067811865475, 0, 0.7071067811865475, 1e-15);
}

/* Degenerate faces never give NaN: a 2-corner face, a cornerless face, a
 * zero-area quad, a face with a NaN vertex and an isolated vertex. The
 * corners of degenerate faces get their vertex's normal over its usable
 * faces (the flat square's +z), or zero where there is none. */
static void poly_degenerate(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, NAN, 0, 0, 5, 5, 5, 0.5, 0, 0};
	/* square (0,1,2,3); 2-corner (0, 2); empty; zero-area (0, 6, 1, 6); NaN (1, 4, 2); vertex 5 unused */
	const uint32_t idx[] = {0, 1, 2, 3, 0, 2, 0, 6, 1, 6, 1, 4, 2};
	const uint32_t off[] = {0, 4, 6, 6, 10, 13};
	for (unsigned m = 0; m < vn_method_count; ++m)
		for (int t = 0; t < 2; ++t) {
			double out[13 * 3];
			vn_stats st;
			assert_int_equal(pcorners(pos, 7, idx, off, 5, (vn_method)m, t ? 0.1 : PI, NULL, 1, out, &st),
			                 vn_result_success);
			for (int c = 0; c < 13; ++c)
				for (int a = 0; a < 3; ++a)
					assert_false(isnan(out[3 * c + a]));
			const int zero[13] = {0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 0};
			for (int c = 0; c < 13; ++c)
				if (zero[c])
					assert_vec(out + 3 * c, 0, 0, 0, 0);
				else if (m != vn_method_mewcsa)
					assert_vec(out + 3 * c, 0, 0, 1, 1e-15);
			assert_int_equal(st.faces, 5);
			assert_int_equal(st.degenerate_faces, 4);
			assert_int_equal(st.zero_normals, 3);
			assert_int_equal(st.nonfinite_vertices, 1);
		}
}

static void poly_errors(void** state)
{
	(void)state;
	double out[24 * 3];
	for (int i = 0; i < 72; ++i)
		out[i] = 42.0;
	uint32_t bad[24];
	memcpy(bad, qcube_idx, sizeof(bad));
	bad[23] = 8;
	for (unsigned threads = 1; threads <= 2; ++threads)
		assert_int_equal(pcorners(cube_pos, 8, bad, qcube_off, 6, vn_method_mwe, PI, NULL, threads, out, NULL),
		                 vn_result_index_out_of_range);
	for (int i = 0; i < 72; ++i)
		assert_true(out[i] == 42.0);
	assert_int_equal(pcorners(cube_pos, 8, qcube_idx, qcube_off, 6, vn_method_mwe, -0.5, NULL, 1, out, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(pcorners(cube_pos, 8, qcube_idx, qcube_off, 6, vn_method_mwe, NAN, NULL, 1, out, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(pcorners(cube_pos, 8, qcube_idx, NULL, 6, vn_method_mwe, PI, NULL, 1, out, NULL),
	                 vn_result_invalid_argument);
	const uint32_t backwards[] = {0, 4, 3, 12};
	assert_int_equal(pcorners(cube_pos, 8, qcube_idx, backwards, 3, vn_method_mwe, PI, NULL, 1, out, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(pcorners(cube_pos, 8, qcube_idx, qcube_off, 6, vn_method_count, PI, NULL, 1, out, NULL),
	                 vn_result_unknown_method);
	assert_int_equal(pcorners(cube_pos, 8, NULL, qcube_off, 6, vn_method_mwe, PI, NULL, 1, out, NULL),
	                 vn_result_invalid_argument);
	for (int i = 0; i < 72; ++i)
		assert_true(out[i] == 42.0);
	/* No corners: success, nothing written. */
	const uint32_t none[] = {0, 0};
	vn_stats st;
	assert_int_equal(pcorners(cube_pos, 8, NULL, none, 1, vn_method_mwe, PI, NULL, 1, NULL, &st), vn_result_success);
	assert_int_equal(st.faces, 1);
	assert_int_equal(st.degenerate_faces, 1);
}

/* Work memory: from the allocator (every failure reported, nothing leaked
 * or written), or none at all from a workspace of vn.h's size. */
static void poly_memory(void** state)
{
	(void)state;
	double out[24 * 3];
	const vn_positions p = {cube_pos, 8, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	counting c = {0, 0, -1};
	vn_options opt = counting_options(&c);
	assert_int_equal(vn_polygon_corner_normals(&o, &p, qcube_idx, qcube_off, 6, vn_method_mwe, DEG30, NULL, &opt, NULL),
	                 vn_result_success);
	assert_true(c.allocations > 0);
	assert_int_equal(c.allocations, c.frees);
	const int total = c.allocations;
	for (int k = 0; k < total; ++k) {
		counting f = {0, 0, k};
		const vn_options fail = counting_options(&f);
		out[0] = 42.0;
		assert_int_equal(
		    vn_polygon_corner_normals(&o, &p, qcube_idx, qcube_off, 6, vn_method_mwe, DEG30, NULL, &fail, NULL),
		    vn_result_out_of_memory);
		assert_true(out[0] == 42.0);
		assert_int_equal(f.allocations, f.frees);
	}
	/* 36 bytes a corner + 24 a face + 4 a vertex + 64 a thread + 64. */
	unsigned char ws[36 * 24 + 24 * 6 + 4 * 8 + 64 + 64];
	counting none = {0, 0, 0};
	opt = counting_options(&none);
	opt.workspace = ws;
	opt.workspace_size = sizeof(ws);
	assert_int_equal(vn_polygon_corner_normals(&o, &p, qcube_idx, qcube_off, 6, vn_method_mwe, DEG30, NULL, &opt, NULL),
	                 vn_result_success);
	assert_int_equal(none.allocations, 0);
	assert_vec(out, 0, 0, -1, 0);
}

/* ---------------------------------------------------------------- face strengths (Face Influence) */

enum { WEAK = -16384, MEDIUM = 0, STRONG = 16384 }; /* Blender's values */

/* The quad cube with -z strong, -y and -x weak, the others medium. MWA (all
 * corners right angles): each vertex's normal is the mean of its strongest
 * faces' normals: the four -z vertices get -z; (0,0,1) only +z; (1,0,1)
 * +z and +x; (0,1,1) +z and +y; (1,1,1) all three. Triangles (two per
 * quad, the same strengths) give the same. With -z's edges flagged, each
 * bottom vertex has two fans: -z alone, and its two side faces, where the
 * strong face no longer outranks them: (-1,-1,0)/sqrt 2 at vertex 0 (two
 * weak faces, both counted), (1,1,0)/sqrt 2 at vertex 2 (two medium), +x
 * at vertex 1 and +y at vertex 3 (one medium face and one weak). */
static void strength_cube(void** state)
{
	(void)state;
	const int32_t quad[6] = {STRONG, MEDIUM, WEAK, MEDIUM, WEAK, MEDIUM};
	int32_t tri[12];
	for (int t = 0; t < 12; ++t)
		tri[t] = quad[t / 2];
	const double h = 0.7071067811865475, k = 0.5773502691896258;
	const double want[8][3] = {{0, 0, -1}, {0, 0, -1}, {0, 0, -1}, {0, 0, -1},
	                           {0, 0, 1},  {h, 0, h},  {k, k, k},  {0, h, h}};
	double out[36 * 3];
	for (int tris = 0; tris < 2; ++tris) {
		const uint32_t* idx = tris ? cube_idx : qcube_idx;
		const size_t n = tris ? 36 : 24;
		assert_int_equal(scorners(cube_pos, 8, idx, tris ? NULL : qcube_off, tris ? 12 : 6, vn_method_mwa, PI, NULL,
		                          tris ? tri : quad, 1, out),
		                 vn_result_success);
		for (size_t c = 0; c < n; ++c) {
			const double* w = want[idx[c]];
			assert_vec(out + 3 * c, w[0], w[1], w[2], 1e-15);
		}
	}
	const uint8_t sharp[24] = {1, 1, 1, 1}; /* the -z quad's four edges */
	assert_int_equal(scorners(cube_pos, 8, qcube_idx, qcube_off, 6, vn_method_mwa, PI, sharp, quad, 1, out),
	                 vn_result_success);
	const double side[4][3] = {{-h, -h, 0}, {1, 0, 0}, {h, h, 0}, {0, 1, 0}};
	for (int c = 0; c < 24; ++c) {
		const uint32_t v = qcube_idx[c];
		if (c < 4)
			assert_vec(out + 3 * c, 0, 0, -1, 0);
		else if (v < 4)
			assert_vec(out + 3 * c, side[v][0], side[v][1], side[v][2], 1e-15);
	}
}

/* Random strengths (weak, medium, strong) on the mixed torus with faces
 * removed, random flags and crease angles, polygons and the same faces as
 * triangle fans: the library agrees with the brute force within 1e-12;
 * strengths all equal give the result without strengths bit for bit. */
static void strength_matches_brute_force(void** state)
{
	(void)state;
	double pos[3 * 2 * TU * TV];
	uint32_t idx[6 * TU * TV], off[2 * TU * TV + 1];
	size_t nv;
	size_t nf = mixed_torus(TU, TV, 13, pos, &nv, idx, off);
	const size_t f = 31, gone = off[f + 1] - off[f]; /* one face removed: a boundary */
	memmove(idx + off[f], idx + off[f + 1], sizeof(uint32_t) * (off[nf] - off[f + 1]));
	for (size_t h = f; h < nf; ++h)
		off[h] = off[h + 1] - (uint32_t)gone;
	--nf;
	const size_t n = off[nf];
	uint32_t* tri = (uint32_t*)malloc(sizeof(uint32_t) * 3 * n);
	uint32_t* tri_off = (uint32_t*)malloc(sizeof(uint32_t) * (n + 1));
	int32_t* strength = (int32_t*)malloc(sizeof(int32_t) * nf);
	int32_t* tri_strength = (int32_t*)malloc(sizeof(int32_t) * n);
	int32_t* equal = (int32_t*)calloc(n, sizeof(int32_t));
	uint32_t seed = 41;
	size_t nt = 0;
	for (size_t g = 0; g < nf; ++g) {
		const int32_t levels[3] = {WEAK, MEDIUM, STRONG};
		strength[g] = levels[next_random(&seed) % 3];
		for (uint32_t c = off[g] + 1; c + 1 < off[g + 1]; ++c) {
			tri[3 * nt] = idx[off[g]], tri[3 * nt + 1] = idx[c], tri[3 * nt + 2] = idx[c + 1];
			tri_off[nt] = (uint32_t)(3 * nt);
			tri_strength[nt++] = strength[g];
		}
	}
	tri_off[nt] = (uint32_t)(3 * nt);
	double* out = (double*)malloc(sizeof(double) * 9 * n);
	double* want = (double*)malloc(sizeof(double) * 9 * n);
	uint8_t* sharp = (uint8_t*)malloc(3 * n);
	const double creases[3] = {0.4, 1.2, PI};
	for (unsigned m = 0; m < SEVEN; ++m)
		for (int t = 0; t < 6; ++t) {
			const int tris = t % 2;
			const size_t faces = tris ? nt : nf, corners = tris ? 3 * nt : n;
			const uint32_t* fi = tris ? tri : idx;
			const uint32_t* fo = tris ? tri_off : off;
			for (size_t c = 0; c < corners; ++c)
				sharp[c] = next_random(&seed) % 6 == 0;
			const int32_t* s = tris ? tri_strength : strength;
			assert_int_equal(scorners(pos, nv, fi, tris ? NULL : fo, faces, (vn_method)m, creases[t / 2], sharp, s, 1,
			                          out),
			                 vn_result_success);
			brute_corner_normals(pos, fi, fo, faces, (int)m, creases[t / 2], sharp, s, want);
			for (size_t c = 0; c < corners; ++c)
				assert_vec(out + 3 * c, want[3 * c], want[3 * c + 1], want[3 * c + 2], 1e-12);
			assert_int_equal(scorners(pos, nv, fi, tris ? NULL : fo, faces, (vn_method)m, creases[t / 2], sharp,
			                          equal, 1, out),
			                 vn_result_success);
			assert_int_equal(scorners(pos, nv, fi, tris ? NULL : fo, faces, (vn_method)m, creases[t / 2], sharp, NULL,
			                          1, want),
			                 vn_result_success);
			assert_memory_equal(out, want, sizeof(double) * 3 * corners);
		}
	free(sharp);
	free(want);
	free(out);
	free(equal);
	free(tri_strength);
	free(strength);
	free(tri_off);
	free(tri);
}

/* Weak faces that share no vertex with each other, the rest medium, on the
 * closed mixed torus with nothing sharp: every star stays one fan when the
 * weak faces are removed, and each of its vertices keeps a medium face, so
 * the other corners' normals are those of the mesh without the weak faces,
 * bit for bit (the same contributions added in the same order); the weak
 * faces' own corners get their vertex's normal. */
static void strength_is_removing_weak_faces(void** state)
{
	(void)state;
	double pos[3 * 2 * TU * TV];
	uint32_t idx[6 * TU * TV], off[2 * TU * TV + 1], kept_idx[6 * TU * TV], kept_off[2 * TU * TV + 1];
	size_t nv;
	const size_t nf = mixed_torus(TU, TV, 19, pos, &nv, idx, off);
	int32_t strength[2 * TU * TV];
	unsigned char used[2 * TU * TV] = {0};
	size_t weak = 0, kept = 0, nk = 0;
	kept_off[0] = 0;
	for (size_t f = 0; f < nf; ++f) {
		int free_vertices = f % 3 == 0;
		for (uint32_t c = off[f]; c < off[f + 1]; ++c)
			free_vertices &= !used[idx[c]];
		strength[f] = free_vertices ? WEAK : MEDIUM;
		for (uint32_t c = off[f]; c < off[f + 1]; ++c) {
			used[idx[c]] |= free_vertices;
			if (!free_vertices)
				kept_idx[nk++] = idx[c];
		}
		weak += free_vertices;
		if (!free_vertices)
			kept_off[++kept] = (uint32_t)nk;
	}
	assert_true(weak > 10);
	double out[3 * 6 * TU * TV], want[3 * 6 * TU * TV], vert[3 * 2 * TU * TV];
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors ov = {vert, 0, vn_scalar_float64};
	for (unsigned m = 0; m < SEVEN; ++m) {
		assert_int_equal(scorners(pos, nv, idx, off, nf, (vn_method)m, PI, NULL, strength, 1, out), vn_result_success);
		assert_int_equal(scorners(pos, nv, kept_idx, kept_off, kept, (vn_method)m, PI, NULL, NULL, 1, want),
		                 vn_result_success);
		assert_int_equal(vn_polygon_normals(&ov, &p, kept_idx, kept_off, kept, (vn_method)m, NULL, NULL),
		                 vn_result_success);
		for (size_t f = 0, k = 0; f < nf; ++f)
			for (uint32_t c = off[f]; c < off[f + 1]; ++c)
				assert_same(out + 3 * c, strength[f] == WEAK ? vert + 3 * (size_t)idx[c] : want + 3 * k++);
	}
}

/* With face strengths, results are bit-identical for 1, 2, 3 and 7
 * threads (polygons and triangles) on a mesh big enough for 7 workers. */
static void strength_threads_bit_identical(void** state)
{
	(void)state;
	const int U = 220, V = 150;
	double* pos = (double*)malloc(sizeof(double) * 3 * 2 * U * V);
	uint32_t* idx = (uint32_t*)malloc(sizeof(uint32_t) * 6 * U * V);
	uint32_t* off = (uint32_t*)malloc(sizeof(uint32_t) * (2 * U * V + 1));
	size_t nv;
	const size_t nf = mixed_torus(U, V, 5, pos, &nv, idx, off), n = off[nf];
	assert_true(nv > 7 * 4096);
	uint32_t* tri = (uint32_t*)malloc(sizeof(uint32_t) * 3 * n);
	int32_t* strength = (int32_t*)malloc(sizeof(int32_t) * 3 * n);
	uint8_t* sharp = (uint8_t*)malloc(3 * n);
	uint32_t seed = 29;
	for (size_t c = 0; c < 3 * n; ++c) {
		strength[c] = (int32_t)(next_random(&seed) % 3) - 1;
		sharp[c] = next_random(&seed) % 9 == 0;
	}
	size_t nt = 0;
	for (size_t f = 0; f < nf; ++f)
		for (uint32_t c = off[f] + 1; c + 1 < off[f + 1]; ++c, ++nt)
			tri[3 * nt] = idx[off[f]], tri[3 * nt + 1] = idx[c], tri[3 * nt + 2] = idx[c + 1];
	double* one = (double*)malloc(sizeof(double) * 9 * n);
	double* many = (double*)malloc(sizeof(double) * 9 * n);
	const unsigned counts[3] = {2, 3, 7};
	for (int tris = 0; tris < 2; ++tris) {
		const uint32_t* fi = tris ? tri : idx;
		const size_t faces = tris ? nt : nf, corners = tris ? 3 * nt : n;
		assert_int_equal(scorners(pos, nv, fi, tris ? NULL : off, faces, vn_method_mwa, 0.4, sharp, strength, 1, one),
		                 vn_result_success);
		for (int t = 0; t < 3; ++t) {
			memset(many, 0xff, sizeof(double) * 3 * corners);
			assert_int_equal(scorners(pos, nv, fi, tris ? NULL : off, faces, vn_method_mwa, 0.4, sharp, strength,
			                          counts[t], many),
			                 vn_result_success);
			assert_memory_equal(one, many, sizeof(double) * 3 * corners);
		}
	}
	free(many);
	free(one);
	free(sharp);
	free(strength);
	free(tri);
	free(off);
	free(idx);
	free(pos);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(weld_exact_duplicates),
	    cmocka_unit_test(weld_epsilon_chain),
	    cmocka_unit_test(weld_signed_zero),
	    cmocka_unit_test(weld_nan_never),
	    cmocka_unit_test(weld_infinite_and_huge),
	    cmocka_unit_test(weld_subnormal_epsilon),
	    cmocka_unit_test(weld_types_and_strides),
	    cmocka_unit_test(weld_uv_sphere_seam),
	    cmocka_unit_test(weld_invalid_arguments),
	    cmocka_unit_test(weld_allocator),
	    cmocka_unit_test(weld_matches_brute_force),
	    cmocka_unit_test(weld_exact_matches_brute_force),
	    cmocka_unit_test(weld_exact_crowded),
	    cmocka_unit_test(weld_exact_agrees_with_grid),
	    cmocka_unit_test(cube_crease_30),
	    cmocka_unit_test(cube_mewcsa_per_wedge),
	    cmocka_unit_test(cube_crease_pi),
	    cmocka_unit_test(torus_crease_pi),
	    cmocka_unit_test(strip_smooth_and_hard),
	    cmocka_unit_test(strip_sharp_flags),
	    cmocka_unit_test(boundary_edges),
	    cmocka_unit_test(nonmanifold_edges),
	    cmocka_unit_test(repeated_index_gets_vertex_normal),
	    cmocka_unit_test(zero_area_and_nonfinite),
	    cmocka_unit_test(index_out_of_range_writes_nothing),
	    cmocka_unit_test(corner_invalid_arguments),
	    cmocka_unit_test(corner_types_and_strides),
	    cmocka_unit_test(corner_allocator),
	    cmocka_unit_test(uv_seam_welded),
	    cmocka_unit_test(poly_cube),
	    cmocka_unit_test(poly_hinge),
	    cmocka_unit_test(poly_matches_vertex_normals),
	    cmocka_unit_test(poly_matches_brute_force),
	    cmocka_unit_test(poly_high_valence),
	    cmocka_unit_test(poly_matches_triangle_corners),
	    cmocka_unit_test(poly_threads_bit_identical),
	    cmocka_unit_test(poly_repeated_index),
	    cmocka_unit_test(poly_degenerate),
	    cmocka_unit_test(poly_errors),
	    cmocka_unit_test(poly_memory),
	    cmocka_unit_test(strength_cube),
	    cmocka_unit_test(strength_matches_brute_force),
	    cmocka_unit_test(strength_is_removing_weak_faces),
	    cmocka_unit_test(strength_threads_bit_identical),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
