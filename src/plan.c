/* Per-frame plans: the topology work of a normal computation done once.
 *
 * vn_plan_create checks the indices once, copies them and lists the corners
 * of every vertex in 8 fixed slots (corner 3 f + k, ascending, so in face
 * order; unused slots name a zero corner; vertices with more corners
 * continue in an overflow list). vn_plan_normals then gathers, for the
 * weighted family on triangles, in two passes:
 *  - faces: corner 3 f + k of the corner buffer gets its contribution
 *    n * w_k (n the unnormalized normal, w_k vn_triangle_weights' weight,
 *    the scatter's product) as x, y, z, 0; zeros when the face contributes
 *    nothing;
 *  - vertices: each vertex adds its slots' 16 (float) or 32 (double) bytes
 *    in order, normalizes and stores.
 * The passes are interleaved in chunks of CHUNK faces: after each chunk, a
 * worker sums the vertices whose last face it was (a schedule built at
 * create), while the chunk's records are still in cache; vertices whose
 * faces fall in two workers' ranges, and isolated ones, are summed after
 * all faces. A vertex's sum is formed by one worker in a fixed order
 * whatever the split, so results are bit-identical for any thread count; and the double
 * path adds the scatter's products (n * w, vn_add_scaled) in the scatter's
 * order, plus exact zeros, so it equals vn_triangle_normals bit for bit.
 * Float32 positions are computed in float arithmetic: eight triangles per
 * AVX2 step instead of four. The scalar and AVX2 kernels of each path do
 * the same IEEE operations (simd.h), so they agree bit for bit too.
 *
 * Everything else (polygons, the other schemes, per-corner normals) runs
 * the existing entry points on the plan's copy of the indices, with the
 * plan's memory as their workspace. */
#include <stdlib.h>

#include "internal.h"
#include "simd.h"
#include "weights.h"

#define SLOTS 8
#define MAX_WORKERS 256 /* vn_parallel's limit */
/* Faces per chunk: 64 KB of float32 records, 128 KB of double. */
#define CHUNK 2048
/* Corners 3 f + k take 31 bits; the top bit of a vertex's last slot says
 * that it continues in the overflow list. */
#define MAX_GATHER_FACES (1u << 29)
#define MORE 0x80000000u
/* Corner c's x, y, z, 0 in the corner buffer, in scalars. */
#define CORNER(c) (4 * (size_t)((c) & ~MORE))
/* Float sums normalized directly; outside, rescaled first (vn_normalize). */
#define LEN2F_MIN 0x1p-100f
#define LEN2F_MAX 0x1p100f

struct vn_plan {
	vn_options opt; /* the caller's, workspace set to the plan's memory */
	uint32_t vertex_count;
	size_t face_count, index_count;
	uint32_t* indices;
	uint32_t* offsets; /* NULL for triangles */
	int gather;        /* triangles with the slot table below */
	int simd;
	unsigned workers;
	uint32_t* slots; /* SLOTS codes a vertex */
	size_t over_count;
	uint32_t* over_vertex; /* vertices with more than SLOTS corners, ascending */
	uint32_t* over_start;  /* over_count + 1 offsets into over_code */
	uint32_t* over_code;
	/* Vertices in the order they are summed: worker t's chunk k's vertices
	 * are order[start[base[t] + k] .. start[base[t] + k + 1]), then the
	 * rest (shared and isolated vertices) from start[chunks] to the end. */
	uint32_t* order;
	uint32_t* start;
	uint32_t base[MAX_WORKERS + 1];
	unsigned char* records; /* the corner buffer: 96 bytes a face and a zero corner, 64-byte aligned; also the workspace */
};

