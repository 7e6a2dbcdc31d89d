/* Welding and split normals: vn_weld_positions and vn_corner_normals.
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
	for (unsigned m = 0; m < vn_method_count; ++m) {
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
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
