/* Per-frame plans: the topology work of a normal computation done once.
 *
 * vn_plan_create checks the indices once, copies them and lists the corners
 * of every vertex in 8 fixed slots (in input face order; unused slots name
 * a zero corner; vertices with more corners continue in an overflow list).
 * vn_plan_normals on float32 positions then gathers, for the weighted
 * family on triangles, in float arithmetic:
 *  - faces, eight per AVX2 step: each corner's contribution n * w_k (n the
 *    unnormalized normal, w_k the corner's weight as vn_triangle_weights
 *    defines it) as x, y, z, 0; zeros when the face contributes nothing;
 *  - vertices: each adds its slots' corners in order, normalizes, stores.
 * The passes are interleaved in chunks of CHUNK faces, so the corners are
 * read back from cache: each worker writes its faces' corners to a ring,
 * and after each chunk sums the vertices whose last face it held (a
 * schedule built at create). A vertex whose faces span more than the ring,
 * or two workers, or none, is far: its corners are also copied to a far
 * buffer and it is summed after all faces. When most vertices would be far
 * (input without locality), the faces are taken in a breadth-first order
 * instead, the slots still in input order. Each vertex's sum is formed in
 * one fixed order whatever the split and the face order, so results are
 * bit-identical for any thread count; the scalar and AVX2 kernels do the
 * same IEEE operations (fused ones with fmaf), so they agree bit for bit
 * too.
 *
 * float64 positions take vn_triangle_normals' scatter kernels (MWA with
 * vn_atan2_poly's angles), whose results a double gather would have to
 * reproduce bit for bit anyway, and which were as fast here
 * (docs/PERFORMANCE.md); everything else (polygons, the other schemes,
 * per-corner normals) runs the existing entry points on the plan's copy of
 * the indices, with the plan's memory as workspace. */
#include <stdlib.h>

#include "internal.h"
#include "simd.h"
#include "weights.h"

#define SLOTS 8
#define MAX_WORKERS 256 /* vn_parallel's limit */
/* Faces per chunk (48 KB of corners), and the largest ring: the faces whose
 * corners a worker keeps (768 KB, within a core's L2; vertices whose faces
 * span more are far). */
#define CHUNK 2048
#define WINDOW 16384
/* Slots hold byte offsets of corners (16 bytes each), so far corners must
 * be fewer than 2^28. */
#define MAX_FAR (1u << 28)
/* Corner c's x, y, z, 0 in a corner buffer, in floats. */
#define CORNER(c) (4 * (size_t)(c))
/* Float sums normalized directly; outside, rescaled first (vn_normalize). */
#define LEN2F_MIN 0x1p-100f
#define LEN2F_MAX 0x1p100f

struct vn_plan {
	vn_options opt; /* the caller's, workspace set to the plan's memory */
	uint32_t vertex_count;
	size_t face_count, index_count;
	uint32_t* indices;
	uint32_t* offsets; /* NULL for triangles */
	/* The gather's faces: indices, or their locality order when the input
	 * has none (vn_plan_create); the slots keep each vertex's corners in
	 * input order either way. */
	uint32_t* faces;
	/* For the gather's position loads (one instruction fewer than index
	 * times stride): indices[i] * words_stride / 4, the position's offset
	 * in 4-byte words for that stride (0: none yet), in faces' order; made for packed
	 * float32 at create, again for another stride when a call brings one. */
	uint32_t* words;
	size_t words_stride;
	int gather;        /* triangles with the corner table below */
	int simd;
	unsigned workers;
	uint32_t* slots; /* SLOTS corners of each vertex in order[], as byte offsets into its buffer */
	size_t over_count;
	uint32_t* over_vertex; /* vertices with more than SLOTS corners (all far), ascending */
	uint32_t* over_start;  /* over_count + 1 offsets into over_code */
	uint32_t* over_code;
	/* Vertices in the order they are summed: worker t's chunk k's vertices
	 * are order[start[base[t] + k] .. start[base[t] + k + 1]), then the
	 * far vertices from start[chunks] to the end. */
	uint32_t* order;
	uint32_t* start;
	uint32_t base[MAX_WORKERS + 1];
	/* Each worker writes its faces' corners to a ring of ring_faces faces
	 * (3 planes of ring_faces corners, then a zero corner and padding to 64
	 * bytes), corner k of face f at k ring_faces + (f - first face) mod
	 * ring_faces. A vertex summed after a chunk names ring corners
	 * (its faces are all still there); any other (far) vertex names
	 * corners of the far buffer (far_count and a zero one), in which its
	 * corners are consecutive: chunk k copies ring corner far_from[e] to
	 * far_to[e] for e in far_start[k] .. far_start[k + 1]. */
	uint32_t ring_faces;
	size_t far_count;
	uint32_t* far_start;
	uint32_t* far_from;
	uint32_t* far_to;
	uint8_t* last_in_chunk; /* whether a face of chunk k has the last vertex */
	float* corners; /* the rings, then the far buffer, 4 floats a corner, 64-byte aligned; also the workspace */
};

/* The floats of a worker's ring, its zero corner and padding: rings stay
 * 64-byte aligned for the face pass's 32-byte stores. */
#define RING(plan) CORNER(3 * (size_t)(plan)->ring_faces + 4)

/* One vn_plan_normals call on the gather path, shared by its workers. */
typedef struct pass {
	const vn_plan* plan;
	vn_work reader;        /* positions */
	const uint32_t* words; /* plan->words for the positions' stride, or NULL */
	vn_method method;
	const vn_vectors* out;
	int want_stats;
	vn_range_stats stats[MAX_WORKERS];
} pass;

/* The range of worker t of n when items are split into multiples of 8. */
static void split(size_t n, unsigned t, unsigned nt, size_t* lo, size_t* hi)
{
	*lo = t ? ((uint64_t)n * t / nt) & ~(size_t)7 : 0;
	*hi = t + 1 < nt ? ((uint64_t)n * (t + 1) / nt) & ~(size_t)7 : n;
}

/* ---------------------------------------------------------------- float32 faces
 *
 * A face's three corners go to three planes of its worker's ring: corner k
 * of the face at ring place r is corner k * ring_faces + r, so eight faces'
 * corners k are 128 consecutive bytes (four 32-byte stores). */

VN_INLINE void subf(const float a[3], const float b[3], float r[3])
{
	r[0] = a[0] - b[0], r[1] = a[1] - b[1], r[2] = a[2] - b[2];
}

/* Fused, as the AVX2 kernels' dot8: fmaf rounds once, like their FMA. */
VN_INLINE float dotf(const float a[3], const float b[3])
{
	return fmaf(a[0], b[0], fmaf(a[1], b[1], a[2] * b[2]));
}

VN_INLINE void loadf(const vn_work* w, uint32_t i, float p[3])
{
	const unsigned char* src = w->positions + (size_t)i * w->stride;
	memcpy(&p[0], src, 4), memcpy(&p[1], src + 4, 4), memcpy(&p[2], src + 8, 4);
}

/* a b - c d with the rounding error of c d added back (Kahan's algorithm
 * with fused multiply-adds): within 2 ulps even when the products cancel.
 * A plain float cross product is off by about FLT_EPSILON / the sine of a
 * thin triangle's smallest angle; on the 1M torus two faces (sines 0.06
 * and 0.13) put vertices 1.3e-4 degrees off, over vn.h's bound
 * (tests/test_plan.c, float_thin_triangles). */