/* One vn_plan_normals call on the gather path, shared by its workers. */
typedef struct pass {
	const vn_plan* plan;
	vn_work reader; /* positions */
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

/* ---------------------------------------------------------------- float32 faces */

VN_INLINE void subf(const float a[3], const float b[3], float r[3])
{
	r[0] = a[0] - b[0], r[1] = a[1] - b[1], r[2] = a[2] - b[2];
}

VN_INLINE float dotf(const float a[3], const float b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

VN_INLINE void loadf(const vn_work* w, uint32_t i, float p[3])
{
	const unsigned char* src = w->positions + (size_t)i * w->stride;
	memcpy(&p[0], src, 4), memcpy(&p[1], src + 4, 4), memcpy(&p[2], src + 8, 4);
}

/* A face that float arithmetic cannot represent (zero or non-finite area,
 * or weights beyond float range) in double, its contributions rounded to
 * float and clamped to its range. Returns 0, and zeros, when it
 * contributes nothing in double either. */
static int face_fallback(const vn_work* w, vn_method method, const uint32_t* idx, float rec[12])
{
	double p0[3], p1[3], p2[3], e01[3], e12[3], e20[3], n[3], wt[3];
	vn_load(w, vn_scalar_float32, idx[0], p0);
	vn_load(w, vn_scalar_float32, idx[1], p1);
	vn_load(w, vn_scalar_float32, idx[2], p2);
	memset(rec, 0, 12 * sizeof(float));
	const double l2 = vn_triangle_edges(p0, p1, p2, e01, e12, e20, n);
	if (!vn_usable(l2))
		return 0;
	vn_triangle_weights(method, e01, e12, e20, l2, wt);
	for (int k = 0; k < 3; ++k)
		for (int i = 0; i < 3; ++i)
			rec[4 * k + i] = (float)fmax(fmin(n[i] * wt[k], FLT_MAX), -FLT_MAX);
	return 1;
}

/* Face idx[0..3)'s corners in float arithmetic; 0 when it must take the
 * fallback. The AVX2 kernel below does the same operations on 8 lanes. */
VN_INLINE int face_float(const vn_work* w, vn_method method, const uint32_t* idx, float rec[12])
{
	float p0[3], p1[3], p2[3], e01[3], e12[3], e20[3], n[3];
	loadf(w, idx[0], p0), loadf(w, idx[1], p1), loadf(w, idx[2], p2);
	subf(p1, p0, e01), subf(p2, p1, e12), subf(p0, p2, e20);
	n[0] = e20[1] * e01[2] - e20[2] * e01[1];
	n[1] = e20[2] * e01[0] - e20[0] * e01[2];
	n[2] = e20[0] * e01[1] - e20[1] * e01[0];
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
		memcpy(rec + 4 * k, c, sizeof(c));
	}
	return ok;
}

/* Faces [f0, f1) in float arithmetic, one at a time; returns the degenerate count. */
VN_INLINE size_t faces_float(const vn_work* w, vn_method method, const uint32_t* indices, float* records, size_t f0,
                             size_t f1)
{
	size_t degenerate = 0;
	for (size_t f = f0; f < f1; ++f)
		if (!face_float(w, method, indices + 3 * f, records + 12 * f))
			degenerate += !face_fallback(w, method, indices + 3 * f, records + 12 * f);
	return degenerate;
}

#ifdef VN_HAVE_AVX2
/* Eight (x, y, z, junk) rows -> x, y, z lanes (lane j = row j). */
VN_AVX2_INLINE void transpose8(const __m128 v[8], __m256* x, __m256* y, __m256* z)
{
	__m256 r[4];
	for (int j = 0; j < 4; ++j)
		r[j] = _mm256_insertf128_ps(_mm256_castps128_ps256(v[j]), v[j + 4], 1);
	const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpacklo_ps(r[2], r[3]);
	const __m256 t2 = _mm256_unpackhi_ps(r[0], r[1]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
	*x = _mm256_shuffle_ps(t0, t1, 0x44);
	*y = _mm256_shuffle_ps(t0, t1, 0xee);
	*z = _mm256_shuffle_ps(t2, t3, 0x44);
}

VN_AVX2_INLINE __m256 dot8(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz)
{
	return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)), _mm256_mul_ps(az, bz));
}

/* face_float on the eight faces idx[0..24), corners rec[0..96); returns the
 * mask of the lanes that must take the fallback. */
