/* The edge-based cotangent family: MEWCSA (Desbrun, Meyer, Schroder, Barr
 * 1999; the paper's eq. 9).
 *
 *   -2 H A N  =  sum_j (cot a_ij + cot b_ij)(x_i - x_j)
 *
 * Summed per face instead of per edge, the same vector is the area gradient
 * 2 grad_v A = sum_f (p_next - p_prev) x N_f: on a triangle (v, a, b),
 * (a - b) x N = |e|^2-weighted cotangents of the two angles opposite the
 * edges at v. The per-face form needs no edge adjacency and extends to
 * polygons as the gradient of Newell's vector area.
 *
 * As in the paper the sign is not corrected: the vector points along the
 * outward normal where the mean curvature is positive and inward where it is
 * negative, which is the failure mode the paper reports.
 *
 * SMEWCSA corrects it (vn.h): a pass of the MWSELR kernels gives the seed
 * normals, then the MEWCSA kernels sum each vertex's contributions and, in
 * the fourth accumulator, their lengths, and vn_run's finalize applies the
 * rule (vn_smewcsa_finalize) instead of normalizing. */
#include "internal.h"
#include "simd.h"

/* Adds d x n to acc[0..2] and, with lengths (SMEWCSA), |d x n| to acc[3]. */
VN_INLINE void add_edge_cross(double* acc, const double d[3], const double n[3], int lengths)
{
	double c[3];
	vn_cross(d, n, c);
	acc[0] += c[0], acc[1] += c[1], acc[2] += c[2];
	if (lengths)
		acc[3] += sqrt(vn_dot(c, c));
}

/* The unit normal (n, normalized in place) and each corner's p_next - p_prev:
 * p1 - p2 = -e12 at corner 0, and so on. */
VN_INLINE void unit_and_chords(const double e01[3], const double e12[3], const double e20[3], double l2, double n[3],
                               double d[3][3])
{
	const double inv = 1.0 / sqrt(l2);
	n[0] *= inv, n[1] *= inv, n[2] *= inv;
	for (int i = 0; i < 3; ++i)
		d[0][i] = -e12[i], d[1][i] = -e20[i], d[2][i] = -e01[i];
}

VN_INLINE void triangles(const vn_work* w, vn_scalar type, int lengths, vn_range range, vn_range_stats* st)
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

		double p0[3], p1[3], p2[3], e01[3], e12[3], e20[3], n[3], d[3][3];
		vn_load(w, type, i0, p0);
		vn_load(w, type, i1, p1);
		vn_load(w, type, i2, p2);
		const double l2 = vn_triangle_edges(p0, p1, p2, e01, e12, e20, n);
		if (!vn_usable(l2)) {
			degenerate += o0;
			continue;
		}
		unit_and_chords(e01, e12, e20, l2, n, d);
		if (o0)
			add_edge_cross(acc + 4 * (size_t)i0, d[0], n, lengths);
		if (o1)
			add_edge_cross(acc + 4 * (size_t)i1, d[1], n, lengths);
		if (o2)
			add_edge_cross(acc + 4 * (size_t)i2, d[2], n, lengths);
	}
	st->degenerate_faces += degenerate;
}

int vn_cotangent_triangle(vn_method method, const double p0[3], const double p1[3], const double p2[3], double c[3][3])
{
	(void)method;
	double e01[3], e12[3], e20[3], n[3], d[3][3];
	const double l2 = vn_triangle_edges(p0, p1, p2, e01, e12, e20, n);
	if (!vn_usable(l2))
		return 0;
	unit_and_chords(e01, e12, e20, l2, n, d);
	for (int k = 0; k < 3; ++k)
		vn_cross(d[k], n, c[k]);
	return 1;
}

/* One copy per position type, without and with lengths (SMEWCSA). */
static void triangles_f(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	VN_DISPATCH_RANGE(w, lo, hi, triangles(w, vn_scalar_float32, 0, range, st));
}

static void triangles_d(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	VN_DISPATCH_RANGE(w, lo, hi, triangles(w, vn_scalar_float64, 0, range, st));
}

static void triangles_fl(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	VN_DISPATCH_RANGE(w, lo, hi, triangles(w, vn_scalar_float32, 1, range, st));
}

static void triangles_dl(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	VN_DISPATCH_RANGE(w, lo, hi, triangles(w, vn_scalar_float64, 1, range, st));
}

#ifdef VN_HAVE_AVX2
/* triangles()' corner vectors on four lanes, operation for operation (see
 * simd.h): the unit normal, then (p_next - p_prev) x N_f at each corner. */
VN_AVX2_INLINE void cotangent_group(vn_method method, const __m256d e[3][3], const __m256d n[3], __m256d l2,
                                    __m256d cx[3], __m256d cy[3], __m256d cz[3])
{
	(void)method;
	const __m256d neg = _mm256_set1_pd(-0.0);
	const __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), _mm256_sqrt_pd(l2));
	const __m256d ux = _mm256_mul_pd(n[0], inv), uy = _mm256_mul_pd(n[1], inv), uz = _mm256_mul_pd(n[2], inv);
	/* p_next - p_prev at corner 0 is -e12, at 1 -e20, at 2 -e01. */
	for (int k = 0; k < 3; ++k) {
		const __m256d* d = e[k == 0 ? 1 : k == 1 ? 2 : 0];
		vn_cross4(_mm256_xor_pd(neg, d[0]), _mm256_xor_pd(neg, d[1]), _mm256_xor_pd(neg, d[2]), ux, uy, uz, &cx[k],
		          &cy[k], &cz[k]);
	}
}

