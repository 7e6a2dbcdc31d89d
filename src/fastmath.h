/* atan2 for the corner angles of MWA, without libm's slow path.
 *
 * glibc's atan2 costs ~20 ns on this workload; MWA needs two per triangle.
 * This is Cephes' atan (S. L. Moshier, "Methods and Programs for Mathematical
 * Functions", 1989): argument reduction to [0, 0.66] or to (x-1)/(x+1), then a
 * rational approximation with peak relative error 2.6e-18, so the result is
 * within a few ulp of the correctly rounded angle (tests/test_core.c checks
 * it against libm over the whole range). */
#ifndef VN_FASTMATH_H
#define VN_FASTMATH_H

#include "internal.h"
#include "simd.h"

#define VN_PI 3.14159265358979323846
#define VN_PI_2 1.57079632679489661923
#define VN_PI_4 0.78539816339744830962
#define VN_ATAN_MOREBITS 6.123233995736765886130e-17 /* pi/2 - (double)(pi/2) */

#define VN_ATAN_P0 -8.750608600031904122785e-1
#define VN_ATAN_P1 -1.615753718733365076637e1
#define VN_ATAN_P2 -7.500855792314704667340e1
#define VN_ATAN_P3 -1.228866684490136173410e2
#define VN_ATAN_P4 -6.485021904942025371773e1
#define VN_ATAN_Q0 2.485846490142306297962e1
#define VN_ATAN_Q1 1.650270098316988542046e2
#define VN_ATAN_Q2 4.328810604912902668951e2
#define VN_ATAN_Q3 4.853903996359136964868e2
#define VN_ATAN_Q4 1.945506571482613964425e2

/* atan(num / den) for 0 <= num <= den, den > 0. Above 0.66 the reduction is
 * atan(t) = pi/4 + atan((t - 1) / (t + 1)), formed as (num - den) / (num + den)
 * so that each branch costs one division. */
VN_INLINE double vn_atan_ratio(double num, double den)
{
	const int big = num > 0.66 * den;
	const double x = big ? (num - den) / (num + den) : num / den;
	const double z = x * x;
	const double p = (((VN_ATAN_P0 * z + VN_ATAN_P1) * z + VN_ATAN_P2) * z + VN_ATAN_P3) * z + VN_ATAN_P4;
	const double q = ((((z + VN_ATAN_Q0) * z + VN_ATAN_Q1) * z + VN_ATAN_Q2) * z + VN_ATAN_Q3) * z + VN_ATAN_Q4;
	const double r = x + x * (z * p / q);
	return big ? (VN_PI_4 + 0.5 * VN_ATAN_MOREBITS) + r : r;
}

/* atan2(y, x) for y >= 0 (the length of a cross product): an angle in [0, pi].
 * Returns 0 when both are 0. */
VN_INLINE double vn_atan2_nonneg(double y, double x)
{
	const double ax = fabs(x);
	const int steep = y > ax;
	const double num = steep ? ax : y, den = steep ? y : ax;
	double a = den > 0.0 ? vn_atan_ratio(num, den) : 0.0;
	if (steep)
		a = (VN_PI_2 - a) + VN_ATAN_MOREBITS;
	return x < 0.0 ? (VN_PI - a) + 2.0 * VN_ATAN_MOREBITS : a;
}

/* The float32 corner angle of the per-frame plans (plan.c): Cephes' atanf
 * (reduction to |t| <= tan(pi/8) by (t - 1) / (t + 1), a degree-9 odd
 * polynomial evaluated with fused multiply-adds), within 3e-7 rad (about
 * two float ulps at pi) of atan2 over [0, pi] (tests/test_plan.c checks the
 * bound); float arithmetic throughout. fmaf and the AVX2 kernel's fused
 * operations round once each, so both give the same bits. */
#define VN_ATANF_P0 8.05374449538e-2f
#define VN_ATANF_P1 -1.38776856032e-1f
#define VN_ATANF_P2 1.99777106478e-1f
#define VN_ATANF_P3 -3.33329491539e-1f