VN_INLINE float diff_of_products(float a, float b, float c, float d)
{
	const float w = c * d;
	return fmaf(a, b, -w) + fmaf(-c, d, w);
}

/* A face that float arithmetic cannot represent (zero or non-finite area,
 * or weights beyond float range) in double, its contributions rounded to
 * float and clamped to its range; corner k at dst + k * plane. Returns 0,
 * and zeros, when it contributes nothing in double either. */
static int face_fallback(const vn_work* w, vn_method method, const uint32_t* idx, float* dst, size_t plane)
{
	double p0[3], p1[3], p2[3], e01[3], e12[3], e20[3], n[3], wt[3];
	vn_load(w, vn_scalar_float32, idx[0], p0);
	vn_load(w, vn_scalar_float32, idx[1], p1);
	vn_load(w, vn_scalar_float32, idx[2], p2);
	const double l2 = vn_triangle_edges(p0, p1, p2, e01, e12, e20, n);
	const int usable = vn_usable(l2);
	if (usable)
		vn_triangle_weights(method, e01, e12, e20, l2, wt);
	for (int k = 0; k < 3; ++k) {
		float* c = dst + k * plane;
		for (int i = 0; i < 3; ++i)
			c[i] = usable ? (float)fmax(fmin(n[i] * wt[k], FLT_MAX), -FLT_MAX) : 0.0f;
		c[3] = 0.0f;
	}
	return usable;
}

/* Face idx[0..3)'s corners in float arithmetic, corner k at dst + k *
 * plane; 0 when it must take the fallback. The AVX2 kernel below does the
 * same operations on 8 lanes. */
VN_INLINE int face_float(const vn_work* w, vn_method method, const uint32_t* idx, float* dst, size_t plane)
{
	float p0[3], p1[3], p2[3], e01[3], e12[3], e20[3], n[3];
	loadf(w, idx[0], p0), loadf(w, idx[1], p1), loadf(w, idx[2], p2);
	subf(p1, p0, e01), subf(p2, p1, e12), subf(p0, p2, e20);
	n[0] = diff_of_products(e20[1], e01[2], e20[2], e01[1]);
	n[1] = diff_of_products(e20[2], e01[0], e20[0], e01[2]);
	n[2] = diff_of_products(e20[0], e01[1], e20[1], e01[0]);
	const float l2 = dotf(n, n);
	float wt[3], den = 1.0f;
	switch (method) {
	case vn_method_mwe:
		wt[0] = wt[1] = wt[2] = 1.0f / sqrtf(l2);
		break;
	case vn_method_mwa: {
		const float l = sqrtf(l2), inv = 1.0f / l;
		const float a0 = vn_atan2f_nonneg(l, -dotf(e20, e01)), a1 = vn_atan2f_nonneg(l, -dotf(e01, e12));
		wt[0] = a0 * inv, wt[1] = a1 * inv, wt[2] = ((float)VN_PI - a0 - a1) * inv;
		break;
	}
	case vn_method_mwselr: {
		const float sa = dotf(e01, e01), sb = dotf(e12, e12), sc = dotf(e20, e20);
		den = sa * sb * sc;
		const float inv = 1.0f / den;
		wt[0] = sb * inv, wt[1] = sc * inv, wt[2] = sa * inv;
		break;
	}
	case vn_method_mwaat:
		wt[0] = wt[1] = wt[2] = 1.0f;
		break;
	default: { /* MWELR, MWRELR */
		float a = sqrtf(dotf(e01, e01)), b = sqrtf(dotf(e12, e12)), c = sqrtf(dotf(e20, e20));
		if (method == vn_method_mwrelr)
			a = sqrtf(a), b = sqrtf(b), c = sqrtf(c);
		den = a * b * c * sqrtf(l2);
		const float inv = 1.0f / den;
		wt[0] = b * inv, wt[1] = c * inv, wt[2] = a * inv;
		break;
	}
	}
	const int ok = l2 >= FLT_MIN && l2 <= FLT_MAX && den >= FLT_MIN && den <= FLT_MAX && wt[0] <= FLT_MAX &&
	               wt[1] <= FLT_MAX && wt[2] <= FLT_MAX;
	for (int k = 0; k < 3; ++k) {
		const float c[4] = {n[0] * wt[k], n[1] * wt[k], n[2] * wt[k], 0.0f};
		memcpy(dst + k * plane, c, sizeof(c));
	}
	return ok;
}

/* The n faces idx[0..3n) in float arithmetic, one at a time, face f's
 * corners at dst + 4 f in each plane; returns the degenerate count. */
VN_INLINE size_t faces_float(const vn_work* w, vn_method method, const uint32_t* idx, size_t n, float* dst,
                             size_t plane)
{
	size_t degenerate = 0;
	for (size_t f = 0; f < n; ++f)
		if (!face_float(w, method, idx + 3 * f, dst + 4 * f, plane))
			degenerate += !face_fallback(w, method, idx + 3 * f, dst + 4 * f, plane);
	return degenerate;
}

#ifdef VN_HAVE_AVX2
VN_AVX2_FMA_INLINE __m256 diff_of_products8(__m256 a, __m256 b, __m256 c, __m256 d)
{
	const __m256 w = _mm256_mul_ps(c, d);
	return _mm256_add_ps(_mm256_fmsub_ps(a, b, w), _mm256_fnmadd_ps(c, d, w));
}

VN_AVX2_FMA_INLINE __m256 dot8(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz)
{
	return _mm256_fmadd_ps(ax, bx, _mm256_fmadd_ps(ay, by, _mm256_mul_ps(az, bz)));
}

/* Eight (x, y, z, any) rows -> x, y, z lanes, row pairs (2p, 2p + 1) in
 * lanes p and p + 4, so that rows() writes them back as adjacent pairs. */
