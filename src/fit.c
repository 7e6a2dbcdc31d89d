/* The fitting family: QUADRIC, JET and ADAPTIVE (vn.h).
 *
 * Per vertex v with seed normal S (MWA's, computed first by the
 * weighted family's kernels):
 *   1. ring: the vertices sharing a usable face with v (a triangle's other
 *      two corners; a polygon's other corners when it has at most
 *      RING_ALL_MAX, else its two edge neighbours); the 2-ring adds the
 *      rings of those. Unusable faces (the seven's degenerate faces: zero or
 *      non-finite area) add nothing, so a non-finite coordinate never enters.
 *   2. h = the mean distance from v to its 1-ring members; every coordinate
 *      is divided by h, so the system's entries are O(1) at any scale.
 *   3. fit (vn_fit_frame): in the frame (t1, t2, a), weighted least squares
 *      of z = f(x, y) over the vertex itself and its ring, f with a constant
 *      term (so the vertex's own position error is averaged, not
 *      interpolated), weights 1 / (1 + r^2) with r the point's distance / h.
 *   4. normal a - f_x t1 - f_y t2, normalized; one refit in its frame.
 * A fit that cannot be trusted falls back: the jet to the quadric on the
 * 1-ring, the quadric to S. Untrusted means fewer points than unknowns, an
 * ill-conditioned system (a Cholesky pivot of the unit-diagonal normal
 * matrix below PIVOT_MIN: some monomial is, to 1e-4 in the weighted norm, a
 * combination of the others, e.g. collinear members; or its reciprocal
 * condition below RCOND_MIN: several such near-dependencies), or a normal more than
 * 60 degrees from S (the neighbourhood is not a height field over S's plane).
 * A vertex with a zero seed (isolated, or every face degenerate) gets zero,
 * as with the seven; every other result is a unit vector with a positive
 * dot product with S. Boundary vertices fit their one-sided rings;
 * non-manifold vertices the union of their sheets' rings.
 *
 * Adjacency: a vertex -> corners table (CSR by counting sort, each worker
 * the vertices of its own range, in corner order), then from it every
 * vertex's 1-ring (CSR, in the order of its corners), built once per call
 * from the allocator; wider rings are gathered from the 1-rings on the fly,
 * deduplicated with a per-worker stamp array. Each vertex's result depends
 * only on data that does not depend on the split, so it is bit-identical
 * for any thread count.
 *
 * Work memory, from the allocator (the workspace serves the seed pass):
 * 24 bytes a vertex (seeds) + 4 a corner + 1 a face (+ 4 a corner for
 * polygons) + 8 a vertex + 4 a 1-ring member + 4 a vertex per thread + ring
 * scratch.
 *
 * ADAPTIVE (vn.h) adds the 4-ring, gathered past the 2-ring up to the ring
 * capacity, and fits a quadric and a cubic there; each vertex keeps two
 * outcomes (the jet or the quadric, the jet or the cubic, by GCV score) and
 * the statistic of its cubic terms, and a last pass takes one outcome by
 * that statistic over the vertex's 1-ring (56 more bytes a vertex); its
 * fallback, MWAAT, is a second pass of the weighted kernels (24 more). */
#include "internal.h"
#include "simd.h"

/* A polygon of more corners gives only its two edge neighbours to a ring:
 * all corners of a large n-gon would make rings quadratic in its size. */
#define RING_ALL_MAX 8
/* Smallest pivot of the unit-diagonal normal matrix's Cholesky factor. */
#define PIVOT_MIN 1e-8
/* Smallest reciprocal condition 1 / (k trace(M~^-1)) of that matrix M~:
 * below it, rounding moves the normal by more than about 1e-13 / RCOND_MIN
 * = 1e-3 radians (pivots alone admit condition numbers up to 1e17). */
#define RCOND_MIN 1e-10
/* The fitted normal must stay within 60 degrees of the seed. */
#define SEED_COS_MIN 0.5
/* ADAPTIVE (docs/ACCURACY.md): the 2-ring jet alone where its weighted RMS
 * residual over h is at most ADAPTIVE_JET_EXACT (exact to its model: no
 * wider fit can do better); the rough fallback where the chosen fit's
 * residual over h exceeds ADAPTIVE_FIT_MAX (no polynomial describes the
 * neighbourhood: fractal or turbulent), both chosen with vneval. The 4-ring
 * cubic rather than the quadric where the mean log T over the 1-ring
 * exceeds log ADAPTIVE_T, T = |slope difference|^2 / its variance: 2 is
 * where the quadric's estimated squared slope bias |d|^2 - var(d) passes
 * the variance the cubic adds, var(d) (nested least squares), so the
 * constant is the mean squared error's break-even, not a fitted one. */
#define ADAPTIVE_JET_EXACT 1e-4
#define ADAPTIVE_FIT_MAX 0.06
#define ADAPTIVE_T 2.0
/* log T is kept within +-T_LOG_MAX (T infinite where the cubic's residual is 0). */
#define T_LOG_MAX 50.0
/* ADAPTIVE's rough fallback: MWAAT, the best of the seven on the paper's
 * fractal height fields (and within 10% of the best on turbulence). */
#define ADAPTIVE_ROUGH vn_method_mwaat
#define MAX_THREADS 256
/* Below this many vertices per worker, a thread costs more than it saves. */
#define MIN_VERTICES_PER_THREAD 4096

/* ---------------------------------------------------------------- the fit */

void vn_fit_prepare(const vn_fit_points* p, double h)
{
	const double inv = 1.0 / h;
	for (uint32_t i = 0; i < p->m; ++i) {
		const double x = p->x[i] * inv, y = p->y[i] * inv, z = p->z[i] * inv;
		p->x[i] = x, p->y[i] = y, p->z[i] = z;
		p->w[i] = 1.0 / (1.0 + (x * x + y * y + z * z));
	}
}

/* Fits run LANES vertices at a time, each step of the arithmetic done for
 * every lane before the next step: a fit is a chain of dependent divisions
 * and square roots, and the lanes' chains overlap (the compiler also maps
 * lanes to SIMD registers). A lane's arithmetic is the same whatever the
 * other lanes hold, so results do not depend on how vertices are batched. */
#define LANES 4
/* Loops over lanes or at most 10 unknowns: unrolled where the count is a
 * constant. */
#if defined(__GNUC__) || defined(__clang__)
#define UNROLL _Pragma("GCC unroll 10")
#else
#define UNROLL
#endif

