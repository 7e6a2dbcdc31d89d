/* The fitting family: QUADRIC, JET and ADAPTIVE (vn.h).
 *
 * Per vertex v with seed normal S (MWA's, computed first by the
 * weighted family's kernels):
 *   1. ring: the vertices sharing a usable face with v (a triangle's other
 *      two corners; a polygon's other corners when it has at most
 *      RING_ALL_MAX, else its two edge neighbours); the 2-ring adds the
 *      rings of those. Unusable faces (the seven's degenerate faces: zero or
 *      non-finite area) add nothing, so a non-finite coordinate never enters.
 *   2. h = the mean distance from v to its 1-ring members; every coordinate
 *      is divided by h, so the system's entries are O(1) at any scale.
 *   3. fit (vn_fit_frame): in the frame (t1, t2, a), weighted least squares
 *      of z = f(x, y) over the vertex itself and its ring, f with a constant
 *      term (so the vertex's own position error is averaged, not
 *      interpolated), weights 1 / (1 + r^2) with r the point's distance / h.
 *   4. normal a - f_x t1 - f_y t2, normalized; one refit in its frame.
 * A fit that cannot be trusted falls back: the jet to the quadric on the
 * 1-ring, the quadric to S. Untrusted means fewer points than unknowns, an
 * ill-conditioned system (a Cholesky pivot of the unit-diagonal normal
 * matrix below PIVOT_MIN: some monomial is, to 1e-4 in the weighted norm, a
 * combination of the others, e.g. collinear members), or a normal more than
 * 60 degrees from S (the neighbourhood is not a height field over S's plane).
 * A vertex with a zero seed (isolated, or every face degenerate) gets zero,
 * as with the seven; every other result is a unit vector with a positive
 * dot product with S. Boundary vertices fit their one-sided rings;
 * non-manifold vertices the union of their sheets' rings.
 *
 * Adjacency: a vertex -> corners table (CSR by counting sort, each worker
 * the vertices of its own range, in corner order), built once per call from
 * the allocator; rings are gathered from it on the fly, deduplicated with a
 * per-worker stamp array. Each vertex's result depends only on data that
 * does not depend on the split, so it is bit-identical for any thread count.
 *
 * Work memory, from the allocator (the workspace serves the seed pass):
 * 24 bytes a vertex (seeds) + 4 a corner + 1 a face (+ 4 a corner for
 * polygons) + 4 a vertex + 4 a vertex per thread + ring scratch.
 *
 * ADAPTIVE's threshold, 0.03 h, and MWA as the seed and fallback were
 * chosen with vneval on the paper's ensemble: the jet's residual on smooth
 * models stays mostly below it, on fractal and turbulence models above. */
#include "internal.h"

/* A polygon of more corners gives only its two edge neighbours to a ring:
 * all corners of a large n-gon would make rings quadratic in its size. */
#define RING_ALL_MAX 8
/* Smallest pivot of the unit-diagonal normal matrix's Cholesky factor. */
#define PIVOT_MIN 1e-8
/* The fitted normal must stay within 60 degrees of the seed. */
#define SEED_COS_MIN 0.5
/* ADAPTIVE: the jet where its weighted RMS residual, over h, is below this. */
#define ADAPTIVE_RESIDUAL_MAX 0.03
#define MAX_THREADS 256
/* Below this many vertices per worker, a thread costs more than it saves. */
#define MIN_VERTICES_PER_THREAD 4096

/* ---------------------------------------------------------------- the fit */

/* A unit tangent pair (t1, t2) with t1 x t2 = a: t1 is perpendicular to a
 * and to the axis where a is smallest. */
static void tangent_frame(const double a[3], double t1[3], double t2[3])
{
	const double ax = fabs(a[0]), ay = fabs(a[1]), az = fabs(a[2]);
	double e[3] = {0.0, 0.0, 0.0};
	e[ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2] = 1.0;
	vn_cross(e, a, t1);
	const double inv = 1.0 / sqrt(vn_dot(t1, t1));
	t1[0] *= inv, t1[1] *= inv, t1[2] *= inv;
	vn_cross(a, t1, t2);
}

