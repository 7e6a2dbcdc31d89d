/* Per-corner normals with hard edges (vn.h, "welding and split normals"):
 * vn_corner_normals (triangles) and vn_polygon_corner_normals (polygons),
 * one algorithm.
 *
 * 1. Contributions, in parallel over faces: each face's unit normal (for the
 *    crease test; 0 when the face contributes nothing) and each corner's
 *    contribution, 3 doubles a corner. Triangles get them from the kernels'
 *    vn_triangle_fn, polygons from the polygon walk itself (vn_polygons in
 *    per-corner mode), so the arithmetic is the vertex-normal path's, and a
 *    sum of contributions formed in corner order equals that path's vertex
 *    sum bit for bit.
 * 2. Vertex -> corners lists (CSR), a counting sort by vertex: each worker
 *    counts, then lists, the corners of its own range of vertices, in corner
 *    order; O(n) a worker, no sorting, deterministic.
 * 3. Fans, in parallel over vertices: at vertex v, each corner of a usable
 *    face stands for two edges, v -> next vertex (out) and previous vertex ->
 *    v (in). Sorted by the other vertex (a handful of keys), an edge with
 *    exactly one out and one in use is manifold; unless flagged or creased it
 *    joins the two corners (union-find on the vertex's few corners, the
 *    lowest corner the root). A zero-length edge v -> v inside a face joins
 *    its two corners. A face that contributes nothing (not usable: fewer
 *    than 3 corners, zero or non-finite Newell normal) takes part in no edge,
 *    and its corners get the sum over all the vertex's usable faces.
 * 4. Each fan's sum, from 0, adds its corners' contributions in corner order,
 *    is normalized as parallel.c's finalize does (vn_normalize) and written
 *    to every corner of the fan. With options->face_strength (Blender's Face
 *    Influence) only the corners of the fan's strongest faces are added;
 *    those vertices all take the general path (vertex_fans).
 *
 * Every corner's result is formed by one worker from data that does not
 * depend on the split, so results are bit-identical for any thread count.
 * With nothing sharp on a closed manifold mesh, every fan is its vertex's
 * whole star and every corner gets vn_triangle_normals' (triangles) or
 * vn_polygon_normals' (polygons) vertex normal bit for bit.
 *
 * Work memory, from options->workspace when it is large enough, else from
 * the allocator: 32 bytes a corner (36 for polygons), 24 a face, 4 a vertex;
 * a vertex of more than FEW corners adds 64 bytes per corner of the largest
 * star per worker, from the allocator. */
#include <stdlib.h>

#include "fastmath.h" /* VN_PI */
#include "internal.h"
#include "simd.h"

#define NONE UINT32_MAX
#define UNUSABLE (NONE - 1)
/* Faces per call of the polygon walk: its contributions stay in cache
 * between being zeroed and added to. */
#define CHUNK 256
/* Below this many vertices per worker, a thread costs more than it saves. */
#define MIN_VERTICES_PER_THREAD 4096
#define MAX_THREADS 256

/* Whether the angle theta between unit normals a and b exceeds the crease
 * angle c in [0, pi), given cos c and sin c. With s = |a x b| = sin theta
 * and d = a . b = cos theta, theta > c <=> sin(theta - c) = s cos c - d sin c
 * > 0 for theta and c in [0, pi], except at theta = pi, c = 0 (s = 0, d < 0).
 * No trigonometry per edge. */
static int creased(const double a[3], const double b[3], double cos_c, double sin_c)
{
	const double d = vn_dot(a, b);
	/* The usual smooth edge, without the square root: for c <= pi/2 and
	 * d > cos c + 2^-20, c - theta lies in (0, pi/2] and
	 * sin(c - theta) >= (2/pi)(c - theta) >= (2/pi)(cos theta - cos c), far
	 * above the few ulps of error of the test below (a and b are unit to
	 * rounding), which therefore says "not creased" too. */
	if (cos_c >= 0.0 && d > cos_c + 0x1p-20)
		return 0;
	double x[3];
	vn_cross(a, b, x);
	const double s = sqrt(vn_dot(x, x));
	return s * cos_c - d * sin_c > 0.0 || (s == 0.0 && d < 0.0);
}

/* What one worker met. */
typedef struct worker {
	size_t degenerate, zero, nonfinite;
	uint32_t valence; /* largest star among its vertices */
	uint32_t base;    /* where its vertices' corners start in the lists */
} worker;

