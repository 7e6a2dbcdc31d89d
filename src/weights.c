/* The face-normal weighted family: N_v || sum_f w(f, v) N_f.
 *
 * For a face f around vertex v, N_f is f's unit normal, E and E' run from v to
 * its previous and next corner in f, and alpha = atan2(|E x E'|, E . E').
 *   MWE     w = 1                               Gouraud 1971            (eq. 1)
 *   MWA     w = alpha                           Thurmer & Wuthrich 1998 (eq. 2)
 *   MWSELR  w = sin(alpha) / (|E||E'|)          Max 1999                (eq. 4)
 *   MWAAT   w = |E x E'|                        Max 1999                (eq. 5)
 *   MWELR   w = 1 / (|E||E'|)                   Max 1999                (eq. 6)
 *   MWRELR  w = 1 / sqrt(|E||E'|)               Max 1999                (eq. 7)
 *
 * On a triangle |E x E'| is the same at all three corners: the length l of
 * the unnormalized normal n. So w N_f = n * (w / l), and every weight needs
 * only l and the squared edge lengths (sin(alpha)/(|E||E'|) * N_f =
 * n / (|E|^2 |E'|^2), |E x E'| N_f = n).
 *
 * Scalar sqrt and division throughput bounds this loop, so each method uses
 * one division per triangle and as few square roots as its weight allows.
 */
#include "internal.h"

#include "weights.h"

/* ---------------------------------------------------------------- triangles */

VN_INLINE void triangles(const vn_work* w, vn_scalar type, vn_method method, vn_range range, vn_range_stats* st)
{
	const uint32_t* idx = w->indices;
	double* acc = w->acc;
	size_t degenerate = 0;

	for (size_t f = 0; f < w->face_count; ++f) {
		const uint32_t i0 = idx[3 * f], i1 = idx[3 * f + 1], i2 = idx[3 * f + 2];
		if (vn_bad_triangle(w, i0, i1, i2, st))
			return;
		const int o0 = vn_owned(i0, range), o1 = vn_owned(i1, range), o2 = vn_owned(i2, range);
		if (!(o0 | o1 | o2))
			continue;

		double p0[3], p1[3], p2[3], e01[3], e12[3], e20[3], n[3], wt[3];
		vn_load(w, type, i0, p0);
		vn_load(w, type, i1, p1);
		vn_load(w, type, i2, p2);
		const double l2 = vn_triangle_edges(p0, p1, p2, e01, e12, e20, n);
		if (!vn_usable(l2)) {
			degenerate += o0;
			continue;
		}
		vn_triangle_weights(method, e01, e12, e20, l2, wt);
		if (o0)
			vn_add_scaled(acc + 4 * (size_t)i0, n, wt[0]);
		if (o1)
			vn_add_scaled(acc + 4 * (size_t)i1, n, wt[1]);
		if (o2)
			vn_add_scaled(acc + 4 * (size_t)i2, n, wt[2]);
	}
	st->degenerate_faces += degenerate;
}

int vn_weighted_triangle(vn_method method, const double p0[3], const double p1[3], const double p2[3], double c[3][3])
{
	double e01[3], e12[3], e20[3], n[3], wt[3];
	const double l2 = vn_triangle_edges(p0, p1, p2, e01, e12, e20, n);
	if (!vn_usable(l2))
		return 0;
	vn_triangle_weights(method, e01, e12, e20, l2, wt);
	for (int k = 0; k < 3; ++k)
		c[k][0] = n[0] * wt[k], c[k][1] = n[1] * wt[k], c[k][2] = n[2] * wt[k];
	return 1;
}

#ifdef VN_HAVE_AVX2
/* Corner k's vector n wt[k]. */
VN_AVX2_INLINE void weighted_corners(const __m256d n[3], const __m256d wt[3], __m256d cx[3], __m256d cy[3],
                                     __m256d cz[3])
{
	for (int k = 0; k < 3; ++k)
		cx[k] = _mm256_mul_pd(n[0], wt[k]), cy[k] = _mm256_mul_pd(n[1], wt[k]), cz[k] = _mm256_mul_pd(n[2], wt[k]);
}

/* triangles()' contributions on four lanes, operation for operation (see simd.h). */
VN_AVX2_INLINE void weighted_group(vn_method method, const __m256d e[3][3], const __m256d n[3], __m256d l2,
                                   __m256d cx[3], __m256d cy[3], __m256d cz[3])
{
	__m256d wt[3];
	vn_triangle_weights4(method, e, l2, wt);
	weighted_corners(n, wt, cx, cy, cz);
}

