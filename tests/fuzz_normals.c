/*
 * libFuzzer entry point for the computation itself (the other fuzz_*
 * targets feed the parsers): bytes become a small triangle or polygon mesh,
 * its coordinates either raw floats (NaN, infinities, denormals, 1e300) or
 * small multiples of 1/8 (coincident, collinear and coplanar points, the
 * degenerate rings the fits must refuse), and its indices may reach one
 * past the last vertex. Every scheme runs through vn_triangle_normals or
 * vn_polygon_normals, the corner-normal function and a plan, with the
 * vector kernels and without. Checked: the documented result (index out
 * of range exactly when an index is), every output finite and either zero
 * or unit, bit-identical results with and without SIMD, and a plan's
 * results equal to the calls it replaces, to the bit (its fast paths, the
 * six sums on triangles, round otherwise (vn.h), and where contributions
 * cancel, e.g. a face and its reverse, that rounding is the direction:
 * there only checked as outputs).
 *
 * Input: byte 0 the method; byte 1 flags (bit 0 float32 positions, 1
 * polygons, 2 raw coordinates, 3 indices may reach vertex_count, 4-5 the
 * crease angle: none, 30, 90 or 0 degrees); byte 2 the vertex count - 1
 * (mod 64); then the coordinates (raw: 4 or 8 bytes each; else one signed
 * byte / 8 each); then each face (polygons: a byte for its corner count,
 * 1 to 10) and its indices (a byte each, mod the vertex count, + 1 with
 * bit 3).
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "vn.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

enum { MAX_VERTICES = 64, MAX_CORNERS = 1024 };

/* Every vector of out (count of them, float64) finite, and zero or unit
 * to `slack` in its squared length. */
static void check_vectors(const double* out, size_t count, double slack)
{
	for (size_t i = 0; i < count; ++i) {
		const double* n = out + 3 * i;
		if (!isfinite(n[0]) || !isfinite(n[1]) || !isfinite(n[2]))
			abort();
		const double len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
		if (len2 != 0.0 && fabs(len2 - 1.0) > slack)
			abort();
	}
}

/* The result r of a call on indices that are all in range (or not). */
static void check_result(vn_result r, int in_range)
{
	if (r != (in_range ? vn_result_success : vn_result_index_out_of_range))
		abort();
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	if (size < 3)
		return 0;
	const vn_method method = (vn_method)(data[0] % (unsigned)vn_method_count);
	const unsigned flags = data[1];
	const int f32 = flags & 1, polygons = (flags >> 1) & 1, raw = (flags >> 2) & 1, past = (flags >> 3) & 1;
	static const double creases[4] = {4.0, 0.5235987755982988, 1.5707963267948966, 0.0}; /* radians */
	const double crease = creases[(flags >> 4) & 3];
	const size_t nv = 1 + data[2] % MAX_VERTICES;
	size_t at = 3;

	double pos64[3 * MAX_VERTICES];
	float pos32[3 * MAX_VERTICES];
	const size_t scalar = f32 ? sizeof(float) : sizeof(double);
	for (size_t i = 0; i < 3 * nv; ++i) {
		double x = 0.0;
		if (raw && at + scalar <= size) {
			if (f32) {
				float v;
				memcpy(&v, data + at, sizeof v);
				x = v;
			} else {
				memcpy(&x, data + at, sizeof x);
			}
			at += scalar;
		} else if (!raw && at < size) {
			x = (int8_t)data[at++] / 8.0;
		}
		pos64[i] = x, pos32[i] = (float)x;
	}

	uint32_t idx[MAX_CORNERS], offsets[MAX_CORNERS + 1];
	size_t ni = 0, nf = 0;
	int in_range = 1;
	offsets[0] = 0;
	while (at < size && ni < MAX_CORNERS - 10) {
		const size_t k = polygons ? 1 + data[at++] % 10 : 3;
		if (at + k > size)
			break;
		for (size_t c = 0; c < k; ++c) {
			idx[ni] = (uint32_t)(data[at++] % (nv + (size_t)past));
			in_range &= idx[ni] < nv;
			++ni;
		}
		offsets[++nf] = (uint32_t)ni;
	}

	const vn_positions p = {f32 ? (const void*)pos32 : (const void*)pos64, nv, 0,
	                        f32 ? vn_scalar_float32 : vn_scalar_float64};
	double a[3 * MAX_CORNERS], b[3 * MAX_CORNERS];
	const vn_vectors va = {a, 0, vn_scalar_float64}, vb = {b, 0, vn_scalar_float64};
	vn_options o;
	memset(&o, 0, sizeof o);

	/* Vertex normals, with the vector kernels and without. */
	for (int simd = 0; simd < 2; ++simd) {
		o.simd = simd ? vn_simd_off : vn_simd_auto;
		const vn_vectors* v = simd ? &vb : &va;
		const vn_result r = polygons ? vn_polygon_normals(v, &p, idx, offsets, nf, method, &o, NULL)
		                             : vn_triangle_normals(v, &p, idx, ni, method, &o, NULL);
		check_result(r, in_range);
	}
	if (in_range) {
		check_vectors(a, nv, 1e-12);
		if (memcmp(a, b, 3 * sizeof(double) * nv) != 0)
			abort();
	}
	o.simd = vn_simd_auto;

	/* Corner normals. */
	const vn_result rc = polygons ? vn_polygon_corner_normals(&va, &p, idx, offsets, nf, method, crease, NULL, &o, NULL)
	                              : vn_corner_normals(&va, &p, idx, ni, method, crease, NULL, &o, NULL);
	check_result(rc, in_range);
	if (in_range)
		check_vectors(a, ni, 1e-12);

	/* A plan gives what the calls give. */
	vn_plan* plan = NULL;
	const vn_result rp = vn_plan_create(idx, polygons ? offsets : NULL, polygons ? nf : ni / 3, nv, &o, &plan);
	check_result(rp, in_range);
	if (rp == vn_result_success) {
		if (vn_plan_normals(plan, &p, method, &vb, NULL) != vn_result_success)
			abort();
		const vn_result r = polygons ? vn_polygon_normals(&va, &p, idx, offsets, nf, method, &o, NULL)
		                             : vn_triangle_normals(&va, &p, idx, ni, method, &o, NULL);
		if (r != vn_result_success)
			abort();
		const int fast = !polygons && method <= vn_method_mwrelr && (f32 || method == vn_method_mwa);
		check_vectors(b, nv, fast && f32 ? 1e-6 : 1e-12); /* float arithmetic */
		if (!fast && memcmp(a, b, 3 * sizeof(double) * nv) != 0)
			abort();
		if (vn_plan_corner_normals(plan, &p, method, crease, NULL, &vb, NULL) != vn_result_success)
			abort();
		const vn_result s = polygons
		                        ? vn_polygon_corner_normals(&va, &p, idx, offsets, nf, method, crease, NULL, &o, NULL)
		                        : vn_corner_normals(&va, &p, idx, ni, method, crease, NULL, &o, NULL);
		if (s != vn_result_success || memcmp(a, b, 3 * sizeof(double) * ni) != 0)
			abort();
	}
	vn_plan_destroy(plan);
	return 0;
}