/* The work of one call, shared by the workers. */
typedef struct job {
	vn_work w;          /* positions, indices, offsets (NULL: triangles), face_count, method */
	vn_accumulate_fn walk; /* polygons: the family's polygon walk */
	vn_triangle_fn triangle; /* triangles: the family's corner contributions */
	uint32_t n, nv;     /* corners, vertices */
	unsigned nt;
	const uint8_t* sharp;
	const int32_t* strength; /* options->face_strength, or NULL */
	int crease, want_stats, avx2;
	double cos_c, sin_c;
	vn_vectors out;
	double* contrib;   /* 3 per corner */
	double* unit;      /* 3 per face */
	uint32_t* face_of; /* per corner (polygons): its face, UNUSABLE for a face that contributes
	                      nothing, NONE for a corner before the first face */
	uint32_t* start;   /* nv + 1: counts, then where each vertex's corners end */
	uint32_t* list;    /* n: corners by vertex, in corner order */
	unsigned char* single; /* NULL, or per vertex: 1 when its corners make one fan of
	                          usable, equally strong faces (its whole star) */
	unsigned char* scratch; /* per worker, scratch_bytes each */
	size_t scratch_bytes;
	worker* workers;
} job;

/* ---------------------------------------------------------------- phase 1: contributions and counts */

static void triangle_contributions(const job* j, uint32_t f0, uint32_t f1, worker* wk)
{
	const vn_work* w = &j->w;
	for (uint32_t t = f0; t < f1; ++t) {
		double p[3][3], e01[3], e12[3], e20[3];
		double* u = j->unit + 3 * (size_t)t;
		double* c = j->contrib + 9 * (size_t)t;
		for (int i = 0; i < 3; ++i)
			vn_load(w, w->type, w->indices[3 * (size_t)t + i], p[i]);
		const double l2 = vn_triangle_edges(p[0], p[1], p[2], e01, e12, e20, u);
		if (vn_usable(l2) && j->triangle(w->method, p[0], p[1], p[2], (double(*)[3])c)) {
			const double inv = 1.0 / sqrt(l2);
			u[0] *= inv, u[1] *= inv, u[2] *= inv;
		} else {
			u[0] = u[1] = u[2] = 0.0;
			memset(c, 0, 9 * sizeof(double));
			++wk->degenerate;
		}
	}
}

static void polygon_contributions(const job* j, uint32_t f0, uint32_t f1, worker* wk)
{
	const uint32_t* off = j->w.offsets;
	vn_work w = j->w;
	w.acc = j->contrib;
	vn_range_stats st = {0, 0, 0, 0};
	if (f0 == 0)
		for (uint32_t c = 0; c < off[0]; ++c)
			j->face_of[c] = NONE;
	for (uint32_t a = f0; a < f1; a += CHUNK) {
		const uint32_t b = f1 - a < CHUNK ? f1 : a + CHUNK;
		memset(j->contrib + 3 * (size_t)off[a], 0, 3 * sizeof(double) * (size_t)(off[b] - off[a]));
		w.offsets = off + a;
		w.face_count = b - a;
		w.face_normals = j->unit + 3 * (size_t)a;
		j->walk(&w, 0, w.vertex_count, &st);
		for (uint32_t f = a; f < b; ++f) {
			const uint32_t mark = vn_is_zero(j->unit + 3 * (size_t)f) ? UNUSABLE : f;
			for (uint32_t c = off[f]; c < off[f + 1]; ++c)
				j->face_of[c] = mark;
		}
	}
	wk->degenerate += st.degenerate_faces;
}

VN_INLINE uint32_t range_lo(uint32_t count, unsigned t, unsigned nt)
{
	return (uint32_t)((uint64_t)count * t / nt);
}

static void phase_contributions(void* ctx, unsigned t)
{
	const job* j = (const job*)ctx;
	worker* wk = j->workers + t;
	const uint32_t nf = (uint32_t)j->w.face_count;
	const uint32_t f0 = range_lo(nf, t, j->nt), f1 = range_lo(nf, t + 1, j->nt);
	if (j->w.offsets)
		polygon_contributions(j, f0, f1, wk);
	else
		triangle_contributions(j, f0, f1, wk);

	/* Counts of this worker's vertices, into start[v + 1]. */
	const uint32_t v0 = range_lo(j->nv, t, j->nt), v1 = range_lo(j->nv, t + 1, j->nt), span = v1 - v0;
	uint32_t* count = j->start + 1;
	memset(count + v0, 0, sizeof(uint32_t) * span);
	const uint32_t* idx = j->w.indices;
	if (j->nt == 1)
		for (uint32_t c = 0; c < j->n; ++c)
			++count[idx[c]];
	else
		for (uint32_t c = 0; c < j->n; ++c)
			if (idx[c] - v0 < span)
				++count[idx[c]];
	uint32_t top = 0, sum = 0;
	for (uint32_t v = v0; v < v1; ++v) {
		top = count[v] > top ? count[v] : top;
		sum += count[v];
	}
	wk->valence = top;
	wk->base = sum; /* this worker's total until the caller turns it into a base */
}

/* ---------------------------------------------------------------- phase 2: lists and fans */

