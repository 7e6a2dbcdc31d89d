/* Internal interfaces between the library's source files; not installed. */
#ifndef VN_INTERNAL_H
#define VN_INTERNAL_H

#include <float.h>
#include <math.h>
#include <string.h>

#include "vn.h"

#if defined(__GNUC__) || defined(__clang__)
#  define VN_INLINE static inline __attribute__((always_inline))
#  define VN_PREFETCH(p) __builtin_prefetch(p)
#else
#  define VN_INLINE static inline
#  define VN_PREFETCH(p) ((void)(p))
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
	int keep_existing; /* vn_options.keep_existing: zero normals are not stored */
	/* Per-corner mode of the polygon walk (corner.c), when not NULL: face f's
	 * unit normal, or 0 when it contributes nothing, goes to face_normals[3f..],
	 * and corner c's contribution is added to acc[3 (offsets[f] + c)..]
	 * (3 doubles a corner, indexed by the corner's place in indices)
	 * instead of to its vertex's sum. */
	double* face_normals;
	/* SMEWCSA's MEWCSA pass, when not NULL: the seed (MWSELR) normals, 3
	 * doubles a vertex; the kernels also sum the contributions' lengths in
	 * acc[3], and vn_run finalizes by vn_smewcsa_finalize. */
	const double* seed;
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

/* cotangent.c: SMEWCSA, a pass of the seed kernels, then one of the MEWCSA
 * kernels finalized by its rule; the same contract as vn_run. */
vn_result vn_smewcsa_run(const vn_work* w, vn_accumulate_fn mewcsa, vn_accumulate_fn seed, const vn_options* o,
                         vn_range_stats* st);
/* SMEWCSA's rule (vn.h) at one vertex: n from its MEWCSA sum acc[0..2], the
 * sum of its contributions' lengths acc[3] and its seed normal s (unit or
 * zero); returns 1 when n is zero. */
int vn_smewcsa_finish(const double acc[4], const double s[3], double n[3]);
/* vn_smewcsa_finish on the vertices [lo, hi) of w (w->seed set) into w->out,
 * as vn_run's finalize does. */
void vn_smewcsa_finalize(const vn_work* w, uint32_t lo, uint32_t hi, vn_range_stats* st);

/* fit.c: QUADRIC, JET and ADAPTIVE (w->method); the same contract as vn_run. */
vn_result vn_fit_run(const vn_work* w, const vn_options* o, vn_range_stats* st);
/* The fit of fit.c over the m points p (3 doubles each: x, y, z relative to
 * the vertex, the origin, which is one more point), coordinates divided by
 * h and weighted 1 / (1 + |p|^2) after that, in the frame of the unit axis
 * a; degree 2 (the quadric: 1, x, y, x^2, xy, y^2) or 3 (the jet: also
 * the cubic monomials). scratch: 16 m doubles. On success writes the unit
 * normal n and, when residual is not NULL, the weighted RMS residual (over
 * h), and returns 1; returns 0 (nothing written) with fewer points than
 * unknowns, an ill-conditioned system or a zero normal. */
int vn_fit_frame(const double* p, uint32_t m, double h, double* scratch, const double a[3], int degree, double n[3],
                 double* residual);
/* The rounding of w's coordinates, as ADAPTIVE's sphere test takes it
 * (fit.c): *unit relative to a coordinate, *quantum absolute (0: none). */
void vn_coordinate_rounding(const vn_work* w, double* unit, double* quantum);

/* One triangle's corner contributions: c[k] receives the vector the method's
 * triangle kernel adds to corner k's sum, computed with the same operations,
 * so sums of them formed in face order equal vn_triangle_normals' sums bit
 * for bit. Returns 0 (c untouched) when the triangle contributes nothing. */
typedef int (*vn_triangle_fn)(vn_method method, const double p0[3], const double p1[3], const double p2[3],
                              double c[3][3]);
/* weights.c: MWE .. MWRELR. */
int vn_weighted_triangle(vn_method method, const double p0[3], const double p1[3], const double p2[3], double c[3][3]);
/* api.c: vn_triangle_normals for MWA with vn_atan2_poly's corner angles
 * (fastmath.h): the per-frame plans' float64 MWA. */
vn_result vn_triangle_normals_mwa_poly(const vn_vectors* normals, const vn_positions* positions,
                                       const uint32_t* indices, size_t index_count, const vn_options* options,
                                       vn_stats* stats);
/* cotangent.c: MEWCSA (method is not read). */
int vn_cotangent_triangle(vn_method method, const double p0[3], const double p1[3], const double p2[3], double c[3][3]);

/* ---------------------------------------------------------------- checks shared by entry points */

/* The bytes of one x, y, z triple of type t. */
VN_INLINE size_t vn_triple_bytes(vn_scalar t)
{
	return 3 * (t == vn_scalar_float64 ? sizeof(double) : sizeof(float));
}