VN_AVX2_INLINE void transpose8(const __m128 v[8], __m256* x, __m256* y, __m256* z)
{
	__m256 r[4];
	for (int p = 0; p < 4; ++p)
		r[p] = _mm256_insertf128_ps(_mm256_castps128_ps256(v[2 * p]), v[2 * p + 1], 1);
	const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpacklo_ps(r[2], r[3]);
	const __m256 t2 = _mm256_unpackhi_ps(r[0], r[1]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
	*x = _mm256_shuffle_ps(t0, t1, 0x44);
	*y = _mm256_shuffle_ps(t0, t1, 0xee);
	*z = _mm256_shuffle_ps(t2, t3, 0x44);
}

/* transpose8 back: row pairs (2p, 2p + 1) as (x, y, z, w) each in out[p]. */
VN_AVX2_INLINE void rows(__m256 x, __m256 y, __m256 z, __m256 w, __m256 out[4])
{
	const __m256 a0 = _mm256_unpacklo_ps(x, y), a1 = _mm256_unpackhi_ps(x, y);
	const __m256 a2 = _mm256_unpacklo_ps(z, w), a3 = _mm256_unpackhi_ps(z, w);
	out[0] = _mm256_shuffle_ps(a0, a2, 0x44), out[1] = _mm256_shuffle_ps(a0, a2, 0xee);
	out[2] = _mm256_shuffle_ps(a1, a3, 0x44), out[3] = _mm256_shuffle_ps(a1, a3, 0xee);
}

/* A lane mask (lane p holds row 2p, lane p + 4 row 2p + 1) as a row mask. */
VN_INLINE int lanes_to_rows(int lanes)
{
	int r = 0;
	for (int p = 0; p < 4; ++p)
		r |= (lanes >> p & 1) << (2 * p) | (lanes >> (p + 4) & 1) << (2 * p + 1);
	return r;
}

/* face_float on the eight faces idx[0..24) (positions at words[0..24) when
 * not NULL), corners at dst (32-byte aligned) as there; returns the mask of
 * the faces that must take the fallback. */
VN_AVX2_FMA_INLINE int faces_float8(const vn_work* w, vn_method method, const uint32_t* idx, const uint32_t* words,
                                    float* dst, size_t plane)
{
	const unsigned char* base = w->positions;
	const size_t s = w->stride;
	__m256 px[3], py[3], pz[3];
	for (int c = 0; c < 3; ++c) {
		__m128 v[8];
		if (words)
			for (int j = 0; j < 8; ++j)
				v[j] = _mm_loadu_ps((const float*)(base + 4 * (size_t)words[3 * j + c]));
		else
			for (int j = 0; j < 8; ++j)
				v[j] = _mm_loadu_ps((const float*)(base + idx[3 * j + c] * s));
		transpose8(v, &px[c], &py[c], &pz[c]);
	}
	__m256 e[3][3]; /* e[k] runs from corner k to the next */
	for (int k = 0; k < 3; ++k) {
		const int j = k == 2 ? 0 : k + 1;
		e[k][0] = _mm256_sub_ps(px[j], px[k]);
		e[k][1] = _mm256_sub_ps(py[j], py[k]);
		e[k][2] = _mm256_sub_ps(pz[j], pz[k]);
	}
	const __m256 *e01 = e[0], *e12 = e[1], *e20 = e[2];
	const __m256 nx = diff_of_products8(e20[1], e01[2], e20[2], e01[1]);
	const __m256 ny = diff_of_products8(e20[2], e01[0], e20[0], e01[2]);
	const __m256 nz = diff_of_products8(e20[0], e01[1], e20[1], e01[0]);
	const __m256 l2 = dot8(nx, ny, nz, nx, ny, nz);
	const __m256 one = _mm256_set1_ps(1.0f);
	__m256 wt[3], den = one;
	switch (method) {
	case vn_method_mwe:
		wt[0] = wt[1] = wt[2] = _mm256_div_ps(one, _mm256_sqrt_ps(l2));
		break;
	case vn_method_mwa: {
		const __m256 l = _mm256_sqrt_ps(l2), inv = _mm256_div_ps(one, l), neg = _mm256_set1_ps(-0.0f);
		const __m256 a0 =
		    vn_atan2f_nonneg8(l, _mm256_xor_ps(neg, dot8(e20[0], e20[1], e20[2], e01[0], e01[1], e01[2])));
		const __m256 a1 =
		    vn_atan2f_nonneg8(l, _mm256_xor_ps(neg, dot8(e01[0], e01[1], e01[2], e12[0], e12[1], e12[2])));
		wt[0] = _mm256_mul_ps(a0, inv);
		wt[1] = _mm256_mul_ps(a1, inv);
		wt[2] = _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(_mm256_set1_ps((float)VN_PI), a0), a1), inv);
		break;
	}
	case vn_method_mwselr: {
		const __m256 sa = dot8(e01[0], e01[1], e01[2], e01[0], e01[1], e01[2]);
		const __m256 sb = dot8(e12[0], e12[1], e12[2], e12[0], e12[1], e12[2]);
		const __m256 sc = dot8(e20[0], e20[1], e20[2], e20[0], e20[1], e20[2]);
		den = _mm256_mul_ps(_mm256_mul_ps(sa, sb), sc);
		const __m256 inv = _mm256_div_ps(one, den);
		wt[0] = _mm256_mul_ps(sb, inv), wt[1] = _mm256_mul_ps(sc, inv), wt[2] = _mm256_mul_ps(sa, inv);
		break;
	}
	case vn_method_mwaat:
		wt[0] = wt[1] = wt[2] = one;
		break;
	default: {
		__m256 a = _mm256_sqrt_ps(dot8(e01[0], e01[1], e01[2], e01[0], e01[1], e01[2]));
		__m256 b = _mm256_sqrt_ps(dot8(e12[0], e12[1], e12[2], e12[0], e12[1], e12[2]));
		__m256 c = _mm256_sqrt_ps(dot8(e20[0], e20[1], e20[2], e20[0], e20[1], e20[2]));
		if (method == vn_method_mwrelr)
			a = _mm256_sqrt_ps(a), b = _mm256_sqrt_ps(b), c = _mm256_sqrt_ps(c);
		den = _mm256_mul_ps(_mm256_mul_ps(_mm256_mul_ps(a, b), c), _mm256_sqrt_ps(l2));
		const __m256 inv = _mm256_div_ps(one, den);
		wt[0] = _mm256_mul_ps(b, inv), wt[1] = _mm256_mul_ps(c, inv), wt[2] = _mm256_mul_ps(a, inv);
		break;
	}
	}
	/* face_float's test. Without a denominator (MWE, MWA, MWAAT) its other
	 * terms hold whenever l2's do: the weights are then at most pi times
	 * 1 / sqrt(FLT_MIN). */
	const __m256 lo = _mm256_set1_ps(FLT_MIN), hi = _mm256_set1_ps(FLT_MAX);
	__m256 ok = _mm256_and_ps(_mm256_cmp_ps(l2, lo, _CMP_GE_OQ), _mm256_cmp_ps(l2, hi, _CMP_LE_OQ));
	if (method == vn_method_mwselr || method == vn_method_mwelr || method == vn_method_mwrelr) {
		ok = _mm256_and_ps(ok, _mm256_and_ps(_mm256_cmp_ps(den, lo, _CMP_GE_OQ), _mm256_cmp_ps(den, hi, _CMP_LE_OQ)));
		for (int k = 0; k < 3; ++k)
			ok = _mm256_and_ps(ok, _mm256_cmp_ps(wt[k], hi, _CMP_LE_OQ));
	}

	const __m256 zero = _mm256_setzero_ps();
	for (int k = 0; k < 3; ++k) {
		__m256 r[4];
		rows(_mm256_mul_ps(nx, wt[k]), _mm256_mul_ps(ny, wt[k]), _mm256_mul_ps(nz, wt[k]), zero, r);
		for (int p = 0; p < 4; ++p)
			_mm256_store_ps(dst + k * plane + 8 * p, r[p]);
	}
	const int bad = ~_mm256_movemask_ps(ok) & 0xff;
	return bad ? lanes_to_rows(bad) : 0;
}

/* faces_float on AVX2, eight faces a step (positions at words when not
 * NULL). Unless checked is 0, a step with the last vertex takes
 * faces_float: the 16-byte loads read past its z. */