VN_AVX2_INLINE int faces_float8(const vn_work* w, vn_method method, const uint32_t* idx, float* rec)
{
	const unsigned char* base = w->positions;
	const size_t s = w->stride;
	__m256 px[3], py[3], pz[3];
	for (int c = 0; c < 3; ++c) {
		__m128 v[8];
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
	const __m256 nx = _mm256_sub_ps(_mm256_mul_ps(e20[1], e01[2]), _mm256_mul_ps(e20[2], e01[1]));
	const __m256 ny = _mm256_sub_ps(_mm256_mul_ps(e20[2], e01[0]), _mm256_mul_ps(e20[0], e01[2]));
	const __m256 nz = _mm256_sub_ps(_mm256_mul_ps(e20[0], e01[1]), _mm256_mul_ps(e20[1], e01[0]));
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
	const __m256 lo = _mm256_set1_ps(FLT_MIN), hi = _mm256_set1_ps(FLT_MAX);
	__m256 ok = _mm256_and_ps(_mm256_cmp_ps(l2, lo, _CMP_GE_OQ), _mm256_cmp_ps(l2, hi, _CMP_LE_OQ));
	ok = _mm256_and_ps(ok, _mm256_and_ps(_mm256_cmp_ps(den, lo, _CMP_GE_OQ), _mm256_cmp_ps(den, hi, _CMP_LE_OQ)));
	for (int k = 0; k < 3; ++k)
		ok = _mm256_and_ps(ok, _mm256_cmp_ps(wt[k], hi, _CMP_LE_OQ));

	/* Corner k of face j at rec[12 j + 4 k]: lanes to rows, faces j and j + 4
	 * in the two halves of a register. */
	const __m256 zero = _mm256_setzero_ps();
	for (int k = 0; k < 3; ++k) {
		const __m256 cx = _mm256_mul_ps(nx, wt[k]), cy = _mm256_mul_ps(ny, wt[k]), cz = _mm256_mul_ps(nz, wt[k]);
		const __m256 a0 = _mm256_unpacklo_ps(cx, cy), a1 = _mm256_unpackhi_ps(cx, cy);
		const __m256 a2 = _mm256_unpacklo_ps(cz, zero), a3 = _mm256_unpackhi_ps(cz, zero);
		const __m256 row[4] = {_mm256_shuffle_ps(a0, a2, 0x44), _mm256_shuffle_ps(a0, a2, 0xee),
		                       _mm256_shuffle_ps(a1, a3, 0x44), _mm256_shuffle_ps(a1, a3, 0xee)};
		for (int j = 0; j < 4; ++j) {
			_mm_store_ps(rec + 12 * j + 4 * k, _mm256_castps256_ps128(row[j]));
			_mm_store_ps(rec + 12 * (j + 4) + 4 * k, _mm256_extractf128_ps(row[j], 1));
		}
	}
	return ~_mm256_movemask_ps(ok) & 0xff;
}

VN_AVX2_INLINE size_t faces_float_avx2(const vn_work* w, vn_method method, const uint32_t* indices, float* records,
                                       size_t f0, size_t f1)
{
	const uint32_t last = w->vertex_count - 1;
	const vn_range all = {0, 0, 1};
	size_t degenerate = 0, f = f0;
	for (; f + 8 <= f1; f += 8) {
		const uint32_t* idx = indices + 3 * f;
		/* 16-byte loads read past the last vertex's z: the scalar kernel there. */
		if (vn_group_kind(idx, last, all) != VN_GROUP_SIMD || vn_group_kind(idx + 12, last, all) != VN_GROUP_SIMD) {
			degenerate += faces_float(w, method, indices, records, f, f + 8);
			continue;
		}
		int redo = faces_float8(w, method, idx, records + 12 * f);
		while (redo) {
			const int j = __builtin_ctz((unsigned)redo);
			redo &= redo - 1;
			degenerate += !face_fallback(w, method, idx + 3 * j, records + 12 * (f + j));
		}
	}
	return degenerate + faces_float(w, method, indices, records, f, f1);
}
#endif

/* ---------------------------------------------------------------- double faces */

/* vn_triangle_normals' arithmetic (triangles() in weights.c): the corners'
 * n * w_k, or zeros when the face contributes nothing. */
VN_INLINE size_t faces_double(const vn_work* w, vn_method method, const uint32_t* indices, double* records, size_t f0,
                              size_t f1)
{
	size_t degenerate = 0;
	for (size_t f = f0; f < f1; ++f) {
		const uint32_t* idx = indices + 3 * f;
		double* rec = records + 12 * f;
		double p0[3], p1[3], p2[3], e01[3], e12[3], e20[3], n[3], wt[3];
		vn_load(w, vn_scalar_float64, idx[0], p0);
		vn_load(w, vn_scalar_float64, idx[1], p1);
		vn_load(w, vn_scalar_float64, idx[2], p2);
		const double l2 = vn_triangle_edges(p0, p1, p2, e01, e12, e20, n);
		if (!vn_usable(l2)) {
			memset(rec, 0, 12 * sizeof(double));
			++degenerate;
			continue;
		}
		vn_triangle_weights(method, e01, e12, e20, l2, wt);
		for (int k = 0; k < 3; ++k) {
			const double c[4] = {n[0] * wt[k], n[1] * wt[k], n[2] * wt[k], 0.0};
			memcpy(rec + 4 * k, c, sizeof(c));
		}
	}
	return degenerate;
}

#ifdef VN_HAVE_AVX2
VN_AVX2_INLINE size_t faces_double_avx2(const vn_work* w, vn_method method, const uint32_t* indices, double* records,
                                        size_t f0, size_t f1)
{
	const uint32_t last = w->vertex_count - 1;
	const vn_range all = {0, 0, 1};
	size_t degenerate = 0, f = f0;
	for (; f + 4 <= f1; f += 4) {
		const uint32_t* idx = indices + 3 * f;
		if (vn_group_kind(idx, last, all) != VN_GROUP_SIMD) {
			degenerate += faces_double(w, method, indices, records, f, f + 4);
			continue;
		}
		vn_group p;
		vn_load_group(w, vn_scalar_float64, idx, &p);
		__m256d e[3][3], n[3], wt[3];
		for (int k = 0; k < 3; ++k) {
			const int j = k == 2 ? 0 : k + 1;
			e[k][0] = _mm256_sub_pd(p.x[j], p.x[k]);
			e[k][1] = _mm256_sub_pd(p.y[j], p.y[k]);
			e[k][2] = _mm256_sub_pd(p.z[j], p.z[k]);
		}
		vn_cross4(e[2][0], e[2][1], e[2][2], e[0][0], e[0][1], e[0][2], &n[0], &n[1], &n[2]);
		const __m256d l2 = vn_dot4(n[0], n[1], n[2], n[0], n[1], n[2]);
		const int usable = vn_usable4(l2);
		degenerate += (size_t)(4 - __builtin_popcount((unsigned)usable));
		vn_triangle_weights4(method, (const __m256d(*)[3])e, l2, wt);
		const __m256d keep = _mm256_and_pd(_mm256_cmp_pd(l2, _mm256_set1_pd(DBL_MIN), _CMP_GE_OQ),
		                                   _mm256_cmp_pd(l2, _mm256_set1_pd(DBL_MAX), _CMP_LE_OQ));
		const __m256d zero = _mm256_setzero_pd();
		for (int k = 0; k < 3; ++k)
			n[k] = _mm256_and_pd(n[k], keep), wt[k] = _mm256_and_pd(wt[k], keep);
		double* rec = records + 12 * f;
		for (int k = 0; k < 3; ++k) {
			const __m256d cx = _mm256_mul_pd(n[0], wt[k]), cy = _mm256_mul_pd(n[1], wt[k]);
			const __m256d cz = _mm256_mul_pd(n[2], wt[k]);
			const __m256d t0 = _mm256_unpacklo_pd(cx, cy), t1 = _mm256_unpackhi_pd(cx, cy);
			const __m256d t2 = _mm256_unpacklo_pd(cz, zero), t3 = _mm256_unpackhi_pd(cz, zero);
			_mm256_store_pd(rec + 4 * k, _mm256_permute2f128_pd(t0, t2, 0x20));
			_mm256_store_pd(rec + 12 + 4 * k, _mm256_permute2f128_pd(t1, t3, 0x20));
			_mm256_store_pd(rec + 24 + 4 * k, _mm256_permute2f128_pd(t0, t2, 0x31));
			_mm256_store_pd(rec + 36 + 4 * k, _mm256_permute2f128_pd(t1, t3, 0x31));
		}
	}
	return degenerate + faces_double(w, method, indices, records, f, f1);
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

static size_t face_range_scalar(const pass* p, size_t f0, size_t f1)
{
	const vn_plan* plan = p->plan;
	size_t d = 0;
	if (p->reader.type == vn_scalar_float32)
		WITH_METHOD(p->method, d = faces_float(&p->reader, m, plan->indices, (float*)plan->records, f0, f1))
	else
		WITH_METHOD(p->method, d = faces_double(&p->reader, m, plan->indices, (double*)plan->records, f0, f1))
	return d;
}

#ifdef VN_HAVE_AVX2
static VN_AVX2 size_t face_range_avx2(const pass* p, size_t f0, size_t f1)
{
	const vn_plan* plan = p->plan;
	size_t d = 0;
	if (p->reader.type == vn_scalar_float32)
		WITH_METHOD(p->method, d = faces_float_avx2(&p->reader, m, plan->indices, (float*)plan->records, f0, f1))
	else
		WITH_METHOD(p->method, d = faces_double_avx2(&p->reader, m, plan->indices, (double*)plan->records, f0, f1))
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

/* Vertex v's corners beyond the slots: *codes and their number. */
VN_INLINE uint32_t overflow_codes(const vn_plan* plan, uint32_t v, const uint32_t** codes)
{
	if (!(plan->slots[SLOTS * (size_t)v + SLOTS - 1] & MORE))
		return 0;
	const size_t k = overflow_of(plan, v);
	*codes = plan->over_code + plan->over_start[k];
	return plan->over_start[k + 1] - plan->over_start[k];
}

/* vn_normalize in float arithmetic. */
VN_INLINE int normalizef(float a[3])
{
	float x = a[0], y = a[1], z = a[2];
	const float len2 = x * x + y * y + z * z;
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

VN_INLINE int store_double(const pass* p, uint32_t v, double a[3])
{
	const int zero = vn_normalize(a);
	if (!(zero && p->plan->opt.keep_existing))
		vn_store(p->out, v, a);
	return zero;
}

/* Adds the corners codes[0..k) of float records to a, in order. */
VN_INLINE void gather_float(const float* records, const uint32_t* codes, uint32_t k, float a[3])
{
	for (uint32_t s = 0; s < k; ++s) {
		const float* r = records + CORNER(codes[s]);
		a[0] += r[0], a[1] += r[1], a[2] += r[2];
	}
}

VN_INLINE void gather_double(const double* records, const uint32_t* codes, uint32_t k, double a[3])
{
	for (uint32_t s = 0; s < k; ++s) {
		const double* r = records + CORNER(codes[s]);
		a[0] += r[0], a[1] += r[1], a[2] += r[2];
	}
}

/* The vertices list[0..n), one at a time; returns the zero normals. */
static size_t vertices_scalar(const pass* p, const uint32_t* list, size_t n)
{
	const vn_plan* plan = p->plan;
	size_t zero = 0;
	for (size_t i = 0; i < n; ++i) {
		const uint32_t v = list[i];
		const uint32_t* more = NULL;
		const uint32_t extra = overflow_codes(plan, v, &more);
		if (p->reader.type == vn_scalar_float32) {
			float a[3] = {0.0f, 0.0f, 0.0f};
			gather_float((const float*)plan->records, plan->slots + SLOTS * (size_t)v, SLOTS, a);
			gather_float((const float*)plan->records, more, extra, a);
			zero += store_float(p, v, a);
		} else {
			double a[3] = {0.0, 0.0, 0.0};
			gather_double((const double*)plan->records, plan->slots + SLOTS * (size_t)v, SLOTS, a);
			gather_double((const double*)plan->records, more, extra, a);
			zero += store_double(p, v, a);
		}
	}
	return zero;
}

#ifdef VN_HAVE_AVX2
/* vertices_scalar on 8 vertices at a time: the sums interleaved over the
 * slots, then normalized together (lanes out of range one by one). */
static VN_AVX2 size_t vertices_float_avx2(const pass* p, const uint32_t* list, size_t n)
{
	const vn_plan* plan = p->plan;
	const float* records = (const float*)plan->records;
	size_t zero = 0, i = 0;
	for (; i + 8 <= n; i += 8) {
		const uint32_t* vs = list + i;
		__m128 acc[8];
		for (int j = 0; j < 8; ++j)
			acc[j] = _mm_setzero_ps();
		for (int s = 0; s < SLOTS; ++s)
			for (int j = 0; j < 8; ++j) {
				const uint32_t c = plan->slots[SLOTS * (size_t)vs[j] + s];
				acc[j] = _mm_add_ps(acc[j], _mm_load_ps(records + CORNER(c)));
			}
		for (int j = 0; j < 8; ++j) {
			const uint32_t* more = NULL;
			const uint32_t extra = overflow_codes(plan, vs[j], &more);
			for (uint32_t e = 0; e < extra; ++e) {
				acc[j] = _mm_add_ps(acc[j], _mm_load_ps(records + CORNER(more[e])));
			}
		}
		__m256 x, y, z;
		transpose8(acc, &x, &y, &z);
		const __m256 len2 = dot8(x, y, z, x, y, z);
		const __m256 in = _mm256_and_ps(_mm256_cmp_ps(len2, _mm256_set1_ps(LEN2F_MIN), _CMP_GE_OQ),
		                                _mm256_cmp_ps(len2, _mm256_set1_ps(LEN2F_MAX), _CMP_LE_OQ));
		const int all_in = _mm256_movemask_ps(in) == 0xff;
		float nx[8], ny[8], nz[8];
		if (all_in) {
			const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(len2));
			x = _mm256_mul_ps(x, inv), y = _mm256_mul_ps(y, inv), z = _mm256_mul_ps(z, inv);
		}
		_mm256_storeu_ps(nx, x), _mm256_storeu_ps(ny, y), _mm256_storeu_ps(nz, z);
		unsigned char* const out = (unsigned char*)p->out->data;
		const size_t os = p->out->stride;
		if (!all_in) {
			for (int j = 0; j < 8; ++j) {
				float a[3] = {nx[j], ny[j], nz[j]};
				zero += store_float(p, vs[j], a);
			}
		} else if (p->out->type == vn_scalar_float32) {
			for (int j = 0; j < 8; ++j) {
				const float f[3] = {nx[j], ny[j], nz[j]};
				memcpy(out + vs[j] * os, f, sizeof(f));
			}
		} else {
			for (int j = 0; j < 8; ++j) {
				const double d[3] = {nx[j], ny[j], nz[j]};
				memcpy(out + vs[j] * os, d, sizeof(d));
			}
		}
	}
	return zero + vertices_scalar(p, list + i, n - i);
}

/* The double sums four vertices at a time, normalized as vn_run's finalize does. */
static VN_AVX2 size_t vertices_double_avx2(const pass* p, const uint32_t* list, size_t n)
{
	const vn_plan* plan = p->plan;
	const double* records = (const double*)plan->records;
	size_t zero = 0, i = 0;
	for (; i + 4 <= n; i += 4) {
		const uint32_t* vs = list + i;
		__m256d acc[4];
		for (int j = 0; j < 4; ++j)
			acc[j] = _mm256_setzero_pd();
		for (int s = 0; s < SLOTS; ++s)
			for (int j = 0; j < 4; ++j) {
				const uint32_t c = plan->slots[SLOTS * (size_t)vs[j] + s];
				acc[j] = _mm256_add_pd(acc[j], _mm256_load_pd(records + CORNER(c)));
			}
		for (int j = 0; j < 4; ++j) {
			const uint32_t* more = NULL;
			const uint32_t extra = overflow_codes(plan, vs[j], &more);
			for (uint32_t e = 0; e < extra; ++e) {
				acc[j] = _mm256_add_pd(acc[j], _mm256_load_pd(records + CORNER(more[e])));
			}
		}
		const __m256d t0 = _mm256_unpacklo_pd(acc[0], acc[1]), t1 = _mm256_unpackhi_pd(acc[0], acc[1]);
		const __m256d t2 = _mm256_unpacklo_pd(acc[2], acc[3]), t3 = _mm256_unpackhi_pd(acc[2], acc[3]);
		__m256d x = _mm256_permute2f128_pd(t0, t2, 0x20), y = _mm256_permute2f128_pd(t1, t3, 0x20);
		__m256d z = _mm256_permute2f128_pd(t0, t2, 0x31);
		const __m256d len2 = vn_dot4(x, y, z, x, y, z);
		const __m256d in = _mm256_and_pd(_mm256_cmp_pd(len2, _mm256_set1_pd(VN_LEN2_MIN), _CMP_GE_OQ),
		                                 _mm256_cmp_pd(len2, _mm256_set1_pd(VN_LEN2_MAX), _CMP_LE_OQ));
		const int all_in = _mm256_movemask_pd(in) == 15;
		if (all_in) {
			const __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), _mm256_sqrt_pd(len2));
			x = _mm256_mul_pd(x, inv), y = _mm256_mul_pd(y, inv), z = _mm256_mul_pd(z, inv);
		}
		double nx[4], ny[4], nz[4];
		_mm256_storeu_pd(nx, x), _mm256_storeu_pd(ny, y), _mm256_storeu_pd(nz, z);
		for (int j = 0; j < 4; ++j) {
			double a[3] = {nx[j], ny[j], nz[j]};
			if (all_in)
				vn_store(p->out, vs[j], a);
			else
				zero += store_double(p, vs[j], a);
		}
	}
	return zero + vertices_scalar(p, list + i, n - i);
}
#endif

static size_t face_range(const pass* p, size_t f0, size_t f1)
{
#ifdef VN_HAVE_AVX2
	if (p->plan->simd)
		return face_range_avx2(p, f0, f1);
#endif
	return face_range_scalar(p, f0, f1);
}

static size_t vertex_list(const pass* p, const uint32_t* list, size_t n)
{
#ifdef VN_HAVE_AVX2
	if (p->plan->simd)
		return p->reader.type == vn_scalar_float32 ? vertices_float_avx2(p, list, n) : vertices_double_avx2(p, list, n);
#endif
	return vertices_scalar(p, list, n);
}

/* Worker t's faces, chunk by chunk, each followed by the vertices it completes. */
static void chunk_pass(void* ctx, unsigned t)
{
	pass* p = (pass*)ctx;
	const vn_plan* plan = p->plan;
	size_t f0, f1, degenerate = 0, zero = 0;
	split(plan->face_count, t, plan->workers, &f0, &f1);
	for (uint32_t k = plan->base[t]; k < plan->base[t + 1]; ++k, f0 += CHUNK) {
		degenerate += face_range(p, f0, f1 - f0 < CHUNK ? f1 : f0 + CHUNK);
		zero += vertex_list(p, plan->order + plan->start[k], plan->start[k + 1] - plan->start[k]);
	}
	p->stats[t].degenerate_faces = degenerate;
	p->stats[t].zero_normals = zero;
}

/* The rest of the vertices, split evenly, and the non-finite count. */
static void rest_pass(void* ctx, unsigned t)
{
	pass* p = (pass*)ctx;
	const vn_plan* plan = p->plan;
	const size_t first = plan->start[plan->base[plan->workers]], n = plan->vertex_count - first;
	const size_t lo = first + n * t / plan->workers, hi = first + n * (t + 1) / plan->workers;
	p->stats[t].zero_normals += vertex_list(p, plan->order + lo, hi - lo);
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

/* The order in which the chunk pass sums the vertices: a vertex after the
 * chunk of its last face when its first face is in the same worker's range,
 * else in the rest (so are isolated vertices). A counting sort by bucket,
 * ascending vertex numbers within one; first[] is overwritten. */
static void schedule(vn_plan* plan, const uint32_t* count, uint32_t* first, const uint32_t* last)
{
	const unsigned nt = plan->workers;
	const uint32_t chunks = plan->base[nt], nv = plan->vertex_count;
	size_t from[MAX_WORKERS];
	for (unsigned t = 0; t < nt; ++t) {
		size_t hi;
		split(plan->face_count, t, nt, &from[t], &hi);
	}
	uint32_t* start = plan->start;
	memset(start, 0, sizeof(uint32_t) * ((size_t)chunks + 2));
	for (uint32_t v = 0; v < nv; ++v) {
		uint32_t b = chunks;
		if (count[v]) {
			unsigned lo = 0, hi = nt; /* the last worker whose range starts at or before last[v] */
			while (hi - lo > 1) {
				const unsigned mid = (lo + hi) / 2;
				if (from[mid] <= last[v])
					lo = mid;
				else
					hi = mid;
			}
			if (first[v] >= from[lo])
				b = plan->base[lo] + (uint32_t)((last[v] - from[lo]) / CHUNK);
		}
		first[v] = b;
		++start[b + 1];
	}
	for (uint32_t b = 0; b <= chunks; ++b)
		start[b + 1] += start[b];
	for (uint32_t v = 0; v < nv; ++v)
		plan->order[start[first[v]]++] = v;
	for (uint32_t b = chunks + 1; b > 0; --b)
		start[b] = start[b - 1];
	start[0] = 0;
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
	const int gather = !face_offsets && face_count <= MAX_GATHER_FACES;
	/* Corners per vertex, then each overflow vertex's ordinal. */
	/* Scratch: corners, overflow ordinal, first and last face of each vertex. */
	uint32_t* count = NULL;
	size_t over_count = 0, over_codes = 0;
	if (gather && nv) {
		if (!(count = (uint32_t*)heap.allocate(heap.user, 4 * sizeof(uint32_t) * nv)))
			return vn_result_out_of_memory;
		uint32_t *first = count + 2 * (size_t)nv, *last = count + 3 * (size_t)nv;
		memset(count, 0, sizeof(uint32_t) * nv);
		for (size_t f = face_count; f-- > 0;)
			for (int k = 0; k < 3; ++k)
				first[indices[3 * f + k]] = (uint32_t)f;
		for (size_t f = 0; f < face_count; ++f)
			for (int k = 0; k < 3; ++k) {
				const uint32_t v = indices[3 * f + k];
				++count[v];
				last[v] = (uint32_t)f;
			}
		for (uint32_t v = 0; v < nv; ++v)
			if (count[v] > SLOTS)
				count[nv + v] = (uint32_t)over_count++, over_codes += count[v] - SLOTS;
	}

	const unsigned workers = vn_worker_count(nv, o->threads);
	uint32_t chunks = 0, base[MAX_WORKERS + 1];
	for (unsigned t = 0; t < workers; ++t) {
		size_t f0, f1;
		split(face_count, t, workers, &f0, &f1);
		base[t] = chunks;
		chunks += gather ? (uint32_t)((f1 - f0 + CHUNK - 1) / CHUNK) : 0;
	}
	base[workers] = chunks;
	const size_t record_bytes = gather ? 96 * (face_count + 1) : 0;
	size_t work = vn_workspace_size(nv, o);
	const size_t corner_bytes = corner_work_bytes(ni, face_count, nv, o->threads);
	work = work > corner_bytes ? work : corner_bytes;
	work = work > record_bytes ? work : record_bytes;
	const size_t head = round64(sizeof(vn_plan));
	const size_t idx_bytes = round64(sizeof(uint32_t) * ni);
	const size_t off_bytes = face_offsets ? round64(sizeof(uint32_t) * (face_count + 1)) : 0;
	const size_t slot_bytes = gather ? round64(sizeof(uint32_t) * SLOTS * (size_t)nv) : 0;
	const size_t over_bytes = round64(sizeof(uint32_t) * (2 * over_count + 1 + over_codes));
	const size_t order_bytes = gather ? round64(sizeof(uint32_t) * ((size_t)nv + chunks + 2)) : 0;
	const size_t total = head + idx_bytes + off_bytes + slot_bytes + over_bytes + order_bytes + round64(work) + 64;
	unsigned char* block = (unsigned char*)heap.allocate(heap.user, total);
	if (!block) {
		if (count)
			heap.deallocate(heap.user, count);
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
	plan->simd = o->simd == vn_simd_auto && vn_cpu_has_avx2();
	plan->workers = workers;
	plan->indices = (uint32_t*)at;
	if (ni)
		memcpy(plan->indices, indices, sizeof(uint32_t) * ni);
	at += idx_bytes;
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
	/* The records want 64-byte alignment (a double record is a cache line). */
	plan->records = block + ((((uintptr_t)at + 63) & ~(uintptr_t)63) - (uintptr_t)block);
	plan->opt.workspace = plan->records;
	plan->opt.workspace_size = work;

	if (count) {
		/* Slots in ascending corner order; count[] becomes the fill cursor. */
		const uint32_t pad = (uint32_t)(3 * face_count);
		for (size_t i = 0; i < SLOTS * (size_t)nv; ++i)
			plan->slots[i] = pad;
		uint32_t start = 0;
		for (uint32_t v = 0; v < nv; ++v)
			if (count[v] > SLOTS) {
				const uint32_t k = count[nv + v];
				plan->over_vertex[k] = v;
				plan->over_start[k] = start;
				start += count[v] - SLOTS;
			}
		plan->over_start[over_count] = start;
		schedule(plan, count, count + 2 * (size_t)nv, count + 3 * (size_t)nv);
		memset(count, 0, sizeof(uint32_t) * nv);
		for (size_t i = 0; i < ni; ++i) {
			const uint32_t v = indices[i], j = count[v]++;
			const uint32_t code = (uint32_t)i;
			if (j < SLOTS)
				plan->slots[SLOTS * (size_t)v + j] = code;
			else
				plan->over_code[plan->over_start[count[nv + v]] + j - SLOTS] = code;
		}
		for (size_t k = 0; k < over_count; ++k)
			plan->slots[SLOTS * (size_t)plan->over_vertex[k] + SLOTS - 1] |= MORE;
		heap.deallocate(heap.user, count);
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
	if (!plan->gather || method > vn_method_mwrelr || !plan->vertex_count) {
		if (plan->offsets)
			return vn_polygon_normals(normals, positions, plan->indices, plan->offsets, plan->face_count, method,
			                          &plan->opt, stats);
		return vn_triangle_normals(normals, positions, plan->indices, plan->index_count, method, &plan->opt, stats);
	}

	vn_vectors out = *normals;
	out.stride = vn_vectors_stride(normals);
	pass p;
	p.plan = plan;
	p.reader = vn_position_reader(positions, stride);
	p.method = method;
	p.out = &out;
	p.want_stats = stats != NULL;
	const unsigned nt = plan->workers;
	memset(p.stats, 0, sizeof(p.stats[0]) * nt);
	/* The zero corner the padding slots name. */
	const size_t corner_bytes = positions->type == vn_scalar_float32 ? 16 : 32;
	memset(plan->records + corner_bytes * 3 * plan->face_count, 0, corner_bytes);

	vn_parallel(nt, chunk_pass, &p);
	if (p.want_stats || plan->start[plan->base[nt]] < plan->vertex_count)
		vn_parallel(nt, rest_pass, &p);

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