/* index_out_of_range when an index is >= vertex_count. A max reduction has
 * no early exit, so it vectorizes; errors are rare. */
static inline vn_result vn_check_indices(const uint32_t* indices, size_t count, uint32_t vertex_count)
{
	uint32_t top = 0;
	for (size_t i = 0; i < count; ++i)
		top = indices[i] > top ? indices[i] : top;
	return count && top >= vertex_count ? vn_result_index_out_of_range : vn_result_success;
}

/* The byte stride of valid positions (0 resolved to packed), or 0 when they
 * are not: NULL, an unknown type, a stride shorter than a triple, more
 * vertices than 32-bit indices reach, or no data for a non-zero count. */
VN_INLINE size_t vn_positions_stride(const vn_positions* p)
{
	if (!p || (p->type != vn_scalar_float32 && p->type != vn_scalar_float64))
		return 0;
	const size_t triple = vn_triple_bytes(p->type);
	if ((p->stride && p->stride < triple) || p->count > UINT32_MAX || (p->count && !p->data))
		return 0;
	return p->stride ? p->stride : triple;
}

/* The byte stride of a valid output array (0 resolved to packed), or 0 when
 * it is not: NULL, an unknown type or a stride shorter than a triple. */
VN_INLINE size_t vn_vectors_stride(const vn_vectors* v)
{
	if (!v || (v->type != vn_scalar_float32 && v->type != vn_scalar_float64))
		return 0;
	const size_t triple = vn_triple_bytes(v->type);
	if (v->stride && v->stride < triple)
		return 0;
	return v->stride ? v->stride : triple;
}

/* NULL, or a whole allocator (both functions or neither) and a known simd value. */
VN_INLINE int vn_options_valid(const vn_options* o)
{
	return !o || (!o->allocator.allocate == !o->allocator.deallocate &&
	              (o->simd == vn_simd_auto || o->simd == vn_simd_off));
}

/* A reader of positions for vn_load, which needs nothing else of a vn_work. */
VN_INLINE vn_work vn_position_reader(const vn_positions* p, size_t stride)
{
	vn_work w;
	memset(&w, 0, sizeof(w));
	w.positions = (const unsigned char*)p->data;
	w.stride = stride;
	w.type = p->type;
	w.vertex_count = (uint32_t)p->count;
	return w;
}

/* Union-find over 32-bit ids in which a parent is never higher than its
 * child: every set's root is its lowest id whatever the order of the unions,
 * so the result is deterministic. Path halving keeps the paths short. */
VN_INLINE uint32_t vn_find(uint32_t* parent, uint32_t x)
{
	while (parent[x] != x) {
		parent[x] = parent[parent[x]];
		x = parent[x];
	}
	return x;
}

VN_INLINE void vn_unite(uint32_t* parent, uint32_t a, uint32_t b)
{
	a = vn_find(parent, a);
	b = vn_find(parent, b);
	if (a < b)
		parent[b] = a;
	else
		parent[a] = b;
}

/* alloc.c: `a` when it has both functions, else malloc/free (for an all-NULL
 * allocator; callers reject half-set ones first). */
vn_allocator vn_heap(const vn_allocator* a);

/* parallel.c: runs fn(ctx, t) for every t in [0, nt), t = 0 on the caller's
 * thread and the others each on a thread of their own (on the caller's when
 * one cannot be started); returns when all have. nt <= 256. */
void vn_parallel(unsigned nt, void (*fn)(void* ctx, unsigned t), void* ctx);

/* parallel.c: zeroes, accumulates and normalizes on o->threads workers, in
 * o->workspace when it is large enough, else in memory from o->allocator. */
vn_result vn_run(const vn_work* w, vn_accumulate_fn accumulate, const vn_options* o, vn_range_stats* st);
/* The workers vn_run uses for nv vertices and the options' threads: fewer
 * than asked below 16384 vertices a worker, at most 256. */
unsigned vn_worker_count(uint32_t nv, unsigned threads);
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

/* Whether a is the zero vector (+0 or -0 in each component): the normal
 * of a vertex no usable face reaches, or of an unusable face. */
VN_INLINE int vn_is_zero(const double a[3])
{
	return a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0;
}

VN_INLINE void vn_add_scaled(double* acc, const double v[3], double s)
{
	acc[0] += v[0] * s, acc[1] += v[1] * s, acc[2] += v[2] * s;
}

/* A triangle's edges e01 = p1 - p0, e12 = p2 - p1, e20 = p0 - p2 and its
 * unnormalized normal n = e20 x e01 = (p1 - p0) x (p2 - p0), of length twice
 * its area; returns |n|^2. */
VN_INLINE double vn_triangle_edges(const double p0[3], const double p1[3], const double p2[3], double e01[3],
                                   double e12[3], double e20[3], double n[3])
{
	vn_sub(p1, p0, e01);
	vn_sub(p2, p1, e12);
	vn_sub(p0, p2, e20);
	vn_cross(e20, e01, n);
	return vn_dot(n, n);
}

