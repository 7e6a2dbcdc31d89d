/* The schemes beyond the paper: SMEWCSA (cotangent.c), QUADRIC, JET and
 * ADAPTIVE (fit.c). Hand-computed cases, exactness of the fit on polynomial
 * height fields (through fit.c's internal vn_fit_frame), convergence orders
 * on an irregularly sampled ellipsoid, orientation on a torus, degenerate
 * rings, thread counts and per-corner results. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h" /* vn_fit_frame */

#define PI 3.141592653589793

static const vn_method fits[] = {vn_method_smewcsa, vn_method_quadric, vn_method_jet, vn_method_adaptive};

static vn_result tri(const double* pos, size_t nv, const uint32_t* idx, size_t ni, vn_method m, unsigned threads,
                     double* out)
{
	const vn_positions p = {pos, nv, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	vn_options opt;
	memset(&opt, 0, sizeof(opt));
	opt.threads = threads;
	return vn_triangle_normals(&o, &p, idx, ni, m, &opt, NULL);
}

static void assert_vec(const double* got, double x, double y, double z, double tol)
{
	if (!(fabs(got[0] - x) <= tol && fabs(got[1] - y) <= tol && fabs(got[2] - z) <= tol))
		fail_msg("got (%.17g, %.17g, %.17g), expected (%.17g, %.17g, %.17g)", got[0], got[1], got[2], x, y, z);
}

/* A deterministic value in [-1, 1). */
static double jitter(uint32_t* s)
{
	*s = *s * 1664525u + 1013904223u;
	return (double)(*s >> 8) / (double)(1u << 23) - 1.0;
}

/* ---------------------------------------------------------------- SMEWCSA by hand */

/* A square pyramid, apex 0 over (or under: a dimple) the base 1..4 in z = 0,
 * faces wound to face +z. */
static const uint32_t pyramid_idx[] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};