/* Sorts a few keys in place: insertion sort for the usual handful, heapsort
 * (O(k log k)) for a vertex with very many corners. */
static void sift_down(uint64_t* a, size_t i, size_t count)
{
	for (size_t c; (c = 2 * i + 1) < count; i = c) {
		if (c + 1 < count && a[c + 1] > a[c])
			++c;
		if (a[i] >= a[c])
			return;
		const uint64_t t = a[i];
		a[i] = a[c], a[c] = t;
	}
}

static void sort_keys(uint64_t* a, size_t count)
{
	if (count <= 24) {
		for (size_t i = 1; i < count; ++i) {
			const uint64_t x = a[i];
			size_t j = i;
			for (; j > 0 && a[j - 1] > x; --j)
				a[j] = a[j - 1];
			a[j] = x;
		}
		return;
	}
	for (size_t i = count / 2; i-- > 0;)
		sift_down(a, i, count);
	for (size_t end = count; --end > 0;) {
		const uint64_t t = a[0];
		a[0] = a[end], a[end] = t;
		sift_down(a, 0, end);
	}
}

/* Per-worker scratch for one vertex of up to `valence` corners. */
typedef struct fan_scratch {
	uint64_t* keys;   /* 2 per corner: other vertex << 32 | local corner << 1 | in */
	double* acc;      /* 3 per corner */
	uint32_t* parent; /* union-find over local corners */
	uint32_t* face;   /* the corner's face, or NONE (no face) or NONE - 1 (a face that is not usable) */
	uint32_t* prev;   /* the corner before it in its face */
	uint32_t* out;    /* the vertex after it in its face, NONE when not an edge to match */
	uint32_t* in;     /* the vertex before it in its face, NONE likewise */
	int32_t* top;     /* with face strengths: at a fan's root, the fan's highest strength */
} fan_scratch;

#define SCRATCH_PER_CORNER (2 * sizeof(uint64_t) + 3 * sizeof(double) + 6 * sizeof(uint32_t))

VN_INLINE size_t scratch_bytes_for(uint32_t valence)
{
	return ((size_t)valence ? valence : 1) * SCRATCH_PER_CORNER;
}

static fan_scratch scratch_at(unsigned char* p, uint32_t valence)
{
	const size_t k = valence ? valence : 1;
	fan_scratch s;
	s.keys = (uint64_t*)p;
	s.acc = (double*)(p + 2 * sizeof(uint64_t) * k);
	s.parent = (uint32_t*)(p + (2 * sizeof(uint64_t) + 3 * sizeof(double)) * k);
	s.face = s.parent + k;
	s.prev = s.face + k;
	s.out = s.prev + k;
	s.in = s.out + k;
	s.top = (int32_t*)(s.in + k);
	return s;
}

/* The local index of corner c among L[0..k) (sorted), which holds it. */
static uint32_t local_of(const uint32_t* L, uint32_t k, uint32_t c)
{
	uint32_t lo = 0, hi = k;
	while (hi - lo > 1) {
		const uint32_t mid = lo + (hi - lo) / 2;
		if (L[mid] <= c)
			lo = mid;
		else
			hi = mid;
	}
	return lo;
}

/* Joins out use io and in use ii of one manifold edge unless it is sharp. */
VN_INLINE void join_edge(const job* j, const fan_scratch* s, const uint32_t* L, uint32_t io, uint32_t ii)
{
	if (j->sharp && (j->sharp[L[io]] || j->sharp[s->prev[ii]]))
		return;
	if (j->crease && creased(j->unit + 3 * (size_t)s->face[io], j->unit + 3 * (size_t)s->face[ii], j->cos_c, j->sin_c))
		return;
	vn_unite(s->parent, io, ii);
}

/* Below this many corners a vertex matches its edges by direct comparison
 * (k^2 predictable compares), above by sorting. */
#define FEW 24

#define SMALL 8

/* For each out use io < k of small_fans' edges v -> out[io], the in use ii
 * (in[ii] == out[io]) when the edge has exactly one of each, else NONE.
 * Unused entries of out and in are NONE, which no vertex is. */
static void pairs(const uint32_t out[SMALL], const uint32_t in[SMALL], uint32_t k, uint32_t pair[SMALL])
{
	for (uint32_t io = 0; io < k; ++io) {
		const uint32_t b = out[io];
		uint32_t outs = 0, ins = 0, ii = 0;
		for (uint32_t i = 0; i < SMALL; ++i) {
			outs += out[i] == b;
			ins += in[i] == b;
			ii |= in[i] == b ? i : 0;
		}
		pair[io] = outs == 1 && ins == 1 ? ii : NONE;
	}
}