/* atan2(y, x) for y >= 0 in float arithmetic; 0 when both are 0. */
VN_INLINE float vn_atan2f_nonneg(float y, float x)
{
	const float ax = fabsf(x);
	const int steep = y > ax;
	const float num = steep ? ax : y, den = steep ? y : ax;
	const int big = num > 0.41421356f * den;
	const float t = big ? (num - den) / (num + den) : num / den;
	const float z = t * t;
	const float p = fmaf(fmaf(fmaf(VN_ATANF_P0, z, VN_ATANF_P1), z, VN_ATANF_P2), z, VN_ATANF_P3);
	float a = fmaf(p * z, t, t);
	a = big ? (float)VN_PI_4 + a : a;
	a = den > 0.0f ? a : 0.0f;
	a = steep ? (float)VN_PI_2 - a : a;
	return x < 0.0f ? (float)VN_PI - a : a;
}

#ifdef VN_HAVE_AVX2
/* vn_atan2f_nonneg on eight lanes, with the same operations. */
VN_AVX2_FMA_INLINE __m256 vn_atan2f_nonneg8(__m256 y, __m256 x)
{
#define C(v) _mm256_set1_ps(v)
	const __m256 zero = _mm256_setzero_ps();
	const __m256 ax = _mm256_andnot_ps(C(-0.0f), x);
	const __m256 steep = _mm256_cmp_ps(y, ax, _CMP_GT_OQ);
	const __m256 num = _mm256_blendv_ps(y, ax, steep), den = _mm256_blendv_ps(ax, y, steep);
	const __m256 big = _mm256_cmp_ps(num, _mm256_mul_ps(C(0.41421356f), den), _CMP_GT_OQ);
	const __m256 t = _mm256_div_ps(_mm256_blendv_ps(num, _mm256_sub_ps(num, den), big),
	                               _mm256_blendv_ps(den, _mm256_add_ps(num, den), big));
	const __m256 z = _mm256_mul_ps(t, t);
	__m256 p = _mm256_fmadd_ps(C(VN_ATANF_P0), z, C(VN_ATANF_P1));
	p = _mm256_fmadd_ps(p, z, C(VN_ATANF_P2));
	p = _mm256_fmadd_ps(p, z, C(VN_ATANF_P3));
	__m256 a = _mm256_fmadd_ps(_mm256_mul_ps(p, z), t, t);
	a = _mm256_blendv_ps(a, _mm256_add_ps(C((float)VN_PI_4), a), big);
	a = _mm256_blendv_ps(zero, a, _mm256_cmp_ps(den, zero, _CMP_GT_OQ));
	a = _mm256_blendv_ps(a, _mm256_sub_ps(C((float)VN_PI_2), a), steep);
	return _mm256_blendv_ps(a, _mm256_sub_ps(C((float)VN_PI), a), _mm256_cmp_ps(x, zero, _CMP_LT_OQ));
#undef C
}
#endif

#ifdef VN_HAVE_AVX2
/* vn_atan2_nonneg on four lanes: both sides of every branch, then a blend, so
 * each lane gets exactly the scalar result. */