static void smewcsa_flips_a_dimple(void** state)
{
	(void)state;
	const double dimple[] = {0, 0, -1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
	double m[15], s[15];
	assert_int_equal(tri(dimple, 5, pyramid_idx, 12, vn_method_mewcsa, 1, m), vn_result_success);
	assert_int_equal(tri(dimple, 5, pyramid_idx, 12, vn_method_smewcsa, 1, s), vn_result_success);
	assert_vec(m, 0, 0, -1, 0); /* MEWCSA points into the dimple */
	assert_vec(s, 0, 0, 1, 0);
}

static void smewcsa_keeps_a_bump(void** state)
{
	(void)state;
	const double bump[] = {0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
	double s[15];
	assert_int_equal(tri(bump, 5, pyramid_idx, 12, vn_method_smewcsa, 1, s), vn_result_success);
	assert_vec(s, 0, 0, 1, 0);
	/* Base vertex 1 = (1,0,0), on the boundary: MEWCSA there is
	 * (p2 - p0) x N_012 + (p0 - p4) x N_041 = (4, 0, -2) / sqrt 3, 71.6
	 * degrees from MWSELR's (1, 0, 1) / sqrt 2 (mostly tangential: the
	 * boundary's area gradient), so the result is MWSELR's. */
	assert_vec(s + 3, 1 / sqrt(2.0), 0, 1 / sqrt(2.0), 1e-15);
}

/* Flat and irregular: the area gradient is zero up to rounding, so the
 * result is MWSELR's (0, 0, 1), exactly. */
static void smewcsa_flat_falls_back(void** state)
{
	(void)state;
	const double flat[] = {0.1, -0.2, 0, 1, 0, 0, 0.3, 1.2, 0, -1.1, 0.2, 0, 0.1, -0.9, 0};
	double s[15];
	assert_int_equal(tri(flat, 5, pyramid_idx, 12, vn_method_smewcsa, 1, s), vn_result_success);
	assert_vec(s, 0, 0, 1, 0);
}

/* A 5 x 5 jittered grid in x, y (one row a line), triangulated with
 * alternating diagonals, faces facing +z; interior vertices 6..8, 11..13,
 * 16..18. */
static const double smew_xy[25][2] = {
    {0.006, 0.02},  {0.114, -0.014}, {0.19, 0.019},  {0.275, 0.016},  {0.415, -0.002},
    {-0.01, 0.089}, {0.088, 0.097},  {0.2, 0.103},   {0.325, 0.115},  {0.406, 0.124},
    {-0.014, 0.183}, {0.106, 0.177}, {0.177, 0.201}, {0.298, 0.221},  {0.406, 0.201},
    {0, 0.287},     {0.076, 0.285},  {0.21, 0.285},  {0.293, 0.275},  {0.417, 0.283},
    {-0.012, 0.419}, {0.1, 0.417},   {0.207, 0.412}, {0.28, 0.402},   {0.4, 0.419}};
static const uint32_t smew_idx[] = {
    0,  1,  5,  1,  6,  5,  1,  2,  7,  1,  7,  6,  2,  3,  7,  3,  8,  7,  3,  4,  9,  3,  9,  8,
    5,  6,  11, 5,  11, 10, 6,  7,  11, 7,  12, 11, 7,  8,  13, 7,  13, 12, 8,  9,  13, 9,  14, 13,
    10, 11, 15, 11, 16, 15, 11, 12, 17, 11, 17, 16, 12, 13, 17, 13, 18, 17, 13, 14, 19, 13, 19, 18,
    15, 16, 21, 15, 21, 20, 16, 17, 21, 17, 22, 21, 17, 18, 23, 17, 23, 22, 18, 19, 23, 19, 24, 23};

/* The grid on z = 0.25 + 0.3 x - 0.45 y + bowl ((x - 0.2)^2 + (y - 0.2)^2),
 * method m's normals with positions of type t (float32 rounded from the
 * doubles), SIMD on and off (which must agree bit for bit). */
static void smew_grid(double bowl, vn_scalar t, vn_method m, double out[75])
{
	double pos[75];
	float pos32[75];
	for (int v = 0; v < 25; ++v) {
		const double x = smew_xy[v][0], y = smew_xy[v][1], dx = x - 0.2, dy = y - 0.2;
		pos[3 * v] = x, pos[3 * v + 1] = y, pos[3 * v + 2] = 0.25 + 0.3 * x - 0.45 * y + bowl * (dx * dx + dy * dy);
	}
	for (int i = 0; i < 75; ++i)
		pos32[i] = (float)pos[i];
	const vn_positions p = {t == vn_scalar_float32 ? (const void*)pos32 : (const void*)pos, 25, 0, t};
	double scalar[75];
	const vn_vectors o = {out, 0, vn_scalar_float64}, os = {scalar, 0, vn_scalar_float64};
	vn_options opt;
	memset(&opt, 0, sizeof(opt));
	assert_int_equal(vn_triangle_normals(&o, &p, smew_idx, 96, m, &opt, NULL), vn_result_success);
	opt.simd = vn_simd_off;
	assert_int_equal(vn_triangle_normals(&os, &p, smew_idx, 96, m, &opt, NULL), vn_result_success);
	assert_memory_equal(out, scalar, sizeof(scalar));
}

/* A tilted plane: its MEWCSA sums are rounding noise (at most ~1e-6 of
 * their contributions' lengths for float32 positions, ~1e-15 for double),
 * whose direction lands within 30 degrees of MWSELR at some vertices, so
 * only the flatness test makes SMEWCSA give MWSELR's normal at every vertex,
 * bit for bit. */
static void smewcsa_tilted_plane_is_mwselr(void** state)
{
	(void)state;
	size_t near = 0;
	for (int t = 0; t < 2; ++t) {
		double smew[75], seed[75], mew[75];
		smew_grid(0, (vn_scalar)t, vn_method_smewcsa, smew);
		smew_grid(0, (vn_scalar)t, vn_method_mwselr, seed);
		smew_grid(0, (vn_scalar)t, vn_method_mewcsa, mew);
		assert_memory_equal(smew, seed, sizeof(smew));
		for (int v = 0; v < 25; ++v)
			near += fabs(mew[3 * v] * seed[3 * v] + mew[3 * v + 1] * seed[3 * v + 1] +
			             mew[3 * v + 2] * seed[3 * v + 2]) >= cos(PI / 6);
	}
	assert_true(near > 0);
}

/* A gentle bowl (curvature 0.02, MEWCSA sums 3 to 5 times the flatness
 * threshold at interior vertices): SMEWCSA keeps MEWCSA's normal there,
 * turned to face +z like MWSELR's. */
static void smewcsa_gentle_bowl_keeps_cotangent(void** state)
{
	(void)state;
	static const int interior[] = {6, 7, 8, 11, 12, 13, 16, 17, 18};
	for (int t = 0; t < 2; ++t) {
		double smew[75], mew[75];
		smew_grid(0.01, (vn_scalar)t, vn_method_smewcsa, smew);
		smew_grid(0.01, (vn_scalar)t, vn_method_mewcsa, mew);
		for (int k = 0; k < 9; ++k) {
			const double* m = mew + 3 * interior[k];
			assert_true(m[2] < 0); /* the area gradient points out of the bowl */
			assert_vec(smew + 3 * interior[k], -m[0], -m[1], -m[2], 0);
		}
	}
}

/* ---------------------------------------------------------------- exactness of the fit */

#define GRID 9

/* z = f(x, y) on a jittered GRID x GRID grid (spacing 0.1, jitter 0.03). */
static void height_grid(double (*f)(double, double), double pos[GRID * GRID][3])
{
	uint32_t s = 7;
	for (int j = 0; j < GRID; ++j)
		for (int i = 0; i < GRID; ++i) {
			const double x = 0.1 * i + 0.03 * jitter(&s), y = 0.1 * j + 0.03 * jitter(&s);
			pos[j * GRID + i][0] = x, pos[j * GRID + i][1] = y, pos[j * GRID + i][2] = f(x, y);
		}
}

/* The 1-ring (ring 1) or 2-ring (ring 2) of grid vertex (i, j) in the
 * triangulation split along (i, j)-(i+1, j+1), relative to the vertex. */
static uint32_t grid_ring(double pos[GRID * GRID][3], int i, int j, int ring, double* q)
{
	static const int one[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}};
	uint32_t m = 0;
	for (int dj = -2; dj <= 2; ++dj)
		for (int di = -2; di <= 2; ++di) {
			int in = 0; /* di, dj a sum of `ring` or fewer 1-ring steps, not 0 */
			for (int a = 0; a < 6; ++a) {
				in |= di == one[a][0] && dj == one[a][1];
				for (int b = 0; ring == 2 && b < 6; ++b)
					in |= di == one[a][0] + one[b][0] && dj == one[a][1] + one[b][1] && (di || dj);
			}
			if (!in)
				continue;
			const double* p = pos[(j + dj) * GRID + i + di];
			const double* o = pos[j * GRID + i];
			q[3 * m] = p[0] - o[0], q[3 * m + 1] = p[1] - o[1], q[3 * m + 2] = p[2] - o[2];
			++m;
		}
	return m;
}

static double quadric_field(double x, double y)
{
	return 0.7 * x * x - 1.3 * x * y + 0.4 * y * y + 0.25 * x - 0.6 * y;
}

static double cubic_field(double x, double y)
{
	return quadric_field(x, y) + 0.9 * x * x * x - 0.5 * x * x * y + 1.1 * x * y * y - 0.8 * y * y * y;
}

/* fit.c's fit of the ring q (3 doubles a member), coordinates over 0.1. */
static int fit_ring(const double* q, uint32_t m, int degree, double n[3], double* res)
{
	double scratch[16 * 24];
	const double up[3] = {0, 0, 1};
	return vn_fit_frame(q, m, 0.1, scratch, up, degree, n, res);
}

/* Every interior vertex (2-ring inside the grid): the fit in the frame of
 * the height axis returns the analytic normal (-f_x, -f_y, 1), normalized. */
static void check_exact(double (*f)(double, double), int degree, int ring, uint32_t members)
{
	double pos[GRID * GRID][3], q[3 * 24];
	height_grid(f, pos);
	int checked = 0;
	for (int j = 2; j < GRID - 2; ++j)
		for (int i = 2; i < GRID - 2; ++i) {
			const uint32_t m = grid_ring(pos, i, j, ring, q);
			assert_int_equal(m, members);
			double n[3], res;
			assert_int_equal(fit_ring(q, m, degree, n, &res), 1);
			const double x = pos[j * GRID + i][0], y = pos[j * GRID + i][1], e = 1e-6;
			const double fx = (f(x + e, y) - f(x - e, y)) / (2 * e), fy = (f(x, y + e) - f(x, y - e)) / (2 * e);
			/* central differences are exact to rounding on these polynomials up to e^2 f''' */
			const double len = sqrt(fx * fx + fy * fy + 1);
			assert_vec(n, -fx / len, -fy / len, 1 / len, 1e-9);
			/* The residual comes from the moments (sum w z^2 - c . t), so
			 * an exact fit's is rounding: about sqrt(eps) of the RMS z. */
			assert_true(res < 1e-7);
			++checked;
		}
	assert_int_equal(checked, (GRID - 4) * (GRID - 4));
}

static void quadric_exact_on_quadric_field(void** state)
{
	(void)state;
	check_exact(quadric_field, 2, 1, 6);
}

static void jet_exact_on_cubic_field(void** state)
{
	(void)state;
	check_exact(cubic_field, 3, 2, 18);
}

/* The quadric is not exact on a cubic: the same check fails, as it must. */
static void quadric_not_exact_on_cubic_field(void** state)
{
	(void)state;
	double pos[GRID * GRID][3], q[3 * 24], n[3], res;
	height_grid(cubic_field, pos);
	const uint32_t m = grid_ring(pos, 4, 4, 1, q);
	assert_int_equal(fit_ring(q, m, 2, n, &res), 1);
	assert_true(res > 1e-5);
}

/* ---------------------------------------------------------------- meshes made here */

typedef struct grid_mesh {
	double* pos;
	uint32_t* idx;
	double* exact;
	size_t nv, ni;
} grid_mesh;

static void grid_free(grid_mesh* g)
{
	free(g->pos), free(g->idx), free(g->exact);
}

/* A torus (R = 1, r = 0.4) or an ellipsoid (semi-axes 1, 0.8, 0.6) on an
 * nu x nv parameter grid, parameters jittered by up to `jit` of a cell, the
 * positions on the surface, outward triangles, exact normals. The ellipsoid
 * keeps its poles out (v in [0.1 pi, 0.9 pi]): an open band. */
static grid_mesh make_surface(int torus, uint32_t nu, uint32_t nv, double jit)
{
	grid_mesh g;
	const uint32_t rows = torus ? nv : nv + 1;
	g.nv = (size_t)nu * rows;
	g.pos = (double*)malloc(3 * sizeof(double) * g.nv);
	g.exact = (double*)malloc(3 * sizeof(double) * g.nv);
	g.idx = (uint32_t*)malloc(6 * sizeof(uint32_t) * (size_t)nu * nv);
	uint32_t s = 11;
	for (uint32_t j = 0; j < rows; ++j)
		for (uint32_t i = 0; i < nu; ++i) {
			const double u = 2 * PI * (i + jit * jitter(&s)) / nu;
			const double jv = j + jit * jitter(&s);
			double* p = g.pos + 3 * ((size_t)j * nu + i);
			double* n = g.exact + 3 * ((size_t)j * nu + i);
			if (torus) {
				const double v = 2 * PI * jv / nv;
				p[0] = (1 + 0.4 * cos(v)) * cos(u), p[1] = (1 + 0.4 * cos(v)) * sin(u), p[2] = 0.4 * sin(v);
				n[0] = cos(v) * cos(u), n[1] = cos(v) * sin(u), n[2] = sin(v);
			} else {
				const double v = PI * (0.1 + 0.8 * jv / nv);
				p[0] = sin(v) * cos(u), p[1] = 0.8 * sin(v) * sin(u), p[2] = 0.6 * cos(v);
				n[0] = p[0], n[1] = p[1] / 0.64, n[2] = p[2] / 0.36;
				const double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
				n[0] /= l, n[1] /= l, n[2] /= l;
			}
		}
	g.ni = 0;
	for (uint32_t j = 0; j < nv; ++j)
		for (uint32_t i = 0; i < nu; ++i) {
			const uint32_t a = j * nu + i, b = j * nu + (i + 1) % nu, c = ((j + 1) % rows) * nu + (i + 1) % nu,
			               d = ((j + 1) % rows) * nu + i;
			/* (u, v) is right-handed for the torus' outward normal; the
			 * ellipsoid's v runs from the north pole, so it is reversed */
			const uint32_t t[6] = {a, b, c, a, c, d}, r[6] = {a, c, b, a, d, c};
			memcpy(g.idx + g.ni, torus ? t : r, sizeof(t));
			g.ni += 6;
		}
	return g;
}

static double angle_deg(const double* a, const double* b)
{
	double c[3];
	vn_cross(a, b, c);
	return atan2(sqrt(vn_dot(c, c)), vn_dot(a, b)) * 180 / PI;
}

static int compare_double(const void* a, const void* b)
{
	const double x = *(const double*)a, y = *(const double*)b;
	return (x > y) - (x < y);
}

/* Median error in degrees over the vertices away from the band's edges. */
static double median_error(const grid_mesh* g, uint32_t nu, vn_method m)
{
	double* out = (double*)malloc(3 * sizeof(double) * g->nv);
	double* err = (double*)malloc(sizeof(double) * g->nv);
	assert_int_equal(tri(g->pos, g->nv, g->idx, g->ni, m, 1, out), vn_result_success);
	const size_t rows = g->nv / nu;
	size_t k = 0;
	for (size_t v = 3 * nu; v < (rows - 3) * nu; ++v)
		err[k++] = angle_deg(out + 3 * v, g->exact + 3 * v);
	qsort(err, k, sizeof(double), compare_double);
	const double med = err[k / 2];
	free(out), free(err);
	return med;
}

/* Measured orders of the median error between 3 resolutions (h halving). */
static void check_order(vn_method m, double order)
{
	double e[3];
	for (int r = 0; r < 3; ++r) {
		const uint32_t nu = 32u << r, nv = 16u << r;
		grid_mesh g = make_surface(0, nu, nv, 0.3);
		e[r] = median_error(&g, nu, m);
		grid_free(&g);
	}
	for (int r = 0; r < 2; ++r) {
		const double got = log2(e[r] / e[r + 1]);
		print_message("%s: median %g -> %g degrees, order %.3f\n", vn_method_name(m), e[r], e[r + 1], got);
		if (fabs(got - order) > 0.3)
			fail_msg("%s: order %.3f between resolutions %d and %d (errors %g, %g), expected %.1f +- 0.3",
			         vn_method_name(m), got, r, r + 1, e[r], e[r + 1], order);
	}
}

static void quadric_converges_as_h2(void** state)
{
	(void)state;
	check_order(vn_method_quadric, 2);
}

static void jet_converges_as_h3(void** state)
{
	(void)state;
	check_order(vn_method_jet, 3);
}

/* The seven are O(h) there: MWA's measured order is 1, not 2. */
static void mwa_converges_as_h(void** state)
{
	(void)state;
	check_order(vn_method_mwa, 1);
}

/* ---------------------------------------------------------------- orientation, threads, degenerate rings */

static void torus_outward_everywhere(void** state)
{
	(void)state;
	grid_mesh g = make_surface(1, 48, 20, 0.3);
	double* out = (double*)malloc(3 * sizeof(double) * g.nv);
	for (size_t k = 0; k < sizeof(fits) / sizeof(fits[0]); ++k) {
		assert_int_equal(tri(g.pos, g.nv, g.idx, g.ni, fits[k], 1, out), vn_result_success);
		size_t inner = 0;
		for (size_t v = 0; v < g.nv; ++v) {
			if (!(angle_deg(out + 3 * v, g.exact + 3 * v) < 60))
				fail_msg("%s: vertex %zu is %.2f degrees off", vn_method_name(fits[k]), v,
				         angle_deg(out + 3 * v, g.exact + 3 * v));
			inner += g.pos[3 * v] * g.pos[3 * v] + g.pos[3 * v + 1] * g.pos[3 * v + 1] < 1; /* saddle side */
		}
		assert_int_equal(inner, 486); /* x^2 + y^2 < 1: the saddle-shaped inner half */
	}
	free(out);
	grid_free(&g);
}

/* ADAPTIVE on the ellipsoid band (64 x 32, jittered): sampled exactly, as
 * accurate as the jet; with every vertex moved along its exact normal by up
 * to `noise` of the mean edge (as marching tetrahedra misplace vertices),
 * better than every one of the seven by its 5-ring fits; with noise as large
 * as the edges, MWA, its fallback off a lattice. Returns the median errors
 * of ADAPTIVE, JET, the best of the seven and MWA. */
static void adaptive_medians(double noise, double med[4])
{
	grid_mesh g = make_surface(0, 64, 32, 0.3);
	uint32_t s = 5;
	const double edge = 2 * PI / 64 * 0.9; /* about the band's mean edge */
	for (size_t v = 0; v < g.nv; ++v) {
		const double d = noise * edge * jitter(&s);
		for (int k = 0; k < 3; ++k)
			g.pos[3 * v + k] += d * g.exact[3 * v + k];
	}
	med[0] = median_error(&g, 64, vn_method_adaptive);
	med[1] = median_error(&g, 64, vn_method_jet);
	med[2] = DBL_MAX;
	for (int m = 0; m < 6; ++m) /* MEWCSA, the seventh, is never the best here */
		med[2] = fmin(med[2], median_error(&g, 64, (vn_method)m));
	med[3] = median_error(&g, 64, vn_method_mwa);
	print_message("noise %.2f: adaptive %g, jet %g, best of the seven %g, mwa %g degrees\n", noise, med[0], med[1],
	              med[2], med[3]);
	grid_free(&g);
}

static void adaptive_across_noise(void** state)
{
	(void)state;
	double med[4];
	adaptive_medians(0, med);
	assert_true(med[0] == med[1]);        /* the jet everywhere it matters */
	assert_true(med[0] < 0.25 * med[2]);  /* O(h^3) against O(h) */
	adaptive_medians(0.05, med);
	assert_true(med[0] < 0.5 * med[1]);   /* the wide fits average the noise out */
	assert_true(med[0] < 0.5 * med[2]);
	adaptive_medians(1.0, med);
	assert_true(med[0] == med[3]); /* no fit describes it: the fallback */
}

/* ADAPTIVE takes MWSELR's normal where the jet agrees with it to within
 * half its residual: on the torus's latitude-longitude grid, where MWSELR
 * is exact (its grid quads have their corners on circles, its parameter
 * lines are circles), ADAPTIVE is exact too, where the jet is not. */
static void adaptive_exact_where_mwselr_is(void** state)
{
	(void)state;
	grid_mesh g = make_surface(1, 48, 24, 0);
	const double a = median_error(&g, 48, vn_method_adaptive), s = median_error(&g, 48, vn_method_mwselr),
	             j = median_error(&g, 48, vn_method_jet);
	print_message("torus grid: adaptive %g, mwselr %g, jet %g degrees\n", a, s, j);
	assert_true(s < 1e-9);
	assert_true(a < 1e-9);
	assert_true(j > 1e-3);
	grid_free(&g);
}

/* A latitude-longitude sphere as Blender makes it (nu segments, nv rings,
 * fans at the poles), centred at c with semi-axes r, r and rz, outward;
 * its positions rounded to float32 values when `floats` is set. */
static grid_mesh make_uv_sphere(uint32_t nu, uint32_t nv, const double c[3], double r, double rz, int floats)
{
	grid_mesh g;
	g.nv = (size_t)nu * (nv - 1) + 2;
	g.pos = (double*)malloc(3 * sizeof(double) * g.nv);
	g.exact = NULL;
	g.idx = (uint32_t*)malloc(6 * sizeof(uint32_t) * (size_t)nu * nv);
	const uint32_t south = (uint32_t)g.nv - 1;
	for (size_t v = 0; v < g.nv; ++v) {
		const uint32_t ring = v == 0 ? 0 : v == south ? nv : 1 + (uint32_t)(v - 1) / nu, i = (uint32_t)(v - 1) % nu;
		const double t = PI * ring / nv, u = 2 * PI * i / nu, xy = v == 0 || v == south ? 0.0 : sin(t);
		const double p[3] = {c[0] + r * xy * cos(u), c[1] + r * xy * sin(u), c[2] + rz * cos(t)};
		memcpy(g.pos + 3 * v, p, sizeof(p));
	}
	/* Rounded in a pass of its own: GCC 12 at -O3 (SLP vectorization) lost
	 * the rounding when it was a choice in the loop above. */
	for (size_t i = 0; floats && i < 3 * g.nv; ++i)
		g.pos[i] = (float)g.pos[i];
	g.ni = 0;
	for (uint32_t i = 0; i < nu; ++i) {
		const uint32_t a = 1 + i, b = 1 + (i + 1) % nu, la = south - nu + i, lb = south - nu + (i + 1) % nu;
		const uint32_t fans[6] = {0, a, b, south, lb, la};
		memcpy(g.idx + g.ni, fans, sizeof(fans)), g.ni += 6;
		for (uint32_t j = 0; j + 2 < nv; ++j) {
			const uint32_t quad[6] = {a + j * nu, a + (j + 1) * nu, b + j * nu, b + j * nu, a + (j + 1) * nu,
			                          b + (j + 1) * nu};
			memcpy(g.idx + g.ni, quad, sizeof(quad)), g.ni += 6;
		}
	}
	return g;
}

/* How many of g's vertices get MWSELR's normal, bit for bit, from ADAPTIVE
 * (positions as float32 when `floats`, else float64); *worst: ADAPTIVE's
 * largest angle (degrees) from the radial direction of a sphere about c. */
static size_t adaptive_is_mwselr(const grid_mesh* g, int floats, const double c[3], double* worst)
{
	float* f = (float*)malloc(3 * sizeof(float) * g->nv);
	for (size_t i = 0; i < 3 * g->nv; ++i)
		f[i] = (float)g->pos[i];
	const vn_positions p = {floats ? (const void*)f : (const void*)g->pos, g->nv, 0,
	                        floats ? vn_scalar_float32 : vn_scalar_float64};
	double* out[2];
	for (int k = 0; k < 2; ++k) {
		out[k] = (double*)malloc(3 * sizeof(double) * g->nv);
		const vn_vectors o = {out[k], 0, vn_scalar_float64};
		vn_options opt;
		memset(&opt, 0, sizeof(opt));
		assert_int_equal(vn_triangle_normals(&o, &p, g->idx, g->ni, k ? vn_method_mwselr : vn_method_adaptive, &opt,
		                                     NULL),
		                 vn_result_success);
	}
	size_t same = 0;
	*worst = 0;
	for (size_t v = 0; v < g->nv; ++v) {
		same += memcmp(out[0] + 3 * v, out[1] + 3 * v, 3 * sizeof(double)) == 0;
		const double radial[3] = {g->pos[3 * v] - c[0], g->pos[3 * v + 1] - c[1], g->pos[3 * v + 2] - c[2]};
		*worst = fmax(*worst, angle_deg(out[0] + 3 * v, radial));
	}
	free(f), free(out[0]), free(out[1]);
	return same;
}

/* Where a vertex's 2-ring lies on a sphere to the rounding of its
 * coordinates, ADAPTIVE takes MWSELR's normal, exact there (Max 1999),
 * where the jet is only O(h^3): Blender's 16 x 8 UV sphere (float32, as
 * glTF stores it), also when its float32 values come as float64 (vnconvert
 * passes joined primitives so), and a float64 sphere. A sphere flattened by
 * 1% is no sphere: there ADAPTIVE is not MWSELR. */
static void adaptive_exact_on_spheres(void** state)
{
	(void)state;
	const double c[3] = {0.3, -0.2, 5.0};
	double worst;
	grid_mesh g = make_uv_sphere(16, 8, c, 2.0, 2.0, 1);
	assert_int_equal(adaptive_is_mwselr(&g, 1, c, &worst), g.nv);
	print_message("float32 sphere: adaptive within %g degrees of radial\n", worst);
	assert_true(worst < 1e-4);
	assert_int_equal(adaptive_is_mwselr(&g, 0, c, &worst), g.nv);
	grid_free(&g);
	g = make_uv_sphere(16, 8, c, 2.0, 2.0, 0);
	assert_int_equal(adaptive_is_mwselr(&g, 0, c, &worst), g.nv);
	print_message("float64 sphere: adaptive within %g degrees of radial\n", worst);
	assert_true(worst < 1e-9);
	double* jet = (double*)malloc(3 * sizeof(double) * g.nv);
	assert_int_equal(tri(g.pos, g.nv, g.idx, g.ni, vn_method_jet, 1, jet), vn_result_success);
	const double radial[3] = {g.pos[3 * 20] - c[0], g.pos[3 * 20 + 1] - c[1], g.pos[3 * 20 + 2] - c[2]};
	assert_true(angle_deg(jet + 3 * 20, radial) > 0.01); /* the jet is not exact there */
	free(jet);
	/* Its quads as polygons (the poles' fans stay triangles): the 2-ring
	 * takes the quads' far corners too, on the sphere as well. */
	const size_t nq = g.ni / 6 - 16; /* 6 indices: a quad's two triangles, or a segment's two fans */
	uint32_t* poly = (uint32_t*)malloc(sizeof(uint32_t) * (4 * nq + 3 * 2 * 16));
	uint32_t* offsets = (uint32_t*)malloc(sizeof(uint32_t) * (nq + 2 * 16 + 1));
	size_t np = 0, nf = 0;
	for (size_t t = 0; t < g.ni; t += 6) {
		const uint32_t* x = g.idx + t;
		const int fans = t % (6 * 7) == 0; /* each segment: its two fans, then its 6 quads */
		const uint32_t corners[2][4] = {{x[0], x[1], x[2], 0}, {x[3], x[4], x[5], 0}}, quad[4] = {x[0], x[1], x[5], x[2]};
		for (int k = 0; k < (fans ? 2 : 1); ++k) {
			offsets[nf++] = (uint32_t)np;
			memcpy(poly + np, fans ? corners[k] : quad, (fans ? 3 : 4) * sizeof(uint32_t)), np += fans ? 3 : 4;
		}
	}
	offsets[nf] = (uint32_t)np;
	double* out[2];
	const vn_positions pp = {g.pos, g.nv, 0, vn_scalar_float64};
	for (int k = 0; k < 2; ++k) {
		out[k] = (double*)malloc(3 * sizeof(double) * g.nv);
		const vn_vectors o = {out[k], 0, vn_scalar_float64};
		assert_int_equal(vn_polygon_normals(&o, &pp, poly, offsets, nf, k ? vn_method_mwselr : vn_method_adaptive,
		                                    NULL, NULL),
		                 vn_result_success);
	}
	assert_memory_equal(out[0], out[1], 3 * sizeof(double) * g.nv);
	free(poly), free(offsets), free(out[0]), free(out[1]);
	grid_free(&g);
	g = make_uv_sphere(16, 8, c, 2.0, 1.98, 1);
	const size_t same = adaptive_is_mwselr(&g, 1, c, &worst);
	print_message("flattened sphere: %zu of %zu vertices take MWSELR\n", same, g.nv);
	assert_true(same < g.nv / 4);
	grid_free(&g);
}

/* vn_coordinate_rounding of n <= 3 float64 vertices (x[i], 0, 0). */
static void rounding_of(const double* x, size_t n, double* unit, double* quantum)
{
	double p[9] = {0};
	for (size_t i = 0; i < n; ++i)
		p[3 * i] = x[i];
	vn_work w;
	memset(&w, 0, sizeof(w));
	w.positions = (const unsigned char*)p, w.stride = 3 * sizeof(double), w.type = vn_scalar_float64;
	w.vertex_count = (uint32_t)n;
	vn_coordinate_rounding(&w, unit, quantum);
}

/* The rounding ADAPTIVE's sphere test allows coordinates, by hand: float32
 * values; decimals (fixed places and significant digits: 0.25 is 2 places
 * and 2 digits, 1e-5 5 places and 1 digit); no fixed places past 12, but
 * digits at any exponent (printf's where 10^k is not exact); float64 where a
 * coordinate needs 16 digits or more. */
static void coordinate_rounding_by_hand(void** state)
{
	(void)state;
	double unit, quantum;
	const double floats[3] = {0.5, 1.25, -3.0};
	rounding_of(floats, 3, &unit, &quantum);
	assert_true(unit == FLT_EPSILON / 2 && quantum == 0.0);
	const double places[3] = {0.1, -0.25, 1e-5}; /* 5 places, 2 digits */
	rounding_of(places, 3, &unit, &quantum);
	assert_true(fabs(unit - 0.05) < 1e-17 && fabs(quantum - 5e-6) < 1e-21);
	const double obj[3] = {0.995185, -2.480785, 1234.5}; /* Blender's OBJ: 6 places; 7 digits */
	rounding_of(obj, 3, &unit, &quantum);
	assert_true(fabs(unit - 5e-7) < 1e-22 && fabs(quantum - 5e-7) < 1e-22);
	const double stl[3] = {9.951847e-01, 6.123234e-17, -2.5e+30}; /* %e: 7 digits, places past 12 */
	rounding_of(stl, 3, &unit, &quantum);
	assert_true(fabs(unit - 5e-7) < 1e-22 && quantum == 0.0);
	const double tiny[3] = {1e-300, 4.9406564584124654e-324, 1e22}; /* 1 digit each, the middle one a subnormal */
	rounding_of(tiny, 3, &unit, &quantum);
	assert_true(unit == 0.5 && quantum == 0.0);
	const double sum[3] = {0.1 + 0.2, 1.0, 2.0}; /* 0.30000000000000004: 17 digits */
	rounding_of(sum, 3, &unit, &quantum);
	assert_true(unit == DBL_EPSILON / 2 && quantum == 0.0);
	const double powers[3] = {9.999999, 10.0, 0.001}; /* near and at powers of ten: 7 digits, 6 places */
	rounding_of(powers, 3, &unit, &quantum);
	assert_true(fabs(unit - 5e-7) < 1e-22 && fabs(quantum - 5e-7) < 1e-22);
}

/* g's positions as text writes them: printf's `format`, read back by
 * strtod (a correctly rounding reader, as vn's). */
static void as_text(grid_mesh* g, const char* format)
{
	char text[64];
	for (size_t i = 0; i < 3 * g->nv; ++i) {
		snprintf(text, sizeof(text), format, g->pos[i]);
		g->pos[i] = strtod(text, NULL);
	}
}

/* The same where the coordinates were read from text with few digits: 6
 * places (Blender's OBJ), 7 significant digits (ASCII STL's %e). Their
 * rounding is the text's: the float64 sphere's rule would not hold them
 * (one coordinate off the decimals, 1 ulp, and ADAPTIVE is MWSELR at few
 * vertices); 1% flattened is still no sphere. */
static void adaptive_exact_on_decimal_spheres(void** state)
{
	(void)state;
	const double c[3] = {0.3, -0.2, 5.0};
	const char* formats[2] = {"%.6f", "%.6e"};
	double worst;
	for (int k = 0; k < 2; ++k) {
		grid_mesh g = make_uv_sphere(16, 8, c, 2.0, 2.0, 0);
		as_text(&g, formats[k]);
		assert_int_equal(adaptive_is_mwselr(&g, 0, c, &worst), g.nv);
		print_message("sphere as %s text: adaptive within %g degrees of radial\n", formats[k], worst);
		assert_true(worst < 1e-3);
		g.pos[3 * 40 + 1] = nextafter(g.pos[3 * 40 + 1], 1.0);
		const size_t same = adaptive_is_mwselr(&g, 0, c, &worst);
		print_message("one coordinate 1 ulp off: %zu of %zu vertices take MWSELR\n", same, g.nv);
		assert_true(same < g.nv / 4);
		grid_free(&g);
	}
	/* A small sphere near the origin with a vertex at 12345.678901 (no face
	 * uses it), 6 places: 11 digits, whose unit is far below the places'
	 * rounding of the sphere's coordinates (half of 1e-6). */
	const double o[3] = {0.01, -0.02, 0.03};
	grid_mesh g = make_uv_sphere(16, 8, o, 0.5, 0.5, 0);
	g.pos = (double*)realloc(g.pos, 3 * sizeof(double) * ++g.nv);
	const double far[3] = {12345.678901, 0.0, 0.0};
	memcpy(g.pos + 3 * (g.nv - 1), far, sizeof(far));
	as_text(&g, formats[0]);
	assert_int_equal(adaptive_is_mwselr(&g, 0, o, &worst), g.nv);
	print_message("small sphere as %s text, 11 digits: adaptive within %g degrees of radial\n", formats[0], worst);
	assert_true(worst < 1e-3);
	grid_free(&g);
	g = make_uv_sphere(16, 8, c, 2.0, 1.98, 0);
	as_text(&g, formats[0]);
	const size_t same = adaptive_is_mwselr(&g, 0, c, &worst);
	print_message("flattened sphere as text: %zu of %zu vertices take MWSELR\n", same, g.nv);
	assert_true(same < g.nv / 4);
	grid_free(&g);
}

static void threads_bit_identical(void** state)
{
	(void)state;
	grid_mesh g = make_surface(1, 256, 160, 0.3);
	double* a = (double*)malloc(3 * sizeof(double) * g.nv);
	double* b = (double*)malloc(3 * sizeof(double) * g.nv);
	for (size_t k = 0; k < sizeof(fits) / sizeof(fits[0]); ++k) {
		assert_int_equal(tri(g.pos, g.nv, g.idx, g.ni, fits[k], 1, a), vn_result_success);
		for (unsigned t = 2; t <= 4; t += 2) {
			assert_int_equal(tri(g.pos, g.nv, g.idx, g.ni, fits[k], t, b), vn_result_success);
			assert_memory_equal(a, b, 3 * sizeof(double) * g.nv);
		}
	}
	free(a), free(b);
	grid_free(&g);
}

/* A vertex with a NaN coordinate makes its faces unusable: the fits come
 * out as if those faces were not in the mesh, bit for bit, with SIMD and
 * without, through both entries. */
static void nonfinite_vertex_as_if_absent(void** state)
{
	(void)state;
	grid_mesh g = make_surface(1, 24, 12, 0.3);
	const uint32_t bad = 5 * 24 + 7;
	g.pos[3 * bad + 1] = NAN;
	uint32_t* kept = (uint32_t*)malloc(sizeof(uint32_t) * g.ni);
	size_t nk = 0;
	for (size_t f = 0; f < g.ni; f += 3)
		if (g.idx[f] != bad && g.idx[f + 1] != bad && g.idx[f + 2] != bad)
			memcpy(kept + nk, g.idx + f, 3 * sizeof(uint32_t)), nk += 3;
	assert_int_equal(nk, g.ni - 18); /* valence 6 */
	double* a = (double*)malloc(3 * sizeof(double) * g.nv);
	double* b = (double*)malloc(3 * sizeof(double) * g.nv);
	const vn_positions p = {g.pos, g.nv, 0, vn_scalar_float64};
	const vn_vectors oa = {a, 0, vn_scalar_float64}, ob = {b, 0, vn_scalar_float64};
	/* The polygon entry too, each triangle a face: its usability is decided
	 * apart from the triangles'. */
	uint32_t* offsets = (uint32_t*)malloc(sizeof(uint32_t) * (g.ni / 3 + 1));
	for (size_t f = 0; f <= g.ni / 3; ++f)
		offsets[f] = (uint32_t)(3 * f);
	for (int entry = 0; entry < 4; ++entry)
		for (size_t k = 0; k < sizeof(fits) / sizeof(fits[0]); ++k) {
			vn_options opt;
			memset(&opt, 0, sizeof(opt));
			opt.simd = entry & 1 ? vn_simd_auto : vn_simd_off;
			if (entry & 2) {
				assert_int_equal(vn_polygon_normals(&oa, &p, g.idx, offsets, g.ni / 3, fits[k], &opt, NULL),
				                 vn_result_success);
				assert_int_equal(vn_polygon_normals(&ob, &p, kept, offsets, nk / 3, fits[k], &opt, NULL),
				                 vn_result_success);
			} else {
				assert_int_equal(vn_triangle_normals(&oa, &p, g.idx, g.ni, fits[k], &opt, NULL), vn_result_success);
				assert_int_equal(vn_triangle_normals(&ob, &p, kept, nk, fits[k], &opt, NULL), vn_result_success);
			}
			assert_memory_equal(a, b, 3 * sizeof(double) * g.nv);
			assert_vec(a + 3 * bad, 0, 0, 0, 0);
			for (size_t v = 0; v < g.nv; ++v) { /* every other vertex a unit vector */
				const double* n = a + 3 * v;
				if (v != bad && !(fabs(sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1) <= 1e-12))
					fail_msg("%s, vertex %zu: (%g, %g, %g)", vn_method_name(fits[k]), v, n[0], n[1], n[2]);
			}
		}
	free(a), free(b), free(kept), free(offsets);
	grid_free(&g);
}

/* A face of zero area joins its corners to the rings: they are samples of
 * the surface like any other. The origin on z = xy has three triangles (3
 * members and itself: too few for the quadric's 6 unknowns, so alone it
 * keeps MWA's normal) and a sliver along the x axis, where z = xy is 0, to
 * (0.5, 0, 0) and (1.2, 0, 0). With those two, QUADRIC is the quadric fit
 * over all five members (vn_fit_frame in MWA's frame, then in the
 * result's), 22 degrees from MWA's; JET (whose 2-ring has no more points)
 * and ADAPTIVE fall back to it. The sliver's other corners have no area at
 * all: zero, as with MWA. */
static void zero_area_face_joins_rings(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0.2, 0.2, -0.6, 0.9, -0.54, -0.3, -1, 0.3, 0.5, 0, 0, 1.2, 0, 0};
	const uint32_t idx[] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 0, 4, 5};
	double mwa[18], out[18], first[3], fit[3], scratch[16 * 5], h = 0;
	for (int i = 1; i < 6; ++i)
		h += sqrt(pos[3 * i] * pos[3 * i] + pos[3 * i + 1] * pos[3 * i + 1] + pos[3 * i + 2] * pos[3 * i + 2]) / 5;
	assert_int_equal(tri(pos, 6, idx, 12, vn_method_mwa, 1, mwa), vn_result_success);
	assert_true(vn_fit_frame(pos + 3, 5, h, scratch, mwa, 2, first, NULL));
	assert_true(vn_fit_frame(pos + 3, 5, h, scratch, first, 2, fit, NULL));
	assert_true(fit[0] * mwa[0] + fit[1] * mwa[1] + fit[2] * mwa[2] < cos(20 * PI / 180));
	for (size_t k = 1; k < sizeof(fits) / sizeof(fits[0]); ++k) {
		assert_int_equal(tri(pos, 6, idx, 12, fits[k], 1, out), vn_result_success);
		assert_vec(out, fit[0], fit[1], fit[2], 1e-14);
		assert_vec(out + 12, 0, 0, 0, 0);
		assert_vec(out + 15, 0, 0, 0, 0);
	}
}