VN_AVX2_FMA_INLINE size_t faces_float_avx2(const vn_work* w, vn_method method, const uint32_t* idx,
                                           const uint32_t* words, size_t n, float* dst, size_t plane, int checked)
{
	const uint32_t last = w->vertex_count - 1;
	const vn_range all = {0, 0, 1};
	size_t degenerate = 0, f = 0;
	for (; f + 8 <= n; f += 8) {
		const uint32_t* i = idx + 3 * f;
		float* d = dst + 4 * f;
		if (checked && (vn_group_kind(i, last, all) != VN_GROUP_SIMD || vn_group_kind(i + 12, last, all) != VN_GROUP_SIMD)) {
			degenerate += faces_float(w, method, i, 8, d, plane);
			continue;
		}
		int redo = faces_float8(w, method, i, words ? words + 3 * f : NULL, d, plane);
		while (redo) {
			const int j = __builtin_ctz((unsigned)redo);
			redo &= redo - 1;
			degenerate += !face_fallback(w, method, i + 3 * j, d + 4 * j, plane);
		}
	}
	return degenerate + faces_float(w, method, idx + 3 * f, n - f, dst + 4 * f, plane);
}
#endif

/* ---------------------------------------------------------------- face pass */

/* Calls body with m a constant vn_method of the weighted family, so that each
 * inlined copy folds its switch away. */
#define WITH_METHOD(method, body)                          \
	switch (method) {                                      \
	case vn_method_mwe: {                                  \
		const vn_method m = vn_method_mwe;                 \
		body;                                              \
	} break;                                               \
	case vn_method_mwa: {                                  \
		const vn_method m = vn_method_mwa;                 \
		body;                                              \
	} break;                                               \
	case vn_method_mwselr: {                               \
		const vn_method m = vn_method_mwselr;              \
		body;                                              \
	} break;                                               \
	case vn_method_mwaat: {                                \
		const vn_method m = vn_method_mwaat;               \
		body;                                              \
	} break;                                               \
	case vn_method_mwelr: {                                \
		const vn_method m = vn_method_mwelr;               \
		body;                                              \
	} break;                                               \
	default: {                                             \
		const vn_method m = vn_method_mwrelr;              \
		body;                                              \
	} break;                                               \
	}

/* The n faces idx[0..3n) into the planes at dst. */
static size_t face_range_scalar(const pass* p, const uint32_t* idx, size_t n, float* dst, size_t plane)
{
	size_t d = 0;
	WITH_METHOD(p->method, d = faces_float(&p->reader, m, idx, n, dst, plane))
	return d;
}

#ifdef VN_HAVE_AVX2
static VN_AVX2_FMA size_t face_range_avx2(const pass* p, const uint32_t* idx, const uint32_t* words, size_t n,
                                          float* dst, size_t plane, int checked)
{
	size_t d = 0;
	WITH_METHOD(p->method, d = faces_float_avx2(&p->reader, m, idx, words, n, dst, plane, checked))
	return d;
}
#endif

/* ---------------------------------------------------------------- vertex pass */

/* The overflow entry of vertex v (which has one). */
static size_t overflow_of(const vn_plan* plan, uint32_t v)
{
	size_t lo = 0, hi = plan->over_count;
	while (lo < hi) {
		const size_t mid = lo + (hi - lo) / 2;
		if (plan->over_vertex[mid] < v)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo;
}

/* Vertex v's corners beyond the slots, when it is far: *codes and their
 * number (only far vertices have any). */
VN_INLINE uint32_t overflow_codes(const vn_plan* plan, int far, uint32_t v, const uint32_t** codes)
{
	if (!far || !plan->over_count)
		return 0;
	const size_t k = overflow_of(plan, v);
	if (k == plan->over_count || plan->over_vertex[k] != v)
		return 0;
	*codes = plan->over_code + plan->over_start[k];
	return plan->over_start[k + 1] - plan->over_start[k];
}

/* vn_normalize in float arithmetic, the squared length fused as dot8's. */
VN_INLINE int normalizef(float a[3])
{
	float x = a[0], y = a[1], z = a[2];
	const float len2 = dotf(a, a);
	if (len2 >= LEN2F_MIN && len2 <= LEN2F_MAX) {
		const float inv = 1.0f / sqrtf(len2);
		a[0] = x * inv, a[1] = y * inv, a[2] = z * inv;
		return 0;
	}
	const float m = fabsf(x) + fabsf(y) + fabsf(z);
	if (m > 0.0f && m <= FLT_MAX) {
		x /= m, y /= m, z /= m;
		const float inv = 1.0f / sqrtf(x * x + y * y + z * z);
		a[0] = x * inv, a[1] = y * inv, a[2] = z * inv;
		return 0;
	}
	a[0] = a[1] = a[2] = 0.0f;
	return 1;
}

/* Stores vertex v's unit normal n (float or double), or leaves a zero one
 * out under keep_existing; returns 1 for a zero normal. */
VN_INLINE int store_float(const pass* p, uint32_t v, float a[3])
{
	const int zero = normalizef(a);
	if (zero && p->plan->opt.keep_existing)
		return 1;
	unsigned char* dst = (unsigned char*)p->out->data + (size_t)v * p->out->stride;
	if (p->out->type == vn_scalar_float32) {
		memcpy(dst, a, 3 * sizeof(float));
	} else {
		const double d[3] = {a[0], a[1], a[2]};
		memcpy(dst, d, sizeof(d));
	}
	return zero;
}

/* The corner at byte offset code of records. */
VN_INLINE const float* corner_at(const float* records, uint32_t code)
{
	return (const float*)((const char*)records + code);
}

/* The vertices list[0..n), one at a time, with slots[SLOTS i ..] the
 * corners of list[i] at records (far: the far buffer): each sum starts
 * from its first corner and adds the others in order; returns the zero
 * normals. */
static size_t vertices_scalar(const pass* p, const float* records, int far, const uint32_t* list,
                              const uint32_t* slots, size_t n)
{
	const vn_plan* plan = p->plan;
	size_t zero = 0;
	for (size_t i = 0; i < n; ++i) {
		const uint32_t v = list[i];
		const uint32_t* codes = slots + SLOTS * i;
		const uint32_t* more = NULL;
		const uint32_t extra = overflow_codes(plan, far, v, &more);
		const float* c = corner_at(records, codes[0]);
		float a[3] = {c[0], c[1], c[2]};
		for (uint32_t s = 1; s < SLOTS + extra; ++s) {
			c = corner_at(records, s < SLOTS ? codes[s] : more[s - SLOTS]);
			a[0] += c[0], a[1] += c[1], a[2] += c[2];
		}
		zero += store_float(p, v, a);
	}
	return zero;
}

#ifdef VN_HAVE_AVX2
/* vertices_scalar on 8 vertices at a time: the sums interleaved over the
 * slots, then normalized together and stored straight from the registers
 * (lanes out of range one by one). */
static VN_AVX2_FMA size_t vertices_float_avx2(const pass* p, const float* records, int far, const uint32_t* list,
                                              const uint32_t* slots, size_t n)
{
	const vn_plan* plan = p->plan;
	unsigned char* const out = (unsigned char*)p->out->data;
	const size_t os = p->out->stride;
	const int f32 = p->out->type == vn_scalar_float32, packed = f32 && os == 3 * sizeof(float);
	size_t zero = 0, i = 0;
	for (; i + 8 <= n; i += 8) {
		const uint32_t* vs = list + i;
		const uint32_t* codes = slots + SLOTS * i;
		__m128 acc[8];
		for (int j = 0; j < 8; ++j)
			acc[j] = _mm_load_ps(corner_at(records, codes[SLOTS * j]));
		for (int s = 1; s < SLOTS; ++s)
			for (int j = 0; j < 8; ++j)
				acc[j] = _mm_add_ps(acc[j], _mm_load_ps(corner_at(records, codes[SLOTS * j + s])));
		for (int j = 0; far && j < 8; ++j) {
			const uint32_t* more = NULL;
			const uint32_t extra = overflow_codes(plan, far, vs[j], &more);
			for (uint32_t e = 0; e < extra; ++e)
				acc[j] = _mm_add_ps(acc[j], _mm_load_ps(corner_at(records, more[e])));
		}
		__m256 x, y, z;
		transpose8(acc, &x, &y, &z);
		const __m256 len2 = dot8(x, y, z, x, y, z);
		const __m256 in = _mm256_and_ps(_mm256_cmp_ps(len2, _mm256_set1_ps(LEN2F_MIN), _CMP_GE_OQ),
		                                _mm256_cmp_ps(len2, _mm256_set1_ps(LEN2F_MAX), _CMP_LE_OQ));
		if (_mm256_movemask_ps(in) != 0xff) {
			for (int j = 0; j < 8; ++j) {
				float a[4];
				_mm_storeu_ps(a, acc[j]);
				zero += store_float(p, vs[j], a);
			}
			continue;
		}
		const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(len2));
		__m256 r[4];
		rows(_mm256_mul_ps(x, inv), _mm256_mul_ps(y, inv), _mm256_mul_ps(z, inv), z, r);
		if (packed && vs[7] - vs[0] == 7) {
			/* Eight consecutive vertices (lists ascend): 16-byte stores in
			 * order, each fourth float overwritten by the next vertex's x,
			 * the last one exact. */
			unsigned char* dst = out + (size_t)vs[0] * 12;
			for (int j = 0; j < 7; ++j)
				_mm_storeu_ps((float*)(dst + 12 * j),
				              j & 1 ? _mm256_extractf128_ps(r[j / 2], 1) : _mm256_castps256_ps128(r[j / 2]));
			const __m128 row = _mm256_extractf128_ps(r[3], 1);
			const int zbits = _mm_extract_ps(row, 2);
			_mm_storel_pi((__m64*)(dst + 84), row);
			memcpy(dst + 92, &zbits, 4);
			continue;
		}
		for (int j = 0; j < 8; ++j) {
			const __m128 row = j & 1 ? _mm256_extractf128_ps(r[j / 2], 1) : _mm256_castps256_ps128(r[j / 2]);
			unsigned char* dst = out + (size_t)vs[j] * os;
			if (f32) {
				const int zbits = _mm_extract_ps(row, 2);
				_mm_storel_pi((__m64*)dst, row);
				memcpy(dst + 8, &zbits, 4);
			} else {
				const __m256d d = _mm256_cvtps_pd(row);
				_mm_storeu_pd((double*)dst, _mm256_castpd256_pd128(d));
				_mm_store_sd((double*)dst + 2, _mm256_extractf128_pd(d, 1));
			}
		}
	}
	return zero + vertices_scalar(p, records, far, list + i, slots + SLOTS * i, n - i);
}
#endif

