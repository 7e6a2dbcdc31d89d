/* The fitting family: QUADRIC, JET and ADAPTIVE (vn.h).
 *
 * Per vertex v with seed normal S (MWA's, computed first by the
 * weighted family's kernels):
 *   1. ring: the vertices sharing a usable face with v (a triangle's other
 *      two corners; a polygon's other corners when it has at most
 *      RING_ALL_MAX, else its two edge neighbours); the 2-ring adds the
 *      rings of those but a hub's (RING_HUB_MAX). A face is usable when
 *      every corner's coordinates are finite (a polygon: and it has 3
 *      corners or more), so a non-finite coordinate never enters; a face of
 *      zero area still joins its corners, which are samples of the surface
 *      like any other (the fits weigh points, not faces).
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
 * 24 bytes a vertex (seeds) + 8 a corner + 9 a vertex + 1 a polygon + 4 a
 * 1-ring member + 4 a vertex per thread + ring scratch.
 *
 * ADAPTIVE (vn.h) adds, where the jet succeeded, is not exact and the
 * vertex is not rough, a quadric and a cubic on the 5-ring, gathered then
 * past the 2-ring up to the ring capacity; each vertex keeps two
 * outcomes (the jet or the quadric, the jet or the cubic, by GCV score) and
 * the statistic of its cubic terms, and a last pass takes one outcome by
 * that statistic over the vertex's 1-ring (56 more bytes a vertex); its
 * rough fallback is S, or MWAAT's normal on a lattice (lattice_ring), a
 * second pass of the weighted kernels, and MWSELR, which it takes on a
 * sphere (sphere_lanes) and for a jet that agrees with it, a third (24
 * more bytes a vertex each). Where the jet cannot be fitted, or only
 * interpolates its points, it falls back as JET does. */
#include <stdio.h>
#include <stdlib.h>

#include "internal.h"
#include "simd.h"

/* A polygon of more corners gives only its two edge neighbours to a ring:
 * all corners of a large n-gon would make rings quadratic in its size. */
#define RING_ALL_MAX 8
/* A ring member with a 1-ring of more members (the hub of a fan: a disc or
 * a cone's cap triangulated from one point) is not expanded into wider
 * rings: each rim vertex's 2-ring would be the whole fan, and the fits
 * quadratic in its size. The hub itself stays a member. */
#define RING_HUB_MAX 256
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
 * wider fit can do better); the rough fallback where it exceeds
 * ADAPTIVE_ROUGH_MAX (no cubic describes the surface at the scale of its
 * edges: fractal or turbulent). The jet's residual decides, not a wide
 * fit's: on a smooth surface whose features are a few rings across (a
 * noisy isosurface), a wide fit's residual is its model's bias over the
 * ring, not roughness, and a face-weighted normal is 4 to 6 times worse
 * there than the wide cubic (perlin_mt, medium: MWA 2.11 degrees, MWELR
 * 3.06, ADAPTIVE 0.52). A wide fit replaces the jet where its GCV score is
 * below ADAPTIVE_JET_MARGIN times the jet's: the jet's score rests on about 14
 * effective points for 10 unknowns, so it scatters, and the wide fits'
 * averaging is kept unless the jet is clearly better. The ring
 * (ADAPTIVE_RINGS) and the Gaussian's width (ADAPTIVE_WIDTH, relative to
 * the members' RMS distance) trade the noise averaged out against the
 * model's bias. These four were chosen with vneval. Where the jet is
 * taken, MWSELR's normal replaces it if the two are within
 * ADAPTIVE_MWSELR_AGREE times the jet's residual over h, in radians: the
 * jet cannot tell them apart, and MWSELR is exact where the jet is only
 * O(h^3): at a vertex whose parameter lines are circles through it and
 * whose grid quads have their corners on circles, as on a sphere's or a
 * torus's latitude-longitude grid (MWSELR's sum is twice the vector area
 * of the 1-ring inverted in a sphere about the vertex, Max 1999; there
 * the inverted ring's area is the cross product of the grid's two
 * diagonals, tangent to the parameter circles). The wide
 * cubic rather than the quadric where the mean log T over the 1-ring
 * exceeds log ADAPTIVE_T, T = |slope difference|^2 / its variance: 2 is
 * where the quadric's estimated squared slope bias |d|^2 - var(d) passes
 * the variance the cubic adds, var(d) (nested least squares), so the
 * constant is the mean squared error's break-even, not a fitted one. */
#define ADAPTIVE_JET_EXACT 1e-4
#define ADAPTIVE_ROUGH_MAX 0.05
/* ADAPTIVE takes MWSELR's normal outright where the vertex's 2-ring lies on
 * a sphere through it, tangent to MWSELR's plane, to ADAPTIVE_SPHERE_ROUNDING
 * units of rounding of the coordinates' precision (float32's where every
 * coordinate is a float32 value, as from glTF, whatever type the caller
 * passes; the text's where every one was read from few decimal digits,
 * vn_coordinate_rounding; else float64's), and at most ADAPTIVE_JET_EXACT
 * h: MWSELR is then that sphere's normal (Max 1999), which no fit
 * reproduces, and the data cannot be told from a sphere. Measured in those
 * units: Blender's UV spheres (float32) up to 275 at 500 segments; every
 * vertex of the paper's other models above 1e8 (float64), and above 6e-4
 * h. */
#define ADAPTIVE_SPHERE_ROUNDING 1024.0
/* The sphere needs two points beyond the three that fit one. */
#define ADAPTIVE_SPHERE_POINTS 5
#define ADAPTIVE_MWSELR_AGREE 0.5
#define ADAPTIVE_JET_MARGIN 2.0
#define ADAPTIVE_RINGS 5
#define ADAPTIVE_WIDTH 0.6
#define ADAPTIVE_T 2.0
/* log T is kept within +-T_LOG_MAX (T infinite where the cubic's residual is 0). */
#define T_LOG_MAX 50.0
/* ADAPTIVE's rough fallback where the 1-ring is a height field sampled on
 * a lattice (lattice_ring): MWAAT, whose sum, the ring's vector area, is a
 * central difference there, and the best of the seven on the paper's
 * fractal height fields. Elsewhere the fallback is the seed S, MWA's
 * normal: off a lattice, face areas say how the surface was cut, not how
 * far a face reaches, and area weights are the worst of the six
 * face-weighted schemes on the paper's rough isosurface (MWAAT 6 to 11%
 * above the best there, MWA 2 to 5%, docs/ACCURACY.md). */
#define ADAPTIVE_LATTICE_ROUGH vn_method_mwaat
/* A lattice ring has at most this many members (8 quads). */
#define LATTICE_MEMBERS_MAX 16
/* A ring is a lattice's where its second differences are parallel to
 * this fraction of h: a structural test, not one of precision (MWAAT's
 * sum stays a central difference to first order in the departure), loose
 * enough for float32 grids up to about 40,000 cells from the origin (a
 * difference holds four roundings of at most 6e-8 of a coordinate), tight
 * against the rings of marching tetrahedra and jittered grids, whose
 * departures are tenths of h. */
#define LATTICE_SLACK 1e-2
#define MAX_THREADS 256
/* Below this many vertices per worker, a thread costs more than it saves. */
#define MIN_VERTICES_PER_THREAD 4096

/* ---------------------------------------------------------------- the fit */

/* Fits run LANES vertices at a time, each step of the arithmetic done for
 * every lane before the next step: a fit is a chain of dependent divisions
 * and square roots, and the lanes' chains overlap (the compiler also maps
 * lanes to SIMD registers). A lane's arithmetic is the same whatever the
 * other lanes hold, so results do not depend on how vertices are batched. */
#define LANES 4
/* A batch's points are interleaved, so that one load reads a coordinate of
 * every lane: lane l's point i (relative to its vertex) is x = q[PT i + l],
 * y, z and its weight LANES, 2 LANES and 3 LANES further. A lane sums its
 * own points in order, and the moments need no sum across a register. */
#define PT (4 * LANES)
_Static_assert(PT == 16, "vn_fit_frame takes 16 doubles of scratch a point (internal.h)");
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

typedef double lanes __attribute__((vector_size(LANES * sizeof(double))));
typedef long long masks __attribute__((vector_size(LANES * sizeof(long long))));

/* Unaligned loads and stores of LANES doubles. */
typedef double unaligned_lanes __attribute__((vector_size(LANES * sizeof(double)), aligned(8), may_alias));
#define LOAD(p) ((lanes) * (const unaligned_lanes*)(const void*)(p))
#define STORE(p, v) (*(unaligned_lanes*)(void*)(p) = (v))

/* Square roots of each lane, as sqrt rounds them (SSE2 on x86-64). */
VN_INLINE void sqrt_lanes(lanes* x)
{
#ifdef VN_HAVE_AVX2
	__m128d half[2];
	memcpy(half, x, sizeof(half));
	half[0] = _mm_sqrt_pd(half[0]), half[1] = _mm_sqrt_pd(half[1]);
	memcpy(x, half, sizeof(half));
#else
	UNROLL for (int l = 0; l < LANES; ++l)
		(*x)[l] = sqrt((*x)[l]);
#endif
}