/* A tetrahedron (valence 3), one triangle, an isolated vertex (6), and a
 * vertex (7) whose 1-ring (8..12) is collinear: too few points or an
 * ill-conditioned system, so QUADRIC, JET and ADAPTIVE give the seed, MWA's
 * normal, and SMEWCSA a unit vector; never NaN. */
static void degenerate_rings(void** state)
{
	(void)state;
	const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, /* tetrahedron 0..3 */
	                      5, 0, 0, 6, 0, 0,                   /* 4, 5: with 13, a lone triangle */
	                      9, 9, 9,                            /* 6: isolated */
	                      0, 1, 5,                            /* 7: over a line */
	                      -2, 0, 5, -1, 0, 5, 0, 0, 5, 1, 0, 5, 2, 0, 5, /* 8..12 */
	                      5, 1, 0};
	const uint32_t idx[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 4, 5, 13,
	                        7, 8, 9, 7, 9, 10, 7, 10, 11, 7, 11, 12};
	double seed[42], out[42];
	assert_int_equal(tri(pos, 14, idx, 27, vn_method_mwa, 1, seed), vn_result_success);
	for (size_t k = 0; k < sizeof(fits) / sizeof(fits[0]); ++k) {
		assert_int_equal(tri(pos, 14, idx, 27, fits[k], 1, out), vn_result_success);
		for (int i = 0; i < 42; ++i)
			assert_true(isfinite(out[i]));
		assert_vec(out + 18, 0, 0, 0, 0); /* isolated */
		assert_vec(out + 12, 0, 0, 1, 1e-15); /* the lone triangle */
		if (fits[k] == vn_method_smewcsa)
			continue;
		assert_memory_equal(out, seed, 4 * 3 * sizeof(double)); /* valence 3: 4 points < 6 unknowns */
		assert_memory_equal(out + 21, seed + 21, 3 * sizeof(double)); /* collinear */
	}
}