/* Faces first .. first + n into the planes at dst. */
static size_t face_range(const pass* p, size_t first, size_t n, float* dst, size_t plane, int checked)
{
	const uint32_t* idx = p->plan->faces + 3 * first;
#ifdef VN_HAVE_AVX2
	if (p->plan->simd)
		return face_range_avx2(p, idx, p->words ? p->words + 3 * first : NULL, n, dst, plane, checked);
#endif
	(void)checked;
	return face_range_scalar(p, idx, n, dst, plane);
}

static size_t vertex_list(const pass* p, const float* records, int far, size_t first, size_t n)
{
	const uint32_t* list = p->plan->order + first;
	const uint32_t* slots = p->plan->slots + SLOTS * first;
#ifdef VN_HAVE_AVX2
	if (p->plan->simd)
		return vertices_float_avx2(p, records, far, list, slots, n);
#endif
	return vertices_scalar(p, records, far, list, slots, n);
}

/* Worker t's faces, chunk by chunk into its ring: the chunk's corners of
 * far vertices copied to the far buffer, then the vertices the chunk
 * completes summed from the ring. */
static void chunk_pass(void* ctx, unsigned t)
{
	pass* p = (pass*)ctx;
	const vn_plan* plan = p->plan;
	float* ring = plan->corners + (size_t)t * RING(plan);
	float* far = plan->corners + (size_t)plan->workers * RING(plan);
	const size_t plane = CORNER(plan->ring_faces);
	/* 16-byte loads of the last vertex read past its z when the stride is
	 * below 16: the chunks with it check their faces. */
	const int short_stride = p->reader.stride < 16;
	size_t f0, f1, degenerate = 0, zero = 0;
	split(plan->face_count, t, plan->workers, &f0, &f1);
	for (uint32_t k = plan->base[t], at = 0; k < plan->base[t + 1]; ++k, f0 += CHUNK, at += CHUNK) {
		const size_t n = f1 - f0 < CHUNK ? f1 - f0 : CHUNK;
		at = at == plan->ring_faces ? 0 : at;
		degenerate += face_range(p, f0, n, ring + CORNER(at), plane, short_stride && plan->last_in_chunk[k]);
		for (uint32_t e = plan->far_start[k]; e < plan->far_start[k + 1]; ++e)
			memcpy(far + CORNER(plan->far_to[e]), ring + CORNER(plan->far_from[e]), 4 * sizeof(float));
		zero += vertex_list(p, ring, 0, plan->start[k], plan->start[k + 1] - plan->start[k]);
	}
	p->stats[t].degenerate_faces = degenerate;
	p->stats[t].zero_normals = zero;
}

/* The far vertices, split evenly, and the non-finite count. */
static void far_pass(void* ctx, unsigned t)
{
	pass* p = (pass*)ctx;
	const vn_plan* plan = p->plan;
	const float* far = plan->corners + (size_t)plan->workers * RING(plan);
	const size_t first = plan->start[plan->base[plan->workers]], n = plan->vertex_count - first;
	const size_t lo = first + n * t / plan->workers, hi = first + n * (t + 1) / plan->workers;
	p->stats[t].zero_normals += vertex_list(p, far, 1, lo, hi - lo);
	if (p->want_stats) {
		size_t v0, v1;
		split(plan->vertex_count, t, plan->workers, &v0, &v1);
		p->stats[t].nonfinite_vertices = vn_count_nonfinite(&p->reader, (uint32_t)v0, (uint32_t)v1);
	}
}

/* ---------------------------------------------------------------- entry points */

/* The bytes vn_polygon_corner_normals (and vn_corner_normals) need as a
 * workspace: vn.h's bound. */
static size_t corner_work_bytes(size_t corners, size_t faces, size_t nv, unsigned threads)
{
	return 36 * corners + 24 * faces + 4 * nv + 64 * (size_t)(threads ? threads : 1) + 64;
}

VN_INLINE size_t round64(size_t n)
{
	return (n + 63) & ~(size_t)63;
}

