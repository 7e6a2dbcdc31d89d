/* Internal interfaces between the library's source files; not installed. */
#ifndef VN_INTERNAL_H
#define VN_INTERNAL_H

#include <float.h>
#include <math.h>
#include <string.h>

#include "vn.h"

#if defined(__GNUC__) || defined(__clang__)
#  define VN_INLINE static inline __attribute__((always_inline))
#else
#  define VN_INLINE static inline
#endif

/* One normal computation, shared read-only by every worker. */
typedef struct vn_work {
	const unsigned char* positions;
	size_t stride; /* bytes, already resolved from 0 */
	vn_scalar type;
	uint32_t vertex_count;
	const uint32_t* indices;
	const uint32_t* offsets; /* NULL for triangle meshes */
	size_t face_count;
	vn_method method;
	double* acc; /* 4 doubles per vertex (x, y, z, padding), 32-byte aligned */
	const vn_vectors* out;
	int want_stats;
	int simd; /* the AVX2 kernels may run */
} vn_work;

/* Counts one worker gathers for its vertex range. */
typedef struct vn_range_stats {
	size_t degenerate_faces; /* counted by the worker owning the face's first corner */
	size_t zero_normals;
	size_t nonfinite_vertices;
	int bad_index; /* an index >= vertex_count was met (triangle kernels check as they scan) */
} vn_range_stats;

/* Each accumulator adds, for every face with a corner in [lo, hi), that
 * corner's contribution to acc. Faces are visited in index order, so a
 * vertex's sum does not depend on how vertices are split between workers.
 * Triangle accumulators also check every index of every face, owned or not,
 * before reading through it, and stop with st->bad_index set. */
typedef void (*vn_accumulate_fn)(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st);

/* weights.c: the face-normal weighted family (MWE, MWA, MWSELR, MWAAT, MWELR, MWRELR). */
void vn_accumulate_weighted_triangles(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st);
void vn_accumulate_weighted_polygons(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st);
/* cotangent.c: the edge-based cotangent family (MEWCSA). */
void vn_accumulate_cotangent_triangles(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st);
void vn_accumulate_cotangent_polygons(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st);

/* api.c: `a` when it has both functions, else malloc/free (for an all-NULL
 * allocator; callers reject half-set ones first). */
vn_allocator vn_heap(const vn_allocator* a);

/* parallel.c: zeroes, accumulates and normalizes on o->threads workers, in
 * o->workspace when it is large enough, else in memory from o->allocator. */
vn_result vn_run(const vn_work* w, vn_accumulate_fn accumulate, const vn_options* o, vn_range_stats* st);
/* The work memory vn_run needs for nv vertices. */
size_t vn_work_bytes(uint32_t nv, unsigned threads);

/* ---------------------------------------------------------------- geometry helpers */

/* Position i as doubles; the float -> double conversion is exact, so edge
 * vectors computed from it are exact differences of the input. */
VN_INLINE void vn_load(const vn_work* w, vn_scalar type, uint32_t i, double p[3])
{
	const unsigned char* src = w->positions + (size_t)i * w->stride;
	/* One memcpy per scalar: a single 12-byte copy goes through the stack as
	 * integer moves and stalls store-to-load forwarding (4x slower). */
	if (type == vn_scalar_float32) {
		float x, y, z;
		memcpy(&x, src, 4), memcpy(&y, src + 4, 4), memcpy(&z, src + 8, 4);
		p[0] = x, p[1] = y, p[2] = z;
	} else {
		memcpy(&p[0], src, 8), memcpy(&p[1], src + 8, 8), memcpy(&p[2], src + 16, 8);
	}
}

VN_INLINE void vn_sub(const double a[3], const double b[3], double r[3])
{
	r[0] = a[0] - b[0], r[1] = a[1] - b[1], r[2] = a[2] - b[2];
}

VN_INLINE void vn_cross(const double a[3], const double b[3], double r[3])
{
	r[0] = a[1] * b[2] - a[2] * b[1];
	r[1] = a[2] * b[0] - a[0] * b[2];
	r[2] = a[0] * b[1] - a[1] * b[0];
}

VN_INLINE double vn_dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

VN_INLINE void vn_add_scaled(double* acc, const double v[3], double s)
{
	acc[0] += v[0] * s, acc[1] += v[1] * s, acc[2] += v[2] * s;
}

/* A face normal is usable when its squared length is a finite normal number:
 * this rejects zero area, NaN and Inf coordinates, and keeps every weight
 * below derived from it finite. */
VN_INLINE int vn_usable(double len2)
{
	return len2 >= DBL_MIN && len2 <= DBL_MAX;
}