/* Points [0, top) of a batch: coordinates divided by each lane's h (inv =
 * 1 / h), weights 1 / (1 + |p|^2) from the result. */
VN_INLINE void prepare_lanes(double* q, uint32_t top, const lanes* scale)
{
	const lanes one = {1.0, 1.0, 1.0, 1.0}, inv = *scale;
	for (uint32_t i = 0; i < top; ++i) {
		double* b = q + PT * (size_t)i;
		const lanes x = LOAD(b) * inv, y = LOAD(b + LANES) * inv, z = LOAD(b + 2 * LANES) * inv;
		STORE(b, x), STORE(b + LANES, y), STORE(b + 2 * LANES, z);
		STORE(b + 3 * LANES, one / (one + (x * x + y * y + z * z)));
	}
}

/* A batch's points [0, top) as gathered (relative to their vertices), over
 * each lane's h, the mean distance to its first first[l] points (the
 * 1-ring), and weighted (prepare_lanes); scale[l] receives 1 / h. A lane
 * whose h is 0 or not finite leaves act. */
VN_INLINE void scale_lanes(double* q, const uint32_t first[LANES], uint32_t top, int act[LANES], double scale[LANES])
{
	const lanes zero = {0.0, 0.0, 0.0, 0.0};
	lanes h = zero, count = zero, divisor, inv;
	uint32_t most = 0;
	UNROLL for (int l = 0; l < LANES; ++l) {
		const uint32_t c = act[l] ? first[l] : 0;
		count[l] = (double)c, divisor[l] = c ? (double)c : 1.0, most = c > most ? c : most;
	}
	for (uint32_t i = 0; i < most; ++i) { /* each lane's sum in its order: + 0 past its count */
		const double* b = q + PT * (size_t)i;
		const lanes x = LOAD(b), y = LOAD(b + LANES), z = LOAD(b + 2 * LANES);
		lanes r = x * x + y * y + z * z;
		sqrt_lanes(&r);
		h += (lanes)((masks)r & ((lanes){(double)i, (double)i, (double)i, (double)i} < count));
	}
	h /= divisor;
	UNROLL for (int l = 0; l < LANES; ++l) {
		act[l] = count[l] > 0.0 && h[l] > 0.0 && h[l] <= DBL_MAX;
		inv[l] = act[l] ? 1.0 / h[l] : 1.0;
		scale[l] = inv[l];
	}
	prepare_lanes(q, top, &inv);
}

/* exp(x) for x <= 0 in each lane, without a libm call (which was 12% of
 * ADAPTIVE's instructions): x = n ln 2 + r with |r| <= ln 2 / 2 (n by the
 * 1.5 2^52 rounding trick, which also leaves n in the low bits of x log2 e
 * + 1.5 2^52; ln 2 in two parts so that n ln2_hi is exact), e^r by its
 * Taylor series to r^13 (truncation below 4e-18 relative), times 2^n made
 * in the exponent bits; 0 below -708 (and for NaN), where exp leaves the
 * normal range (a weight under 1e-307 adds nothing). Within a few ulps of
 * exp. */
VN_INLINE void exp_nonpositive(lanes* v)
{
	static const double inv_factorial[13] = {1.0 / 479001600.0, 1.0 / 39916800.0, 1.0 / 3628800.0, 1.0 / 362880.0,
	                                         1.0 / 40320.0,     1.0 / 5040.0,     1.0 / 720.0,     1.0 / 120.0,
	                                         1.0 / 24.0,        1.0 / 6.0,        0.5,             1.0,
	                                         1.0};
	const lanes zero = {0.0, 0.0, 0.0, 0.0}, x = *v, shift = zero + 0x1.8p52;
	const lanes t = x * 1.4426950408889634 + shift, n = t - shift;
	const lanes r = (x - n * 6.93147180369123816490e-01) - n * 1.90821492927058770002e-10;
	lanes e = zero + 1.0 / 6227020800.0; /* 1 / 13! */
	UNROLL for (int i = 0; i < 13; ++i)
		e = e * r + inv_factorial[i];
	typedef unsigned long long words __attribute__((vector_size(LANES * sizeof(long long))));
	const words bits = ((words)t - (words)shift + 1023) << 52; /* t's low bits hold n */
	*v = (lanes)((masks)(e * (lanes)bits) & (x >= -708.0));
}

/* ADAPTIVE's wide fits: the weights of each lane's first count[l] points
 * (the others keep theirs) become exp(-|p|^2 / (2 r^2)), r ADAPTIVE_WIDTH
 * times the members' RMS distance. Sets neff[l],
 * the effective number of points (sum w)^2 / sum w^2, and sum[l], sum w,
 * the vertex (weight 1) included in both, where count[l] > 0. Each lane's
 * sums in its order (+ 0 past its count). */
VN_INLINE void gaussian_lanes(double* q, const uint32_t count[LANES], double neff[LANES], double sum[LANES])
{
	const lanes zero = {0.0, 0.0, 0.0, 0.0}, one = zero + 1.0;
	lanes r2 = zero, m = zero, sw = one, sww = one;
	uint32_t most = 0;
	UNROLL for (int l = 0; l < LANES; ++l)
		m[l] = (double)count[l], most = count[l] > most ? count[l] : most;
	for (uint32_t i = 0; i < most; ++i) {
		const double* b = q + PT * (size_t)i;
		const lanes x = LOAD(b), y = LOAD(b + LANES), z = LOAD(b + 2 * LANES);
		r2 += (lanes)((masks)(x * x + y * y + z * z) & ((zero + (double)i) < m));
	}
	const masks some = m > 0.0;
	const lanes k = -0.5 / (ADAPTIVE_WIDTH * ADAPTIVE_WIDTH) * m / (lanes)(((masks)r2 & some) | ((masks)one & ~some));
	for (uint32_t i = 0; i < most; ++i) {
		double* b = q + PT * (size_t)i;
		const lanes x = LOAD(b), y = LOAD(b + LANES), z = LOAD(b + 2 * LANES);
		const masks in = (zero + (double)i) < m;
		lanes w = k * (x * x + y * y + z * z);
		exp_nonpositive(&w);
		STORE(b + 3 * LANES, (lanes)(((masks)w & in) | ((masks)LOAD(b + 3 * LANES) & ~in)));
		sw += (lanes)((masks)w & in), sww += (lanes)((masks)(w * w) & in);
	}
	const lanes effective = sw * sw / sww;
	UNROLL for (int l = 0; l < LANES; ++l)
		if (count[l])
			neff[l] = effective[l], sum[l] = sw[l];
}

/* LANES fits: frames (t1, t2, a), coefficients c, unit normals n, the
 * slopes' variance factor vs = (M^-1)_11 + (M^-1)_22, the weighted sum of
 * squared residuals e2 and the sum of the weights sw (the vertex included
 * in both: rms_residual makes the RMS), and whether each succeeded. */
typedef struct fits {
	lanes t1[3], t2[3], a[3], c[10], n[3], vs, e2, sw;
	int ok[LANES];
} fits;

/* One point of each lane (b: x, y, z relative to the lane's vertex,
 * weight; the weight taken as 0 where `in` is clear) added to the moments,
 * in each lane's frame. */
#define ADD(k, e) (acc[k] += (e))
VN_INLINE void moments_point(const double* b, const masks* in, const fits* f, int cubic, lanes acc[MOMENTS])
{
	const lanes px = LOAD(b), py = LOAD(b + LANES), pz = LOAD(b + 2 * LANES);
	const lanes w = (lanes)((masks)LOAD(b + 3 * LANES) & *in);
	const lanes x = px * f->t1[0] + py * f->t1[1] + pz * f->t1[2];
	const lanes y = px * f->t2[0] + py * f->t2[1] + pz * f->t2[2];
	const lanes z = px * f->a[0] + py * f->a[1] + pz * f->a[2];
	const lanes wx = w * x, wy = w * y, xx = x * x, xy = x * y, yy = y * y;
	const lanes wxx = wx * x, wxy = wx * y, wyy = wy * y, wz = w * z;
	ADD(0, w), ADD(1, wx), ADD(2, wy), ADD(3, wxx), ADD(4, wxy), ADD(5, wyy);
	ADD(ZZ, wz * z);
	ADD(S_MAX, wz), ADD(S_MAX + 1, wz * x), ADD(S_MAX + 2, wz * y);
	ADD(S_MAX + 3, wz * xx), ADD(S_MAX + 4, wz * xy), ADD(S_MAX + 5, wz * yy);
	if (!cubic) {
		ADD(6, wxx * x), ADD(7, wxx * y), ADD(8, wxy * y), ADD(9, wyy * y);
		ADD(10, wxx * xx), ADD(11, wxx * xy), ADD(12, wxx * yy), ADD(13, wxy * yy), ADD(14, wyy * yy);
		return;
	}
	const lanes wxxx = wxx * x, wxxy = wxx * y, wxyy = wxy * y, wyyy = wyy * y;
	const lanes xxx = xx * x, xxy = xx * y, xyy = x * yy, yyy = yy * y;
	ADD(6, wxxx), ADD(7, wxxy), ADD(8, wxyy), ADD(9, wyyy);
	ADD(10, wxxx * x), ADD(11, wxxx * y), ADD(12, wxxy * y), ADD(13, wxyy * y), ADD(14, wyyy * y);
	ADD(15, wxxx * xx), ADD(16, wxxx * xy), ADD(17, wxxx * yy);
	ADD(18, wxxy * yy), ADD(19, wxyy * yy), ADD(20, wyyy * yy);
	ADD(21, wxxx * xxx), ADD(22, wxxx * xxy), ADD(23, wxxx * xyy), ADD(24, wxxx * yyy);
	ADD(25, wxxy * yyy), ADD(26, wxyy * yyy), ADD(27, wyyy * yyy);
	ADD(S_MAX + 6, wz * xxx), ADD(S_MAX + 7, wz * xxy), ADD(S_MAX + 8, wz * xyy), ADD(S_MAX + 9, wz * yyy);
}
#undef ADD