/* The normal equations are sums over the points of products of monomials,
 * so they are built from the weighted moments: s[d (d + 1) / 2 + j] =
 * sum w x^(d - j) y^j for degrees d <= 2 * degree (15 or 28 numbers instead
 * of 21 or 55 matrix entries) and t, the same with w z, for d <= degree;
 * with sum w z^2 (ZZ), they also give the residual without another pass:
 * sum w e^2 = sum w z^2 - c . t at the solution (M c = t). */
enum { S_MAX = 28, T_MAX = 10, ZZ = S_MAX + T_MAX, MOMENTS = ZZ + 1 };

/* The moment of each entry of the normal matrix: the product of monomials
 * i and l (1, x, y, x^2, xy, y^2, x^3, x^2 y, x y^2, y^3; monomial i is
 * moment i). */
static const unsigned char MOMENT[10][10] = {
	{0, 1, 2, 3, 4, 5, 6, 7, 8, 9},            {1, 3, 4, 6, 7, 8, 10, 11, 12, 13},
	{2, 4, 5, 7, 8, 9, 11, 12, 13, 14},        {3, 6, 7, 10, 11, 12, 15, 16, 17, 18},
	{4, 7, 8, 11, 12, 13, 16, 17, 18, 19},     {5, 8, 9, 12, 13, 14, 17, 18, 19, 20},
	{6, 10, 11, 15, 16, 17, 21, 22, 23, 24},   {7, 11, 12, 16, 17, 18, 22, 23, 24, 25},
	{8, 12, 13, 17, 18, 19, 23, 24, 25, 26},   {9, 13, 14, 18, 19, 20, 24, 25, 26, 27},
};

/* LANES fits: frames (t1, t2, a), coefficients c, unit normals n, the
 * slopes' variance factor vs = (M^-1)_11 + (M^-1)_22, the weighted RMS
 * residual res over h (the vertex included), and whether each
 * succeeded. */
typedef double lanes __attribute__((vector_size(LANES * sizeof(double))));
typedef long long masks __attribute__((vector_size(LANES * sizeof(long long))));
typedef struct fits {
	lanes t1[3], t2[3], a[3], c[10], n[3], vs, res;
	int ok[LANES];
} fits;

/* Points X..W[0..LANES) added to the moments of lane `to` (the points'
 * own lanes are summed in a fixed order at the end). */
VN_INLINE void moments_block(const double* X, const double* Y, const double* Z, const double* W, const fits* f,
                             unsigned to, int cubic, lanes acc[MOMENTS])
{
	lanes px, py, pz, w;
	memcpy(&px, X, sizeof(px)), memcpy(&py, Y, sizeof(py)), memcpy(&pz, Z, sizeof(pz)), memcpy(&w, W, sizeof(w));
	const lanes x = px * f->t1[0][to] + py * f->t1[1][to] + pz * f->t1[2][to];
	const lanes y = px * f->t2[0][to] + py * f->t2[1][to] + pz * f->t2[2][to];
	const lanes z = px * f->a[0][to] + py * f->a[1][to] + pz * f->a[2][to];
	const lanes wx = w * x, wy = w * y, xx = x * x, xy = x * y, yy = y * y;
	const lanes wxx = wx * x, wxy = wx * y, wyy = wy * y, wz = w * z;
	acc[0] += w, acc[1] += wx, acc[2] += wy, acc[3] += wxx, acc[4] += wxy, acc[5] += wyy;
	acc[ZZ] += wz * z;
	acc[S_MAX] += wz, acc[S_MAX + 1] += wz * x, acc[S_MAX + 2] += wz * y;
	acc[S_MAX + 3] += wz * xx, acc[S_MAX + 4] += wz * xy, acc[S_MAX + 5] += wz * yy;
	if (!cubic) {
		acc[6] += wxx * x, acc[7] += wxx * y, acc[8] += wxy * y, acc[9] += wyy * y;
		acc[10] += wxx * xx, acc[11] += wxx * xy, acc[12] += wxx * yy, acc[13] += wxy * yy, acc[14] += wyy * yy;
		return;
	}
	const lanes wxxx = wxx * x, wxxy = wxx * y, wxyy = wxy * y, wyyy = wyy * y;
	const lanes xxx = xx * x, xxy = xx * y, xyy = x * yy, yyy = yy * y;
	acc[6] += wxxx, acc[7] += wxxy, acc[8] += wxyy, acc[9] += wyyy;
	acc[10] += wxxx * x, acc[11] += wxxx * y, acc[12] += wxxy * y, acc[13] += wxyy * y, acc[14] += wyyy * y;
	acc[15] += wxxx * xx, acc[16] += wxxx * xy, acc[17] += wxxx * yy;
	acc[18] += wxxy * yy, acc[19] += wxyy * yy, acc[20] += wyyy * yy;
	acc[21] += wxxx * xxx, acc[22] += wxxx * xxy, acc[23] += wxxx * xyy, acc[24] += wxxx * yyy;
	acc[25] += wxxy * yyy, acc[26] += wxyy * yyy, acc[27] += wyyy * yyy;
	acc[S_MAX + 6] += wz * xxx, acc[S_MAX + 7] += wz * xxy, acc[S_MAX + 8] += wz * xyy, acc[S_MAX + 9] += wz * yyy;
}

/* The moments of lane `to`'s points in its frame, into s[.][to] (the
 * vertex itself, the origin with weight 1, included), t[.][to] and
 * zz[to]. */
VN_INLINE void moments(const vn_fit_points* p, const fits* f, unsigned to, int cubic, lanes s[S_MAX], lanes t[T_MAX],
                       lanes* zz)
{
	const int ns = cubic ? S_MAX : 15, nt = cubic ? T_MAX : 6;
	const lanes zero = {0.0, 0.0, 0.0, 0.0};
	lanes acc[MOMENTS];
	UNROLL for (int q = 0; q < ns; ++q)
		acc[q] = zero;
	UNROLL for (int q = 0; q < nt; ++q)
		acc[S_MAX + q] = zero;
	acc[ZZ] = zero;
	uint32_t i = 0;
	for (; i + LANES <= p->m; i += LANES)
		moments_block(p->x + i, p->y + i, p->z + i, p->w + i, f, to, cubic, acc);
	if (i < p->m) { /* the rest, padded with weight-0 points at the origin: they add +0 */
		double tail[4][LANES];
		memset(tail, 0, sizeof(tail));
		for (uint32_t l = 0; i + l < p->m; ++l)
			tail[0][l] = p->x[i + l], tail[1][l] = p->y[i + l], tail[2][l] = p->z[i + l], tail[3][l] = p->w[i + l];
		moments_block(tail[0], tail[1], tail[2], tail[3], f, to, cubic, acc);
	}
	UNROLL for (int q = 0; q < ns; ++q)
		s[q][to] = (acc[q][0] + acc[q][1]) + (acc[q][2] + acc[q][3]);
	UNROLL for (int q = 0; q < nt; ++q)
		t[q][to] = (acc[S_MAX + q][0] + acc[S_MAX + q][1]) + (acc[S_MAX + q][2] + acc[S_MAX + q][3]);
	(*zz)[to] = (acc[ZZ][0] + acc[ZZ][1]) + (acc[ZZ][2] + acc[ZZ][3]);
	s[0][to] += 1.0;
}

