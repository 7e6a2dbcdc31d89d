/* AVX2 helpers for the triangle kernels: four triangles at a time.
 *
 * The kernels load the 12 corners of a group of four triangles, transpose
 * them to structure-of-arrays doubles, do the per-face arithmetic on four
 * lanes, and transpose back to add each corner's vector to its accumulator.
 *
 * Bit-identical to the scalar code by construction: the same IEEE operations
 * (add, sub, mul, div, sqrt, exact conversions) in the same order, no FMA
 * (the library builds with -ffp-contract=off), and accumulators updated
 * triangle by triangle, corner by corner, exactly as the scalar loop does. */
#ifndef VN_SIMD_H
#define VN_SIMD_H

#include "internal.h"

#if (defined(__x86_64__) || defined(_M_X64)) && (defined(__GNUC__) || defined(__clang__))
#define VN_HAVE_AVX2 1
/* The groups of four triangles a vn_pair_fn takes in one step. */
#define VN_PG 2
#include <immintrin.h>

#define VN_AVX2 __attribute__((target("avx2")))
#define VN_AVX2_INLINE static inline __attribute__((target("avx2"), always_inline))
/* The per-frame plans' float kernels also fuse multiply-adds (plan.c). */
#define VN_AVX2_FMA __attribute__((target("avx2,fma")))
#define VN_AVX2_FMA_INLINE static inline __attribute__((target("avx2,fma"), always_inline))

/* The corners of one group: x, y, z of corner c, lane k = triangle k. */
typedef struct vn_group {
	__m256d x[3], y[3], z[3];
} vn_group;

/* How a group of four triangles (idx[0..12)) is handled:
 *  - VN_GROUP_SCALAR: an index is the last vertex or beyond. The loads below
 *    read 16 (float) or 32 (double) bytes from each vertex, past its z, which
 *    the last vertex's data may not have; and an index beyond must be
 *    reported. The scalar loop checks each index and reads exactly.
 *  - VN_GROUP_SKIP: no corner is owned by this worker.
 *  - VN_GROUP_SIMD: otherwise. */
enum { VN_GROUP_SIMD, VN_GROUP_SCALAR, VN_GROUP_SKIP };

/* Lanes of a that are <= limit (unsigned), as a mask of 8 and 4 bits. */
VN_AVX2_INLINE int vn_le8(__m256i a, uint32_t limit)
{
	const __m256i m = _mm256_cmpeq_epi32(_mm256_min_epu32(a, _mm256_set1_epi32((int)limit)), a);
	return _mm256_movemask_ps(_mm256_castsi256_ps(m));
}

VN_AVX2_INLINE int vn_le4(__m128i a, uint32_t limit)
{
	const __m128i m = _mm_cmpeq_epi32(_mm_min_epu32(a, _mm_set1_epi32((int)limit)), a);
	return _mm_movemask_ps(_mm_castsi128_ps(m));
}

VN_AVX2_INLINE int vn_group_kind(const uint32_t* idx, uint32_t last, vn_range range)
{
	const __m256i a = _mm256_loadu_si256((const __m256i*)idx);
	const __m128i b = _mm_loadu_si128((const __m128i*)(idx + 8));
	if (last == 0 || vn_le8(a, last - 1) != 0xff || vn_le4(b, last - 1) != 0xf)
		return VN_GROUP_SCALAR;
	if (range.full)
		return VN_GROUP_SIMD;
	const __m256i lo8 = _mm256_set1_epi32((int)range.lo);
	const int owned = vn_le8(_mm256_sub_epi32(a, lo8), range.span - 1) |
	                  vn_le4(_mm_sub_epi32(b, _mm256_castsi256_si128(lo8)), range.span - 1);
	return owned ? VN_GROUP_SIMD : VN_GROUP_SKIP;
}

/* 4 vertices (x, y, z, junk) -> x, y, z lanes as doubles. */
VN_AVX2_INLINE void vn_load4(const vn_work* w, vn_scalar type, uint32_t a, uint32_t b, uint32_t c, uint32_t d,
                             __m256d* x, __m256d* y, __m256d* z)
{
	const unsigned char* base = w->positions;
	const size_t s = w->stride;
	if (type == vn_scalar_float32) {
		const __m128 va = _mm_loadu_ps((const float*)(base + a * s)), vb = _mm_loadu_ps((const float*)(base + b * s));
		const __m128 vc = _mm_loadu_ps((const float*)(base + c * s)), vd = _mm_loadu_ps((const float*)(base + d * s));
		const __m128 t0 = _mm_unpacklo_ps(va, vb), t1 = _mm_unpacklo_ps(vc, vd);
		const __m128 t2 = _mm_unpackhi_ps(va, vb), t3 = _mm_unpackhi_ps(vc, vd);
		*x = _mm256_cvtps_pd(_mm_movelh_ps(t0, t1));
		*y = _mm256_cvtps_pd(_mm_movehl_ps(t1, t0));
		*z = _mm256_cvtps_pd(_mm_movelh_ps(t2, t3));
	} else {
		const __m256d va = _mm256_loadu_pd((const double*)(base + a * s));
		const __m256d vb = _mm256_loadu_pd((const double*)(base + b * s));
		const __m256d vc = _mm256_loadu_pd((const double*)(base + c * s));
		const __m256d vd = _mm256_loadu_pd((const double*)(base + d * s));
		const __m256d t0 = _mm256_unpacklo_pd(va, vb), t1 = _mm256_unpackhi_pd(va, vb);
		const __m256d t2 = _mm256_unpacklo_pd(vc, vd), t3 = _mm256_unpackhi_pd(vc, vd);
		*x = _mm256_permute2f128_pd(t0, t2, 0x20);
		*y = _mm256_permute2f128_pd(t1, t3, 0x20);
		*z = _mm256_permute2f128_pd(t0, t2, 0x31);
	}
}