/* Solves M c = r for the k x k symmetric M (upper triangle given) by
 * Cholesky after scaling M to unit diagonal; 0 when a pivot is below
 * PIVOT_MIN. */
static int solve(double M[10][10], const double r[10], int k, double c[10])
{
	double s[10], L[10][10], y[10];
	for (int i = 0; i < k; ++i) {
		if (!(M[i][i] > 0.0))
			return 0;
		s[i] = 1.0 / sqrt(M[i][i]);
	}
	for (int j = 0; j < k; ++j) {
		double d = 1.0;
		for (int p = 0; p < j; ++p)
			d -= L[j][p] * L[j][p];
		if (!(d >= PIVOT_MIN))
			return 0;
		L[j][j] = sqrt(d);
		for (int i = j + 1; i < k; ++i) {
			double x = M[j][i] * s[i] * s[j];
			for (int p = 0; p < j; ++p)
				x -= L[i][p] * L[j][p];
			L[i][j] = x / L[j][j];
		}
	}
	for (int i = 0; i < k; ++i) {
		double x = r[i] * s[i];
		for (int p = 0; p < i; ++p)
			x -= L[i][p] * y[p];
		y[i] = x / L[i][i];
	}
	for (int i = k; i-- > 0;) {
		double x = y[i];
		for (int p = i + 1; p < k; ++p)
			x -= L[p][i] * c[p];
		c[i] = x / L[i][i];
	}
	for (int i = 0; i < k; ++i)
		c[i] *= s[i];
	return 1;
}

/* The monomials x, y, x^2, xy, y^2 (and x^3, x^2 y, x y^2, y^3). */
VN_INLINE void monomials(double x, double y, int k, double m[10])
{
	m[0] = 1.0, m[1] = x, m[2] = y, m[3] = x * x, m[4] = x * y, m[5] = y * y;
	if (k == 10)
		m[6] = m[3] * x, m[7] = m[3] * y, m[8] = m[5] * x, m[9] = m[5] * y;
}

int vn_fit_frame(const double* q, uint32_t m, const double a[3], int degree, double h, double n[3],
                 double* residual)
{
	const int k = degree == 3 ? 10 : 6;
	if (m + 1 < (uint32_t)k || !(h > 0.0) || !(h <= DBL_MAX))
		return 0;
	double t1[3], t2[3];
	tangent_frame(a, t1, t2);
	const double inv = 1.0 / h;
	double M[10][10], r[10], c[10], mono[10];
	memset(M, 0, sizeof(M));
	memset(r, 0, sizeof(r));
	M[0][0] = 1.0; /* the vertex itself: the origin, weight 1 */
	for (uint32_t i = 0; i < m; ++i) {
		const double* p = q + 3 * (size_t)i;
		const double x = vn_dot(p, t1) * inv, y = vn_dot(p, t2) * inv, z = vn_dot(p, a) * inv;
		const double w = 1.0 / (1.0 + x * x + y * y + z * z);
		monomials(x, y, k, mono);
		for (int j = 0; j < k; ++j) {
			const double wm = w * mono[j];
			r[j] += wm * z;
			for (int l = j; l < k; ++l)
				M[j][l] += wm * mono[l];
		}
	}
	if (!solve(M, r, k, c))
		return 0;
	double sw = 1.0, swr = c[0] * c[0];
	for (uint32_t i = 0; i < m; ++i) {
		const double* p = q + 3 * (size_t)i;
		const double x = vn_dot(p, t1) * inv, y = vn_dot(p, t2) * inv, z = vn_dot(p, a) * inv;
		const double w = 1.0 / (1.0 + x * x + y * y + z * z);
		monomials(x, y, k, mono);
		double e = z;
		for (int j = 0; j < k; ++j)
			e -= c[j] * mono[j];
		sw += w, swr += w * e * e;
	}
	for (int i = 0; i < 3; ++i)
		n[i] = a[i] - c[1] * t1[i] - c[2] * t2[i];
	if (vn_normalize(n))
		return 0;
	*residual = sqrt(swr / sw);
	return 1;
}

/* ---------------------------------------------------------------- adjacency */

