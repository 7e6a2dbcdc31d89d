/* The weighted family's per-corner weights on one triangle, shared by the
 * scatter kernels (weights.c) and the per-frame plans' face pass (plan.c),
 * so that both compute them with the same operations. */
#ifndef VN_WEIGHTS_H
#define VN_WEIGHTS_H

#include "internal.h"

#include "fastmath.h"

/* MWA with vn_atan2_poly's corner angles, which the per-frame plans' float64
 * path runs (vn.h); no public method. */
#define VN_MWA_POLY vn_method_count

/* Corner k's weight over l = sqrt(l2) = |n|, so that w[k] n = w(f, k) N_f,
 * with one division per triangle: the products |E||E'| at the three corners
 * are ca, ab, bc for edge lengths a = |e01|, b = |e12|, c = |e20|, so
 * 1 / (ca) = b / (abc). */
VN_INLINE void vn_triangle_weights(vn_method method, const double e01[3], const double e12[3], const double e20[3],
                                   double l2, double w[3])
{
	switch (method) {
	case vn_method_mwe:
		w[0] = w[1] = w[2] = 1.0 / sqrt(l2);
		break;
	case vn_method_mwa:
	case VN_MWA_POLY: {
		/* Angles at corners 0 and 1 from atan2(|E x E'|, E . E'); the
		 * third is pi minus both (exact for a triangle). */
		const double l = sqrt(l2), inv = 1.0 / l, c0 = -vn_dot(e20, e01), c1 = -vn_dot(e01, e12);
		const int poly = method == VN_MWA_POLY;
		const double a0 = poly ? vn_atan2_poly(l, c0) : vn_atan2_nonneg(l, c0);
		const double a1 = poly ? vn_atan2_poly(l, c1) : vn_atan2_nonneg(l, c1);
		w[0] = a0 * inv, w[1] = a1 * inv, w[2] = (VN_PI - a0 - a1) * inv;
		break;
	}
	case vn_method_mwselr: { /* sin(alpha) / (|E||E'|) * N_f = n / (|E|^2 |E'|^2) */
		const double sa = vn_dot(e01, e01), sb = vn_dot(e12, e12), sc = vn_dot(e20, e20);
		const double inv = 1.0 / (sa * sb * sc);
		w[0] = sb * inv, w[1] = sc * inv, w[2] = sa * inv;
		break;
	}
	case vn_method_mwaat: /* |E x E'| N_f = n */
		w[0] = w[1] = w[2] = 1.0;
		break;
	case vn_method_mwelr: {
		const double a = sqrt(vn_dot(e01, e01)), b = sqrt(vn_dot(e12, e12)), c = sqrt(vn_dot(e20, e20));
		const double inv = 1.0 / (a * b * c * sqrt(l2));
		w[0] = b * inv, w[1] = c * inv, w[2] = a * inv;
		break;
	}
	default: { /* vn_method_mwrelr: 1 / sqrt(|E||E'|) with A = sqrt(a) etc. */
		const double a = sqrt(sqrt(vn_dot(e01, e01))), b = sqrt(sqrt(vn_dot(e12, e12))),
		             c = sqrt(sqrt(vn_dot(e20, e20)));
		const double inv = 1.0 / (a * b * c * sqrt(l2));
		w[0] = b * inv, w[1] = c * inv, w[2] = a * inv;
		break;
	}
	}
}

#ifdef VN_HAVE_AVX2
/* Minus the dot products e20 . e01 and e01 . e12 (e as below): the cosines
 * of the angles at corners 0 and 1 times their edges' lengths, MWA's atan2
 * arguments. */
VN_AVX2_INLINE void vn_mwa_cosines4(const __m256d e[3][3], __m256d c[2])
{
	const __m256d neg = _mm256_set1_pd(-0.0), *e01 = e[0], *e12 = e[1], *e20 = e[2];
	c[0] = _mm256_xor_pd(neg, vn_dot4(e20[0], e20[1], e20[2], e01[0], e01[1], e01[2]));
	c[1] = _mm256_xor_pd(neg, vn_dot4(e01[0], e01[1], e01[2], e12[0], e12[1], e12[2]));
}

/* vn_triangle_weights on four lanes, operation for operation (see simd.h):
 * e[0] = e01, e[1] = e12, e[2] = e20 (x, y, z lanes each). */
VN_AVX2_INLINE void vn_triangle_weights4(vn_method method, const __m256d e[3][3], __m256d l2, __m256d wt[3])
{
	const __m256d *e01 = e[0], *e12 = e[1], *e20 = e[2];
	const __m256d one = _mm256_set1_pd(1.0);
	switch (method) {
	case vn_method_mwe:
		wt[0] = wt[1] = wt[2] = _mm256_div_pd(one, _mm256_sqrt_pd(l2));
		break;
	case vn_method_mwa: {
		const __m256d l = _mm256_sqrt_pd(l2), inv = _mm256_div_pd(one, l);
		__m256d c[2];
		vn_mwa_cosines4(e, c);
		const __m256d a0 = vn_atan2_nonneg4(l, c[0]), a1 = vn_atan2_nonneg4(l, c[1]);
		wt[0] = _mm256_mul_pd(a0, inv);
		wt[1] = _mm256_mul_pd(a1, inv);
		wt[2] = _mm256_mul_pd(_mm256_sub_pd(_mm256_sub_pd(_mm256_set1_pd(VN_PI), a0), a1), inv);
		break;
	}
	case vn_method_mwselr: {
		const __m256d sa = vn_dot4(e01[0], e01[1], e01[2], e01[0], e01[1], e01[2]);
		const __m256d sb = vn_dot4(e12[0], e12[1], e12[2], e12[0], e12[1], e12[2]);
		const __m256d sc = vn_dot4(e20[0], e20[1], e20[2], e20[0], e20[1], e20[2]);
		const __m256d inv = _mm256_div_pd(one, _mm256_mul_pd(_mm256_mul_pd(sa, sb), sc));
		wt[0] = _mm256_mul_pd(sb, inv), wt[1] = _mm256_mul_pd(sc, inv), wt[2] = _mm256_mul_pd(sa, inv);
		break;
	}
	case vn_method_mwaat:
		wt[0] = wt[1] = wt[2] = one;
		break;
	default: { /* MWELR, MWRELR: a, b, c are edge lengths or their square roots */
		__m256d a = _mm256_sqrt_pd(vn_dot4(e01[0], e01[1], e01[2], e01[0], e01[1], e01[2]));
		__m256d b = _mm256_sqrt_pd(vn_dot4(e12[0], e12[1], e12[2], e12[0], e12[1], e12[2]));
		__m256d c = _mm256_sqrt_pd(vn_dot4(e20[0], e20[1], e20[2], e20[0], e20[1], e20[2]));
		if (method == vn_method_mwrelr)
			a = _mm256_sqrt_pd(a), b = _mm256_sqrt_pd(b), c = _mm256_sqrt_pd(c);
		const __m256d inv =
		    _mm256_div_pd(one, _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(a, b), c), _mm256_sqrt_pd(l2)));
		wt[0] = _mm256_mul_pd(b, inv), wt[1] = _mm256_mul_pd(c, inv), wt[2] = _mm256_mul_pd(a, inv);
		break;
	}
	}
}
#endif

#endif /* VN_WEIGHTS_H */