/* Triangles idx[0..12) as corners of a group. */
VN_AVX2_INLINE void vn_load_group(const vn_work* w, vn_scalar type, const uint32_t* idx, vn_group* g)
{
	for (int c = 0; c < 3; ++c)
		vn_load4(w, type, idx[c], idx[3 + c], idx[6 + c], idx[9 + c], &g->x[c], &g->y[c], &g->z[c]);
}

VN_AVX2_INLINE __m256d vn_dot4(__m256d ax, __m256d ay, __m256d az, __m256d bx, __m256d by, __m256d bz)
{
	return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ax, bx), _mm256_mul_pd(ay, by)), _mm256_mul_pd(az, bz));
}

/* r = a x b, lane by lane, in vn_cross's order of operations. */
VN_AVX2_INLINE void vn_cross4(__m256d ax, __m256d ay, __m256d az, __m256d bx, __m256d by, __m256d bz, __m256d* rx,
                              __m256d* ry, __m256d* rz)
{
	*rx = _mm256_sub_pd(_mm256_mul_pd(ay, bz), _mm256_mul_pd(az, by));
	*ry = _mm256_sub_pd(_mm256_mul_pd(az, bx), _mm256_mul_pd(ax, bz));
	*rz = _mm256_sub_pd(_mm256_mul_pd(ax, by), _mm256_mul_pd(ay, bx));
}

/* The usable lanes (vn_usable) as a 4-bit mask. */
VN_AVX2_INLINE int vn_usable4(__m256d len2)
{
	const __m256d ok = _mm256_and_pd(_mm256_cmp_pd(len2, _mm256_set1_pd(DBL_MIN), _CMP_GE_OQ),
	                                 _mm256_cmp_pd(len2, _mm256_set1_pd(DBL_MAX), _CMP_LE_OQ));
	return _mm256_movemask_pd(ok);
}

/* Adds corner c's vector (x[c], y[c], z[c]) lane k to acc[idx[3k + c]] for the
 * usable lanes whose corner is owned, triangle by triangle in index order;
 * with lengths, its length to the fourth double too (else 0). */
VN_AVX2_INLINE void vn_scatter_group(double* acc, const uint32_t* idx, int usable, vn_range range, int lengths,
                                     const __m256d x[3], const __m256d y[3], const __m256d z[3])
{
	__m256d v[3][4]; /* [corner][lane]: (x, y, z, length or 0) */
	for (int c = 0; c < 3; ++c) {
		const __m256d l = lengths ? _mm256_sqrt_pd(vn_dot4(x[c], y[c], z[c], x[c], y[c], z[c])) : _mm256_setzero_pd();
		const __m256d t0 = _mm256_unpacklo_pd(x[c], y[c]), t1 = _mm256_unpackhi_pd(x[c], y[c]);
		const __m256d t2 = _mm256_unpacklo_pd(z[c], l), t3 = _mm256_unpackhi_pd(z[c], l);
		v[c][0] = _mm256_permute2f128_pd(t0, t2, 0x20);
		v[c][1] = _mm256_permute2f128_pd(t1, t3, 0x20);
		v[c][2] = _mm256_permute2f128_pd(t0, t2, 0x31);
		v[c][3] = _mm256_permute2f128_pd(t1, t3, 0x31);
	}
	for (int k = 0; k < 4; ++k) {
		if (!(usable >> k & 1))
			continue;
		for (int c = 0; c < 3; ++c) {
			const uint32_t i = idx[3 * k + c];
			if (vn_owned(i, range)) {
				double* a = acc + 4 * (size_t)i;
				_mm256_store_pd(a, _mm256_add_pd(_mm256_load_pd(a), v[c][k]));
			}
		}
	}
}

/* Degenerate faces of a group counted as the scalar loop does: by the worker
 * owning corner 0. */
VN_INLINE size_t vn_group_degenerate(const uint32_t* idx, int usable, vn_range range)
{
	size_t n = 0;
	if (usable != 15)
		for (int k = 0; k < 4; ++k)
			n += !(usable >> k & 1) && vn_owned(idx[3 * k], range);
	return n;
}