/* z = 0.5 x^2 + 0.2 y^2 on a regular 7 x 7 grid (spacing 0.1) centred on
 * the origin, and at the origin's neighbour H = (0.1, 0) a fan of `spokes`
 * triangles to a circle 0.1 above the surface: H's 1-ring has spokes + 6
 * members. JET at the origin: returns its normal's largest component off
 * (0, 0, 1). */
static double jet_beside_a_hub(uint32_t spokes)
{
	enum { N = 7 };
	const uint32_t nv = N * N + spokes, nt = 2 * (N - 1) * (N - 1) + spokes, hub = 3 * N + 4;
	double* pos = (double*)malloc(3 * sizeof(double) * nv);
	double* out = (double*)malloc(3 * sizeof(double) * nv);
	uint32_t* idx = (uint32_t*)malloc(3 * sizeof(uint32_t) * nt);
	uint32_t t = 0;
	for (int j = 0; j < N; ++j)
		for (int i = 0; i < N; ++i) {
			double* p = pos + 3 * (j * N + i);
			p[0] = 0.1 * (i - 3), p[1] = 0.1 * (j - 3), p[2] = 0.5 * p[0] * p[0] + 0.2 * p[1] * p[1];
			if (i + 1 < N && j + 1 < N) {
				const uint32_t a = (uint32_t)(j * N + i);
				idx[3 * t] = a, idx[3 * t + 1] = a + 1, idx[3 * t + 2] = a + N + 1, ++t;
				idx[3 * t] = a, idx[3 * t + 1] = a + N + 1, idx[3 * t + 2] = a + N, ++t;
			}
		}
	for (uint32_t k = 0; k < spokes; ++k) {
		double* p = pos + 3 * (N * N + k);
		p[0] = 0.1 + 0.05 * cos(2 * PI * k / spokes), p[1] = 0.05 * sin(2 * PI * k / spokes), p[2] = 0.105;
		idx[3 * t] = hub, idx[3 * t + 1] = N * N + k, idx[3 * t + 2] = N * N + (k + 1) % spokes, ++t;
	}
	assert_int_equal(tri(pos, nv, idx, 3 * (size_t)nt, vn_method_jet, 1, out), vn_result_success);
	const double* o = out + 3 * (3 * N + 3);
	const double off = fmax(fmax(fabs(o[0]), fabs(o[1])), fabs(o[2] - 1));
	free(idx), free(out), free(pos);
	return off;
}