#ifdef VN_HAVE_AVX2
/* pairs() with the eight entries compared at once. */
static VN_AVX2 void pairs_avx2(const uint32_t out[SMALL], const uint32_t in[SMALL], uint32_t k, uint32_t pair[SMALL])
{
	const __m256i o = _mm256_loadu_si256((const __m256i*)out), i8 = _mm256_loadu_si256((const __m256i*)in);
	for (uint32_t io = 0; io < k; ++io) {
		const __m256i b = _mm256_set1_epi32((int)out[io]);
		const unsigned mo = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(o, b)));
		const unsigned mi = (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(i8, b)));
		/* exactly one bit each: mo is never 0 (io itself) */
		pair[io] = (mo & (mo - 1)) == 0 && mi && (mi & (mi - 1)) == 0 ? (uint32_t)__builtin_ctz(mi) : NONE;
	}
}
#endif

/* Steps 3 and 4 for the usual vertex: at most SMALL corners, all of usable
 * faces, no zero-length edge. Fixed-size arrays and loops, labels instead
 * of union-find (a corner's label is its fan's lowest corner), so that the
 * work has few unpredictable branches. Returns the number of zero normals
 * written, or SIZE_MAX (nothing written) when the vertex is not usual. */
static size_t small_fans(const job* j, uint32_t v, const uint32_t* L, uint32_t k)
{
	const uint32_t* idx = j->w.indices;
	const uint32_t* off = j->w.offsets;
	uint32_t out[SMALL], in[SMALL], face[SMALL], prev[SMALL], label[SMALL];
	for (uint32_t i = 0; i < SMALL; ++i)
		out[i] = in[i] = NONE, label[i] = i;
	for (uint32_t i = 0; i < k; ++i) {
		const uint32_t c = L[i];
		uint32_t f, lo, hi;
		if (off) {
			f = j->face_of[c];
			if (f >= UNUSABLE)
				return SIZE_MAX;
			lo = off[f], hi = off[f + 1];
		} else {
			f = c / 3, lo = 3 * f, hi = lo + 3;
			if (vn_is_zero(j->unit + 3 * (size_t)f))
				return SIZE_MAX;
		}
		const uint32_t next = c + 1 == hi ? lo : c + 1, pc = c == lo ? hi - 1 : c - 1;
		out[i] = idx[next], in[i] = idx[pc], face[i] = f, prev[i] = pc;
		if (out[i] == v || in[i] == v)
			return SIZE_MAX;
	}
	/* Each edge v -> b with an out use io: manifold when it has no other out
	 * use and exactly one in use ii (b -> v). */
	uint32_t pair[SMALL];
#ifdef VN_HAVE_AVX2
	if (j->avx2)
		pairs_avx2(out, in, k, pair);
	else
#endif
		pairs(out, in, k, pair);
	for (uint32_t io = 0; io < k; ++io) {
		const uint32_t ii = pair[io];
		if (ii == NONE)
			continue;
		if (j->sharp && (j->sharp[L[io]] || j->sharp[prev[ii]]))
			continue;
		if (j->crease && creased(j->unit + 3 * (size_t)face[io], j->unit + 3 * (size_t)face[ii], j->cos_c, j->sin_c))
			continue;
		const uint32_t la = label[io], lb = label[ii], keep = la < lb ? la : lb, drop = la < lb ? lb : la;
		for (uint32_t i = 0; i < SMALL; ++i)
			label[i] = label[i] == drop ? keep : label[i];
	}
	if (j->single) {
		uint32_t one = 1;
		for (uint32_t i = 0; i < k; ++i)
			one &= label[i] == 0;
		j->single[v] = (unsigned char)one;
	}
	size_t zero = 0;
	for (uint32_t r = 0; r < k; ++r) {
		if (label[r] != r)
			continue;
		double a[3] = {0.0, 0.0, 0.0};
		for (uint32_t i = r; i < k; ++i)
			if (label[i] == r) {
				const double* c = j->contrib + 3 * (size_t)L[i];
				a[0] += c[0], a[1] += c[1], a[2] += c[2];
			}
		const int z = vn_normalize(a);
		for (uint32_t i = r; i < k; ++i)
			if (label[i] == r) {
				zero += (size_t)z;
				vn_store(&j->out, L[i], a);
			}
	}
	return zero;
}

/* Face Influence (Blender's Weighted Normal modifier): s->top[r] receives
 * the highest face strength of the fan rooted at r, for every root; returns
 * the highest of the whole star. Roots are their fans' lowest corners, so a
 * root comes first among its fan's corners. */
static int32_t fan_strengths(const job* j, const fan_scratch* s, uint32_t k)
{
	int32_t star = INT32_MIN;
	for (uint32_t i = 0; i < k; ++i) {
		if (s->face[i] >= UNUSABLE)
			continue;
		const int32_t st = j->strength[s->face[i]];
		const uint32_t r = s->parent[i];
		s->top[r] = r == i || st > s->top[r] ? st : s->top[r];
		star = st > star ? st : star;
	}
	return star;
}