/* Squared lengths normalized directly; outside, the sum is rescaled first. */
#define VN_LEN2_MIN 0x1p-900
#define VN_LEN2_MAX 0x1p900

/* Normalizes a sum in place; one with no usable direction (zero, or beyond
 * double range) becomes the zero vector, and the function returns 1. */
VN_INLINE int vn_normalize(double a[3])
{
	double x = a[0], y = a[1], z = a[2];
	const double len2 = x * x + y * y + z * z;
	if (len2 >= VN_LEN2_MIN && len2 <= VN_LEN2_MAX) {
		const double inv = 1.0 / sqrt(len2);
		a[0] = x * inv, a[1] = y * inv, a[2] = z * inv;
		return 0;
	}
	/* Rare: rescale first so that squaring neither overflows nor underflows.
	 * The sum of magnitudes also catches NaN and Inf. */
	const double m = fabs(x) + fabs(y) + fabs(z);
	if (m > 0.0 && m <= DBL_MAX) {
		x /= m, y /= m, z /= m;
		const double inv = 1.0 / sqrt(x * x + y * y + z * z);
		a[0] = x * inv, a[1] = y * inv, a[2] = z * inv;
		return 0;
	}
	a[0] = a[1] = a[2] = 0.0;
	return 1;
}

/* Writes v as element i of out, whose stride is already resolved. */
VN_INLINE void vn_store(const vn_vectors* out, size_t i, const double v[3])
{
	unsigned char* dst = (unsigned char*)out->data + i * out->stride;
	if (out->type == vn_scalar_float32) {
		const float f[3] = {(float)v[0], (float)v[1], (float)v[2]};
		memcpy(dst, f, sizeof(f));
	} else {
		memcpy(dst, v, 3 * sizeof(double));
	}
}

/* Whether vertex v's coordinates are all finite. */
VN_INLINE int vn_finite_at(const vn_work* w, uint32_t v)
{
	double p[3];
	vn_load(w, w->type, v, p);
	return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

/* The vertices in [lo, hi) with a NaN or infinite coordinate. */
VN_INLINE size_t vn_count_nonfinite(const vn_work* w, uint32_t lo, uint32_t hi)
{
	size_t bad = 0;
	for (uint32_t v = lo; v < hi; ++v)
		bad += !vn_finite_at(w, v);
	return bad;
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
 * zero length (another vertex at the same point), so the corner contributes
 * nothing. */
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
 * then every owned corner with a rolling window prev, cur, next. Corners in
 * a row with one index ("a b b c", as files write a triangle in a quad) are
 * one corner of the face, the last of them: its edges go to the nearest
 * corners with other indices, and it contributes once. The walk starts at a
 * corner whose previous one has another index, so no row wraps around. */
VN_INLINE void vn_polygons(const vn_work* w, vn_range range, vn_range_stats* st, vn_corner_fn corner)
{
	const uint32_t* off = w->offsets;
	double* const fn = w->face_normals; /* per-corner mode (vn_work) */

	for (size_t f = 0; f < w->face_count; ++f) {
		const uint32_t* face = w->indices + off[f];
		const uint32_t k = off[f + 1] - off[f];
		if (k == 0) { /* cornerless: counted once, by the first worker */
			st->degenerate_faces += range.full || range.lo == 0;
			if (fn)
				fn[3 * f] = fn[3 * f + 1] = fn[3 * f + 2] = 0.0;
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
			if (fn)
				fn[3 * f] = fn[3 * f + 1] = fn[3 * f + 2] = 0.0;
			continue;
		}
		if (fn)
			memcpy(fn + 3 * f, n, sizeof(n));
		uint32_t s = 0; /* a usable face has two indices at least */
		while (face[s] == face[s ? s - 1 : k - 1])
			++s;
		double prev[3], cur[3], next[3], e[3], e2[3];
		vn_load(w, w->type, face[s ? s - 1 : k - 1], prev);
		vn_load(w, w->type, face[s], cur);
		for (uint32_t i = 0, c = s; i < k; ++i, c = c + 1 == k ? 0 : c + 1) {
			const uint32_t after = c + 1 == k ? 0 : c + 1;
			if (face[after] == face[c])
				continue; /* the row goes on: its last corner contributes */
			vn_load(w, w->type, face[after], next);
			if (vn_owned(face[c], range) && vn_corner_edges(prev, cur, next, e, e2))
				corner(w->method, fn ? w->acc + 3 * ((size_t)off[f] + c) : w->acc + 4 * (size_t)face[c], n, e, e2);
			memcpy(prev, cur, sizeof(cur));
			memcpy(cur, next, sizeof(next));
		}
	}
}

#endif /* VN_INTERNAL_H */