#define VN_TRIANGLES_FAST(name, type, method)                                                                       \
	static VN_AVX2 void name##_avx2(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)                 \
	{                                                                                                               \
		VN_DISPATCH_RANGE(w, lo, hi, vn_triangles_avx2(w, type, method, 0, range, st, weighted_group, NULL, name)); \
	}
#else
#define VN_TRIANGLES_FAST(name, type, method)
#endif

/* One specialized copy per (position type, method): the switch above folds
 * away and the loop keeps no per-face branches on the method. */
#define VN_TRIANGLES(name, type, method)                                                                   \
	static void name(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)                       \
	{                                                                                                      \
		VN_DISPATCH_RANGE(w, lo, hi, triangles(w, type, method, range, st));                               \
	}                                                                                                      \
	VN_TRIANGLES_FAST(name, type, method)
VN_TRIANGLES(tri_f_mwe, vn_scalar_float32, vn_method_mwe)
VN_TRIANGLES(tri_f_mwa, vn_scalar_float32, vn_method_mwa)
VN_TRIANGLES(tri_f_mwselr, vn_scalar_float32, vn_method_mwselr)
VN_TRIANGLES(tri_f_mwaat, vn_scalar_float32, vn_method_mwaat)
VN_TRIANGLES(tri_f_mwelr, vn_scalar_float32, vn_method_mwelr)
VN_TRIANGLES(tri_f_mwrelr, vn_scalar_float32, vn_method_mwrelr)
VN_TRIANGLES(tri_d_mwe, vn_scalar_float64, vn_method_mwe)
VN_TRIANGLES(tri_d_mwa, vn_scalar_float64, vn_method_mwa)
VN_TRIANGLES(tri_d_mwselr, vn_scalar_float64, vn_method_mwselr)
VN_TRIANGLES(tri_d_mwaat, vn_scalar_float64, vn_method_mwaat)
VN_TRIANGLES(tri_d_mwelr, vn_scalar_float64, vn_method_mwelr)
VN_TRIANGLES(tri_d_mwrelr, vn_scalar_float64, vn_method_mwrelr)

/* VN_MWA_POLY, float64 positions only (the per-frame plans' float64 MWA). */
static void tri_d_mwa_poly(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	VN_DISPATCH_RANGE(w, lo, hi, triangles(w, vn_scalar_float64, VN_MWA_POLY, range, st));
}

#ifdef VN_HAVE_AVX2
/* triangles()' VN_MWA_POLY weights of k <= VN_PG groups from l2 and the
 * cosines c[2h], c[2h + 1] of group h, their angles' chains interleaved. */
VN_AVX2_FMA_INLINE void mwa_poly_weights(int k, const __m256d* l2, const __m256d* c, __m256d (*wt)[3])
{
	__m256d l[VN_PG], y[2 * VN_PG], a[2 * VN_PG];
	for (int h = 0; h < k; ++h)
		y[2 * h] = y[2 * h + 1] = l[h] = _mm256_sqrt_pd(l2[h]);
	vn_atan2_poly4(2 * k, y, c, a);
	for (int h = 0; h < k; ++h) {
		const __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), l[h]);
		wt[h][0] = _mm256_mul_pd(a[2 * h], inv);
		wt[h][1] = _mm256_mul_pd(a[2 * h + 1], inv);
		wt[h][2] = _mm256_mul_pd(_mm256_sub_pd(_mm256_sub_pd(_mm256_set1_pd(VN_PI), a[2 * h]), a[2 * h + 1]), inv);
	}
}

VN_AVX2_FMA_INLINE void mwa_poly_group(vn_method method, const __m256d e[3][3], const __m256d n[3], __m256d l2,
                                       __m256d cx[3], __m256d cy[3], __m256d cz[3])
{
	(void)method;
	__m256d c[2], wt[1][3];
	vn_mwa_cosines4(e, c);
	mwa_poly_weights(1, &l2, c, wt);
	weighted_corners(n, wt[0], cx, cy, cz);
}

/* Each group's cosines right after its edges, so that only the normals
 * stay live until the angles are done. */