typedef struct scratch {
	uint32_t* stamp; /* nv: the tag of the ring a vertex was last added to */
	uint32_t tag;
	uint32_t* ring;  /* up to cap members */
	double* q;       /* 3 per member: its position minus the vertex's */
} scratch;

typedef struct fit_job {
	vn_work w;
	const double* seed;    /* 3 per vertex */
	unsigned char* usable; /* per face */
	uint32_t* face_of;     /* polygons: per corner */
	uint32_t* start;       /* nv + 1: counts, then where each vertex's corners end */
	uint32_t* list;        /* corners by vertex, in corner order */
	uint32_t* top;         /* per worker: its largest 1-ring candidate count */
	scratch* scratch;      /* per worker */
	unsigned nt;
} fit_job;

VN_INLINE uint32_t range_lo(uint32_t count, unsigned t, unsigned nt)
{
	return (uint32_t)((uint64_t)count * t / nt);
}

VN_INLINE uint32_t corner_count(const vn_work* w)
{
	return w->offsets ? w->offsets[w->face_count] : (uint32_t)(3 * w->face_count);
}

/* Faces' usability and each worker's vertices' corner counts. */
static void phase_count(void* ctx, unsigned t)
{
	fit_job* j = (fit_job*)ctx;
	const vn_work* w = &j->w;
	const uint32_t nf = (uint32_t)w->face_count;
	for (uint32_t f = range_lo(nf, t, j->nt), f1 = range_lo(nf, t + 1, j->nt); f < f1; ++f) {
		double n[3];
		if (w->offsets) {
			const uint32_t b = w->offsets[f], k = w->offsets[f + 1] - b;
			j->usable[f] = (unsigned char)(k >= 3 && vn_face_normal(w, w->indices + b, k, n));
			for (uint32_t c = b; c < b + k; ++c)
				j->face_of[c] = f;
		} else {
			double p[3][3], e01[3], e12[3], e20[3];
			for (int i = 0; i < 3; ++i)
				vn_load(w, w->type, w->indices[3 * (size_t)f + i], p[i]);
			j->usable[f] = (unsigned char)vn_usable(vn_triangle_edges(p[0], p[1], p[2], e01, e12, e20, n));
		}
	}
	const uint32_t v0 = range_lo(w->vertex_count, t, j->nt), span = range_lo(w->vertex_count, t + 1, j->nt) - v0;
	uint32_t* count = j->start + 1;
	memset(count + v0, 0, sizeof(uint32_t) * span);
	const uint32_t n = corner_count(w);
	for (uint32_t c = 0; c < n; ++c)
		if (w->indices[c] - v0 < span)
			++count[w->indices[c]];
}

/* The face of corner c, its first corner and its size. */
VN_INLINE uint32_t face_at(const fit_job* j, uint32_t c, uint32_t* b, uint32_t* k)
{
	if (!j->w.offsets) {
		*b = c - c % 3, *k = 3;
		return c / 3;
	}
	const uint32_t f = j->face_of[c];
	*b = j->w.offsets[f], *k = j->w.offsets[f + 1] - *b;
	return f;
}

/* Each worker lists its vertices' corners (start[v] moves from v's first
 * to past its last) and finds its largest 1-ring candidate count. */
static void phase_list(void* ctx, unsigned t)
{
	fit_job* j = (fit_job*)ctx;
	const vn_work* w = &j->w;
	const uint32_t v0 = range_lo(w->vertex_count, t, j->nt), v1 = range_lo(w->vertex_count, t + 1, j->nt);
	const uint32_t n = corner_count(w);
	uint32_t begin = v0 < v1 ? j->start[v0] : 0;
	for (uint32_t c = 0; c < n; ++c)
		if (w->indices[c] - v0 < v1 - v0)
			j->list[j->start[w->indices[c]]++] = c;
	uint32_t top = 0;
	for (uint32_t v = v0; v < v1; begin = j->start[v++]) {
		uint32_t cand = 0;
		for (uint32_t i = begin; i < j->start[v]; ++i) {
			uint32_t b, k;
			face_at(j, j->list[i], &b, &k);
			cand += k <= RING_ALL_MAX ? k - 1 : 2;
		}
		top = cand > top ? cand : top;
	}
	j->top[t] = top;
}

