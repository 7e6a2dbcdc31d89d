/* vn_plan_normals' gather (plan.c's opening comment): float32 positions,
 * the weighted family on triangles, in float arithmetic. Faces eight per
 * AVX2 step into each worker's corner ring, then the vertices each chunk
 * completes summed from it; the far vertices after every face. */
#include "plan.h"
#include "simd.h"
#include "weights.h"

/* Float sums normalized directly; outside, rescaled first (vn_normalize). */
#define LEN2F_MIN 0x1p-100f
#define LEN2F_MAX 0x1p100f

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

void vn_plan_gather(const vn_plan* plan, const vn_positions* positions, size_t stride, const uint32_t* words,
                    vn_method method, const vn_vectors* normals, vn_stats* stats)
{
	vn_vectors out = *normals;
	out.stride = vn_vectors_stride(normals);
	pass p;
	p.plan = plan;
	p.reader = vn_position_reader(positions, stride);
	p.words = words;
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
}