/* Solves M c = t for each lane's k x k normal matrix (M_il = s[MOMENT[i][l]])
 * by LDL^T with reciprocal pivots; a lane fails when a pivot of its M scaled
 * to unit diagonal (D_j / M_jj) is below PIVOT_MIN (some monomial is, to
 * 1e-4 in the weighted norm, a combination of the others) or its
 * reciprocal condition is below RCOND_MIN. zz is sum w z^2, for the
 * residual. Inlined with k a constant, so the loops unroll. */
VN_INLINE void solve(const lanes s[S_MAX], const lanes t_in[T_MAX], const lanes* zz, int k, fits* f)
{
	lanes L[10][10], U[10][10], inv[10], t[10];
	memcpy(t, t_in, sizeof(lanes) * (size_t)k);
	const lanes one = {1.0, 1.0, 1.0, 1.0};
	UNROLL for (int j = 0; j < k; ++j) {
		lanes d = s[MOMENT[j][j]];
		UNROLL for (int p = 0; p < j; ++p)
			d -= U[j][p] * L[j][p];
		const masks good = (d > 0.0) & (d >= PIVOT_MIN * s[MOMENT[j][j]]);
		UNROLL for (int l = 0; l < LANES; ++l)
			f->ok[l] &= good[l] != 0;
		inv[j] = one / (lanes)(((masks)d & good) | ((masks)one & ~good));
		UNROLL for (int i = j + 1; i < k; ++i) {
			lanes x = s[MOMENT[i][j]];
			UNROLL for (int p = 0; p < j; ++p)
				x -= L[i][p] * U[j][p];
			U[i][j] = x, L[i][j] = x * inv[j];
		}
	}
	/* The condition: trace(M~^-1) = sum_j M_jj (M^-1)_jj, M~ = M scaled to
	 * unit diagonal; M^-1 = L^-T D^-1 L^-1, so (M^-1)_jj = sum_i>=j
	 * (L^-1)_ij^2 / D_i, column j of L^-1 by forward substitution. The
	 * slopes' (j = 1, 2) are kept for ADAPTIVE's test. */
	lanes trace = one - one;
	f->vs = trace;
	UNROLL for (int j = 0; j < k; ++j) {
		lanes x[10], sum = inv[j];
		x[j] = one;
		UNROLL for (int i = j + 1; i < k; ++i) {
			x[i] = -L[i][j];
			UNROLL for (int p = j + 1; p < i; ++p)
				x[i] -= L[i][p] * x[p];
			sum += x[i] * x[i] * inv[i];
		}
		trace += s[MOMENT[j][j]] * sum;
		if (j == 1 || j == 2)
			f->vs += sum;
	}
	/* 1 / (k trace) below RCOND_MIN: fail. */
	const masks conditioned = trace * (double)k <= 1.0 / RCOND_MIN;
	UNROLL for (int l = 0; l < LANES; ++l)
		f->ok[l] &= conditioned[l] != 0;
	UNROLL for (int i = 0; i < k; ++i) /* forward: t becomes L^-1 t */
		UNROLL for (int p = 0; p < i; ++p)
			t[i] -= L[i][p] * t[p];
	UNROLL for (int i = k - 1; i >= 0; --i) {
		f->c[i] = t[i] * inv[i];
		UNROLL for (int p = i + 1; p < k; ++p)
			f->c[i] -= L[p][i] * f->c[p];
	}
	UNROLL for (int i = k; i < 10; ++i) /* a quadric's cubic terms */
		f->c[i] = one - one;
	/* sum w e^2 = sum w z^2 - c . t: its rounding error is about eps sum w
	 * z^2, far below any residual ADAPTIVE compares (clamped at 0). */
	lanes e2 = *zz;
	UNROLL for (int i = 0; i < k; ++i)
		e2 -= f->c[i] * t_in[i];
	UNROLL for (int l = 0; l < LANES; ++l) /* s[0] = sum w >= 1 where the lane is active */
		f->res[l] = e2[l] > 0.0 && s[0][l] > 0.0 ? sqrt(e2[l] / s[0][l]) : 0.0;
}

/* The unit normal of each lane's fit, or ok cleared. */
VN_INLINE void fit_normals(fits* f)
{
	UNROLL for (int l = 0; l < LANES; ++l) {
		double n[3];
		UNROLL for (int d = 0; d < 3; ++d)
			n[d] = f->a[d][l] - f->c[1][l] * f->t1[d][l] - f->c[2][l] * f->t2[d][l];
		f->ok[l] &= !vn_normalize(n);
		UNROLL for (int d = 0; d < 3; ++d)
			f->n[d][l] = n[d];
	}
}

/* Fits the active lanes' points p[l] in the frames of the unit axes
 * a[.][l]; the others fail. kind 0: the quadric into f[0]; 1: the cubic
 * into f[0]; 2: both from one pass over the points, the quadric into f[0]
 * and the cubic into f[1] (the quadric's moments are a subset of the
 * cubic's, so each equals its own fit bit for bit). */
VN_INLINE void fit_lanes(const vn_fit_points p[LANES], const int act[LANES], lanes a[3], int kind, fits* f)
{
	const int k = kind == 1 ? 10 : 6;
	/* A unit tangent pair without a square root (Duff et al. 2017). */
	UNROLL for (int l = 0; l < LANES; ++l) {
		const double x = a[0][l], y = a[1][l], z = a[2][l], sign = copysign(1.0, z);
		const double A = -1.0 / (sign + z), B = x * y * A;
		f->t1[0][l] = 1.0 + sign * x * x * A, f->t1[1][l] = sign * B, f->t1[2][l] = -sign * x;
		f->t2[0][l] = B, f->t2[1][l] = sign + y * y * A, f->t2[2][l] = -y;
		f->a[0][l] = x, f->a[1][l] = y, f->a[2][l] = z;
		f->ok[l] = act[l] && p[l].m + 1 >= (uint32_t)k;
	}
	lanes s[S_MAX], t[T_MAX], zz;
	for (unsigned l = 0; l < LANES; ++l) {
		if (f->ok[l])
			moments(p + l, f, l, kind != 0, s, t, &zz);
		else { /* zero: fails the first pivot */
			UNROLL for (int q = 0; q < S_MAX; ++q)
				s[q][l] = 0.0;
			UNROLL for (int q = 0; q < T_MAX; ++q)
				t[q][l] = 0.0;
			zz[l] = 0.0;
		}
	}
	if (kind == 2) {
		memcpy(f[1].t1, f->t1, sizeof(f->t1)), memcpy(f[1].t2, f->t2, sizeof(f->t2)), memcpy(f[1].a, f->a, sizeof(f->a));
		UNROLL for (int l = 0; l < LANES; ++l)
			f[1].ok[l] = f->ok[l] && p[l].m + 1 >= 10;
		solve(s, t, &zz, 10, f + 1);
		fit_normals(f + 1);
	}
	solve(s, t, &zz, k, f);
	fit_normals(f);
}