/* A family's arithmetic for one group: the corner vectors (cx, cy, cz)[k]
 * from the edges e[0] = e01, e[1] = e12, e[2] = e20 (x, y, z lanes each),
 * the unnormalized normal n = e20 x e01 and l2 = n . n. */
typedef void (*vn_group_fn)(vn_method method, const __m256d e[3][3], const __m256d n[3], __m256d l2, __m256d cx[3],
                            __m256d cy[3], __m256d cz[3]);
/* VN_PG consecutive groups idx[0..12 VN_PG) that all take the vector path, as a
 * family's kernel handles them (loads, arithmetic, degenerate count,
 * scatter), their operations interleaved so that their dependency chains
 * overlap in the reorder window; returns the degenerate faces. */
typedef size_t (*vn_pair_fn)(const vn_work* w, const uint32_t* idx, vn_range range);

/* Group idx[0..12)'s edges e[k], from corner k to the next, and normal n;
 * returns l2. */
VN_AVX2_INLINE __m256d vn_group_edges(const vn_work* w, vn_scalar type, const uint32_t* idx, __m256d e[3][3],
                                      __m256d n[3])
{
	vn_group p;
	vn_load_group(w, type, idx, &p);
	for (int k = 0; k < 3; ++k) {
		const int j = k == 2 ? 0 : k + 1;
		e[k][0] = _mm256_sub_pd(p.x[j], p.x[k]);
		e[k][1] = _mm256_sub_pd(p.y[j], p.y[k]);
		e[k][2] = _mm256_sub_pd(p.z[j], p.z[k]);
	}
	vn_cross4(e[2][0], e[2][1], e[2][2], e[0][0], e[0][1], e[0][2], &n[0], &n[1], &n[2]);
	return vn_dot4(n[0], n[1], n[2], n[0], n[1], n[2]);
}

/* The triangle loop both families share, four triangles per step: group
 * classification, loads, edges and normal, degenerate count, scatter (with
 * lengths: vn_scatter_group's). With `pair` (else NULL), VN_PG consecutive
 * groups that all take the vector path go through it in one step. Groups
 * that touch the last vertex, and the tail, go to `scalar`, the family's
 * scalar kernel for the same position type, method and lengths. */
VN_AVX2_INLINE void vn_triangles_avx2(const vn_work* w, vn_scalar type, vn_method method, int lengths,
                                      vn_range range, vn_range_stats* st, vn_group_fn group, vn_pair_fn pair,
                                      vn_accumulate_fn scalar)
{
	const uint32_t last = w->vertex_count - 1;
	const uint32_t lo = range.full ? 0 : range.lo, hi = range.full ? w->vertex_count : range.lo + range.span;
	const size_t groups = w->face_count / 4;
	size_t degenerate = 0;
	vn_work rest = *w;

	for (size_t g = 0; g < groups; ++g) {
		const uint32_t* idx = w->indices + 12 * g;
		const int kind = vn_group_kind(idx, last, range);
		if (pair && kind == VN_GROUP_SIMD && g + VN_PG - 1 < groups) {
			int ok = 1;
			for (int h = 1; h < VN_PG; ++h) ok &= vn_group_kind(idx + 12 * h, last, range) == VN_GROUP_SIMD;
			if (ok) {
				degenerate += pair(w, idx, range);
				g += VN_PG - 1;
				continue;
			}
		}
		if (kind == VN_GROUP_SKIP)
			continue;
		if (kind == VN_GROUP_SCALAR) {
			rest.indices = idx;
			rest.face_count = 4;
			scalar(&rest, lo, hi, st);
			if (st->bad_index)
				return;
			continue;
		}
		__m256d e[3][3], n[3];
		const __m256d l2 = vn_group_edges(w, type, idx, e, n);
		const int usable = vn_usable4(l2);
		degenerate += vn_group_degenerate(idx, usable, range);
		if (!usable)
			continue;
		__m256d cx[3], cy[3], cz[3];
		group(method, (const __m256d(*)[3])e, n, l2, cx, cy, cz);
		vn_scatter_group(w->acc, idx, usable, range, lengths, cx, cy, cz);
	}
	st->degenerate_faces += degenerate;
	/* No arithmetic on a NULL indices (a mesh without faces). */
	rest.indices = groups ? w->indices + 12 * groups : w->indices;
	rest.face_count = w->face_count - 4 * groups;
	scalar(&rest, lo, hi, st);
}

static inline int vn_cpu_has_avx2(void)
{
	return __builtin_cpu_supports("avx2");
}

static inline int vn_cpu_has_avx2_fma(void)
{
	return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

#else
static inline int vn_cpu_has_avx2(void)
{
	return 0;
}

static inline int vn_cpu_has_avx2_fma(void)
{
	return 0;
}
#endif /* x86-64 with GCC or Clang */

#endif /* VN_SIMD_H */