/* A hub (more than 256 ring members) is a member of its neighbours' 2-rings
 * but not expanded: the origin's 2-ring stays on the surface and the jet is
 * exact there; with 250 spokes H is expanded and the raised circle tilts it. */
static void hubs_not_expanded(void** state)
{
	(void)state;
	assert_true(jet_beside_a_hub(251) <= 1e-12);
	assert_true(jet_beside_a_hub(250) > 1e-3);
}

/* A cone's fan, apex (0, 0, 0.5) over a circle of 16 points in z = 0: a rim
 * vertex's 2-ring is the rim (on a conic) and the apex, the jet fails
 * there, and ADAPTIVE gives a face-weighted normal, exact on a cone (any
 * symmetric weights are): the cone's normal (cos t, sin t, 2) / sqrt(5). A
 * quadric on its 5-ring (the same points) would go through them all tilted
 * by 40 degrees. */
static void adaptive_cone_rim(void** state)
{
	(void)state;
	enum { K = 16 };
	double pos[3 * (K + 1)] = {0, 0, 0.5}, out[3 * (K + 1)];
	uint32_t idx[3 * K];
	for (int k = 0; k < K; ++k) {
		pos[3 + 3 * k] = cos(2 * PI * k / K), pos[4 + 3 * k] = sin(2 * PI * k / K);
		idx[3 * k] = 0, idx[3 * k + 1] = 1 + (uint32_t)k, idx[3 * k + 2] = 1 + (uint32_t)(k + 1) % K;
	}
	assert_int_equal(tri(pos, K + 1, idx, 3 * K, vn_method_adaptive, 1, out), vn_result_success);
	assert_vec(out, 0, 0, 1, 1e-15);
	for (int k = 0; k < K; ++k)
		assert_vec(out + 3 + 3 * k, cos(2 * PI * k / K) / sqrt(5), sin(2 * PI * k / K) / sqrt(5), 2 / sqrt(5), 1e-12);
}