static void fit_quadrics(const vn_fit_points p[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(p, act, a, 0, f);
}

static void fit_jets(const vn_fit_points p[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(p, act, a, 1, f);
}

static void fit_pairs(const vn_fit_points p[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(p, act, a, 2, f);
}

/* The same arithmetic in AVX2 registers: the same results, bit for bit
 * (IEEE operations lane by lane, no FMA, sums in the same order). */
typedef void (*fit_fn)(const vn_fit_points*, const int*, lanes*, fits*);
static const fit_fn fit_kinds[3] = {fit_quadrics, fit_jets, fit_pairs};
#ifdef VN_HAVE_AVX2
static VN_AVX2 void fit_quadrics_avx2(const vn_fit_points p[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(p, act, a, 0, f);
}

static VN_AVX2 void fit_jets_avx2(const vn_fit_points p[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(p, act, a, 1, f);
}

static VN_AVX2 void fit_pairs_avx2(const vn_fit_points p[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(p, act, a, 2, f);
}

static const fit_fn fit_kinds_avx2[3] = {fit_quadrics_avx2, fit_jets_avx2, fit_pairs_avx2};

static fit_fn fit_kernel(int kind, int simd)
{
	return (simd ? fit_kinds_avx2 : fit_kinds)[kind];
}
#else
static fit_fn fit_kernel(int kind, int simd)
{
	(void)simd;
	return fit_kinds[kind];
}
#endif

/* Lane l of fit r, if it succeeded within 60 degrees of the seed: its
 * normal into n and, when res is not NULL, its residual; returns whether. */
static int take(const fits* r, int first_ok, unsigned l, const double* seed, double n[3], double* res)
{
	if (!(first_ok && r->n[0][l] * seed[0] + r->n[1][l] * seed[1] + r->n[2][l] * seed[2] >= SEED_COS_MIN))
		return 0;
	for (int d = 0; d < 3; ++d)
		n[d] = r->n[d][l];
	if (res)
		*res = r->res[l];
	return 1;
}

/* The fit in the seed's frame, then once more in the result's, for the
 * active lanes: ok[l] says whether n[l] was written (0 when the first fit
 * fails or the result strays from the seed); res[l] is the residual of the
 * fit written, computed only when res is not NULL. */
static void fit_twice(const vn_fit_points p[LANES], const int act[LANES], const double* const seed[LANES], int cubic,
                      int simd, double n[LANES][3], int ok[LANES], double res[LANES])
{
	fits f[2];
	lanes a[3];
	for (int l = 0; l < LANES; ++l)
		for (int d = 0; d < 3; ++d)
			a[d][l] = act[l] ? seed[l][d] : (d == 2);
	const fit_fn fit = fit_kernel(cubic, simd);
	fit(p, act, a, f);
	fit(p, f[0].ok, f[0].n, f + 1);
	for (unsigned l = 0; l < LANES; ++l)
		ok[l] = take(f[1].ok[l] ? f + 1 : f, f[0].ok[l], l, seed[l], n[l], res ? res + l : NULL);
}

int vn_fit_frame(const vn_fit_points* p, const double a[3], int degree, double n[3], double* residual)
{
	vn_fit_points q[LANES];
	memset(q, 0, sizeof(q));
	q[0] = *p;
	const int act[LANES] = {1, 0, 0, 0};
	lanes axis[3] = {{a[0], 0, 0, 0}, {a[1], 0, 0, 0}, {a[2], 1, 1, 1}};
	fits f;
	(degree == 3 ? fit_jets : fit_quadrics)(q, act, axis, &f);
	if (!f.ok[0])
		return 0;
	for (int d = 0; d < 3; ++d)
		n[d] = f.n[d][0];
	if (residual)
		*residual = f.res[0];
	return 1;
}

/* ---------------------------------------------------------------- adjacency */

typedef struct scratch {
	uint32_t* stamp; /* nv: the tag of the ring a vertex was last added to */
	uint32_t tag;
	uint32_t* ring;  /* up to cap members (and room for one more) */
	double* q;       /* per lane 4 cap: members' x, y, z (minus the vertex's, then over h), weight */
	size_t cap;
} scratch;

typedef struct fit_job {
	vn_work w;
	const double* seed;    /* 3 per vertex */
	const double* rough;   /* ADAPTIVE: 3 per vertex, ADAPTIVE_ROUGH's normals */
	double* pick;          /* ADAPTIVE: 7 per vertex: the outcomes (adaptive_lanes), log T */
	unsigned char* usable; /* per face */
	uint32_t* face_of;     /* polygons: per corner */
	uint32_t* start;       /* nv + 1: counts, then where each vertex's corners end */
	uint32_t* list;        /* corners by vertex, in corner order */
	uint32_t* top;         /* per worker: its largest 1-ring candidate count */
	uint32_t* nstart;      /* nv + 1: where each vertex's 1-ring begins in nbr */
	uint32_t* nbr;         /* every vertex's 1-ring, as gather lists it */
	scratch* scratch;      /* per worker */
	unsigned nt;
} fit_job;

VN_INLINE uint32_t range_lo(uint32_t count, unsigned t, unsigned nt)
{
	return (uint32_t)((uint64_t)count * t / nt);
}

VN_INLINE uint32_t corner_count(const vn_work* w)
{
	return w->offsets ? w->offsets[w->face_count] : (uint32_t)(3 * w->face_count);
}

/* Faces' usability and each worker's vertices' corner counts. */
static void phase_count(void* ctx, unsigned t)
{
	fit_job* j = (fit_job*)ctx;
	const vn_work* w = &j->w;
	const uint32_t nf = (uint32_t)w->face_count;
	for (uint32_t f = range_lo(nf, t, j->nt), f1 = range_lo(nf, t + 1, j->nt); f < f1; ++f) {
		double n[3];
		if (w->offsets) {
			const uint32_t b = w->offsets[f], k = w->offsets[f + 1] - b;
			j->usable[f] = (unsigned char)(k >= 3 && vn_face_normal(w, w->indices + b, k, n));
			for (uint32_t c = b; c < b + k; ++c)
				j->face_of[c] = f;
		} else {
			double p[3][3], e01[3], e12[3], e20[3];
			for (int i = 0; i < 3; ++i)
				vn_load(w, w->type, w->indices[3 * (size_t)f + i], p[i]);
			j->usable[f] = (unsigned char)vn_usable(vn_triangle_edges(p[0], p[1], p[2], e01, e12, e20, n));
		}
	}
	const uint32_t v0 = range_lo(w->vertex_count, t, j->nt), span = range_lo(w->vertex_count, t + 1, j->nt) - v0;
	uint32_t* count = j->start + 1;
	memset(count + v0, 0, sizeof(uint32_t) * span);
	const uint32_t n = corner_count(w);
	for (uint32_t c = 0; c < n; ++c)
		if (w->indices[c] - v0 < span)
			++count[w->indices[c]];
}

/* The face of corner c, its first corner and its size. */
VN_INLINE uint32_t face_at(const fit_job* j, uint32_t c, uint32_t* b, uint32_t* k)
{
	if (!j->w.offsets) {
		*b = c - c % 3, *k = 3;
		return c / 3;
	}
	const uint32_t f = j->face_of[c];
	*b = j->w.offsets[f], *k = j->w.offsets[f + 1] - *b;
	return f;
}

/* Each worker lists its vertices' corners (start[v] moves from v's first
 * to past its last) and finds its largest 1-ring candidate count. */
static void phase_list(void* ctx, unsigned t)
{
	fit_job* j = (fit_job*)ctx;
	const vn_work* w = &j->w;
	const uint32_t v0 = range_lo(w->vertex_count, t, j->nt), v1 = range_lo(w->vertex_count, t + 1, j->nt);
	const uint32_t n = corner_count(w);
	uint32_t begin = v0 < v1 ? j->start[v0] : 0;
	for (uint32_t c = 0; c < n; ++c)
		if (w->indices[c] - v0 < v1 - v0)
			j->list[j->start[w->indices[c]]++] = c;
	uint32_t top = 0;
	for (uint32_t v = v0; v < v1; begin = j->start[v++]) {
		uint32_t cand = 0;
		for (uint32_t i = begin; i < j->start[v]; ++i) {
			uint32_t b, k;
			face_at(j, j->list[i], &b, &k);
			cand += k <= RING_ALL_MAX ? k - 1 : 2;
		}
		top = cand > top ? cand : top;
	}
	j->top[t] = top;
}

/* Appends to s->ring the unstamped vertices sharing a usable face with u,
 * while it has fewer than s->cap members. */
static uint32_t gather(const fit_job* j, scratch* s, uint32_t u, uint32_t m)
{
	static const unsigned char next[3] = {1, 2, 0}, prev[3] = {2, 0, 1};
	const uint32_t* idx = j->w.indices;
	for (uint32_t i = u ? j->start[u - 1] : 0; i < j->start[u]; ++i) {
		const uint32_t c = j->list[i];
		if (!j->w.offsets) { /* a triangle: its next corner, then its previous */
			const uint32_t f = c / 3, at = c - 3 * f;
			if (!j->usable[f])
				continue;
			const uint32_t x = idx[3 * f + next[at]], y = idx[3 * f + prev[at]];
			if (s->stamp[x] != s->tag && m < s->cap)
				s->stamp[x] = s->tag, s->ring[m++] = x;
			if (s->stamp[y] != s->tag && m < s->cap)
				s->stamp[y] = s->tag, s->ring[m++] = y;
			continue;
		}
		uint32_t b, k;
		if (!j->usable[face_at(j, c, &b, &k)])
			continue;
		const uint32_t at = c - b;
		for (uint32_t o = 1; o < k; ++o) {
			if (k > RING_ALL_MAX && o != 1 && o != k - 1)
				continue;
			const uint32_t x = idx[b + (at + o) % k];
			if (s->stamp[x] != s->tag && m < s->cap)
				s->stamp[x] = s->tag, s->ring[m++] = x;
		}
	}
	return m;
}

/* A fresh tag: no vertex is stamped with it yet. */
static void new_tag(const fit_job* j, scratch* s)
{
	if (++s->tag == 0) { /* wrapped: forget every stamp */
		memset(s->stamp, 0, sizeof(uint32_t) * j->w.vertex_count);
		s->tag = 1;
	}
}

/* The 1-rings, once: each worker gathers its vertices' (v stamped first, so
 * it is not its own member), counting them (into nstart[v + 1]) or, when
 * nbr is set, copying them there. Rings of rings then read these lists,
 * not the faces again. */
static void phase_rings(void* ctx, unsigned t)
{
	const fit_job* j = (const fit_job*)ctx;
	scratch* s = j->scratch + t;
	for (uint32_t v = range_lo(j->w.vertex_count, t, j->nt), v1 = range_lo(j->w.vertex_count, t + 1, j->nt); v < v1;
	     ++v) {
		new_tag(j, s);
		s->stamp[v] = s->tag;
		const uint32_t m = gather(j, s, v, 0);
		if (j->nbr)
			memcpy(j->nbr + j->nstart[v], s->ring, sizeof(uint32_t) * m);
		else
			j->nstart[v + 1] = m;
	}
}

/* Appends to s->ring the unstamped members of u's 1-ring, while it has
 * fewer than s->cap members. */
static uint32_t expand(const fit_job* j, scratch* s, uint32_t u, uint32_t m)
{
	/* Without a branch on the stamp, which is as often set as not: every
	 * member is written at m (the ring has room for one more than cap),
	 * and m moves on when it was new. */
	const uint32_t tag = s->tag, cap = (uint32_t)s->cap;
	for (uint32_t i = j->nstart[u]; i < j->nstart[u + 1]; ++i) {
		const uint32_t x = j->nbr[i], fresh = s->stamp[x] != tag;
		s->stamp[x] = tag;
		s->ring[m] = x;
		m += fresh & (m < cap);
	}
	return m;
}

/* ---------------------------------------------------------------- per vertex */

/* Loads ring members [from, to) into lane points p, relative to o. */
static void load_members(const fit_job* j, const scratch* s, uint32_t from, uint32_t to, const double o[3],
                         const vn_fit_points* p)
{
	for (uint32_t i = from; i < to; ++i) {
		double x[3];
		vn_load(&j->w, j->w.type, s->ring[i], x);
		p->x[i] = x[0] - o[0], p->y[i] = x[1] - o[1], p->z[i] = x[2] - o[2];
	}
}

/* Vertex v's points into p: its 1-ring (ring[0, m[0])), then for JET and
 * ADAPTIVE its 2-ring (to m[1]), then for ADAPTIVE its 3- and 4-rings (to
 * m[2] and m[3], the members nearest by rings first when they would pass
 * the scratch's capacity); p->m = m[1]. 0 when v keeps its seed. */
static int gather_vertex(const fit_job* j, scratch* s, uint32_t v, vn_fit_points* p, uint32_t m[4])
{
	const double* seed = j->seed + 3 * (size_t)v;
	if (seed[0] == 0.0 && seed[1] == 0.0 && seed[2] == 0.0)
		return 0;
	new_tag(j, s);
	s->stamp[v] = s->tag;
	m[0] = m[1] = m[2] = m[3] = j->nbr ? expand(j, s, v, 0) : gather(j, s, v, 0);
	if (!m[0])
		return 0;
	double o[3], h = 0.0;
	vn_load(&j->w, j->w.type, v, o);
	load_members(j, s, 0, m[0], o, p);
	for (uint32_t i = 0; i < m[0]; ++i)
		h += sqrt(p->x[i] * p->x[i] + p->y[i] * p->y[i] + p->z[i] * p->z[i]);
	h /= m[0];
	if (!(h > 0.0 && h <= DBL_MAX))
		return 0;
	const int rings = j->w.method == vn_method_quadric ? 1 : j->w.method == vn_method_jet ? 2 : 4;
	for (int r = 1; r < rings; ++r) {
		m[r] = m[r - 1];
		for (uint32_t i = r > 1 ? m[r - 2] : 0; i < m[r - 1]; ++i)
			m[r] = expand(j, s, s->ring[i], m[r]);
		load_members(j, s, m[r - 1], m[r], o, p);
	}
	for (int r = rings; r < 4; ++r)
		m[r] = m[r - 1];
	p->m = m[3];
	vn_fit_prepare(p, h);
	p->m = m[1];
	return 1;
}

/* exp(x) for x <= 0, without a libm call (which was 12% of ADAPTIVE's
 * instructions): x = n ln 2 + r with |r| <= ln 2 / 2 (n by the 1.5 2^52
 * rounding trick, ln 2 in two parts so that n ln2_hi is exact), e^r by its
 * Taylor series to r^13 (truncation below 4e-18 relative), times 2^n made
 * in the exponent bits; 0 below -708, where exp leaves the normal range
 * (a weight under 1e-307 adds nothing). Within a few ulps of exp. */
static double exp_nonpositive(double x)
{
	if (!(x >= -708.0))
		return 0.0;
	const double shift = 0x1.8p52, n = (x * 1.4426950408889634 + shift) - shift;
	const double r = (x - n * 6.93147180369123816490e-01) - n * 1.90821492927058770002e-10;
	double e = 1.0 / 6227020800.0; /* 1 / 13! */
	static const double inv_factorial[13] = {1.0 / 479001600.0, 1.0 / 39916800.0, 1.0 / 3628800.0, 1.0 / 362880.0,
	                                         1.0 / 40320.0,     1.0 / 5040.0,     1.0 / 720.0,     1.0 / 120.0,
	                                         1.0 / 24.0,        1.0 / 6.0,        0.5,             1.0,
	                                         1.0};
	for (int i = 0; i < 13; ++i)
		e = e * r + inv_factorial[i];
	const uint64_t bits = (uint64_t)((int64_t)n + 1023) << 52;
	double scale;
	memcpy(&scale, &bits, sizeof(scale));
	return e * scale;
}

/* ADAPTIVE's wide fits: the points' weights become exp(-|p|^2 / (2 r^2)),
 * r^2 the mean |p|^2 of the members (a Gaussian as wide as the 4-ring).
 * Returns the effective number of points, (sum w)^2 / sum w^2, and sets
 * *sum to sum w, the vertex (weight 1) included in both. */
static double gaussian_weights(const vn_fit_points* p, double* sum)
{
	double r2 = 0.0, sw = 1.0, sww = 1.0;
	for (uint32_t i = 0; i < p->m; ++i)
		r2 += p->x[i] * p->x[i] + p->y[i] * p->y[i] + p->z[i] * p->z[i];
	const double k = -0.5 * p->m / r2;
	for (uint32_t i = 0; i < p->m; ++i) {
		const double w = exp_nonpositive(k * (p->x[i] * p->x[i] + p->y[i] * p->y[i] + p->z[i] * p->z[i]));
		p->w[i] = w, sw += w, sww += w * w;
	}
	*sum = sw;
	return sw * sw / sww;
}

/* Generalized cross-validation score of a fit of k unknowns with weighted
 * RMS residual res over n effective points (Craven & Wahba 1979): the
 * residual inflated for the freedom the fit used to reach it. */
static double gcv(double res, double n, int k)
{
	const double d = 1.0 - k / n;
	return d > 0.0 ? res * res / (d * d) : DBL_MAX;
}

/* The effective number of points (sum w)^2 / sum w^2, the vertex (weight
 * 1) included. */
static double effective_points(const vn_fit_points* p)
{
	double sw = 1.0, sww = 1.0;
	for (uint32_t i = 0; i < p->m; ++i)
		sw += p->w[i], sww += p->w[i] * p->w[i];
	return sw * sw / sww;
}

/* ADAPTIVE at the active lanes, after the 2-ring jet f (ok, residual res):
 * the jet where it is exact; else the quadric and the cubic on the 4-ring
 * with Gaussian weights, in the jet's frame (S's where the jet failed).
 * pick[v] receives two outcomes, the jet or the quadric (the cubic where
 * the quadric failed) by the lower GCV score, and the jet or the cubic
 * (the quadric where the cubic failed) likewise, each the rough fallback
 * where its residual exceeds ADAPTIVE_FIT_MAX, then log T where both wide
 * fits succeeded (NaN elsewhere): phase_choose takes one. Vertices from
 * v1 on are another worker's. */
static void adaptive_lanes(const fit_job* j, vn_fit_points p[LANES], const int act[LANES], const uint32_t m[LANES][4],
                           const double* const seed[LANES], const double f[LANES][3], const int ok[LANES],
                           const double res[LANES], const uint32_t v0, const uint32_t v1)
{
	int wide[LANES], any = 0;
	double neff[LANES], sw[LANES], best[LANES];
	lanes axis[3];
	for (unsigned l = 0; l < LANES; ++l) {
		wide[l] = 0;
		for (int d = 0; d < 3; ++d)
			axis[d][l] = d == 2;
		if (v0 + l >= v1) /* another worker's vertex */
			continue;
		double* out = j->pick + 7 * (size_t)(v0 + l);
		const int jet = act[l] && ok[l];
		/* Without a ring, or where no fit is taken: the fallback. */
		memcpy(out, jet && res[l] <= ADAPTIVE_FIT_MAX ? f[l] : j->rough + 3 * (size_t)(v0 + l), 3 * sizeof(double));
		memcpy(out + 3, out, 3 * sizeof(double));
		out[6] = NAN;
		best[l] = !jet ? DBL_MAX : res[l] <= ADAPTIVE_JET_EXACT ? 0.0 : gcv(res[l], effective_points(p + l), 10);
		wide[l] = act[l] && best[l] > 0.0 && m[l][3] > m[l][0];
		if (wide[l]) {
			p[l].m = m[l][3];
			neff[l] = gaussian_weights(p + l, sw + l);
			any = 1;
			for (int d = 0; d < 3; ++d) /* the wide fits' frame */
				axis[d][l] = ok[l] ? f[l][d] : seed[l][d];
		}
	}
	if (!any)
		return;
	fits w[2];
	fit_kernel(2, j->w.simd)(p, wide, axis, w);
	for (unsigned l = 0; l < LANES; ++l) {
		if (!wide[l])
			continue;
		double* out = j->pick + 7 * (size_t)(v0 + l);
		double q[3], rq = 0.0, c[3], rc = 0.0;
		const int okq = take(w, w[0].ok[l], l, seed[l], q, &rq);
		const int okc = take(w + 1, w[1].ok[l], l, seed[l], c, &rc);
		if (!okq && !okc)
			continue;
		for (int k = 0; k < 2; ++k) { /* k 0: the quadric's outcome, 1: the cubic's */
			const int cubic = k ? okc : !okq;
			double* o = out + 3 * k;
			const double r = cubic ? rc : rq;
			if (gcv(r, neff[l], cubic ? 10 : 6) < best[l])
				memcpy(o, r <= ADAPTIVE_FIT_MAX ? (cubic ? c : q) : j->rough + 3 * (size_t)(v0 + l), 3 * sizeof(double));
		}
		if (okq && okc) {
			/* d, the quadric's slopes minus the cubic's (one frame); var(d)
			 * = sigma^2 (vs_cubic - vs_quadric) for nested least squares,
			 * sigma^2 from the cubic's residual over its degrees of freedom. */
			const double d1 = w[0].c[1][l] - w[1].c[1][l], d2 = w[0].c[2][l] - w[1].c[2][l];
			const double var = rc * rc * sw[l] / ((double)p[l].m + 1.0 - 10.0) * (w[1].vs[l] - w[0].vs[l]);
			const double t = (d1 * d1 + d2 * d2) / var;
			out[6] = !(var > 0.0) ? T_LOG_MAX : t > 0.0 ? fmin(fmax(log(t), -T_LOG_MAX), T_LOG_MAX) : -T_LOG_MAX;
		}
	}
}

/* ADAPTIVE's choice at each vertex: the cubic's outcome where the mean of
 * log T over the vertex and its 1-ring (those that have one) exceeds log
 * ADAPTIVE_T, else the quadric's. The cubic terms are smooth over the
 * surface and T's noise is not, so the mean decides better than one T. */
static void phase_choose(void* ctx, unsigned t)
{
	const fit_job* j = (const fit_job*)ctx;
	const double limit = log(ADAPTIVE_T);
	for (uint32_t v = range_lo(j->w.vertex_count, t, j->nt), v1 = range_lo(j->w.vertex_count, t + 1, j->nt); v < v1;
	     ++v) {
		const double* pick = j->pick + 7 * (size_t)v;
		double sum = 0.0;
		uint32_t count = 0;
		if (!isnan(pick[6]))
			sum += pick[6], ++count;
		for (uint32_t i = j->nstart[v]; i < j->nstart[v + 1]; ++i) {
			const double x = j->pick[7 * (size_t)j->nbr[i] + 6];
			if (!isnan(x))
				sum += x, ++count;
		}
		const double* r = pick + (count && sum > limit * count ? 3 : 0);
		if (!(j->w.keep_existing && r[0] == 0.0 && r[1] == 0.0 && r[2] == 0.0))
			vn_store(j->w.out, v, r);
	}
}

/* Vertices v0 .. v0 + LANES - 1 (those below v1). */
static void fit_batch(const fit_job* j, scratch* s, uint32_t v0, uint32_t v1)
{
	vn_fit_points p[LANES];
	const double* seed[LANES];
	int act[LANES], ok[LANES];
	uint32_t m[LANES][4];
	double n[LANES][3], res[LANES];
	for (unsigned l = 0; l < LANES; ++l) {
		const uint32_t v = v0 + l;
		double* q = s->q + 4 * s->cap * l;
		p[l] = (vn_fit_points){q, q + s->cap, q + 2 * s->cap, q + 3 * s->cap, 0};
		seed[l] = j->seed + 3 * (size_t)(v < v1 ? v : v0);
		act[l] = v < v1 && gather_vertex(j, s, v, p + l, m[l]);
		memcpy(n[l], seed[l], sizeof(n[l]));
	}
	if (j->w.method == vn_method_quadric)
		fit_twice(p, act, seed, 0, j->w.simd, n, ok, NULL);
	else if (j->w.method == vn_method_adaptive) { /* stored by phase_choose */
		double f[LANES][3];
		fit_twice(p, act, seed, 1, j->w.simd, f, ok, res);
		adaptive_lanes(j, p, act, (const uint32_t(*)[4])m, seed, (const double(*)[3])f, ok, res, v0, v1);
		return;
	} else {
		double f[LANES][3];
		fit_twice(p, act, seed, 1, j->w.simd, f, ok, NULL);
		int again = 0;
		for (unsigned l = 0; l < LANES; ++l) {
			if (ok[l])
				memcpy(n[l], f[l], sizeof(f[l]));
			/* JET falls back to the quadric on the 1-ring. */
			act[l] = act[l] && !ok[l];
			again |= act[l];
			p[l].m = m[l][0];
		}
		if (again)
			fit_twice(p, act, seed, 0, j->w.simd, n, ok, NULL);
	}
	for (unsigned l = 0; l < LANES && v0 + l < v1; ++l) {
		const double* r = n[l];
		if (!(j->w.keep_existing && r[0] == 0.0 && r[1] == 0.0 && r[2] == 0.0))
			vn_store(j->w.out, v0 + l, r);
	}
}

static void phase_fit(void* ctx, unsigned t)
{
	const fit_job* j = (const fit_job*)ctx;
	const uint32_t v1 = range_lo(j->w.vertex_count, t + 1, j->nt);
	for (uint32_t v = range_lo(j->w.vertex_count, t, j->nt); v < v1; v += LANES)
		fit_batch(j, j->scratch + t, v, v1);
}

/* Every vertex's 1-ring into j->nbr (from the allocator; NULL on failure),
 * j->nstart its offsets: counted, then listed. Wider rings read these
 * instead of the faces again. */
static vn_result rings(fit_job* j, const vn_allocator* heap)
{
	j->nbr = NULL;
	j->nstart[0] = 0;
	vn_parallel(j->nt, phase_rings, j);
	uint64_t sum = 0;
	for (uint32_t v = 0; v < j->w.vertex_count; ++v)
		j->nstart[v + 1] = (uint32_t)(sum += j->nstart[v + 1]);
	if (sum > UINT32_MAX)
		return vn_result_out_of_memory;
	j->nbr = (uint32_t*)heap->allocate(heap->user, sizeof(uint32_t) * (sum ? (size_t)sum : 1));
	if (!j->nbr)
		return vn_result_out_of_memory;
	vn_parallel(j->nt, phase_rings, j);
	return vn_result_success;
}

/* ---------------------------------------------------------------- driver */

static unsigned worker_count(uint32_t nv, unsigned threads)
{
	unsigned nt = threads ? threads : 1;
	nt = nt > MAX_THREADS ? MAX_THREADS : nt;
	if ((size_t)nt * MIN_VERTICES_PER_THREAD > nv)
		nt = nv / MIN_VERTICES_PER_THREAD > 1 ? nv / MIN_VERTICES_PER_THREAD : 1;
	return nt;
}

vn_result vn_fit_run(const vn_work* work, const vn_options* o, vn_range_stats* st)
{
	const vn_allocator heap = vn_heap(&o->allocator);
	const uint32_t nv = work->vertex_count, nc = corner_count(work);
	const size_t nf = work->face_count;
	const unsigned nt = worker_count(nv, o->threads);

	/* The seeds (and ADAPTIVE's rough fallback), by the weighted family's
	 * kernels (which check the indices). */
	const int adaptive = work->method == vn_method_adaptive;
	double* seed = (double*)heap.allocate(heap.user, (adaptive ? 13 : 3) * sizeof(double) * (size_t)nv);
	if (!seed)
		return vn_result_out_of_memory;
	const vn_accumulate_fn weighted =
	    work->offsets ? vn_accumulate_weighted_polygons : vn_accumulate_weighted_triangles;
	fit_job j;
	memset(&j, 0, sizeof(j));
	j.w = *work;
	j.w.method = vn_method_mwa;
	const vn_vectors seeds = {seed, 3 * sizeof(double), vn_scalar_float64};
	j.w.out = &seeds;
	j.w.keep_existing = 0;
	vn_result r = vn_run(&j.w, weighted, o, st);
	if (adaptive && r == vn_result_success) {
		const vn_vectors rough = {seed + 3 * (size_t)nv, 3 * sizeof(double), vn_scalar_float64};
		vn_range_stats unused = {0, 0, 0, 0};
		j.w.method = ADAPTIVE_ROUGH;
		j.w.out = &rough;
		j.w.want_stats = 0;
		r = vn_run(&j.w, weighted, o, &unused);
		j.rough = seed + 3 * (size_t)nv;
		j.pick = seed + 6 * (size_t)nv;
	}
	j.w = *work;
	j.seed = seed;
	j.nt = nt;

	const size_t words = 2 * ((size_t)nv + 1) + nc + (work->offsets ? nc : 0) + nt;
	const size_t bytes = sizeof(scratch) * nt + sizeof(uint32_t) * words + nf;
	unsigned char* block = r == vn_result_success ? (unsigned char*)heap.allocate(heap.user, bytes) : NULL;
	if (r == vn_result_success && !block)
		r = vn_result_out_of_memory;
	if (block) {
		j.scratch = (scratch*)(void*)block;
		j.start = (uint32_t*)(void*)(j.scratch + nt);
		j.list = j.start + nv + 1;
		j.top = j.list + nc;
		j.nstart = j.top + nt;
		j.face_of = work->offsets ? j.nstart + nv + 1 : NULL;
		j.usable = (unsigned char*)(j.start + words);
		vn_parallel(nt, phase_count, &j);
		/* start[v + 1] holds v's count: make start[v] where v's corners begin. */
		uint32_t sum = 0;
		for (uint32_t v = 0; v < nv; ++v) {
			const uint32_t c = j.start[v + 1];
			j.start[v] = sum;
			sum += c;
		}
		vn_parallel(nt, phase_list, &j);
		uint32_t top = 0;
		for (unsigned t = 0; t < nt; ++t)
			top = j.top[t] > top ? j.top[t] : top;
		/* A 2-ring has at most top (1 + top) members, and fewer than nv. */
		const uint64_t want = (uint64_t)top * (1 + (uint64_t)top);
		const size_t cap = want < nv ? (size_t)want : nv;
		const size_t ring_bytes = (sizeof(uint32_t) * ((size_t)nv + cap + 1) + 7) & ~(size_t)7;
		unsigned t = 0;
		for (; t < nt; ++t) {
			scratch* s = j.scratch + t;
			s->stamp = (uint32_t*)heap.allocate(heap.user, ring_bytes + 4 * LANES * sizeof(double) * cap);
			if (!s->stamp)
				break;
			memset(s->stamp, 0, sizeof(uint32_t) * nv);
			s->tag = 0;
			s->ring = s->stamp + nv;
			s->q = (double*)(void*)((unsigned char*)s->stamp + ring_bytes);
			s->cap = cap;
		}
		if (t == nt) { /* QUADRIC reads each 1-ring once: straight from the faces */
			r = work->method == vn_method_quadric ? vn_result_success : rings(&j, &heap);
		} else {
			r = vn_result_out_of_memory;
		}
		if (r == vn_result_success)
			vn_parallel(nt, phase_fit, &j);
		if (r == vn_result_success && adaptive) /* after every vertex's log T */
			vn_parallel(nt, phase_choose, &j);
		if (j.nbr)
			heap.deallocate(heap.user, j.nbr);
		while (t-- > 0)
			heap.deallocate(heap.user, j.scratch[t].stamp);
		heap.deallocate(heap.user, block);
	}
	heap.deallocate(heap.user, seed);
	return r;
}