/* Whether local corner i (of a usable face) is added to its fan's sum:
 * always, or with face strengths when its face is among the fan's strongest. */
VN_INLINE int counts(const job* j, const fan_scratch* s, uint32_t i)
{
	return !j->strength || j->strength[s->face[i]] == s->top[s->parent[i]];
}

/* Steps 3 and 4 for vertex v, whose corners are L[0..k). Returns the number
 * of zero normals written. */
static size_t vertex_fans(const job* j, uint32_t v, const uint32_t* L, uint32_t k, const fan_scratch* s)
{
	const uint32_t* idx = j->w.indices;
	const uint32_t* off = j->w.offsets;
	int degenerate = 0;
	for (uint32_t i = 0; i < k; ++i)
		s->parent[i] = i;
	for (uint32_t i = 0; i < k; ++i) {
		const uint32_t c = L[i];
		uint32_t f, lo, hi;
		s->out[i] = s->in[i] = NONE;
		if (off) {
			f = j->face_of[c];
			if (f >= UNUSABLE) {
				s->face[i] = f;
				degenerate |= f == UNUSABLE;
				continue;
			}
			lo = off[f], hi = off[f + 1];
		} else {
			f = c / 3, lo = 3 * f, hi = lo + 3;
			if (vn_is_zero(j->unit + 3 * (size_t)f)) {
				s->face[i] = UNUSABLE;
				degenerate = 1;
				continue;
			}
		}
		s->face[i] = f;
		const uint32_t next = c + 1 == hi ? lo : c + 1, prev = c == lo ? hi - 1 : c - 1;
		s->prev[i] = prev;
		const uint32_t out = idx[next], in = idx[prev];
		if (out != v)
			s->out[i] = out;
		else /* a zero-length edge: c and the next corner are one corner of the face */
			vn_unite(s->parent, i, local_of(L, k, next));
		if (in != v)
			s->in[i] = in;
	}
	if (k <= FEW) {
		/* Each edge v -> b with an out use io: manifold when it has no other
		 * out use and exactly one in use (b -> v). */
		for (uint32_t io = 0; io < k; ++io) {
			const uint32_t b = s->out[io];
			if (b == NONE)
				continue;
			uint32_t outs = 0, ins = 0, ii = 0;
			for (uint32_t i = 0; i < k; ++i) {
				outs += s->out[i] == b;
				ins += s->in[i] == b;
				ii = s->in[i] == b ? i : ii;
			}
			if (outs == 1 && ins == 1)
				join_edge(j, s, L, io, ii);
		}
	} else {
		size_t m = 0;
		for (uint32_t i = 0; i < k; ++i) {
			if (s->out[i] != NONE)
				s->keys[m++] = (uint64_t)s->out[i] << 32 | (uint64_t)i << 1;
			if (s->in[i] != NONE)
				s->keys[m++] = (uint64_t)s->in[i] << 32 | (uint64_t)i << 1 | 1;
		}
		sort_keys(s->keys, m);
		for (size_t a = 0, b; a < m; a = b) {
			for (b = a + 1; b < m && s->keys[b] >> 32 == s->keys[a] >> 32;)
				++b;
			if (b - a != 2 || ((s->keys[a] ^ s->keys[a + 1]) & 1) == 0)
				continue; /* a boundary, non-manifold or inconsistently oriented edge */
			const uint64_t ko = s->keys[a] & 1 ? s->keys[a + 1] : s->keys[a];
			const uint64_t ki = s->keys[a] & 1 ? s->keys[a] : s->keys[a + 1];
			join_edge(j, s, L, (uint32_t)ko >> 1, (uint32_t)ki >> 1); /* the out use, the in use */
		}
	}

	for (uint32_t i = 0; i < k; ++i)
		s->parent[i] = s->face[i] < UNUSABLE ? vn_find(s->parent, i) : NONE;
	const int32_t star = j->strength ? fan_strengths(j, s, k) : 0;
	if (j->single) {
		int one = k > 0;
		for (uint32_t i = 0; i < k; ++i)
			one &= s->face[i] < UNUSABLE && s->parent[i] == s->parent[0] && (!j->strength || counts(j, s, i));
		j->single[v] = (unsigned char)one;
	}

	/* The degenerate faces' corners: the sum over every usable face (the
	 * strongest, with face strengths). */
	double all[3] = {0.0, 0.0, 0.0};
	size_t zero = 0;
	if (degenerate) {
		for (uint32_t i = 0; i < k; ++i)
			if (s->face[i] < UNUSABLE && (!j->strength || j->strength[s->face[i]] == star)) {
				const double* c = j->contrib + 3 * (size_t)L[i];
				all[0] += c[0], all[1] += c[1], all[2] += c[2];
			}
		vn_normalize(all);
	}

	/* Each fan's sum in corner order from its root, its lowest corner. With
	 * few corners in registers, root by root (k x fans steps); with many,
	 * in s->acc in one pass. */
	if (k <= FEW) {
		for (uint32_t r = 0; r < k; ++r) {
			if (s->face[r] >= UNUSABLE) {
				const double* a = s->face[r] == UNUSABLE ? all : NULL;
				static const double nothing[3] = {0.0, 0.0, 0.0};
				zero += !a || vn_is_zero(a);
				vn_store(&j->out, L[r], a ? a : nothing);
				continue;
			}
			if (s->parent[r] != r)
				continue;
			double a[3] = {0.0, 0.0, 0.0};
			for (uint32_t i = r; i < k; ++i)
				if (s->parent[i] == r && counts(j, s, i)) {
					const double* c = j->contrib + 3 * (size_t)L[i];
					a[0] += c[0], a[1] += c[1], a[2] += c[2];
				}
			const int z = vn_normalize(a);
			for (uint32_t i = r; i < k; ++i)
				if (s->parent[i] == r) {
					zero += (size_t)z;
					vn_store(&j->out, L[i], a);
				}
		}
		return zero;
	}
	for (uint32_t i = 0; i < k; ++i) {
		const uint32_t r = s->parent[i];
		if (r == NONE)
			continue;
		double* a = s->acc + 3 * (size_t)r;
		const double* c = j->contrib + 3 * (size_t)L[i];
		if (r == i)
			a[0] = a[1] = a[2] = 0.0;
		if (counts(j, s, i))
			a[0] += c[0], a[1] += c[1], a[2] += c[2];
	}
	for (uint32_t i = 0; i < k; ++i)
		if (s->parent[i] == i)
			vn_normalize(s->acc + 3 * (size_t)i);
	static const double nothing[3] = {0.0, 0.0, 0.0};
	for (uint32_t i = 0; i < k; ++i) {
		const double* a = s->face[i] == NONE       ? nothing
		                  : s->face[i] == UNUSABLE ? all
		                                           : s->acc + 3 * (size_t)s->parent[i];
		zero += vn_is_zero(a);
		vn_store(&j->out, L[i], a);
	}
	return zero;
}