/* Appends to s->ring the unstamped vertices sharing a usable face with u. */
static uint32_t gather(const fit_job* j, scratch* s, uint32_t u, uint32_t m)
{
	const uint32_t* idx = j->w.indices;
	for (uint32_t i = u ? j->start[u - 1] : 0; i < j->start[u]; ++i) {
		const uint32_t c = j->list[i];
		uint32_t b, k;
		if (!j->usable[face_at(j, c, &b, &k)])
			continue;
		const uint32_t at = c - b;
		for (uint32_t o = 1; o < k; ++o) {
			if (k > RING_ALL_MAX && o != 1 && o != k - 1)
				continue;
			const uint32_t x = idx[b + (at + o) % k];
			if (s->stamp[x] != s->tag)
				s->stamp[x] = s->tag, s->ring[m++] = x;
		}
	}
	return m;
}

/* ---------------------------------------------------------------- per vertex */

/* The fit in the seed's frame, then once more in the result's; returns 0
 * (n untouched) when the first fit fails or the result strays from S. */
static int fit_twice(const double* q, uint32_t m, const double seed[3], int degree, double h, double n[3],
                     double* residual)
{
	double a[3], b[3], ra, rb;
	if (!vn_fit_frame(q, m, seed, degree, h, a, &ra))
		return 0;
	if (vn_fit_frame(q, m, a, degree, h, b, &rb))
		memcpy(a, b, sizeof(b)), ra = rb;
	if (!(vn_dot(a, seed) >= SEED_COS_MIN))
		return 0;
	memcpy(n, a, sizeof(a));
	*residual = ra;
	return 1;
}

static void fit_vertex(const fit_job* j, scratch* s, uint32_t v, double n[3])
{
	const double* seed = j->seed + 3 * (size_t)v;
	memcpy(n, seed, 3 * sizeof(double));
	if (seed[0] == 0.0 && seed[1] == 0.0 && seed[2] == 0.0)
		return;
	if (++s->tag == 0) { /* wrapped: forget every stamp */
		memset(s->stamp, 0, sizeof(uint32_t) * j->w.vertex_count);
		s->tag = 1;
	}
	s->stamp[v] = s->tag;
	const uint32_t m1 = gather(j, s, v, 0);
	double p[3], x[3], h = 0.0;
	vn_load(&j->w, j->w.type, v, p);
	for (uint32_t i = 0; i < m1; ++i) {
		vn_load(&j->w, j->w.type, s->ring[i], x);
		vn_sub(x, p, s->q + 3 * (size_t)i);
		h += sqrt(vn_dot(s->q + 3 * (size_t)i, s->q + 3 * (size_t)i));
	}
	if (!m1)
		return;
	h /= m1;
	double res;
	if (j->w.method != vn_method_quadric) {
		uint32_t m2 = m1;
		for (uint32_t i = 0; i < m1; ++i)
			m2 = gather(j, s, s->ring[i], m2);
		for (uint32_t i = m1; i < m2; ++i) {
			vn_load(&j->w, j->w.type, s->ring[i], x);
			vn_sub(x, p, s->q + 3 * (size_t)i);
		}
		double f[3];
		if (fit_twice(s->q, m2, seed, 3, h, f, &res)) {
			if (j->w.method == vn_method_jet || res <= ADAPTIVE_RESIDUAL_MAX)
				memcpy(n, f, sizeof(f));
			return;
		}
		if (j->w.method == vn_method_adaptive)
			return;
	}
	fit_twice(s->q, m1, seed, 2, h, n, &res);
}

static void phase_fit(void* ctx, unsigned t)
{
	const fit_job* j = (const fit_job*)ctx;
	scratch* s = j->scratch + t;
	const vn_work* w = &j->w;
	for (uint32_t v = range_lo(w->vertex_count, t, j->nt), v1 = range_lo(w->vertex_count, t + 1, j->nt); v < v1;
	     ++v) {
		double n[3];
		fit_vertex(j, s, v, n);
		if (!(w->keep_existing && n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0))
			vn_store(w->out, v, n);
	}
}