/* An open cylinder of one strip, 12 sides, 2 high: no vertex has points
 * enough for the jet (10 unknowns) or the 1-ring quadric (6), so ADAPTIVE
 * takes JET's fallback, MWA's normal, exact here: (cos t, sin t, 0). Its
 * rough fallback is S too (the ring is no lattice); MWAAT, that on a
 * lattice, is 5.1 degrees off: at each vertex both triangles of one side's
 * quad meet one of the other's, so areas weigh one side twice, where
 * angles weigh each quad's corner alike. */
static void adaptive_unfit_is_jets_fallback(void** state)
{
	(void)state;
	enum { K = 12 };
	double pos[3 * 2 * K], out[3 * 2 * K];
	uint32_t idx[3 * 2 * K];
	for (int k = 0; k < K; ++k) {
		for (int r = 0; r < 2; ++r)
			pos[3 * (k + r * K)] = cos(2 * PI * k / K), pos[3 * (k + r * K) + 1] = sin(2 * PI * k / K),
			                 pos[3 * (k + r * K) + 2] = 2.0 * r;
		const uint32_t a = (uint32_t)k, b = (uint32_t)(k + 1) % K;
		const uint32_t t[6] = {a, b, b + K, a, b + K, a + K};
		memcpy(idx + 6 * k, t, sizeof(t));
	}
	assert_int_equal(tri(pos, 2 * K, idx, 6 * K, vn_method_adaptive, 1, out), vn_result_success);
	for (int v = 0; v < 2 * K; ++v)
		assert_vec(out + 3 * v, cos(2 * PI * (v % K) / K), sin(2 * PI * (v % K) / K), 0, 1e-12);
}