static void phase_fans(void* ctx, unsigned t)
{
	const job* j = (const job*)ctx;
	worker* wk = j->workers + t;
	const uint32_t v0 = range_lo(j->nv, t, j->nt), v1 = range_lo(j->nv, t + 1, j->nt), span = v1 - v0;
	uint32_t* end = j->start + 1; /* end[v]: first the count, then where v's corners begin, then end */
	uint32_t at = wk->base;
	for (uint32_t v = v0; v < v1; ++v) {
		const uint32_t c = end[v];
		end[v] = at;
		at += c;
	}
	const uint32_t* idx = j->w.indices;
	if (j->nt == 1)
		for (uint32_t c = 0; c < j->n; ++c)
			j->list[end[idx[c]]++] = c;
	else
		for (uint32_t c = 0; c < j->n; ++c)
			if (idx[c] - v0 < span)
				j->list[end[idx[c]]++] = c;

	/* Stars of up to FEW corners fit on the stack; bigger ones use the
	 * allocated scratch. */
	uint64_t small[(FEW * SCRATCH_PER_CORNER + 7) / 8];
	const fan_scratch s = j->scratch ? scratch_at(j->scratch + j->scratch_bytes * t, j->workers[0].valence)
	                                 : scratch_at((unsigned char*)small, FEW);
	size_t zero = 0;
	for (uint32_t v = v0, begin = wk->base; v < v1; begin = end[v++]) {
		const uint32_t k = end[v] - begin;
		const size_t z = k <= SMALL && !j->strength ? small_fans(j, v, j->list + begin, k) : SIZE_MAX;
		zero += z != SIZE_MAX ? z : vertex_fans(j, v, j->list + begin, k, &s);
	}
	wk->zero = zero;
	if (j->want_stats)
		wk->nonfinite = vn_count_nonfinite(&j->w, v0, v1);
}

/* ---------------------------------------------------------------- the shared driver */

/* Everything is checked: indices < nv, offsets non-decreasing (polygons). */
/* The work memory for n corners, nf faces, nv vertices and nt workers
 * (face_of only for polygons), with slack to align it. */
static size_t work_bytes(size_t n, size_t nf, size_t nv, unsigned nt, int polygons)
{
	return 3 * sizeof(double) * (n + nf) + sizeof(worker) * nt + sizeof(uint32_t) * (n + (polygons ? n : 0) + nv + 1) +
	       32;
}