#define VN_TRIANGLES_AVX2(name, type, lengths, scalar)                                                         \
	static VN_AVX2 void name(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)                     \
	{                                                                                                            \
		VN_DISPATCH_RANGE(w, lo, hi,                                                                             \
		                  vn_triangles_avx2(w, type, vn_method_mewcsa, lengths, range, st, cotangent_group, NULL, scalar)); \
	}
VN_TRIANGLES_AVX2(triangles_f_avx2, vn_scalar_float32, 0, triangles_f)
VN_TRIANGLES_AVX2(triangles_d_avx2, vn_scalar_float64, 0, triangles_d)
VN_TRIANGLES_AVX2(triangles_fl_avx2, vn_scalar_float32, 1, triangles_fl)
VN_TRIANGLES_AVX2(triangles_dl_avx2, vn_scalar_float64, 1, triangles_dl)
#endif

/* SMEWCSA's pass (w->seed set) also sums the contributions' lengths. */
void vn_accumulate_cotangent_triangles(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	const int f64 = w->type == vn_scalar_float64, lengths = w->seed != NULL;
#ifdef VN_HAVE_AVX2
	if (w->simd) {
		(lengths ? (f64 ? triangles_dl_avx2 : triangles_fl_avx2) : (f64 ? triangles_d_avx2 : triangles_f_avx2))(w, lo, hi,
		                                                                                                        st);
		return;
	}
#endif
	(lengths ? (f64 ? triangles_dl : triangles_fl) : (f64 ? triangles_d : triangles_f))(w, lo, hi, st);
}

/* (p_next - p_prev) x N_f = (E' - E) x N_f for a polygon corner; with
 * lengths, its length too (SMEWCSA, never in corner.c's per-corner mode,
 * whose accumulators have 3 doubles). */
VN_INLINE void polygon_corner(double* acc, const double n[3], const double e[3], const double e2[3], int lengths)
{
	double d[3];
	vn_sub(e2, e, d);
	add_edge_cross(acc, d, n, lengths);
}

static void cotangent_corner(vn_method method, double* acc, const double n[3], const double e[3], const double e2[3])
{
	(void)method;
	polygon_corner(acc, n, e, e2, 0);
}

static void cotangent_corner_lengths(vn_method method, double* acc, const double n[3], const double e[3],
                                     const double e2[3])
{
	(void)method;
	polygon_corner(acc, n, e, e2, 1);
}

void vn_accumulate_cotangent_polygons(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	if (w->seed)
		VN_DISPATCH_RANGE(w, lo, hi, vn_polygons(w, range, st, cotangent_corner_lengths));
	else
		VN_DISPATCH_RANGE(w, lo, hi, vn_polygons(w, range, st, cotangent_corner));
}

/* ---------------------------------------------------------------- SMEWCSA */

/* cos 30 degrees: beyond it from the seed, the MEWCSA vector is mostly its
 * tangential part (discretization error). */
#define SMEWCSA_COS_MIN 0.86602540378443865
/* At or below this fraction of the sum of its contributions' lengths, the
 * MEWCSA sum is about zero (vn.h): rounding float32 positions moves a flat
 * mesh's points off their plane by up to 2^-24 |p|, which leaves a sum of
 * about 2^-24 |p| / h of the lengths (measured: at most 2.5x that), below
 * this while |p| stays under about 1000 edge lengths h; double positions'
 * rounding stays below it anywhere. */
#define SMEWCSA_FLAT 0x1p-12

int vn_smewcsa_finish(const double acc[4], const double s[3], double n[3])
{
	double h[3] = {acc[0], acc[1], acc[2]};
	const int zero_h = vn_normalize(h);
	const double d = vn_dot(h, s);
	/* h . acc is |acc| without squaring acc (no overflow); a zero s fails
	 * the angle test and gives zero. */
	if (!zero_h && vn_dot(h, acc) > SMEWCSA_FLAT * acc[3] && fabs(d) >= SMEWCSA_COS_MIN) {
		const double sign = d < 0.0 ? -1.0 : 1.0;
		n[0] = sign * h[0], n[1] = sign * h[1], n[2] = sign * h[2];
		return 0;
	}
	memcpy(n, s, 3 * sizeof(double));
	return vn_is_zero(s);
}

void vn_smewcsa_finalize(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st)
{
	size_t zero = 0;
	for (uint32_t v = lo; v < hi; ++v) {
		double n[3];
		const int z = vn_smewcsa_finish(w->acc + 4 * (size_t)v, w->seed + 3 * (size_t)v, n);
		zero += (size_t)z;
		if (!(z && w->keep_existing))
			vn_store(w->out, v, n);
	}
	st->zero_normals += zero;
}

vn_result vn_smewcsa_run(const vn_work* work, vn_accumulate_fn mewcsa, vn_accumulate_fn seed, const vn_options* o,
                         vn_range_stats* st)
{
	const vn_allocator heap = vn_heap(&o->allocator);
	const uint32_t nv = work->vertex_count;
	double* s = (double*)heap.allocate(heap.user, 3 * sizeof(double) * (size_t)nv);
	if (!s)
		return vn_result_out_of_memory;
	const vn_vectors sv = {s, 3 * sizeof(double), vn_scalar_float64};
	vn_work w = *work;
	w.keep_existing = 0;
	w.want_stats = 0;
	w.out = &sv;
	w.method = vn_method_mwselr;
	vn_range_stats ignored = {0, 0, 0, 0};
	vn_result r = vn_run(&w, seed, o, &ignored);
	if (r == vn_result_success) {
		w = *work;
		w.method = vn_method_mewcsa;
		w.seed = s;
		r = vn_run(&w, mewcsa, o, st);
	}
	heap.deallocate(heap.user, s);
	return r;
}