/* ADAPTIVE's rough fallback on a 5 x 5 grid of unit cells, each split by
 * the same diagonal or (quads) left whole, with heights no cubic follows
 * (the centre's jet leaves residuals above 0.05 h), and on the triangles
 * as float32 with cells of 0.1 at 1000 from the origin (rounding 3e-4 h a
 * coordinate; the test held to 1e-4 h before): at the centre, whose ring is a lattice's (its neighbours in
 * opposite pairs about it), MWAAT's normal, bit for bit; once its right
 * neighbour is moved a tenth of a cell, MWA's, the seed. */
static void adaptive_rough_lattice_is_mwaat(void** state)
{
	(void)state;
	static const double z[25] = {0.4,  -0.3, 0.6,  -0.5, 0.2,  -0.6, 0.5, -0.4, 0.7,  -0.2, 0.3,  -0.7, 0.1,
	                             -0.5, 0.6,  -0.1, 0.4,  -0.6, 0.3,  -0.4, 0.5, -0.2, 0.7,  -0.3, 0.2};
	double pos[75], out[3][75];
	float pos32[75];
	uint32_t idx[96], quads[64], offsets[17];
	for (uint32_t c = 0; c < 16; ++c) {
		const uint32_t a = c / 4 * 5 + c % 4, t[6] = {a, a + 1, a + 6, a, a + 6, a + 5}, q[4] = {a, a + 1, a + 6, a + 5};
		memcpy(idx + 6 * c, t, sizeof(t));
		memcpy(quads + 4 * c, q, sizeof(q));
		offsets[c] = 4 * c;
	}
	offsets[16] = 64;
	const vn_method m[3] = {vn_method_adaptive, vn_method_mwaat, vn_method_mwa};
	for (int layout = 0; layout < 3; ++layout) /* triangles, quads, float32 triangles far out */
		for (int moved = 0; moved < 2; ++moved) {
			const double origin = layout == 2 ? 1000.0 : 0.0, cell = layout == 2 ? 0.1 : 1.0;
			for (uint32_t v = 0; v < 25; ++v) {
				pos[3 * v] = origin + cell * (v % 5 + (v == 13 && moved ? 0.1 : 0.0));
				pos[3 * v + 1] = origin + cell * (v / 5), pos[3 * v + 2] = cell * z[v];
				for (int d = 0; d < 3; ++d)
					pos32[3 * v + d] = (float)pos[3 * v + d];
			}
			const vn_positions p = {pos, 25, 0, vn_scalar_float64}, p32 = {pos32, 25, 0, vn_scalar_float32};
			for (int k = 0; k < 3; ++k) {
				const vn_vectors o = {out[k], 0, vn_scalar_float64};
				assert_int_equal(layout == 1 ? vn_polygon_normals(&o, &p, quads, offsets, 16, m[k], NULL, NULL)
				                             : vn_triangle_normals(&o, layout ? &p32 : &p, idx, 96, m[k], NULL, NULL),
				                 vn_result_success);
			}
			assert_true(angle_deg(out[1] + 36, out[2] + 36) > 0.5); /* MWAAT and MWA are told apart */
			assert_memory_equal(out[0] + 36, out[moved ? 2 : 1] + 36, 3 * sizeof(double));
		}
}