/* Everything is checked: indices < nv, offsets non-decreasing (polygons). */
static vn_result run(job* j, const vn_options* options, vn_stats* stats)
{
	const vn_allocator heap = vn_heap(options ? &options->allocator : NULL);
	const unsigned threads = options && options->threads ? options->threads : 1;
	unsigned nt = threads > MAX_THREADS ? MAX_THREADS : threads;
	if ((size_t)nt * MIN_VERTICES_PER_THREAD > j->nv)
		nt = j->nv / MIN_VERTICES_PER_THREAD > 1 ? j->nv / MIN_VERTICES_PER_THREAD : 1;
	j->nt = nt;
	const size_t n = j->n, nf = j->w.face_count, nv = j->nv;
	if (n > SIZE_MAX / 64 || nf > SIZE_MAX / 64 || nv > SIZE_MAX / 8) /* 32-bit size_t */
		return vn_result_out_of_memory;
	const int polygons = j->w.offsets != NULL;
	const size_t need = work_bytes(n, nf, nv, nt, polygons);
	const int own = !(options && options->workspace && options->workspace_size >= need);
	unsigned char* block = own ? (unsigned char*)heap.allocate(heap.user, need) : (unsigned char*)options->workspace;
	if (!block)
		return vn_result_out_of_memory;
	unsigned char* mem = block + ((32 - ((uintptr_t)block & 31)) & 31);
	const size_t contrib_bytes = 3 * sizeof(double) * n, unit_bytes = 3 * sizeof(double) * nf;
	const size_t worker_bytes = sizeof(worker) * nt;
	j->contrib = (double*)mem;
	j->unit = (double*)(mem + contrib_bytes);
	j->workers = (worker*)(mem + contrib_bytes + unit_bytes);
	j->start = (uint32_t*)(mem + contrib_bytes + unit_bytes + worker_bytes);
	j->list = j->start + nv + 1;
	j->face_of = polygons ? j->list + n : NULL;
	memset(j->workers, 0, worker_bytes);
	j->start[0] = 0;

	vn_parallel(nt, phase_contributions, j);

	uint32_t valence = 0, base = 0;
	for (unsigned t = 0; t < nt; ++t) {
		const uint32_t total = j->workers[t].base;
		j->workers[t].base = base;
		base += total;
		valence = j->workers[t].valence > valence ? j->workers[t].valence : valence;
	}
	j->workers[0].valence = valence;
	j->scratch = NULL;
	if (valence > FEW) { /* a star too big for the stack scratch */
		j->scratch_bytes = scratch_bytes_for(valence);
		if (valence > INT32_MAX || j->scratch_bytes > SIZE_MAX / nt ||
		    !(j->scratch = (unsigned char*)heap.allocate(heap.user, j->scratch_bytes * nt))) {
			if (own)
				heap.deallocate(heap.user, block);
			return vn_result_out_of_memory;
		}
	}

	vn_parallel(nt, phase_fans, j);

	if (stats) {
		memset(stats, 0, sizeof(*stats));
		stats->faces = nf;
		for (unsigned t = 0; t < nt; ++t) {
			stats->degenerate_faces += j->workers[t].degenerate;
			stats->zero_normals += j->workers[t].zero;
			stats->nonfinite_vertices += j->workers[t].nonfinite;
		}
	}
	if (j->scratch)
		heap.deallocate(heap.user, j->scratch);
	if (own)
		heap.deallocate(heap.user, block);
	return vn_result_success;
}

/* run() with one of the seven (its kernels chosen here). */
static vn_result run_seven(job* j, vn_method m, const vn_options* options, vn_stats* stats)
{
	j->w.method = m;
	j->triangle = m == vn_method_mewcsa ? vn_cotangent_triangle : vn_weighted_triangle;
	j->walk = m == vn_method_mewcsa ? vn_accumulate_cotangent_polygons : vn_accumulate_weighted_polygons;
	return run(j, options, stats);
}

/* The methods beyond the seven per corner: a corner whose fan is its
 * vertex's whole star gets the vertex's normal (the vertex-normal
 * function's), any other its fan's normal by the method's seed (MWA for the
 * fits, MWSELR for SMEWCSA): a fit needs the whole ring, and a partial fan's
 * MEWCSA sum is no mean-curvature normal. */
static vn_result run_whole_star(job* j, vn_method seed, const vn_options* options, vn_stats* stats)
{
	const vn_allocator heap = vn_heap(options ? &options->allocator : NULL);
	const size_t nv = j->nv;
	if (nv > SIZE_MAX / 32)
		return vn_result_out_of_memory;
	unsigned char* block = (unsigned char*)heap.allocate(heap.user, 25 * nv);
	if (!block)
		return vn_result_out_of_memory;
	double* vert = (double*)(void*)block; /* the vertex normals */
	const vn_method method = j->w.method;
	j->single = block + 24 * nv;
	vn_result r = run_seven(j, seed, options, stats);
	if (r == vn_result_success) {
		vn_options o;
		memset(&o, 0, sizeof(o));
		if (options)
			o.threads = options->threads, o.simd = options->simd, o.allocator = options->allocator;
		const vn_positions p = {j->w.positions, nv, j->w.stride, j->w.type};
		const vn_vectors fv = {vert, 3 * sizeof(double), vn_scalar_float64};
		r = j->w.offsets ? vn_polygon_normals(&fv, &p, j->w.indices, j->w.offsets, j->w.face_count, method, &o, NULL)
		                 : vn_triangle_normals(&fv, &p, j->w.indices, j->n, method, &o, NULL);
		for (size_t c = 0; r == vn_result_success && c < j->n; ++c)
			if (j->single[j->w.indices[c]])
				vn_store(&j->out, c, vert + 3 * (size_t)j->w.indices[c]);
	}
	heap.deallocate(heap.user, block);
	return r;
}