VN_AVX2_INLINE __m256d vn_atan2_nonneg4(__m256d y, __m256d x)
{
#define C(v) _mm256_set1_pd(v)
	const __m256d zero = _mm256_setzero_pd();
	const __m256d ax = _mm256_andnot_pd(C(-0.0), x);
	const __m256d steep = _mm256_cmp_pd(y, ax, _CMP_GT_OQ);
	const __m256d num = _mm256_blendv_pd(y, ax, steep), den = _mm256_blendv_pd(ax, y, steep);
	/* vn_atan_ratio */
	const __m256d big = _mm256_cmp_pd(num, _mm256_mul_pd(C(0.66), den), _CMP_GT_OQ);
	const __m256d xr = _mm256_div_pd(_mm256_blendv_pd(num, _mm256_sub_pd(num, den), big),
	                                 _mm256_blendv_pd(den, _mm256_add_pd(num, den), big));
	const __m256d z = _mm256_mul_pd(xr, xr);
	__m256d p = _mm256_add_pd(_mm256_mul_pd(C(VN_ATAN_P0), z), C(VN_ATAN_P1));
	p = _mm256_add_pd(_mm256_mul_pd(p, z), C(VN_ATAN_P2));
	p = _mm256_add_pd(_mm256_mul_pd(p, z), C(VN_ATAN_P3));
	p = _mm256_add_pd(_mm256_mul_pd(p, z), C(VN_ATAN_P4));
	__m256d q = _mm256_add_pd(z, C(VN_ATAN_Q0));
	q = _mm256_add_pd(_mm256_mul_pd(q, z), C(VN_ATAN_Q1));
	q = _mm256_add_pd(_mm256_mul_pd(q, z), C(VN_ATAN_Q2));
	q = _mm256_add_pd(_mm256_mul_pd(q, z), C(VN_ATAN_Q3));
	q = _mm256_add_pd(_mm256_mul_pd(q, z), C(VN_ATAN_Q4));
	const __m256d r = _mm256_add_pd(xr, _mm256_mul_pd(xr, _mm256_div_pd(_mm256_mul_pd(z, p), q)));
	__m256d a = _mm256_blendv_pd(r, _mm256_add_pd(C(VN_PI_4 + 0.5 * VN_ATAN_MOREBITS), r), big);
	/* vn_atan2_nonneg */
	a = _mm256_blendv_pd(zero, a, _mm256_cmp_pd(den, zero, _CMP_GT_OQ));
	a = _mm256_blendv_pd(a, _mm256_add_pd(_mm256_sub_pd(C(VN_PI_2), a), C(VN_ATAN_MOREBITS)), steep);
	return _mm256_blendv_pd(a, _mm256_add_pd(_mm256_sub_pd(C(VN_PI), a), C(2.0 * VN_ATAN_MOREBITS)),
	                        _mm256_cmp_pd(x, zero, _CMP_LT_OQ));
#undef C
}
#endif

/* The float64 corner angle of the per-frame plans (vn.h): atan2 without
 * Cephes' second division, and a short dependency chain. The octant
 * reduction as above, then |t| <= tan(pi/8) by (t - 1) / (t + 1), and
 * atan(t) = t + t z p(z), z = t^2, p of degree 7: a minimax (Remez) fit of
 * absolute error 6.1e-15 on that interval, evaluated by Estrin's scheme
 * with fused multiply-adds (fma, which rounds as the vector FMA does, so
 * both give the same bits). The angle is then base + s atan(t), s = -1
 * where the octant mirrors it (a flip of the polynomial's sign bit), and
 * base (a multiple of pi/4) is chosen from the reductions while the
 * division runs, so one addition follows the polynomial. The
 * result is within 1e-13 rad of atan2 (tests/test_plan.c checks it over
 * [0, pi]). */
#define VN_ATANP_C0 -0.3333333332965795131164534
#define VN_ATANP_C1 0.1999999944346672742050995
#define VN_ATANP_C2 -0.1428568311354966790073515
#define VN_ATANP_C3 0.1111022572339359009451772
#define VN_ATANP_C4 -0.09076504436765646589631387
#define VN_ATANP_C5 0.07551251271327769319219266
#define VN_ATANP_C6 -0.05831502115785053549039518
#define VN_ATANP_C7 0.03005620863890554956547128
#define VN_TAN_PI_8 0.41421356237309504880
/* The most chains vn_atan2_poly4 takes. */
#define VN_ATAN2_CHAINS 8

/* atan2(y, x) for y >= 0; 0 when both are 0. */
VN_INLINE double vn_atan2_poly(double y, double x)
{
	const double ax = fabs(x);
	const int steep = y > ax, neg = x < 0.0;
	const double num = y < ax ? y : ax, den = y > ax ? y : ax; /* minpd, maxpd */
	const int big = num > VN_TAN_PI_8 * den;
	const double t = (num - (big ? den : 0.0)) / (den + (big ? num : 0.0));
	const double base = (steep ? VN_PI_2 : neg ? VN_PI : 0.0) + (big ? (steep != neg ? -VN_PI_4 : VN_PI_4) : 0.0);
	const double z = t * t, z2 = z * z, z4 = z2 * z2;
	const double q0 = fma(VN_ATANP_C1, z, VN_ATANP_C0), q1 = fma(VN_ATANP_C3, z, VN_ATANP_C2);
	const double q2 = fma(VN_ATANP_C5, z, VN_ATANP_C4), q3 = fma(VN_ATANP_C7, z, VN_ATANP_C6);
	const double r = fma(t * z, fma(fma(q3, z2, q2), z4, fma(q1, z2, q0)), t);
	return den > 0.0 ? base + (steep != neg ? -r : r) : 0.0;
}