/* Scratch of vn_plan_create for the gather table, 6 arrays of nv; place
 * (each vertex's place in order[]) reuses first, which only buckets() reads.
 * With a locality order (locality_sort), perm and rank. */
typedef struct build {
	uint32_t *count, *ordinal, *first, *last, *bucket, *far, *place;
	uint32_t* perm; /* the gather's face g is input face perm[g] */
	uint32_t* rank; /* input corner c is corner rank[c] of its vertex, in input order */
	size_t from[MAX_WORKERS + 1]; /* worker t's faces are [from[t], from[t + 1]) */
} build;

/* The bucket of every vertex: the chunk after which it is summed, when its
 * faces are all in one worker's range and still in its ring then, else
 * `chunks` (a far vertex; so are isolated ones and those with more corners
 * than slots); far[] the first far corner of the far ones. Returns the
 * number of far corners. */
static size_t buckets(const vn_plan* plan, build* b)
{
	const unsigned nt = plan->workers;
	const uint32_t chunks = plan->base[nt];
	size_t far = 0;
	for (uint32_t v = 0; v < plan->vertex_count; ++v) {
		uint32_t bucket = chunks;
		if (b->count[v] && b->count[v] <= SLOTS) {
			unsigned lo = 0, hi = nt; /* the worker of the last face: the last range starting at or before it */
			while (hi - lo > 1) {
				const unsigned mid = (lo + hi) / 2;
				if (b->from[mid] <= b->last[v])
					lo = mid;
				else
					hi = mid;
			}
			const size_t chunk = (b->last[v] - b->from[lo]) / CHUNK;
			size_t end = b->from[lo] + (chunk + 1) * CHUNK;
			end = end < b->from[lo + 1] ? end : b->from[lo + 1];
			if (b->first[v] >= b->from[lo] && b->first[v] + (size_t)plan->ring_faces >= end)
				bucket = plan->base[lo] + (uint32_t)chunk;
		}
		b->bucket[v] = bucket;
		if (bucket == chunks) {
			b->far[v] = (uint32_t)far;
			far += b->count[v];
		}
	}
	return far;
}

/* Each vertex's first and last face in the gather's order: input face
 * b->perm[g] (b->perm NULL: g) is its face g. */
static void face_span(const uint32_t* idx, size_t nf, build* b)
{
	for (size_t g = nf; g-- > 0;) {
		const uint32_t* face = idx + 3 * (size_t)(b->perm ? b->perm[g] : g);
		b->first[face[0]] = b->first[face[1]] = b->first[face[2]] = (uint32_t)g;
	}
	for (size_t g = 0; g < nf; ++g) {
		const uint32_t* face = idx + 3 * (size_t)(b->perm ? b->perm[g] : g);
		b->last[face[0]] = b->last[face[1]] = b->last[face[2]] = (uint32_t)g;
	}
}

/* A locality order for faces whose input order has none: breadth first over
 * shared vertices from face 0 (then from the first face not reached, for
 * each further component), so that the faces around a vertex come close
 * together. Sets b->perm and b->rank (from b->count, the corners of each
 * vertex) in one block from the allocator (returned; NULL when it fails);
 * b->bucket and b->far serve as scratch. */
static void* locality_sort(const uint32_t* idx, size_t nf, uint32_t nv, const vn_allocator* heap, build* b)
{
	const size_t ni = 3 * nf;
	/* perm, rank, each vertex's faces (CSR: vface from vstart), reached faces */
	uint32_t* block = (uint32_t*)heap->allocate(heap->user, sizeof(uint32_t) * (nf + 2 * ni + nv + 1) + nf);
	if (!block)
		return NULL;
	uint32_t *perm = block, *rank = perm + nf, *vface = rank + ni, *vstart = vface + ni;
	unsigned char* reached = (unsigned char*)(vstart + nv + 1);
	uint32_t *cursor = b->bucket, *done = b->far;
	vstart[0] = 0;
	for (uint32_t v = 0; v < nv; ++v)
		vstart[v + 1] = vstart[v] + b->count[v], cursor[v] = vstart[v], done[v] = 0;
	for (size_t c = 0; c < ni; ++c) {
		const uint32_t v = idx[c], i = cursor[v]++;
		vface[i] = (uint32_t)(c / 3);
		rank[c] = i - vstart[v];
	}
	memset(reached, 0, nf);
	size_t head = 0, tail = 0;
	for (size_t seed = 0; seed < nf; ++seed) {
		if (reached[seed])
			continue;
		reached[seed] = 1, perm[tail++] = (uint32_t)seed;
		while (head < tail) {
			const uint32_t f = perm[head++];
			for (int k = 0; k < 3; ++k) {
				const uint32_t v = idx[3 * (size_t)f + k];
				for (uint32_t i = vstart[v]; !done[v] && i < vstart[v + 1]; ++i)
					if (!reached[vface[i]])
						reached[vface[i]] = 1, perm[tail++] = vface[i];
				done[v] = 1;
			}
		}
	}
	b->perm = perm, b->rank = rank;
	return block;
}

/* The order in which the vertices are summed: a counting sort by bucket,
 * ascending vertex numbers within one; and each vertex's place in it. */
static void schedule(vn_plan* plan, build* b)
{
	const uint32_t chunks = plan->base[plan->workers], nv = plan->vertex_count;
	uint32_t* start = plan->start;
	memset(start, 0, sizeof(uint32_t) * ((size_t)chunks + 2));
	for (uint32_t v = 0; v < nv; ++v)
		++start[b->bucket[v] + 1];
	for (uint32_t k = 0; k <= chunks; ++k)
		start[k + 1] += start[k];
	for (uint32_t v = 0; v < nv; ++v)
		plan->order[start[b->bucket[v]]++] = v;
	for (uint32_t k = chunks + 1; k > 0; --k)
		start[k] = start[k - 1];
	start[0] = 0;
	b->place = b->first;
	for (uint32_t i = 0; i < nv; ++i)
		b->place[plan->order[i]] = i;
}

/* The slots and overflow codes (ring corners, or far corners for far
 * vertices), the far copies of each chunk, faces in order, and the chunks
 * with the last vertex. */