/* A vertex whose 2-ring has 9 members: with the vertex, as many points as
 * the jet's 10 unknowns, so the jet interpolates them, and its residual,
 * zero, says nothing of the surface. Vertex 0 at the centre of a triangle
 * (1, 2, 3) inside a hexagon (4 to 9), heights no cubic follows: JET's
 * interpolant is 11 degrees from MWA's normal; ADAPTIVE takes JET's
 * fallback there, S (the 1-ring is too small for the quadric), as where
 * the jet cannot be fitted. */
static void adaptive_interpolating_jet_is_unfit(void** state)
{
	(void)state;
	static const double pos[30] = {0, 0, 0.1,     0, 1, 0.4,       -0.866, -0.5, -0.3, 0.866, -0.5, 0.2,
	                               1.732, 1, -0.6, 0, 2, 0.9,       -1.732, 1, 0.5,     -1.732, -1, -0.8,
	                               0, -2, 0.7,     1.732, -1, -0.2};
	static const uint32_t idx[36] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 4, 5, 1, 5, 6, 1, 6, 2,
	                                 2, 6, 7, 2, 7, 8, 2, 8, 3, 3, 8, 9, 3, 9, 4, 3, 4, 1};
	double adaptive[30], jet[30], mwa[30];
	assert_int_equal(tri(pos, 10, idx, 36, vn_method_adaptive, 1, adaptive), vn_result_success);
	assert_int_equal(tri(pos, 10, idx, 36, vn_method_jet, 1, jet), vn_result_success);
	assert_int_equal(tri(pos, 10, idx, 36, vn_method_mwa, 1, mwa), vn_result_success);
	assert_true(angle_deg(jet, mwa) > 5);
	assert_memory_equal(adaptive, mwa, 3 * sizeof(double));
}

/* Ring members near the cubic y = 0.5 x^2 + 0.3 x^3 (to 1e-4; coordinates
 * in units of h = 0.1): every Cholesky pivot of the jet's scaled normal
 * matrix is above 1e-7, yet its reciprocal condition is 6.6e-13 (numpy:
 * 1 / (k trace(M~^-1))), so the cubic's coefficients are rounding noise and
 * the fit is refused; the quadric's (2.7e-4) is fine and exact on z = 0. */
static void fit_refuses_ill_conditioned(void** state)
{
	(void)state;
	const double x[] = {0.92, -0.21, 0.74, 0.29, 0.92, 1.23, -0.75, -1.22, -0.62, -0.92, 0.7};
	const double y[] = {0.656696, 0.019382, 0.395478, 0.049256, 0.656696, 1.314821,
	                    0.154798, 0.199335, 0.120812, 0.189704, 0.348011};
	double q[3 * 11], n[3] = {0, 0, 0};
	for (int i = 0; i < 11; ++i)
		q[3 * i] = 0.1 * x[i], q[3 * i + 1] = 0.1 * y[i], q[3 * i + 2] = 0;
	assert_int_equal(fit_ring(q, 11, 3, n, NULL), 0);
	assert_vec(n, 0, 0, 0, 0); /* nothing written */
	assert_int_equal(fit_ring(q, 11, 2, n, NULL), 1);
	assert_vec(n, 0, 0, 1, 1e-12);
}

/* ---------------------------------------------------------------- per corner */

/* With nothing sharp on a closed mesh every corner gets its vertex's
 * normal; with every edge creased (crease angle 0 on a jittered torus),
 * every corner is a fan of its own: the fits give each its fan's MWA
 * normal, and SMEWCSA its fan's MWSELR normal. */
static void corners_follow_the_vertex_rule(void** state)
{
	(void)state;
	grid_mesh g = make_surface(1, 24, 12, 0.3);
	double* vert = (double*)malloc(3 * sizeof(double) * g.nv);
	double* c = (double*)malloc(3 * sizeof(double) * g.ni);
	double* m1 = (double*)malloc(3 * sizeof(double) * g.ni);
	const vn_positions p = {g.pos, g.nv, 0, vn_scalar_float64};
	const vn_vectors oc = {c, 0, vn_scalar_float64}, o1 = {m1, 0, vn_scalar_float64};
	for (size_t k = 0; k < sizeof(fits) / sizeof(fits[0]); ++k) {
		assert_int_equal(tri(g.pos, g.nv, g.idx, g.ni, fits[k], 1, vert), vn_result_success);
		assert_int_equal(vn_corner_normals(&oc, &p, g.idx, g.ni, fits[k], PI, NULL, NULL, NULL), vn_result_success);
		for (size_t i = 0; i < g.ni; ++i)
			assert_memory_equal(c + 3 * i, vert + 3 * (size_t)g.idx[i], 3 * sizeof(double));
		assert_int_equal(vn_corner_normals(&oc, &p, g.idx, g.ni, fits[k], 0, NULL, NULL, NULL), vn_result_success);
		const vn_method seed = fits[k] == vn_method_smewcsa ? vn_method_mwselr : vn_method_mwa;
		assert_int_equal(vn_corner_normals(&o1, &p, g.idx, g.ni, seed, 0, NULL, NULL, NULL), vn_result_success);
		assert_memory_equal(c, m1, 3 * sizeof(double) * g.ni);
	}
	free(m1), free(c), free(vert);
	grid_free(&g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(smewcsa_flips_a_dimple),
	    cmocka_unit_test(smewcsa_keeps_a_bump),
	    cmocka_unit_test(smewcsa_flat_falls_back),
	    cmocka_unit_test(smewcsa_tilted_plane_is_mwselr),
	    cmocka_unit_test(smewcsa_gentle_bowl_keeps_cotangent),
	    cmocka_unit_test(quadric_exact_on_quadric_field),
	    cmocka_unit_test(jet_exact_on_cubic_field),
	    cmocka_unit_test(quadric_not_exact_on_cubic_field),
	    cmocka_unit_test(quadric_converges_as_h2),
	    cmocka_unit_test(jet_converges_as_h3),
	    cmocka_unit_test(mwa_converges_as_h),
	    cmocka_unit_test(torus_outward_everywhere),
	    cmocka_unit_test(adaptive_across_noise),
	    cmocka_unit_test(adaptive_exact_where_mwselr_is),
	    cmocka_unit_test(adaptive_exact_on_spheres),
	    cmocka_unit_test(coordinate_rounding_by_hand),
	    cmocka_unit_test(adaptive_exact_on_decimal_spheres),
	    cmocka_unit_test(threads_bit_identical),
	    cmocka_unit_test(nonfinite_vertex_as_if_absent),
	    cmocka_unit_test(degenerate_rings),
	    cmocka_unit_test(zero_area_face_joins_rings),
	    cmocka_unit_test(hubs_not_expanded),
	    cmocka_unit_test(adaptive_cone_rim),
	    cmocka_unit_test(adaptive_unfit_is_jets_fallback),
	    cmocka_unit_test(adaptive_rough_lattice_is_mwaat),
	    cmocka_unit_test(adaptive_interpolating_jet_is_unfit),
	    cmocka_unit_test(fit_refuses_ill_conditioned),
	    cmocka_unit_test(corners_follow_the_vertex_rule),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