static vn_result run_method(job* j, const vn_options* options, vn_stats* stats)
{
	switch (j->w.method) {
	case vn_method_smewcsa:
		return run_whole_star(j, vn_method_mwselr, options, stats);
	case vn_method_quadric:
	case vn_method_jet:
	case vn_method_adaptive:
		return run_whole_star(j, vn_method_mwa, options, stats);
	default:
		return run_seven(j, j->w.method, options, stats);
	}
}

/* Checks shared by both entry points; fills j's common part. */
static vn_result prepare(job* j, const vn_vectors* normals, const vn_positions* positions, vn_method method,
                         double crease_angle, const uint8_t* sharp_edges, const vn_options* options, vn_stats* stats)
{
	const size_t in_stride = vn_positions_stride(positions), out_stride = vn_vectors_stride(normals);
	if (!in_stride || !out_stride || !(crease_angle >= 0.0) || !vn_options_valid(options))
		return vn_result_invalid_argument;
	if ((unsigned)method >= vn_method_count)
		return vn_result_unknown_method;
	memset(j, 0, sizeof(*j));
	j->w = vn_position_reader(positions, in_stride);
	j->w.method = method;
	j->nv = (uint32_t)positions->count;
	j->sharp = sharp_edges;
	j->strength = options ? options->face_strength : NULL;
	j->crease = crease_angle < VN_PI;
	j->cos_c = cos(crease_angle);
	j->sin_c = sin(crease_angle);
	j->want_stats = stats != NULL;
	j->avx2 = vn_cpu_has_avx2();
	j->out = *normals;
	j->out.stride = out_stride;
	return vn_result_success;
}

static void empty_stats(vn_stats* stats, size_t faces, size_t degenerate)
{
	if (stats) {
		memset(stats, 0, sizeof(*stats));
		stats->faces = faces;
		stats->degenerate_faces = degenerate;
	}
}

vn_result vn_corner_normals(const vn_vectors* normals, const vn_positions* positions, const uint32_t* indices,
                            size_t index_count, vn_method method, double crease_angle, const uint8_t* sharp_edges,
                            const vn_options* options, vn_stats* stats)
{
	job j;
	vn_result r = prepare(&j, normals, positions, method, crease_angle, sharp_edges, options, stats);
	if (r != vn_result_success)
		return r;
	if (index_count % 3 || index_count > UINT32_MAX || (index_count && (!indices || !normals->data)))
		return vn_result_invalid_argument;
	if ((r = vn_check_indices(indices, index_count, j.nv)) != vn_result_success)
		return r;
	if (!index_count) {
		empty_stats(stats, 0, 0);
		return vn_result_success;
	}
	j.w.indices = indices;
	j.w.face_count = index_count / 3;
	j.n = (uint32_t)index_count;
	return run_method(&j, options, stats);
}

vn_result vn_polygon_corner_normals(const vn_vectors* normals, const vn_positions* positions,
                                    const uint32_t* indices, const uint32_t* face_offsets, size_t face_count,
                                    vn_method method, double crease_angle, const uint8_t* sharp_edges,
                                    const vn_options* options, vn_stats* stats)
{
	job j;
	vn_result r = prepare(&j, normals, positions, method, crease_angle, sharp_edges, options, stats);
	if (r != vn_result_success)
		return r;
	if (!face_offsets || face_count > UINT32_MAX - 1)
		return vn_result_invalid_argument;
	for (size_t f = 0; f < face_count; ++f)
		if (face_offsets[f + 1] < face_offsets[f])
			return vn_result_invalid_argument;
	const size_t index_count = face_offsets[face_count];
	if (index_count && (!indices || !normals->data))
		return vn_result_invalid_argument;
	if ((r = vn_check_indices(indices, index_count, j.nv)) != vn_result_success)
		return r;
	if (!index_count) { /* only cornerless faces, if any */
		empty_stats(stats, face_count, face_count);
		return vn_result_success;
	}
	j.w.indices = indices;
	j.w.offsets = face_offsets;
	j.w.face_count = face_count;
	j.n = (uint32_t)index_count;
	return run_method(&j, options, stats);
}