static void corner_table(vn_plan* plan, build* b)
{
	const uint32_t nv = plan->vertex_count, chunks = plan->base[plan->workers];
	const uint32_t ring_pad = (uint32_t)(sizeof(float) * CORNER(3 * plan->ring_faces));
	const uint32_t far_pad = (uint32_t)(sizeof(float) * CORNER(plan->far_count));
	/* The far vertices come last in the order. */
	const size_t first_far = SLOTS * (size_t)plan->start[chunks];
	for (size_t i = 0; i < SLOTS * (size_t)nv; ++i)
		plan->slots[i] = i < first_far ? ring_pad : far_pad;
	memset(plan->last_in_chunk, 0, chunks);
	uint32_t start = 0;
	for (uint32_t v = 0; v < nv; ++v)
		if (b->count[v] > SLOTS) {
			const uint32_t k = b->ordinal[v];
			plan->over_vertex[k] = v;
			plan->over_start[k] = start;
			start += b->count[v] - SLOTS;
		}
	plan->over_start[plan->over_count] = start;
	memset(b->count, 0, sizeof(uint32_t) * nv);
	unsigned t = 0;
	uint32_t e = 0, next = 0;
	for (size_t f = 0; f < plan->face_count; ++f) { /* f in the gather's order */
		while (f >= b->from[t + 1])
			++t;
		const size_t local = f - b->from[t];
		const uint32_t chunk = plan->base[t] + (uint32_t)(local / CHUNK);
		const uint32_t place = (uint32_t)(local % plan->ring_faces);
		const uint32_t* face = plan->faces + 3 * f;
		const uint32_t* rank = b->rank ? b->rank + 3 * (size_t)b->perm[f] : NULL;
		while (next <= chunk)
			plan->far_start[next++] = e;
		plan->last_in_chunk[chunk] |= (face[0] == nv - 1) | (face[1] == nv - 1) | (face[2] == nv - 1);
		for (uint32_t k = 0; k < 3; ++k) {
			const uint32_t v = face[k], j = rank ? rank[k] : b->count[v]++;
			const uint32_t ring = k * plan->ring_faces + place;
			uint32_t code = (uint32_t)(sizeof(float) * CORNER(ring));
			if (b->bucket[v] == chunks) {
				plan->far_from[e] = ring;
				plan->far_to[e] = b->far[v] + j;
				code = (uint32_t)(sizeof(float) * CORNER(plan->far_to[e++]));
			}
			if (j < SLOTS)
				plan->slots[SLOTS * (size_t)b->place[v] + j] = code;
			else
				plan->over_code[plan->over_start[b->ordinal[v]] + j - SLOTS] = code;
		}
	}
	while (next <= chunks)
		plan->far_start[next++] = e;
}

/* Whether the gather's loads may take plan->words for the stride, made
 * first when they are for another: not when the stride is no multiple of
 * 4 bytes, nor when the last position's 16-byte load ends beyond 2^32
 * words (such loads multiply index by stride). */
static int words_for(vn_plan* plan, size_t stride)
{
	if (stride % 4 || (uint64_t)plan->vertex_count * (stride / 4) + 4 > UINT32_MAX)
		return 0;
	if (plan->words_stride != stride) {
		const uint32_t k = (uint32_t)(stride / 4);
		for (size_t i = 0; i < plan->index_count; ++i)
			plan->words[i] = plan->faces[i] * k;
		plan->words_stride = stride;
	}
	return 1;
}

vn_result vn_plan_create(const uint32_t* indices, const uint32_t* face_offsets, size_t face_count,
                         size_t vertex_count, const vn_options* options, vn_plan** out)
{
	if (!out || !vn_options_valid(options) || vertex_count > UINT32_MAX)
		return vn_result_invalid_argument;
	static const vn_options defaults;
	const vn_options* o = options ? options : &defaults;
	size_t ni;
	if (face_offsets) {
		if (face_count > UINT32_MAX - 1)
			return vn_result_invalid_argument;
		for (size_t f = 0; f < face_count; ++f)
			if (face_offsets[f + 1] < face_offsets[f])
				return vn_result_invalid_argument;
		ni = face_offsets[face_count];
	} else {
		if (face_count > UINT32_MAX / 3)
			return vn_result_invalid_argument;
		ni = 3 * face_count;
	}
	if (ni && !indices)
		return vn_result_invalid_argument;
	const uint32_t nv = (uint32_t)vertex_count;
	vn_result r = vn_check_indices(indices, ni, nv);
	if (r != vn_result_success)
		return r;

	const vn_allocator heap = vn_heap(&o->allocator);
	int gather = !face_offsets && nv;
	const unsigned workers = vn_worker_count(nv, o->threads);
	/* The chunks of each worker, and the ring: a window of faces, fewer when
	 * every worker has fewer. */
	build b;
	memset(&b, 0, sizeof(b));
	uint32_t chunks = 0, base[MAX_WORKERS + 1], ring_faces = CHUNK;
	for (unsigned t = 0; t < workers; ++t) {
		size_t hi;
		split(face_count, t, workers, &b.from[t], &hi);
		b.from[t + 1] = hi;
		base[t] = chunks;
		const size_t k = (hi - b.from[t] + CHUNK - 1) / CHUNK;
		chunks += gather ? (uint32_t)k : 0;
		ring_faces = k * CHUNK > ring_faces ? (uint32_t)(k * CHUNK < WINDOW ? k * CHUNK : WINDOW) : ring_faces;
	}
	base[workers] = chunks;

	/* Scratch: corners, overflow ordinal, first and last face, bucket, far
	 * corner of each vertex; with a locality order, its scratch and faces. */
	size_t over_count = 0, over_codes = 0, far = 0;
	void* sort = NULL;
	vn_plan shape; /* what buckets() reads */
	memset(&shape, 0, sizeof(shape));
	if (gather) {
		if (!(b.count = (uint32_t*)heap.allocate(heap.user, 6 * sizeof(uint32_t) * nv)))
			return vn_result_out_of_memory;
		b.ordinal = b.count + nv, b.first = b.ordinal + nv, b.last = b.first + nv;
		b.bucket = b.last + nv, b.far = b.bucket + nv;
		memset(b.count, 0, sizeof(uint32_t) * nv);
		for (size_t i = 0; i < ni; ++i)
			++b.count[indices[i]];
		for (uint32_t v = 0; v < nv; ++v)
			if (b.count[v] > SLOTS)
				b.ordinal[v] = (uint32_t)over_count++, over_codes += b.count[v] - SLOTS;
		shape.vertex_count = nv;
		shape.workers = workers;
		shape.ring_faces = ring_faces;
		memcpy(shape.base, base, sizeof(uint32_t) * (workers + 1));
		face_span(indices, face_count, &b);
		far = buckets(&shape, &b);
		/* More than a quarter of the corners far: the input's order has no
		 * locality (a shuffled file), so the gather takes faces in a
		 * locality order; a good order stays as it is. */
		if (far > ni / 4) {
			if (!(sort = locality_sort(indices, face_count, nv, &heap, &b))) {
				heap.deallocate(heap.user, b.count);
				return vn_result_out_of_memory;
			}
			face_span(indices, face_count, &b);
			far = buckets(&shape, &b);
		}
		if (far >= MAX_FAR) { /* no locality at all: the existing entry points */
			heap.deallocate(heap.user, b.count);
			if (sort)
				heap.deallocate(heap.user, sort);
			memset(&b, 0, sizeof(b));
			sort = NULL;
			gather = 0, far = 0, over_count = over_codes = 0, chunks = 0;
			memset(base, 0, sizeof(base));
		}
	}

	const size_t record_bytes = gather ? 16 * ((3 * (size_t)ring_faces + 4) * workers + far + 1) : 0;
	size_t work = vn_workspace_size(nv, o);
	const size_t corner_bytes = corner_work_bytes(ni, face_count, nv, o->threads);
	work = work > corner_bytes ? work : corner_bytes;
	work = work > record_bytes ? work : record_bytes;
	const size_t head = round64(sizeof(vn_plan));
	const size_t idx_bytes = round64(sizeof(uint32_t) * ni);
	const size_t word_bytes = gather ? idx_bytes : 0, sorted_bytes = sort ? idx_bytes : 0;
	const size_t off_bytes = face_offsets ? round64(sizeof(uint32_t) * (face_count + 1)) : 0;
	const size_t slot_bytes = gather ? round64(sizeof(uint32_t) * SLOTS * (size_t)nv) : 0;
	const size_t over_bytes = round64(sizeof(uint32_t) * (2 * over_count + 1 + over_codes));
	const size_t order_bytes = gather ? round64(sizeof(uint32_t) * ((size_t)nv + chunks + 2)) : 0;
	const size_t far_bytes = gather ? round64(sizeof(uint32_t) * (chunks + 1 + 2 * far)) + round64(chunks) : 0;
	const size_t total =
	    head + idx_bytes + word_bytes + sorted_bytes + off_bytes + slot_bytes + over_bytes + order_bytes + far_bytes +
	    round64(work) + 64;
	unsigned char* block = (unsigned char*)heap.allocate(heap.user, total);
	if (!block) {
		if (sort)
			heap.deallocate(heap.user, sort);
		if (b.count)
			heap.deallocate(heap.user, b.count);
		return vn_result_out_of_memory;
	}
	vn_plan* plan = (vn_plan*)block;
	memset(plan, 0, sizeof(*plan));
	unsigned char* at = block + head;
	plan->opt = *o;
	plan->vertex_count = nv;
	plan->face_count = face_count;
	plan->index_count = ni;
	plan->gather = gather;
	plan->simd = o->simd == vn_simd_auto && vn_cpu_has_avx2_fma();
	plan->workers = workers;
	plan->indices = (uint32_t*)at;
	if (ni)
		memcpy(plan->indices, indices, sizeof(uint32_t) * ni);
	at += idx_bytes;
	plan->words = (uint32_t*)at;
	at += word_bytes;
	plan->faces = plan->indices;
	if (sort) {
		plan->faces = (uint32_t*)at;
		for (size_t f = 0; f < face_count; ++f)
			memcpy(plan->faces + 3 * f, indices + 3 * (size_t)b.perm[f], 3 * sizeof(uint32_t));
		at += sorted_bytes;
	}
	if (face_offsets) {
		plan->offsets = (uint32_t*)at;
		memcpy(plan->offsets, face_offsets, sizeof(uint32_t) * (face_count + 1));
		at += off_bytes;
	}
	plan->slots = (uint32_t*)at;
	at += slot_bytes;
	plan->over_count = over_count;
	plan->over_vertex = (uint32_t*)at;
	plan->over_start = plan->over_vertex + over_count;
	plan->over_code = plan->over_start + over_count + 1;
	at += over_bytes;
	plan->order = (uint32_t*)at;
	plan->start = plan->order + nv;
	memcpy(plan->base, base, sizeof(uint32_t) * (workers + 1));
	at += order_bytes;
	plan->ring_faces = ring_faces;
	plan->far_count = far;
	plan->far_start = (uint32_t*)at;
	plan->far_from = plan->far_start + chunks + 1;
	plan->far_to = plan->far_from + far;
	plan->last_in_chunk = (uint8_t*)(at + round64(sizeof(uint32_t) * (chunks + 1 + 2 * far)));
	at += far_bytes;
	/* 64-byte alignment: 8 faces' corners k are 2 cache lines. */
	plan->corners = (float*)(block + ((((uintptr_t)at + 63) & ~(uintptr_t)63) - (uintptr_t)block));
	plan->opt.workspace = plan->corners;
	plan->opt.workspace_size = work;

	if (gather) {
		schedule(plan, &b);
		corner_table(plan, &b);
		heap.deallocate(heap.user, b.count);
		if (sort)
			heap.deallocate(heap.user, sort);
		words_for(plan, 3 * sizeof(float)); /* packed float32, the common layout */
	}
	*out = plan;
	return vn_result_success;
}