/* ---------------------------------------------------------------- driver */

static unsigned worker_count(uint32_t nv, unsigned threads)
{
	unsigned nt = threads ? threads : 1;
	nt = nt > MAX_THREADS ? MAX_THREADS : nt;
	if ((size_t)nt * MIN_VERTICES_PER_THREAD > nv)
		nt = nv / MIN_VERTICES_PER_THREAD > 1 ? nv / MIN_VERTICES_PER_THREAD : 1;
	return nt;
}

vn_result vn_fit_run(const vn_work* work, const vn_options* o, vn_range_stats* st)
{
	const vn_allocator heap = vn_heap(&o->allocator);
	const uint32_t nv = work->vertex_count, nc = corner_count(work);
	const size_t nf = work->face_count;
	const unsigned nt = worker_count(nv, o->threads);

	/* The seeds, by the weighted family's kernels (which check the indices). */
	double* seed = (double*)heap.allocate(heap.user, 3 * sizeof(double) * (size_t)nv);
	if (!seed)
		return vn_result_out_of_memory;
	fit_job j;
	memset(&j, 0, sizeof(j));
	j.w = *work;
	j.w.method = vn_method_mwa;
	const vn_vectors seeds = {seed, 3 * sizeof(double), vn_scalar_float64};
	j.w.out = &seeds;
	j.w.keep_existing = 0;
	vn_result r = vn_run(&j.w, work->offsets ? vn_accumulate_weighted_polygons : vn_accumulate_weighted_triangles,
	                     o, st);
	j.w = *work;
	j.seed = seed;
	j.nt = nt;

	const size_t words = (size_t)nv + 1 + nc + (work->offsets ? nc : 0) + nt;
	const size_t bytes = sizeof(scratch) * nt + sizeof(uint32_t) * words + nf;
	unsigned char* block = r == vn_result_success ? (unsigned char*)heap.allocate(heap.user, bytes) : NULL;
	if (r == vn_result_success && !block)
		r = vn_result_out_of_memory;
	if (block) {
		j.scratch = (scratch*)(void*)block;
		j.start = (uint32_t*)(void*)(j.scratch + nt);
		j.list = j.start + nv + 1;
		j.top = j.list + nc;
		j.face_of = work->offsets ? j.top + nt : NULL;
		j.usable = (unsigned char*)(j.start + words);
		vn_parallel(nt, phase_count, &j);
		/* start[v + 1] holds v's count: make start[v] where v's corners begin. */
		uint32_t sum = 0;
		for (uint32_t v = 0; v < nv; ++v) {
			const uint32_t c = j.start[v + 1];
			j.start[v] = sum;
			sum += c;
		}
		vn_parallel(nt, phase_list, &j);
		uint32_t top = 0;
		for (unsigned t = 0; t < nt; ++t)
			top = j.top[t] > top ? j.top[t] : top;
		/* A 2-ring has at most top (1 + top) members, and fewer than nv. */
		const uint64_t want = (uint64_t)top * (1 + (uint64_t)top);
		const size_t cap = want < nv ? (size_t)want : nv;
		const size_t ring_bytes = (sizeof(uint32_t) * ((size_t)nv + cap) + 7) & ~(size_t)7;
		unsigned t = 0;
		for (; t < nt; ++t) {
			scratch* s = j.scratch + t;
			s->stamp = (uint32_t*)heap.allocate(heap.user, ring_bytes + 3 * sizeof(double) * cap);
			if (!s->stamp)
				break;
			memset(s->stamp, 0, sizeof(uint32_t) * nv);
			s->tag = 0;
			s->ring = s->stamp + nv;
			s->q = (double*)(void*)((unsigned char*)s->stamp + ring_bytes);
		}
		if (t == nt)
			vn_parallel(nt, phase_fit, &j);
		else
			r = vn_result_out_of_memory;
		while (t-- > 0)
			heap.deallocate(heap.user, j.scratch[t].stamp);
		heap.deallocate(heap.user, block);
	}
	heap.deallocate(heap.user, seed);
	return r;
}