/* The moments of each lane's first m[l] points in its frame, for the lanes
 * with f->ok set (zero for the others), into acc (s: the first S_MAX, t:
 * T_MAX from S_MAX, then sum w z^2 at ZZ); the vertex itself, the origin
 * with weight 1, is included. Points past a lane's count are read with
 * weight 0: they must be finite (they add +0). */
VN_INLINE void moments(const double* q, const uint32_t m[LANES], const fits* f, int cubic, lanes acc[MOMENTS])
{
	const lanes zero = {0.0, 0.0, 0.0, 0.0};
	lanes count = zero, vertex = zero;
	uint32_t top = 0;
	UNROLL for (int l = 0; l < LANES; ++l) {
		const uint32_t c = f->ok[l] ? m[l] : 0;
		count[l] = (double)c, vertex[l] = f->ok[l] ? 1.0 : 0.0;
		top = c > top ? c : top;
	}
	/* count - count is +0, but not a constant: the compiler makes no memset
	 * of it (a slow rep stos). */
	const lanes zeros = count - count;
	const int ns = cubic ? S_MAX : 15, nt = cubic ? T_MAX : 6;
	UNROLL for (int k = 0; k < ns; ++k)
		acc[k] = zeros;
	UNROLL for (int k = 0; k < nt; ++k)
		acc[S_MAX + k] = zeros;
	acc[ZZ] = zeros;
	for (uint32_t i = 0; i < top; ++i) {
		const masks in = (lanes){(double)i, (double)i, (double)i, (double)i} < count;
		moments_point(q + PT * (size_t)i, &in, f, cubic, acc);
	}
	acc[0] += vertex;
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
	masks ok = {-1, -1, -1, -1};
	UNROLL for (int j = 0; j < k; ++j) {
		lanes d = s[MOMENT[j][j]];
		UNROLL for (int p = 0; p < j; ++p)
			d -= U[j][p] * L[j][p];
		const masks good = (d > 0.0) & (d >= PIVOT_MIN * s[MOMENT[j][j]]);
		ok &= good;
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
	ok &= trace * (double)k <= 1.0 / RCOND_MIN;
	UNROLL for (int l = 0; l < LANES; ++l)
		f->ok[l] &= ok[l] != 0;
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
	f->e2 = *zz, f->sw = s[0];
	UNROLL for (int i = 0; i < k; ++i)
		f->e2 -= f->c[i] * t_in[i];
}

/* Lane l's weighted RMS residual over h. */
static double rms_residual(const fits* f, unsigned l)
{
	const double e2 = f->e2[l], sw = f->sw[l]; /* sw >= 1 where the lane is active */
	return e2 > 0.0 && sw > 0.0 ? sqrt(e2 / sw) : 0.0;
}

/* The unit normal of each lane's fit, or ok cleared. The normal is a unit
 * axis plus tangents, so its squared length is at least about 1; outside
 * vn_normalize's direct range (huge slopes, or not finite) the lane fails
 * (its normal would lie in the tangent plane, past the seed's 60 degrees). */
VN_INLINE void fit_normals(fits* f)
{
	UNROLL for (int d = 0; d < 3; ++d)
		f->n[d] = f->a[d] - f->c[1] * f->t1[d] - f->c[2] * f->t2[d];
	const lanes len2 = f->n[0] * f->n[0] + f->n[1] * f->n[1] + f->n[2] * f->n[2];
	const masks in = (len2 >= VN_LEN2_MIN) & (len2 <= VN_LEN2_MAX);
	const lanes one = {1.0, 1.0, 1.0, 1.0};
	lanes root = (lanes)(((masks)len2 & in) | ((masks)one & ~in));
	sqrt_lanes(&root);
	UNROLL for (int l = 0; l < LANES; ++l)
		f->ok[l] &= in[l] != 0;
	const lanes inv = one / root;
	UNROLL for (int d = 0; d < 3; ++d)
		f->n[d] *= inv;
}

/* Fits the active lanes' first m[l] points of q in the frames of the unit axes
 * a[.][l]; the others fail. kind 0: the quadric into f[0]; 1: the cubic
 * into f[0]; 2: both from one pass over the points, the quadric into f[0]
 * and the cubic into f[1] (the quadric's moments are a subset of the
 * cubic's). */
VN_INLINE void fit_lanes(const double* q, const uint32_t m[LANES], const int act[LANES], lanes a[3], int kind, fits* f)
{
	const int k = kind == 1 ? 10 : 6;
	/* A unit tangent pair without a square root (Duff et al. 2017); sign is
	 * copysign(1, z), made from z's sign bit. */
	const lanes x = a[0], y = a[1], z = a[2], one = {1.0, 1.0, 1.0, 1.0};
	const lanes sign_bit = {-0.0, -0.0, -0.0, -0.0};
	const lanes sign = (lanes)(((masks)z & (masks)sign_bit) | (masks)one);
	const lanes A = -one / (sign + z), B = x * y * A;
	f->t1[0] = one + sign * x * x * A, f->t1[1] = sign * B, f->t1[2] = -sign * x;
	f->t2[0] = B, f->t2[1] = sign + y * y * A, f->t2[2] = -y;
	f->a[0] = x, f->a[1] = y, f->a[2] = z;
	UNROLL for (int l = 0; l < LANES; ++l)
		f->ok[l] = (act[l] != 0) & (m[l] + 1 >= (uint32_t)k);
	lanes acc[MOMENTS];
	moments(q, m, f, kind != 0, acc); /* zero where a lane fails: fails the first pivot */
	const lanes *s = acc, *t = acc + S_MAX, *zz = acc + ZZ;
	if (kind == 2) {
		memcpy(f[1].t1, f->t1, sizeof(f->t1)), memcpy(f[1].t2, f->t2, sizeof(f->t2)), memcpy(f[1].a, f->a, sizeof(f->a));
		UNROLL for (int l = 0; l < LANES; ++l)
			f[1].ok[l] = f->ok[l] && m[l] + 1 >= 10;
		solve(s, t, zz, 10, f + 1);
		fit_normals(f + 1);
	}
	solve(s, t, zz, k, f);
	fit_normals(f);
}

static void fit_quadrics(const double* q, const uint32_t m[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(q, m, act, a, 0, f);
}

static void fit_jets(const double* q, const uint32_t m[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(q, m, act, a, 1, f);
}

static void fit_pairs(const double* q, const uint32_t m[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(q, m, act, a, 2, f);
}

/* The same arithmetic in AVX2 registers: the same results, bit for bit
 * (IEEE operations lane by lane, no FMA, sums in the same order). */
typedef void (*fit_fn)(const double*, const uint32_t*, const int*, lanes*, fits*);
static const fit_fn fit_kinds[3] = {fit_quadrics, fit_jets, fit_pairs};
#ifdef VN_HAVE_AVX2
static VN_AVX2 void fit_quadrics_avx2(const double* q, const uint32_t m[LANES], const int act[LANES], lanes a[3],
                                      fits* f)
{
	fit_lanes(q, m, act, a, 0, f);
}

static VN_AVX2 void fit_jets_avx2(const double* q, const uint32_t m[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(q, m, act, a, 1, f);
}

static VN_AVX2 void fit_pairs_avx2(const double* q, const uint32_t m[LANES], const int act[LANES], lanes a[3], fits* f)
{
	fit_lanes(q, m, act, a, 2, f);
}

static const fit_fn fit_kinds_avx2[3] = {fit_quadrics_avx2, fit_jets_avx2, fit_pairs_avx2};

static fit_fn fit_kernel(int kind, int simd)
{
	return (simd ? fit_kinds_avx2 : fit_kinds)[kind];
}

static VN_AVX2 void scale_batch_avx2(double* q, const uint32_t first[LANES], uint32_t top, int act[LANES],
                                     double scale[LANES])
{
	scale_lanes(q, first, top, act, scale);
}

static VN_AVX2 void gaussian_batch_avx2(double* q, const uint32_t count[LANES], double neff[LANES], double sum[LANES])
{
	gaussian_lanes(q, count, neff, sum);
}
#else
static fit_fn fit_kernel(int kind, int simd)
{
	(void)simd;
	return fit_kinds[kind];
}
#endif

/* scale_lanes, in AVX2 registers where simd is set (the same bits). */
static void scale_batch(double* q, const uint32_t first[LANES], uint32_t top, int act[LANES], double scale[LANES],
                        int simd)
{
#ifdef VN_HAVE_AVX2
	if (simd) {
		scale_batch_avx2(q, first, top, act, scale);
		return;
	}
#else
	(void)simd;
#endif
	scale_lanes(q, first, top, act, scale);
}

/* gaussian_lanes, in AVX2 registers where simd is set (the same bits). */
static void gaussian_batch(double* q, const uint32_t count[LANES], double neff[LANES], double sum[LANES], int simd)
{
#ifdef VN_HAVE_AVX2
	if (simd) {
		gaussian_batch_avx2(q, count, neff, sum);
		return;
	}
#else
	(void)simd;
#endif
	gaussian_lanes(q, count, neff, sum);
}

/* Lane l of fit r, if it succeeded within 60 degrees of the seed: its
 * normal into n and, when res is not NULL, its residual; returns whether. */
static int take(const fits* r, int first_ok, unsigned l, const double* seed, double n[3], double* res)
{
	if (!(first_ok && r->n[0][l] * seed[0] + r->n[1][l] * seed[1] + r->n[2][l] * seed[2] >= SEED_COS_MIN))
		return 0;
	for (int d = 0; d < 3; ++d)
		n[d] = r->n[d][l];
	if (res)
		*res = rms_residual(r, l);
	return 1;
}

/* The fit in the seed's frame, then once more in the result's, for the
 * active lanes: ok[l] says whether n[l] was written (0 when the first fit
 * fails or the result strays from the seed); res[l] is the residual of the
 * fit written, computed only when res is not NULL; fitted[l], when not
 * NULL, whether the first fit succeeded (ok[l] 0 with fitted[l] 1: the
 * result strayed from the seed). */
static void fit_twice(const double* q, const uint32_t m[LANES], const int act[LANES], const double* const seed[LANES],
                      int cubic, int simd, double n[LANES][3], int ok[LANES], double res[LANES], int fitted[LANES])
{
	fits f[2];
	lanes a[3];
	for (int l = 0; l < LANES; ++l)
		for (int d = 0; d < 3; ++d)
			a[d][l] = act[l] ? seed[l][d] : (d == 2);
	const fit_fn fit = fit_kernel(cubic, simd);
	fit(q, m, act, a, f);
	fit(q, m, f[0].ok, f[0].n, f + 1);
	for (unsigned l = 0; l < LANES; ++l) {
		ok[l] = take(f[1].ok[l] ? f + 1 : f, f[0].ok[l], l, seed[l], n[l], res ? res + l : NULL);
		if (fitted)
			fitted[l] = f[0].ok[l];
	}
}

int vn_fit_frame(const double* p, uint32_t m, double h, double* scratch, const double a[3], int degree, double n[3],
                 double* residual)
{
	memset(scratch, 0, sizeof(double) * PT * (size_t)m);
	for (uint32_t i = 0; i < m; ++i)
		for (int d = 0; d < 3; ++d)
			scratch[PT * (size_t)i + d * LANES] = p[3 * (size_t)i + d];
	const lanes inv = {1.0 / h, 1.0, 1.0, 1.0};
	prepare_lanes(scratch, m, &inv);
	const uint32_t count[LANES] = {m, 0, 0, 0};
	const int act[LANES] = {1, 0, 0, 0};
	lanes axis[3] = {{a[0], 0, 0, 0}, {a[1], 0, 0, 0}, {a[2], 1, 1, 1}};
	fits f;
	(degree == 3 ? fit_jets : fit_quadrics)(scratch, count, act, axis, &f);
	if (!f.ok[0])
		return 0;
	for (int d = 0; d < 3; ++d)
		n[d] = f.n[d][0];
	if (residual)
		*residual = rms_residual(&f, 0);
	return 1;
}

/* ---------------------------------------------------------------- adjacency */

typedef struct scratch {
	uint32_t* stamp; /* nv: the tag of the ring a vertex was last added to */
	uint32_t tag;
	uint32_t* rings; /* LANES lists of up to cap members (and room for one more): a batch's lanes' */
	uint32_t* ring;  /* the list being built: the first, or a lane's (gather_vertex) */
	double* q;       /* PT cap: the batch's points (PT): x, y, z minus the vertex's, then over h, weight */
	size_t cap;
} scratch;

typedef struct fit_job {
	vn_work w;
	const double* seed;    /* 3 per vertex */
	const double* lattice; /* ADAPTIVE: 3 per vertex, ADAPTIVE_LATTICE_ROUGH's normals */
	const double* mwselr;  /* ADAPTIVE: 3 per vertex, MWSELR's normals */
	double* pick;          /* ADAPTIVE: 7 per vertex: the outcomes (adaptive_lanes), log T */
	double unit, quantum;  /* ADAPTIVE: the coordinates' rounding (vn_coordinate_rounding) */
	unsigned char* finite; /* per vertex: its coordinates are finite */
	unsigned char* usable; /* polygons: per face, its corners are finite and at least 3 */
	uint32_t* face_of;     /* polygons: per corner */
	uint32_t* start;       /* nv + 1: counts, then where each vertex's corners end */
	uint32_t* list;        /* corners by vertex, in corner order (phase_list) */
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

/* Adds 1 to count[v] for each corner of a vertex v in [v0, v0 + span), of
 * every vertex where all is set (one worker: no test a corner). */
VN_INLINE void count_corners(const uint32_t* idx, uint32_t n, uint32_t v0, uint32_t span, int all, uint32_t* count)
{
	for (uint32_t c = 0; c < n; ++c)
		if (all || idx[c] - v0 < span)
			++count[idx[c]];
}

/* Each worker's vertices' finiteness and corner counts; polygons' corners'
 * faces. A face's usability is read from its corners' finiteness by
 * phase_list: one flag a corner instead of a position. */
static void phase_count(void* ctx, unsigned t)
{
	fit_job* j = (fit_job*)ctx;
	const vn_work* w = &j->w;
	const uint32_t nf = (uint32_t)w->face_count;
	if (w->offsets)
		for (uint32_t f = range_lo(nf, t, j->nt), f1 = range_lo(nf, t + 1, j->nt); f < f1; ++f)
			for (uint32_t c = w->offsets[f]; c < w->offsets[f + 1]; ++c)
				j->face_of[c] = f;
	const uint32_t v0 = range_lo(w->vertex_count, t, j->nt), span = range_lo(w->vertex_count, t + 1, j->nt) - v0;
	for (uint32_t v = v0; v < v0 + span; ++v)
		j->finite[v] = (unsigned char)vn_finite_at(w, v);
	uint32_t* count = j->start + 1;
	memset(count + v0, 0, sizeof(uint32_t) * span);
	if (j->nt == 1)
		count_corners(w->indices, corner_count(w), v0, span, 1, count);
	else
		count_corners(w->indices, corner_count(w), v0, span, 0, count);
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

/* Lists the corners of the triangles' vertices in [v0, v1) (of every
 * vertex where all is set: one worker, no test a corner) as phase_list
 * describes. */
VN_INLINE void list_triangles(const fit_job* j, uint32_t v0, uint32_t v1, int all)
{
	const uint32_t* idx = j->w.indices;
	for (uint32_t f = 0; f < (uint32_t)j->w.face_count; ++f) {
		const uint32_t a = idx[3 * f], b = idx[3 * f + 1], c = idx[3 * f + 2];
		const uint32_t corner[3][3] = {{a, b, c}, {b, c, a}, {c, a, b}}; /* v, next, previous */
		const int ok = j->finite[a] & j->finite[b] & j->finite[c];
		for (int at = 0; at < 3; ++at) {
			const uint32_t v = corner[at][0];
			if (!all && v - v0 >= v1 - v0)
				continue;
			uint32_t* e = j->list + 2 * (size_t)j->start[v]++;
			e[0] = ok ? corner[at][1] : v, e[1] = ok ? corner[at][2] : v;
		}
	}
}

/* Lists the polygon corners of the vertices in [v0, v1) (of every vertex
 * where all is set: one worker, no test a corner), as their corner index. */
VN_INLINE void list_polygon_corners(const fit_job* j, uint32_t v0, uint32_t v1, int all)
{
	const uint32_t* idx = j->w.indices;
	for (uint32_t c = 0, n = corner_count(&j->w); c < n; ++c)
		if (all || idx[c] - v0 < v1 - v0)
			j->list[j->start[idx[c]]++] = c;
}

/* Each worker lists its vertices' corners (start[v] moves from v's first
 * to past its last), finds its largest 1-ring candidate count and decides
 * the usability of its range of polygons. A
 * polygon corner is listed as its corner index; a triangle corner as the
 * triangle's next and previous vertices (two entries), read here in corner
 * order, so that gather does not look up the faces again in vertex order:
 * for an unusable triangle both are the vertex itself, which gather has
 * stamped already. */
static void phase_list(void* ctx, unsigned t)
{
	fit_job* j = (fit_job*)ctx;
	const vn_work* w = &j->w;
	const uint32_t v0 = range_lo(w->vertex_count, t, j->nt), v1 = range_lo(w->vertex_count, t + 1, j->nt);
	const uint32_t* idx = w->indices;
	uint32_t begin = v0 < v1 ? j->start[v0] : 0;
	if (w->offsets) {
		const uint32_t nf = (uint32_t)w->face_count;
		for (uint32_t f = range_lo(nf, t, j->nt), f1 = range_lo(nf, t + 1, j->nt); f < f1; ++f) {
			const uint32_t b = w->offsets[f], e = w->offsets[f + 1];
			int ok = e - b >= 3;
			for (uint32_t c = b; c < e; ++c)
				ok &= j->finite[idx[c]];
			j->usable[f] = (unsigned char)ok;
		}
		if (j->nt == 1)
			list_polygon_corners(j, v0, v1, 1);
		else
			list_polygon_corners(j, v0, v1, 0);
	} else if (j->nt == 1) {
		list_triangles(j, v0, v1, 1);
	} else {
		list_triangles(j, v0, v1, 0);
	}
	uint32_t top = 0;
	for (uint32_t v = v0; v < v1; begin = j->start[v++]) {
		uint32_t cand = 0;
		if (!w->offsets) /* two a triangle */
			cand = 2 * (j->start[v] - begin);
		for (uint32_t i = begin; i < j->start[v] && w->offsets; ++i) {
			uint32_t b, k;
			face_at(j, j->list[i], &b, &k);
			cand += k <= RING_ALL_MAX ? k - 1 : 2;
		}
		top = cand > top ? cand : top;
	}
	j->top[t] = top;
}

/* Appends to s->ring the unstamped vertices sharing a usable face with u.
 * They are at most phase_list's candidate count of u (and fewer than nv),
 * which the capacity holds: no test of it here. */
static uint32_t gather(const fit_job* j, scratch* s, uint32_t u, uint32_t m)
{
	const uint32_t* idx = j->w.indices;
	const uint32_t tag = s->tag;
	if (!j->w.offsets) { /* triangles: each corner's next and previous vertex (phase_list) */
		/* Without a branch on the stamp, as in expand: in a closed fan
		 * every neighbour comes twice. A corner's two at a time. */
		uint32_t *stamp = s->stamp, *ring = s->ring;
		const uint32_t *e = j->list + 2 * (size_t)(u ? j->start[u - 1] : 0), *end = j->list + 2 * (size_t)j->start[u];
		for (; e < end; e += 2) {
			const uint32_t x = e[0], fresh = stamp[x] != tag;
			stamp[x] = tag, ring[m] = x, m += fresh;
			const uint32_t y = e[1], new_y = stamp[y] != tag;
			stamp[y] = tag, ring[m] = y, m += new_y;
		}
		return m;
	}
	for (uint32_t i = u ? j->start[u - 1] : 0; i < j->start[u]; ++i) {
		const uint32_t c = j->list[i];
		uint32_t b, k;
		if (!j->usable[face_at(j, c, &b, &k)])
			continue;
		/* A large polygon: its two edge neighbours (o = 1, k - 1), without
		 * a pass over its corners, which made a big cap quadratic. */
		const uint32_t at = c - b, step = k > RING_ALL_MAX ? k - 2 : 1;
		for (uint32_t o = 1; o < k; o += step) {
			const uint32_t x = idx[b + (at + o) % k];
			if (s->stamp[x] != tag)
				s->stamp[x] = tag, s->ring[m++] = x;
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

/* Loads ring members [from, to) into lane `lane` of the batch's points q,
 * relative to o. */
static void load_members(const fit_job* j, const scratch* s, uint32_t from, uint32_t to, const double o[3],
                         unsigned lane)
{
	for (uint32_t i = from; i < to; ++i) {
		double x[3];
		vn_load(&j->w, j->w.type, s->ring[i], x);
		double* b = s->q + PT * (size_t)i + lane;
		b[0] = x[0] - o[0], b[LANES] = x[1] - o[1], b[2 * LANES] = x[2] - o[2];
	}
}

/* Zeros in lane l's points [from, to) of a batch: the fits read every
 * lane's points up to the batch's longest (with weight 0 past a lane's
 * count), so they must be finite. */
static void zero_points(double* q, unsigned l, uint32_t from, uint32_t to)
{
	for (uint32_t i = from; i < to; ++i)
		for (int d = 0; d < 4; ++d)
			q[PT * (size_t)i + d * LANES + l] = 0.0;
}

/* Rings from + 1 to `to` of a vertex at o whose rings up to `from` are
 * s->ring[0, m[from - 1]) (stamped): each appended to s->ring (to m[r] for
 * ring r + 1; the members nearest by rings first when they would pass the
 * scratch's capacity) and loaded into lane `lane`; m[r] = m[r - 1] past
 * `to`. */
static void expand_rings(const fit_job* j, scratch* s, const double o[3], unsigned lane, int from, int to,
                         uint32_t m[ADAPTIVE_RINGS])
{
	for (int r = from; r < to; ++r) {
		m[r] = m[r - 1];
		for (uint32_t i = r > 1 ? m[r - 2] : 0; i < m[r - 1]; ++i) {
			const uint32_t u = s->ring[i];
			if (j->nstart[u + 1] - j->nstart[u] <= RING_HUB_MAX)
				m[r] = expand(j, s, u, m[r]);
		}
		load_members(j, s, m[r - 1], m[r], o, lane);
	}
	for (int r = to; r < ADAPTIVE_RINGS; ++r)
		m[r] = m[r - 1];
}

/* Vertex v's points into lane `lane` of the batch, relative to v (not yet
 * over h), and its members into the lane's list (s->ring becomes it): its
 * 1-ring (ring[0, m[0])), then for JET and ADAPTIVE its 2-ring (to m[1]);
 * m[r] = m[r - 1] past it (ADAPTIVE's wider rings come later, from
 * widen_vertex, where they are fitted). m all 0 when v keeps its seed. */
static void gather_vertex(const fit_job* j, scratch* s, uint32_t v, unsigned lane, uint32_t m[ADAPTIVE_RINGS])
{
	memset(m, 0, sizeof(uint32_t) * ADAPTIVE_RINGS);
	s->ring = s->rings + (s->cap + 1) * lane;
	const double* seed = j->seed + 3 * (size_t)v;
	if (vn_is_zero(seed))
		return;
	new_tag(j, s);
	s->stamp[v] = s->tag;
	const uint32_t first = j->nbr ? expand(j, s, v, 0) : gather(j, s, v, 0);
	if (!first)
		return;
	double o[3];
	vn_load(&j->w, j->w.type, v, o);
	load_members(j, s, 0, first, o, lane);
	m[0] = first;
	expand_rings(j, s, o, lane, 1, j->w.method == vn_method_quadric ? 1 : 2, m);
}

/* ADAPTIVE's 3- to 5-rings of vertex v (gathered by gather_vertex into
 * lane `lane`, m its ends) into the lane, after its 2-ring (to m[1] .. m[4])
 * and over its h (scale: 1 / h, the same product as scale_lanes's): the
 * points one gathering would give. Its members are stamped again (the
 * other lanes' gathering stamped theirs since). */
static void widen_vertex(const fit_job* j, scratch* s, uint32_t v, unsigned lane, double scale,
                         uint32_t m[ADAPTIVE_RINGS])
{
	s->ring = s->rings + (s->cap + 1) * lane;
	new_tag(j, s);
	s->stamp[v] = s->tag;
	for (uint32_t i = 0; i < m[1]; ++i)
		s->stamp[s->ring[i]] = s->tag;
	double o[3];
	vn_load(&j->w, j->w.type, v, o);
	expand_rings(j, s, o, lane, 2, ADAPTIVE_RINGS, m);
	for (uint32_t i = m[1]; i < m[ADAPTIVE_RINGS - 1]; ++i)
		for (int d = 0; d < 3; ++d)
			s->q[PT * (size_t)i + d * LANES + lane] *= scale;
}

/* The sums of ADAPTIVE's sphere test (sphere_lanes) over each lane's first
 * count[l] points of q, in its order (+ 0 past its count), n[.][l] the
 * lane's unit normal: zb = sum z b, bb = sum b^2, bmax = max b, z = p . n
 * and b = |p|^2 / 2. */
VN_INLINE void sphere_sums(const double* q, const double count[LANES], const lanes n[3], lanes sums[3])
{
	const lanes zero = {0.0, 0.0, 0.0, 0.0}, c = {count[0], count[1], count[2], count[3]};
	lanes zb = zero, bb = zero, bmax = zero;
	uint32_t most = 0;
	UNROLL for (int l = 0; l < LANES; ++l)
		most = (uint32_t)count[l] > most ? (uint32_t)count[l] : most;
	for (uint32_t i = 0; i < most; ++i) {
		const double* p = q + PT * (size_t)i;
		const lanes x = LOAD(p), y = LOAD(p + LANES), z = LOAD(p + 2 * LANES), b = 0.5 * (x * x + y * y + z * z);
		const masks in = (zero + (double)i) < c, above = in & (b > bmax);
		zb += (lanes)((masks)((x * n[0] + y * n[1] + z * n[2]) * b) & in), bb += (lanes)((masks)(b * b) & in);
		bmax = (lanes)(((masks)b & above) | ((masks)bmax & ~above));
	}
	sums[0] = zb, sums[1] = bb, sums[2] = bmax;
}

#ifdef VN_HAVE_AVX2
static VN_AVX2 void sphere_sums_avx2(const double* q, const double count[LANES], const lanes n[3], lanes sums[3])
{
	sphere_sums(q, count, n, sums);
}
#endif

/* sphere_sums, in AVX2 registers where simd is set (the same bits). */
static void sphere_batch(const double* q, const double count[LANES], const lanes n[3], lanes sums[3], int simd)
{
#ifdef VN_HAVE_AVX2
	if (simd) {
		sphere_sums_avx2(q, count, n, sums);
		return;
	}
#else
	(void)simd;
#endif
	sphere_sums(q, count, n, sums);
}

/* ADAPTIVE's sphere test at the batch's lanes l whose vertex v0 + l is below
 * v1 and active: whether its 2-ring (m[l][1] points of q, relative to it,
 * over h = 1 / scale[l]) lies on one sphere through it tangent to MWSELR's
 * plane (unit normal n): z = k b at every point (sphere_sums), k by least
 * squares, to ADAPTIVE_SPHERE_ROUNDING units of rounding of the largest
 * coordinate among them (the vertex's, at least j->quantum, plus the
 * farthest point's distance, each times j->unit), over h, and at most
 * ADAPTIVE_JET_EXACT; not where the sphere is a plane to that tolerance
 * (there the jet is exact). */
static void sphere_lanes(const fit_job* j, const double* q, uint32_t m[LANES][ADAPTIVE_RINGS], const int act[LANES],
                         const double scale[LANES], uint32_t v0, uint32_t v1, int sphere[LANES])
{
	lanes n[3], sums[3];
	double count[LANES];
	for (unsigned l = 0; l < LANES; ++l) {
		const double* s = j->mwselr + 3 * (size_t)(v0 + l < v1 ? v0 + l : v0);
		const int in = v0 + l < v1 && act[l] && m[l][1] >= ADAPTIVE_SPHERE_POINTS && !vn_is_zero(s);
		count[l] = in ? (double)m[l][1] : 0.0;
		for (int d = 0; d < 3; ++d)
			n[d][l] = s[d];
	}
	sphere_batch(q, count, n, sums, j->w.simd);
	for (unsigned l = 0; l < LANES; ++l) {
		sphere[l] = 0;
		if (!(count[l] > 0.0))
			continue;
		double o[3];
		vn_load(&j->w, j->w.type, v0 + l, o);
		const double bmax = sums[2][l], x = fabs(o[0]), y = fabs(o[1]), z = fabs(o[2]), r = x > y ? x : y;
		const double big = j->unit * (r > z ? r : z), vertex = big > j->quantum ? big : j->quantum;
		const double rounding = ADAPTIVE_SPHERE_ROUNDING * (vertex * scale[l] + j->unit * sqrt(2.0 * bmax));
		const double tol = rounding < ADAPTIVE_JET_EXACT ? rounding : ADAPTIVE_JET_EXACT;
		const double k = sums[1][l] > 0.0 ? sums[0][l] / sums[1][l] : 0.0;
		if (!(fabs(k) * bmax > tol))
			continue;
		uint32_t i = 0;
		for (; i < m[l][1]; ++i) {
			const double* p = q + PT * (size_t)i + l;
			const double px = p[0], py = p[LANES], pz = p[2 * LANES];
			if (!(fabs(px * n[0][l] + py * n[1][l] + pz * n[2][l] - k * 0.5 * (px * px + py * py + pz * pz)) <= tol))
				break;
		}
		sphere[l] = i == m[l][1];
	}
}

/* Coordinates read from text with at most this many decimal places, or
 * significant digits, count as decimals (Blender's OBJ and ASCII STL write
 * 6 places, other STL writers %e, 7 digits): their rounding is the text's,
 * not float64's. */
#define DECIMAL_PLACES_MAX 12
#define DECIMAL_DIGITS_MAX 15

/* 10^n for n from -22 to 22 (exact from 0 up): the nearest doubles. */
static const double ten_to[45] = {1e-22, 1e-21, 1e-20, 1e-19, 1e-18, 1e-17, 1e-16, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11,
                                  1e-10, 1e-9,  1e-8,  1e-7,  1e-6,  1e-5,  1e-4,  1e-3,  1e-2,  1e-1,  1e0,   1e1,
                                  1e2,   1e3,   1e4,   1e5,   1e6,   1e7,   1e8,   1e9,   1e10,  1e11,  1e12,  1e13,
                                  1e14,  1e15,  1e16,  1e17,  1e18,  1e19,  1e20,  1e21,  1e22};
#define TEN_TO(n) ten_to[22 + (n)]

/* Whether a > 0 is the double nearest N 10^-k (what a correctly rounding
 * reader makes of text with k places; k < 0: N 10^|k|), N an integer below
 * 2^51: N = a 10^k rounded, and N 10^-k, both factors exact (|k| <= 22), is
 * then correctly rounded. */
static int decimal_at(double a, int k)
{
	const int up = k >= 0;
	const double ten = TEN_TO(up ? k : -k), t = up ? a * ten : a / ten;
	if (!(t < 0x1p51)) /* N's rounding unknown past here */
		return 0;
	const double n = (t + 0x1p52) - 0x1p52; /* t rounded to an integer (0 <= t < 2^51): no libm call */
	return (up ? n / ten : n * ten) == a;
}

/* Whether printf's %e to s significant digits reads back as a. */
static int printed_at(double a, int s)
{
	char text[40];
	snprintf(text, sizeof(text), "%.*e", s - 1, a);
	return strtod(text, NULL) == a;
}

/* How the coordinates seen so far read as decimals: whether every one has
 * at most DECIMAL_PLACES_MAX places (fixed) and at most DECIMAL_DIGITS_MAX
 * significant digits (digits_ok), and the fewest places and digits that
 * write them all. */
typedef struct decimals {
	int fixed, digits_ok, places, digits;
} decimals;

/* Adds finite x to d. A decimal with k places has them all for every k
 * above its fewest (N gains zeros), so x changes nothing where it has
 * min(places, digits - 1 - e) places, e = floor(log10 |x|): one test for
 * most coordinates. e from the binary exponent, then against the powers of
 * ten; where a power needed is not exact (|x| below about 1e-8, as cos(pi /
 * 2) leaves, or 1e22 or above), digits as printf writes them. */
static void add_decimal(double x, decimals* d)
{
	const double a = fabs(x);
	/* Fixed places first: with k <= places, |x| < 10^(digits - places) gives
	 * it at most digits (no e needed). */
	if (a == 0.0 || (d->fixed && d->digits_ok && a < TEN_TO(d->digits - d->places) && decimal_at(a, d->places)))
		return;
	uint64_t bits;
	memcpy(&bits, &a, sizeof(bits));
	/* The binary exponent b (2^b <= a; subnormals: lower, not exact), times
	 * log10 2 (1233 / 4096 is below it by 5e-6), rounded down (made
	 * positive for the division): e is floor(log10 a) or one off. */
	const int b = (int)(bits >> 52) - 1023;
	int e = (b * 1233 + 2048 * 4096) / 4096 - 2048;
	const int exact = e >= -22 && e <= 21;
	if (exact) {
		e -= a < TEN_TO(e);
		e += e < 21 && a >= TEN_TO(e + 1);
	}
	const int both = d->places < d->digits - 1 - e ? d->places : d->digits - 1 - e;
	if (exact && d->fixed && d->digits_ok && both >= -22 && decimal_at(a, both))
		return;
	int k = d->places;
	while (d->fixed && !decimal_at(a, k))
		d->fixed = ++k <= DECIMAL_PLACES_MAX;
	d->places = k;
	int s = d->digits > 1 ? d->digits : 1;
	for (; d->digits_ok; d->digits_ok = ++s <= DECIMAL_DIGITS_MAX) {
		const int shift = s - 1 - e;
		if (exact && shift >= -22 && shift <= 22 ? decimal_at(a, shift) : printed_at(a, s))
			break;
	}
	d->digits = s;
}

/* The rounding of the coordinates, for ADAPTIVE's sphere test: *unit
 * relative to a coordinate, *quantum absolute. float32's unit (quantum 0)
 * where every finite coordinate is a float32 value. Else float64's unit,
 * raised to half a unit in the last of the fewest significant digits that
 * write every coordinate (where there are such), and quantum half a unit
 * in the last of the fewest places that do (where there are such, else
 * 0): text is written to fixed places (%f) or to digits (%g, %e), and each
 * bound holds for the way that leaves it. */
void vn_coordinate_rounding(const vn_work* w, double* unit, double* quantum)
{
	int floats = 1;
	decimals d = {1, 1, 0, 0};
	for (uint32_t v = 0; w->type == vn_scalar_float64 && (floats || d.fixed || d.digits_ok) && v < w->vertex_count;
	     ++v) {
		double p[3];
		vn_load(w, w->type, v, p);
		for (int c = 0; c < 3; ++c)
			if (isfinite(p[c])) {
				floats = floats && fabs(p[c]) <= FLT_MAX && (double)(float)p[c] == p[c];
				if (d.fixed || d.digits_ok)
					add_decimal(p[c], &d);
			}
	}
	*unit = floats ? FLT_EPSILON / 2 : DBL_EPSILON / 2, *quantum = 0.0;
	if (!floats && d.digits_ok && d.digits > 0 && 0.5 * TEN_TO(1 - d.digits) > *unit)
		*unit = 0.5 * TEN_TO(1 - d.digits);
	if (!floats && d.fixed)
		*quantum = 0.5 * TEN_TO(-d.places);
}

/* Generalized cross-validation score of a fit of k unknowns with weighted
 * RMS residual res over n effective points (Craven & Wahba 1979): the
 * residual inflated for the freedom the fit used to reach it. */
static double gcv(double res, double n, int k)
{
	const double d = 1.0 - k / n;
	return d > 0.0 ? res * res / (d * d) : DBL_MAX;
}

/* Whether unit normal a is within `angle` radians of unit normal b (never
 * where a is zero). */
static int within(const double a[3], const double b[3], double angle)
{
	if (vn_is_zero(a))
		return 0;
	double c[3];
	vn_cross(a, b, c);
	return atan2(sqrt(vn_dot(c, c)), vn_dot(a, b)) < angle;
}

/* The effective number of one lane's first m points (q at the lane's
 * first), (sum w)^2 / sum w^2, the vertex (weight 1) included. */
static double effective_points(const double* q, uint32_t m)
{
	double sw = 1.0, sww = 1.0;
	for (uint32_t i = 0; i < m; ++i) {
		const double w = q[PT * (size_t)i + 3 * LANES];
		sw += w, sww += w * w;
	}
	return sw * sw / sww;
}

/* The corners of the face of vertex v's listed corner e (an entry of
 * j->list) after v's, in order into out: its next first, its previous
 * last. Their count, 0 where the face is unusable or has more than max. */
static uint32_t face_after(const fit_job* j, uint32_t v, uint32_t e, uint32_t max, uint32_t* out)
{
	if (!j->w.offsets) {
		const uint32_t* p = j->list + 2 * (size_t)e; /* both v where unusable (phase_list) */
		out[0] = p[0], out[1] = p[1];
		return p[0] == v || max < 2 ? 0 : 2;
	}
	const uint32_t c = j->list[e];
	uint32_t b, k;
	if (!j->usable[face_at(j, c, &b, &k)] || k - 1 > max)
		return 0;
	for (uint32_t o = 1; o < k; ++o)
		out[o - 1] = j->w.indices[b + (c - b + o) % k];
	return k - 1;
}

/* Vertex v's 1-ring in order around it, into ring: where v's faces close
 * one fan, each face's corners after v's but its last, which is the next
 * face's first. The count, 0 where they do not (a boundary, a non-manifold
 * vertex, an unusable face, a member twice or v itself) or where it would
 * not be even, from 4 to LATTICE_MEMBERS_MAX. */
static uint32_t fan(const fit_job* j, uint32_t v, uint32_t ring[LATTICE_MEMBERS_MAX])
{
	const uint32_t first = v ? j->start[v - 1] : 0, count = j->start[v] - first;
	if (count < 2 || count > LATTICE_MEMBERS_MAX || (!j->w.offsets && count % 2)) /* a triangle gives one member */
		return 0;
	/* Corner i's face: after[at[i]] to after[at[i] + size[i]), its members
	 * and then the next face's first. */
	uint32_t after[2 * LATTICE_MEMBERS_MAX + 1], at[LATTICE_MEMBERS_MAX], size[LATTICE_MEMBERS_MAX], members = 0;
	for (uint32_t i = 0, filled = 0; i < count; ++i) {
		at[i] = filled;
		size[i] = face_after(j, v, first + i, LATTICE_MEMBERS_MAX - members + 1, after + filled);
		if (size[i] < 2)
			return 0;
		members += size[i] - 1, filled += size[i];
	}
	if (members < 4 || members % 2) /* no lattice_ring needs */
		return 0;
	uint32_t n = 0, used = 0;
	for (uint32_t step = 0, e = 0; step < count; ++step) {
		used |= 1u << e;
		for (uint32_t i = 0; i + 1 < size[e]; ++i)
			ring[n++] = after[at[e] + i];
		const uint32_t last = after[at[e] + size[e] - 1];
		uint32_t next = 0, found = 0; /* branch-free: which face goes on cannot be predicted */
		for (uint32_t i = 0; i < count; ++i) {
			const uint32_t on = !(used >> i & 1) & (after[at[i]] == last);
			found += on, next = on ? i : next;
		}
		if (step + 1 < count ? found != 1 : last != ring[0]) /* two faces going on from one edge: not a fan */
			return 0;
		e = next;
	}
	for (uint32_t i = 0; i < n; ++i)
		for (uint32_t k = i + 1; k <= n; ++k)
			if (ring[i] == (k < n ? ring[k] : v))
				return 0;
	return n;
}

/* Whether vertex v's 1-ring is a height field sampled on a lattice: its
 * faces close one fan (fan) of an even number 2m >= 4 of members p_i
 * around p = v's position, and the m second differences p_i + p_(i + m) -
 * 2 p are parallel (or zero: a flat lattice), to LATTICE_SLACK h. Seen
 * along their direction the ring is then centrally symmetric, as a
 * lattice's rows, diagonals or quads are, with the heights along it the
 * surface's. */
static int lattice_ring(const fit_job* j, uint32_t v, double h)
{
	uint32_t ring[LATTICE_MEMBERS_MAX];
	const uint32_t n = fan(j, v, ring), m = n / 2;
	if (!n)
		return 0;
	double o[3], u[LATTICE_MEMBERS_MAX / 2][3], longest = 0.0;
	uint32_t at = 0;
	vn_load(&j->w, j->w.type, v, o);
	for (uint32_t i = 0; i < m; ++i) {
		double a[3], b[3];
		vn_load(&j->w, j->w.type, ring[i], a);
		vn_load(&j->w, j->w.type, ring[i + m], b);
		for (int d = 0; d < 3; ++d)
			u[i][d] = (a[d] - o[d]) + (b[d] - o[d]);
		const double len2 = vn_dot(u[i], u[i]);
		if (len2 > longest)
			longest = len2, at = i;
	}
	const double tol = LATTICE_SLACK * h, len = sqrt(longest);
	if (!(len > tol))
		return 1;
	double d[3], c[3];
	for (int k = 0; k < 3; ++k)
		d[k] = u[at][k] / len;
	for (uint32_t i = 0; i < m; ++i) { /* the part of u_i across d */
		vn_cross(u[i], d, c);
		if (!(sqrt(vn_dot(c, c)) <= tol))
			return 0;
	}
	return 1;
}

/* ADAPTIVE's rough fallback at vertex v (h: its mean 1-ring distance, 0
 * where it has no ring): MWAAT's normal where the ring is a lattice
 * (lattice_ring), else S. */
static const double* rough_fallback(const fit_job* j, uint32_t v, double h)
{
	return (h > 0.0 && lattice_ring(j, v, h) ? j->lattice : j->seed) + 3 * (size_t)v;
}

/* ADAPTIVE at the active lanes, after the 2-ring jet f (ok, residual res):
 * the jet where it is exact, the rough fallback where its residual exceeds
 * ADAPTIVE_ROUGH_MAX; else the quadric and the cubic on the 5-ring with
 * Gaussian weights, in the jet's frame. The wide fits only where the
 * jet succeeded: where it failed, the 2-ring is too small or degenerate,
 * and a wide fit would rest on far points (a cone fan's rim vertex: the
 * rim on a conic and the apex, which tilts the quadric at will).
 * pick[v] receives two outcomes, the jet or the quadric (the cubic where
 * the quadric failed) by GCV score (ADAPTIVE_JET_MARGIN), and the jet or
 * the cubic (the quadric where the cubic failed) likewise, then log T where
 * both wide fits succeeded (NaN elsewhere): phase_choose takes one. fall[l]
 * is the fallback where no fit is taken: JET's own where the jet could not
 * be fitted, else NULL for the rough one (rough_fallback). The batch's
 * points (s->q, finite up to top, scale[l] = 1 / h) gain the 5-rings of
 * the lanes that fit them (widen_vertex; m: the ring ends). Vertices from
 * v1 on are another worker's. */
static void adaptive_lanes(const fit_job* j, scratch* s, uint32_t top, const double scale[LANES], const int act[LANES],
                           uint32_t m[LANES][ADAPTIVE_RINGS], const double* const seed[LANES], const double f[LANES][3],
                           const int ok[LANES], const double res[LANES], const double* const fall[LANES],
                           const uint32_t v0, const uint32_t v1)
{
	int wide[LANES], sphere[LANES], any = 0;
	double neff[LANES], sw[LANES], best[LANES];
	double* const pts = s->q;
	sphere_lanes(j, pts, m, act, scale, v0, v1, sphere);
	uint32_t count[LANES], widest = top;
	lanes axis[3];
	for (unsigned l = 0; l < LANES; ++l) {
		wide[l] = 0, count[l] = 0;
		for (int d = 0; d < 3; ++d)
			axis[d][l] = d == 2;
		if (v0 + l >= v1) /* another worker's vertex */
			continue;
		double* out = j->pick + 7 * (size_t)(v0 + l);
		const int jet = act[l] && ok[l];
		/* Without a ring, or where no fit is taken: the fallback. */
		const int smooth = jet && res[l] <= ADAPTIVE_ROUGH_MAX;
		const double* mwselr = j->mwselr + 3 * (size_t)(v0 + l);
		memcpy(out,
		       sphere[l] ? mwselr
		       : !smooth ? (fall[l] ? fall[l] : rough_fallback(j, v0 + l, act[l] ? 1.0 / scale[l] : 0.0))
		       : within(mwselr, f[l], ADAPTIVE_MWSELR_AGREE * res[l]) ? mwselr
		                                                                : f[l],
		       3 * sizeof(double));
		memcpy(out + 3, out, 3 * sizeof(double));
		out[6] = NAN;
		best[l] = sphere[l] || !smooth || res[l] <= ADAPTIVE_JET_EXACT
		              ? 0.0
		              : ADAPTIVE_JET_MARGIN * gcv(res[l], effective_points(pts + l, m[l][1]), 10);
		if (best[l] > 0.0) {
			widen_vertex(j, s, v0 + l, l, scale[l], m[l]);
			widest = m[l][ADAPTIVE_RINGS - 1] > widest ? m[l][ADAPTIVE_RINGS - 1] : widest;
		}
		wide[l] = best[l] > 0.0 && m[l][ADAPTIVE_RINGS - 1] > m[l][0];
		if (wide[l]) {
			any = 1;
			for (int d = 0; d < 3; ++d) /* the wide fits' frame */
				axis[d][l] = f[l][d];
		}
		count[l] = wide[l] ? m[l][ADAPTIVE_RINGS - 1] : 0;
	}
	if (!any)
		return;
	for (unsigned l = 0; l < LANES; ++l) /* [0, top) is finite already */
		zero_points(pts, l, m[l][ADAPTIVE_RINGS - 1] > top ? m[l][ADAPTIVE_RINGS - 1] : top, widest);
	gaussian_batch(pts, count, neff, sw, j->w.simd);
	fits w[2];
	fit_kernel(2, j->w.simd)(pts, count, wide, axis, w);
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
				memcpy(o, cubic ? c : q, 3 * sizeof(double));
		}
		if (okq && okc) {
			/* d, the quadric's slopes minus the cubic's (one frame); var(d)
			 * = sigma^2 (vs_cubic - vs_quadric) for nested least squares,
			 * sigma^2 from the cubic's residual over its degrees of freedom. */
			const double d1 = w[0].c[1][l] - w[1].c[1][l], d2 = w[0].c[2][l] - w[1].c[2][l];
			const double var = rc * rc * sw[l] / ((double)m[l][ADAPTIVE_RINGS - 1] + 1.0 - 10.0) * (w[1].vs[l] - w[0].vs[l]);
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
		if (!(j->w.keep_existing && vn_is_zero(r)))
			vn_store(j->w.out, v, r);
	}
}

/* Vertices v0 .. v0 + LANES - 1 (those below v1). */
static void fit_batch(const fit_job* j, scratch* s, uint32_t v0, uint32_t v1)
{
	const double* seed[LANES];
	int act[LANES], ok[LANES];
	uint32_t m[LANES][ADAPTIVE_RINGS], top = 0, ring[LANES], first[LANES];
	double n[LANES][3], res[LANES], scale[LANES];
	for (unsigned l = 0; l < LANES; ++l) {
		const uint32_t v = v0 + l;
		seed[l] = j->seed + 3 * (size_t)(v < v1 ? v : v0);
		if (v < v1)
			gather_vertex(j, s, v, l, m[l]);
		else
			memset(m[l], 0, sizeof(m[l]));
		act[l] = m[l][0] > 0;
		top = m[l][ADAPTIVE_RINGS - 1] > top ? m[l][ADAPTIVE_RINGS - 1] : top;
		ring[l] = m[l][1], first[l] = m[l][0];
		memcpy(n[l], seed[l], sizeof(n[l]));
	}
	for (unsigned l = 0; l < LANES; ++l)
		zero_points(s->q, l, m[l][ADAPTIVE_RINGS - 1], top);
	scale_batch(s->q, first, top, act, scale, j->w.simd);
	if (j->w.method == vn_method_quadric)
		fit_twice(s->q, first, act, seed, 0, j->w.simd, n, ok, NULL, NULL);
	else if (j->w.method == vn_method_adaptive) { /* stored by phase_choose */
		double f[LANES][3];
		int fitted[LANES], unfit[LANES], quadric_ok[LANES], again = 0;
		fit_twice(s->q, ring, act, seed, 1, j->w.simd, f, ok, res, fitted);
		/* Where the jet cannot be fitted (too few points, or degenerate),
		 * or only interpolates (as many points as its T_MAX unknowns: its
		 * residual, zero, would read as exact): JET's own fallback, the
		 * quadric on the 1-ring, else S (n holds it); where it was fitted
		 * but strays from S, or without a ring (S zero: gather_vertex
		 * gathers nothing): the rough one. */
		const double* fall[LANES];
		for (unsigned l = 0; l < LANES; ++l) {
			if (ring[l] + 1 <= T_MAX)
				fitted[l] = ok[l] = 0;
			unfit[l] = act[l] && !fitted[l];
			again |= unfit[l];
			fall[l] = unfit[l] ? n[l] : NULL;
		}
		if (again)
			fit_twice(s->q, first, unfit, seed, 0, j->w.simd, n, quadric_ok, NULL, NULL);
		adaptive_lanes(j, s, top, scale, act, m, seed, (const double(*)[3])f, ok, res, fall, v0, v1);
		return;
	} else {
		double f[LANES][3];
		fit_twice(s->q, ring, act, seed, 1, j->w.simd, f, ok, NULL, NULL);
		int again = 0;
		for (unsigned l = 0; l < LANES; ++l) {
			if (ok[l])
				memcpy(n[l], f[l], sizeof(f[l]));
			/* JET falls back to the quadric on the 1-ring. */
			act[l] = act[l] && !ok[l];
			again |= act[l];
		}
		if (again)
			fit_twice(s->q, first, act, seed, 0, j->w.simd, n, ok, NULL, NULL);
	}
	for (unsigned l = 0; l < LANES && v0 + l < v1; ++l) {
		const double* r = n[l];
		if (!(j->w.keep_existing && vn_is_zero(r)))
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
	double* seed = (double*)heap.allocate(heap.user, (adaptive ? 16 : 3) * sizeof(double) * (size_t)nv);
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
	for (int k = 1; adaptive && k < 3 && r == vn_result_success; ++k) { /* the lattice's rough fallback, MWSELR */
		const vn_vectors more = {seed + 3 * k * (size_t)nv, 3 * sizeof(double), vn_scalar_float64};
		vn_range_stats unused = {0, 0, 0, 0};
		j.w.method = k == 1 ? ADAPTIVE_LATTICE_ROUGH : vn_method_mwselr;
		j.w.out = &more;
		j.w.want_stats = 0;
		r = vn_run(&j.w, weighted, o, &unused);
	}
	if (adaptive) {
		j.lattice = seed + 3 * (size_t)nv;
		j.mwselr = seed + 6 * (size_t)nv;
		j.pick = seed + 9 * (size_t)nv;
		vn_coordinate_rounding(work, &j.unit, &j.quantum);
	}
	j.w = *work;
	j.seed = seed;
	j.nt = nt;

	/* start, list (two words a triangle corner; one a polygon corner, plus
	 * its face in face_of), top, nstart. */
	const size_t words = 2 * ((size_t)nv + 1) + 2 * (size_t)nc + nt;
	const size_t polygons = work->offsets ? nf : 0;
	const size_t bytes = sizeof(scratch) * nt + sizeof(uint32_t) * words + nv + polygons;
	unsigned char* block = r == vn_result_success ? (unsigned char*)heap.allocate(heap.user, bytes) : NULL;
	if (r == vn_result_success && !block)
		r = vn_result_out_of_memory;
	if (block) {
		j.scratch = (scratch*)(void*)block;
		j.start = (uint32_t*)(void*)(j.scratch + nt);
		j.list = j.start + nv + 1;
		j.top = j.list + (work->offsets ? nc : 2 * (size_t)nc);
		j.nstart = j.top + nt;
		j.face_of = work->offsets ? j.nstart + nv + 1 : NULL;
		j.finite = (unsigned char*)(j.start + words);
		j.usable = work->offsets ? j.finite + nv : NULL;
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
		const size_t ring_bytes = (sizeof(uint32_t) * ((size_t)nv + LANES * (cap + 1)) + 7) & ~(size_t)7;
		unsigned t = 0;
		for (; t < nt; ++t) {
			scratch* s = j.scratch + t;
			s->stamp = (uint32_t*)heap.allocate(heap.user, ring_bytes + PT * sizeof(double) * cap);
			if (!s->stamp)
				break;
			memset(s->stamp, 0, sizeof(uint32_t) * nv);
			s->tag = 0;
			s->rings = s->ring = s->stamp + nv;
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