VN_AVX2_FMA_INLINE size_t mwa_poly_pair(const vn_work* w, const uint32_t* idx, vn_range range)
{
	__m256d n[VN_PG][3], l2[VN_PG], c[2 * VN_PG], wt[VN_PG][3];
	int usable[VN_PG];
	size_t degenerate = 0;
	for (int h = 0; h < VN_PG; ++h) {
		__m256d e[3][3];
		l2[h] = vn_group_edges(w, vn_scalar_float64, idx + 12 * h, e, n[h]);
		usable[h] = vn_usable4(l2[h]);
		degenerate += vn_group_degenerate(idx + 12 * h, usable[h], range);
		vn_mwa_cosines4((const __m256d(*)[3])e, c + 2 * h);
	}
	mwa_poly_weights(VN_PG, l2, c, wt);
	for (int h = 0; h < VN_PG; ++h) {
		__m256d cx[3], cy[3], cz[3];
		weighted_corners(n[h], wt[h], cx, cy, cz);
		vn_scatter_group(w->acc, idx + 12 * h, usable[h], range, 0, cx, cy, cz);
	}
	return degenerate;
}

/* VN_PG groups a step; fused multiply-adds in the polynomial, as fma in
 * triangles(). */
static VN_AVX2_FMA void tri_d_mwa_poly_avx2(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	VN_DISPATCH_RANGE(w, lo, hi,
	                  vn_triangles_avx2(w, vn_scalar_float64, VN_MWA_POLY, 0, range, st, mwa_poly_group, mwa_poly_pair,
	                                    tri_d_mwa_poly));
}
#endif

void vn_accumulate_weighted_triangles(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	/* Indexed by [simd][type][method], in vn_method order up to MWRELR. */
	static const vn_accumulate_fn table[2][2][6] = {
	    {{tri_f_mwe, tri_f_mwa, tri_f_mwselr, tri_f_mwaat, tri_f_mwelr, tri_f_mwrelr},
	     {tri_d_mwe, tri_d_mwa, tri_d_mwselr, tri_d_mwaat, tri_d_mwelr, tri_d_mwrelr}},
#ifdef VN_HAVE_AVX2
	    {{tri_f_mwe_avx2, tri_f_mwa_avx2, tri_f_mwselr_avx2, tri_f_mwaat_avx2, tri_f_mwelr_avx2, tri_f_mwrelr_avx2},
	     {tri_d_mwe_avx2, tri_d_mwa_avx2, tri_d_mwselr_avx2, tri_d_mwaat_avx2, tri_d_mwelr_avx2, tri_d_mwrelr_avx2}},
#else
	    {{tri_f_mwe, tri_f_mwa, tri_f_mwselr, tri_f_mwaat, tri_f_mwelr, tri_f_mwrelr},
	     {tri_d_mwe, tri_d_mwa, tri_d_mwselr, tri_d_mwaat, tri_d_mwelr, tri_d_mwrelr}},
#endif
	};
	if (w->method == VN_MWA_POLY) {
#ifdef VN_HAVE_AVX2
		/* The vector kernel fuses multiply-adds: it needs FMA too. */
		if (w->simd && vn_cpu_has_avx2_fma()) {
			tri_d_mwa_poly_avx2(w, lo, hi, st);
			return;
		}
#endif
		tri_d_mwa_poly(w, lo, hi, st);
		return;
	}
	table[w->simd != 0][w->type == vn_scalar_float64][w->method](w, lo, hi, st);
}

/* ---------------------------------------------------------------- polygons */

/* Adds w(f, v) N_f for a polygon corner with edges E, E' of non-zero length. */
static void weighted_corner(vn_method method, double* acc, const double n[3], const double e[3], const double e2[3])
{
	const double se = vn_dot(e, e), se2 = vn_dot(e2, e2);
	double c[3], wt;
	vn_cross(e, e2, c);
	switch (method) {
	case vn_method_mwe:
		wt = 1.0;
		break;
	case vn_method_mwa:
		wt = vn_atan2_nonneg(sqrt(vn_dot(c, c)), vn_dot(e, e2));
		break;
	case vn_method_mwselr:
		wt = sqrt(vn_dot(c, c)) / (se * se2);
		break;
	case vn_method_mwaat:
		wt = sqrt(vn_dot(c, c));
		break;
	case vn_method_mwelr:
		wt = 1.0 / sqrt(se * se2);
		break;
	default: /* vn_method_mwrelr */
		wt = 1.0 / sqrt(sqrt(se * se2));
		break;
	}
	vn_add_scaled(acc, n, wt);
}

void vn_accumulate_weighted_polygons(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	VN_DISPATCH_RANGE(w, lo, hi, vn_polygons(w, range, st, weighted_corner));
}