/* Newell's unit normal of the polygon face[0..k), k >= 3, or 0 when it is not
 * usable. Newell's sum of p_i x p_{i+1} is translation invariant; taken about
 * face[0] it becomes the fan sum of (p_i - p_0) x (p_{i+1} - p_0), whose
 * differences are exact for float input. */
VN_INLINE int vn_face_normal(const vn_work* w, const uint32_t* face, uint32_t k, double n[3])
{
	double p0[3], a[3], b[3], q[3], c[3];
	vn_load(w, w->type, face[0], p0);
	vn_load(w, w->type, face[1], q);
	vn_sub(q, p0, a);
	n[0] = n[1] = n[2] = 0.0;
	for (uint32_t i = 2; i < k; ++i) {
		vn_load(w, w->type, face[i], q);
		vn_sub(q, p0, b);
		vn_cross(a, b, c);
		n[0] += c[0], n[1] += c[1], n[2] += c[2];
		memcpy(a, b, sizeof(b));
	}
	const double l2 = vn_dot(n, n);
	if (!vn_usable(l2))
		return 0;
	const double inv = 1.0 / sqrt(l2);
	n[0] *= inv, n[1] *= inv, n[2] *= inv;
	return 1;
}

/* A polygon corner's E = prev - cur and E' = next - cur; false when either has
 * zero length (a repeated index), so the corner contributes nothing. */
VN_INLINE int vn_corner_edges(const double prev[3], const double cur[3], const double next[3], double e[3],
                              double e2[3])
{
	vn_sub(prev, cur, e);
	vn_sub(next, cur, e2);
	return vn_dot(e, e) * vn_dot(e2, e2) >= DBL_MIN;
}

/* The vertices a worker owns: [lo, lo + span), or all of them (full), which
 * the kernels are specialized for so that a single worker checks nothing. */
typedef struct vn_range {
	uint32_t lo, span;
	int full;
} vn_range;

/* True, and st->bad_index set, when a triangle has an index out of range. */
VN_INLINE int vn_bad_triangle(const vn_work* w, uint32_t i0, uint32_t i1, uint32_t i2, vn_range_stats* st)
{
	const uint32_t n = w->vertex_count;
	if (i0 < n && i1 < n && i2 < n)
		return 0;
	st->bad_index = 1;
	return 1;
}

VN_INLINE int vn_owned(uint32_t i, vn_range r)
{
	return r.full || (uint32_t)(i - r.lo) < r.span;
}

/* Calls kernel(w, ..., range, st) with the range's `full` a constant in each
 * branch, so that each inlined copy folds its ownership checks away. */
#define VN_DISPATCH_RANGE(w, lo, hi, call)                 \
	do {                                                   \
		if ((lo) == 0 && (hi) == (w)->vertex_count) {      \
			const vn_range range = {0, 0, 1};              \
			call;                                          \
		} else {                                           \
			const vn_range range = {(lo), (hi) - (lo), 0}; \
			call;                                          \
		}                                                  \
	} while (0)

/* Adds one polygon corner's contribution to its accumulator, given the face's
 * unit normal n and the corner's non-degenerate edges E and E'. */
typedef void (*vn_corner_fn)(vn_method method, double* acc, const double n[3], const double e[3], const double e2[3]);

/* The polygon walk both families share: faces in index order, Newell normal,
 * then every owned corner with a rolling window prev, cur, next. */
VN_INLINE void vn_polygons(const vn_work* w, vn_range range, vn_range_stats* st, vn_corner_fn corner)
{
	const uint32_t* off = w->offsets;

	for (size_t f = 0; f < w->face_count; ++f) {
		const uint32_t* face = w->indices + off[f];
		const uint32_t k = off[f + 1] - off[f];
		if (k == 0) { /* cornerless: counted once, by the first worker */
			st->degenerate_faces += range.full || range.lo == 0;
			continue;
		}
		int owned = 0;
		for (uint32_t c = 0; c < k; ++c)
			owned |= vn_owned(face[c], range);
		if (!owned)
			continue;

		double n[3];
		if (k < 3 || !vn_face_normal(w, face, k, n)) {
			st->degenerate_faces += vn_owned(face[0], range);
			continue;
		}
		double prev[3], cur[3], next[3], e[3], e2[3];
		vn_load(w, w->type, face[k - 1], prev);
		vn_load(w, w->type, face[0], cur);
		for (uint32_t c = 0; c < k; ++c) {
			vn_load(w, w->type, face[c + 1 == k ? 0 : c + 1], next);
			if (vn_owned(face[c], range) && vn_corner_edges(prev, cur, next, e, e2))
				corner(w->method, w->acc + 4 * (size_t)face[c], n, e, e2);
			memcpy(prev, cur, sizeof(cur));
			memcpy(cur, next, sizeof(next));
		}
	}
}

#endif /* VN_INTERNAL_H */