#ifdef VN_HAVE_AVX2
/* vn_atan2_poly on four lanes, with the same operations, for y > 0 (the
 * triangle kernels' lengths, so den > 0): a[i] = atan2(y[i], x[i]) for
 * i < n <= VN_ATAN2_CHAINS, the chains' operations interleaved so that
 * they overlap in the reorder window. Masks select by and, not blends. */
VN_AVX2_FMA_INLINE void vn_atan2_poly4(int n, const __m256d* y, const __m256d* x, __m256d* a)
{
#define C(v) _mm256_set1_pd(v)
#define EACH for (int i = 0; i < n; ++i)
	const __m256d sign = C(-0.0);
	__m256d t[VN_ATAN2_CHAINS], base[VN_ATAN2_CHAINS], flip[VN_ATAN2_CHAINS], z[VN_ATAN2_CHAINS];
	__m256d z2[VN_ATAN2_CHAINS], lo[VN_ATAN2_CHAINS], hi[VN_ATAN2_CHAINS];
	EACH {
		const __m256d ax = _mm256_andnot_pd(sign, x[i]);
		const __m256d num = _mm256_min_pd(y[i], ax), den = _mm256_max_pd(y[i], ax);
		const __m256d steep = _mm256_cmp_pd(y[i], ax, _CMP_GT_OQ);
		const __m256d neg = _mm256_cmp_pd(x[i], _mm256_setzero_pd(), _CMP_LT_OQ);
		const __m256d big = _mm256_cmp_pd(num, _mm256_mul_pd(C(VN_TAN_PI_8), den), _CMP_GT_OQ);
		t[i] = _mm256_div_pd(_mm256_sub_pd(num, _mm256_and_pd(big, den)), _mm256_add_pd(den, _mm256_and_pd(big, num)));
		flip[i] = _mm256_and_pd(_mm256_xor_pd(steep, neg), sign);
		const __m256d half = _mm256_or_pd(_mm256_and_pd(steep, C(VN_PI_2)),
		                                  _mm256_andnot_pd(steep, _mm256_and_pd(neg, C(VN_PI))));
		base[i] = _mm256_add_pd(half, _mm256_and_pd(big, _mm256_xor_pd(C(VN_PI_4), flip[i])));
	}
	EACH z[i] = _mm256_mul_pd(t[i], t[i]);
	EACH z2[i] = _mm256_mul_pd(z[i], z[i]);
	EACH lo[i] = _mm256_fmadd_pd(_mm256_fmadd_pd(C(VN_ATANP_C3), z[i], C(VN_ATANP_C2)), z2[i],
	                             _mm256_fmadd_pd(C(VN_ATANP_C1), z[i], C(VN_ATANP_C0)));
	EACH hi[i] = _mm256_fmadd_pd(_mm256_fmadd_pd(C(VN_ATANP_C7), z[i], C(VN_ATANP_C6)), z2[i],
	                             _mm256_fmadd_pd(C(VN_ATANP_C5), z[i], C(VN_ATANP_C4)));
	EACH lo[i] = _mm256_fmadd_pd(hi[i], _mm256_mul_pd(z2[i], z2[i]), lo[i]);
	EACH a[i] = _mm256_fmadd_pd(_mm256_mul_pd(t[i], z[i]), lo[i], t[i]);
	EACH a[i] = _mm256_add_pd(base[i], _mm256_xor_pd(a[i], flip[i]));
#undef EACH
#undef C
}
#endif

#endif /* VN_FASTMATH_H */