void vn_plan_destroy(vn_plan* plan)
{
	if (!plan)
		return;
	const vn_allocator heap = vn_heap(&plan->opt.allocator);
	heap.deallocate(heap.user, plan);
}

/* The positions' stride when they fit the plan, else 0. */
static size_t plan_positions(const vn_plan* plan, const vn_positions* positions, const vn_vectors* normals)
{
	const size_t stride = vn_positions_stride(positions);
	if (!plan || !stride || positions->count != plan->vertex_count || !vn_vectors_stride(normals) ||
	    (positions->count && !normals->data))
		return 0;
	return stride;
}

vn_result vn_plan_normals(vn_plan* plan, const vn_positions* positions, vn_method method, const vn_vectors* normals,
                          vn_stats* stats)
{
	const size_t stride = plan_positions(plan, positions, normals);
	if (!stride)
		return vn_result_invalid_argument;
	if ((unsigned)method >= vn_method_count)
		return vn_result_unknown_method;
	if (!plan->gather || method > vn_method_mwrelr || positions->type != vn_scalar_float32) {
		if (plan->offsets)
			return vn_polygon_normals(normals, positions, plan->indices, plan->offsets, plan->face_count, method,
			                          &plan->opt, stats);
		if (method == vn_method_mwa && positions->type == vn_scalar_float64)
			return vn_triangle_normals_mwa_poly(normals, positions, plan->indices, plan->index_count, &plan->opt,
			                                    stats);
		return vn_triangle_normals(normals, positions, plan->indices, plan->index_count, method, &plan->opt, stats);
	}

	vn_vectors out = *normals;
	out.stride = vn_vectors_stride(normals);
	pass p;
	p.plan = plan;
	p.reader = vn_position_reader(positions, stride);
	p.words = words_for(plan, stride) ? plan->words : NULL;
	p.method = method;
	p.out = &out;
	p.want_stats = stats != NULL;
	const unsigned nt = plan->workers;
	memset(p.stats, 0, sizeof(p.stats[0]) * nt);
	/* The zero corners the padding slots name: after each ring, after the far corners. */
	for (unsigned t = 0; t <= nt; ++t)
		memset(plan->corners + t * RING(plan) + (t < nt ? CORNER(3 * plan->ring_faces) : CORNER(plan->far_count)), 0,
		       4 * sizeof(float));

	vn_parallel(nt, chunk_pass, &p);
	if (p.want_stats || plan->start[plan->base[nt]] < plan->vertex_count)
		vn_parallel(nt, far_pass, &p);

	if (stats) {
		memset(stats, 0, sizeof(*stats));
		stats->faces = plan->face_count;
		for (unsigned t = 0; t < nt; ++t) {
			stats->degenerate_faces += p.stats[t].degenerate_faces;
			stats->zero_normals += p.stats[t].zero_normals;
			stats->nonfinite_vertices += p.stats[t].nonfinite_vertices;
		}
	}
	return vn_result_success;
}

vn_result vn_plan_corner_normals(vn_plan* plan, const vn_positions* positions, vn_method method, double crease_angle,
                                 const uint8_t* sharp_edges, const vn_vectors* normals, vn_stats* stats)
{
	if (!plan_positions(plan, positions, normals))
		return vn_result_invalid_argument;
	if (plan->offsets)
		return vn_polygon_corner_normals(normals, positions, plan->indices, plan->offsets, plan->face_count, method,
		                                 crease_angle, sharp_edges, &plan->opt, stats);
	return vn_corner_normals(normals, positions, plan->indices, plan->index_count, method, crease_angle, sharp_edges,
	                         &plan->opt, stats);
}
