/* Welding vertices by position: the groups are the connected components of
 * the graph joining two vertices when every coordinate differs by at most
 * epsilon (Chebyshev distance), so chains weld too.
 *
 * epsilon 0 (vnconvert's default) has no chains, equality being transitive:
 * a hash table of positions finds the groups in O(n) expected time, and as
 * vertices enter it in index order, a position finds its lowest vertex.
 * Other epsilons take the grids below.
 *
 * Two grids. Fine cells have the side s, the largest power of two <= epsilon:
 * a coordinate's fine cell floor(x / s) is exact (dividing by a power of two
 * is), so two points of one fine cell differ by less than s <= epsilon in
 * every coordinate: a fine cell is a clique and welds whole, untested.
 * Coarse cells have the side 2s > epsilon, so two points within epsilon lie
 * in the same or adjacent coarse cells. Points sort by coarse cell, then
 * fine cell; each coarse cell is compared with itself and with the 13 of its
 * 26 neighbours that sort after it, fine cell by fine cell, and two cliques
 * are one group as soon as one pair of theirs is within epsilon. The
 * neighbours come in 4 rows (dx, dy) whose pointers only move forward.
 * O(n log n) for the sort; the rest is O(n) unless many points crowd cells
 * without being within epsilon of each other.
 *
 * Exact axes: when |x| / s >= 2^54, or x is infinite, the doubles next to x
 * are more than epsilon from it (their spacing there is >= 2s), so x matches
 * x alone; such an axis is keyed by x's bits and has no neighbours along it.
 * NaN positions take no part.
 *
 * Work memory from the options' allocator (the workspace is not used):
 * for epsilon 0, 16 bytes a vertex (up to 32: the table's size is a power
 * of two); for the grids, 64, and remap itself holds the union-find. */
#include <stdlib.h>

#include "internal.h"

typedef struct weld_point {
	int64_t key[3]; /* per axis: the coarse cell, or on an exact axis the coordinate's bits */
	uint32_t id;
	uint8_t exact;  /* bit a set: axis a is exact */
	uint8_t fine;   /* bit a: which half of its coarse cell along axis a (0 when exact) */
} weld_point;

/* Orders the first `axes` axes of a and b: exactness, then key. */
static int compare_axes(const weld_point* a, const weld_point* b, int axes)
{
	for (int i = 0; i < axes; ++i) {
		const int ea = a->exact >> i & 1, eb = b->exact >> i & 1;
		if (ea != eb)
			return ea < eb ? -1 : 1;
		if (a->key[i] != b->key[i])
			return a->key[i] < b->key[i] ? -1 : 1;
	}
	return 0;
}

/* Coarse cell, fine cell, id: a total order, so the sorted array does not
 * depend on the sorting algorithm. */
VN_INLINE int before(const weld_point* a, const weld_point* b)
{
	const int c = compare_axes(a, b, 3);
	if (c)
		return c < 0;
	return a->fine != b->fine ? a->fine < b->fine : a->id < b->id;
}

/* Sorts pts[0..n) through tmp (n more points): insertion-sorted runs of 8,
 * then bottom-up merges. Returns the one of the two arrays holding the result. */
static weld_point* sort_points(weld_point* pts, weld_point* tmp, size_t n)
{
	const size_t run = 8;
	for (size_t lo = 0; lo < n; lo += run)
		for (size_t i = lo + 1; i < lo + run && i < n; ++i) {
			const weld_point x = pts[i];
			size_t j = i;
			for (; j > lo && before(&x, &pts[j - 1]); --j)
				pts[j] = pts[j - 1];
			pts[j] = x;
		}
	for (size_t width = run; width < n; width *= 2) {
		for (size_t lo = 0; lo < n; lo += 2 * width) {
			const size_t mid = n - lo > width ? lo + width : n, hi = n - mid > width ? mid + width : n;
			size_t i = lo, j = mid, o = lo;
			while (i < mid && j < hi)
				tmp[o++] = before(&pts[j], &pts[i]) ? pts[j++] : pts[i++];
			while (i < mid)
				tmp[o++] = pts[i++];
			while (j < hi)
				tmp[o++] = pts[j++];
		}
		weld_point* t = pts;
		pts = tmp, tmp = t;
	}
	return pts;
}

/* Keys axis `axis` of q by coordinate x; shift = -log2(s). */
static void set_key(weld_point* q, int axis, double x, int shift)
{
	const double t = ldexp(x, shift); /* x / s, exact unless it under- or overflows */
	if (fabs(t) < 0x1p54) {
		const int64_t f = (int64_t)floor(t);
		q->key[axis] = (f - (f & 1)) / 2; /* floor(f / 2), also for f < 0 */
		q->fine |= (uint8_t)((f & 1) << axis);
		return;
	}
	x += 0.0; /* -0 + 0 = +0: the two zeros are one position */
	memcpy(&q->key[axis], &x, sizeof(x));
	q->exact |= (uint8_t)(1u << axis);
}

static int within(const double a[3], const double b[3], double epsilon)
{
	for (int i = 0; i < 3; ++i)
		if (!(a[i] == b[i] || fabs(a[i] - b[i]) <= epsilon)) /* == for infinities */
			return 0;
	return 1;
}

typedef struct welder {
	const weld_point* pts;
	size_t count;
	uint32_t* parent;
	vn_work reader;
	double epsilon;
} welder;

/* Welds cliques [c0, c1) and [d0, d1) when any pair of theirs is within epsilon. */
static void join_cliques(const welder* wd, size_t c0, size_t c1, size_t d0, size_t d1)
{
	const weld_point* pts = wd->pts;
	if (vn_find(wd->parent, pts[c0].id) == vn_find(wd->parent, pts[d0].id))
		return;
	for (size_t i = c0; i < c1; ++i) {
		double a[3];
		vn_load(&wd->reader, wd->reader.type, pts[i].id, a);
		for (size_t j = d0; j < d1; ++j) {
			double b[3];
			vn_load(&wd->reader, wd->reader.type, pts[j].id, b);
			if (within(a, b, wd->epsilon)) {
				vn_unite(wd->parent, pts[c0].id, pts[d0].id);
				return;
			}
		}
	}
}

/* The end of the fine cell, a clique, that starts at i (before end). */
static size_t clique_end(const weld_point* pts, size_t i, size_t end)
{
	size_t j = i + 1;
	while (j < end && pts[j].fine == pts[i].fine)
		++j;
	return j;
}

/* Joins every clique of coarse cell [c0, c1) with every clique of [d0, d1). */
static void join_coarse(const welder* wd, size_t c0, size_t c1, size_t d0, size_t d1)
{
	for (size_t i = c0, i1; i < c1; i = i1) {
		i1 = clique_end(wd->pts, i, c1);
		for (size_t j = d0, j1; j < d1; j = j1) {
			j1 = clique_end(wd->pts, j, d1);
			join_cliques(wd, i, i1, j, j1);
		}
	}
}

/* Joins coarse cell [c0, c1) with every coarse cell from index j on that has
 * row's x and y and z of row's kind, up to key z_max. */
static void join_row(const welder* wd, size_t c0, size_t c1, size_t j, const weld_point* row, int64_t z_max)
{
	const weld_point* pts = wd->pts;
	while (j < wd->count && compare_axes(&pts[j], row, 2) == 0 && (pts[j].exact & 4) == (row->exact & 4) &&
	       pts[j].key[2] <= z_max) {
		size_t end = j + 1;
		while (end < wd->count && compare_axes(&pts[end], &pts[j], 3) == 0)
			++end;
		join_coarse(wd, c0, c1, j, end);
		j = end;
	}
}

/* The rows (dx, dy) of the 3 x 3 x 3 neighbourhood that sort after a cell's
 * own row; its own row is searched from the cell on. */
static const int8_t rows[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};

static void join_neighbours(const welder* wd)
{
	const weld_point* pts = wd->pts;
	size_t next[4] = {0};
	for (size_t c0 = 0, c1; c0 < wd->count; c0 = c1) {
		const weld_point* c = &pts[c0];
		for (c1 = c0 + 1; c1 < wd->count && compare_axes(&pts[c1], c, 3) == 0;)
			++c1;
		/* Inside the cell: each clique welds whole, then meets the later ones. */
		for (size_t i = c0, i1; i < c1; i = i1) {
			i1 = clique_end(pts, i, c1);
			for (size_t j = i + 1; j < i1; ++j)
				vn_unite(wd->parent, pts[i].id, pts[j].id);
			join_coarse(wd, i, i1, i1, c1);
		}
		const int z_span = c->exact & 4 ? 0 : 1;
		join_row(wd, c0, c1, c1, c, c->key[2] + z_span);
		for (int r = 0; r < 4; ++r) {
			const int dx = rows[r][0], dy = rows[r][1];
			if ((dx && (c->exact & 1)) || (dy && (c->exact & 2)))
				continue;
			weld_point row = *c;
			row.key[0] += dx, row.key[1] += dy, row.key[2] -= z_span;
			/* Rows move forward with the cells, so each pointer only advances. */
			while (next[r] < wd->count && compare_axes(&pts[next[r]], &row, 3) < 0)
				++next[r];
			join_row(wd, c0, c1, next[r], &row, c->key[2] + z_span);
		}
	}
}

/* Mixes the three coordinates' bits. A coordinate's information sits in its
 * high bits (floats widened to double end in 29 zero bits) and a multiply
 * only carries bits upwards: each xorshift first brings the high half down,
 * and the last one mixes the high bits into the low ones indexing the table. */
static uint64_t hash_position(const double p[3])
{
	uint64_t h = 0;
	for (int a = 0; a < 3; ++a) {
		const double x = p[a] + 0.0; /* -0 + 0 = +0: equal coordinates, equal bits */
		uint64_t b;
		memcpy(&b, &x, sizeof(b));
		h ^= b;
		h ^= h >> 32;
		h *= 0x9e3779b97f4a7c15u;
	}
	return h ^ h >> 32;
}

/* Finds vertex v (hash h) in the table, or enters it. */
static void weld_one(uint64_t* table, size_t mask, uint64_t h, uint32_t v, const vn_work* reader, uint32_t* remap)
{
	remap[v] = v;
	double p[3];
	vn_load(reader, reader->type, v, p);
	if (isnan(p[0]) || isnan(p[1]) || isnan(p[2]))
		return;
	const uint64_t tag = h >> 32 << 32;
	for (size_t s = h & mask;; s = (s + 1) & mask) {
		const uint64_t e = table[s];
		if ((uint32_t)e == UINT32_MAX) {
			table[s] = tag | v;
			return;
		}
		if ((e >> 32 << 32) != tag)
			continue;
		double q[3];
		vn_load(reader, reader->type, (uint32_t)e, q);
		if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) {
			remap[v] = (uint32_t)e;
			return;
		}
	}
}

/* epsilon 0: vertex ids in an open-addressing table at most half full,
 * probed linearly. A vertex finds the first vertex of its position, or
 * enters the table as that first. A slot holds the id and the hash's high
 * half, so that only equal hashes load the other vertex's position; slots
 * are prefetched `ahead` vertices early. Both matter because the table and
 * the positions are far larger than the caches on big meshes (500k
 * vertices: 52 -> 21 ns a vertex, docs/PERFORMANCE.md). */
static vn_result weld_exact(uint32_t* remap, const vn_work* reader, size_t n, vn_allocator heap)
{
	enum { ahead = 16 };
	if (n > SIZE_MAX / (4 * sizeof(uint64_t))) /* the table has fewer than 4n slots */
		return vn_result_out_of_memory;
	size_t slots = 2;
	while (slots < 2 * n)
		slots *= 2;
	uint64_t* table = (uint64_t*)heap.allocate(heap.user, slots * sizeof(uint64_t));
	if (!table)
		return vn_result_out_of_memory;
	memset(table, 0xff, slots * sizeof(uint64_t)); /* empty: id UINT32_MAX, above every id */
	const size_t mask = slots - 1;
	uint64_t hashes[ahead];
	/* Vertex v is welded `ahead` iterations after its hash is computed and
	 * its slot prefetched (hashes[v % ahead] is then free for v + ahead). */
	for (size_t i = 0; i < n + ahead; ++i) {
		if (i >= ahead)
			weld_one(table, mask, hashes[(i - ahead) % ahead], (uint32_t)(i - ahead), reader, remap);
		if (i < n) {
			double p[3];
			vn_load(reader, reader->type, (uint32_t)i, p);
			hashes[i % ahead] = hash_position(p);
			VN_PREFETCH(&table[hashes[i % ahead] & mask]);
		}
	}
	heap.deallocate(heap.user, table);
	return vn_result_success;
}

vn_result vn_weld_positions(uint32_t* remap, const vn_positions* positions, double epsilon, const vn_options* options)
{
	const size_t stride = vn_positions_stride(positions);
	if (!stride || !(epsilon >= 0.0 && epsilon <= DBL_MAX) || !vn_options_valid(options) ||
	    (positions->count && !remap))
		return vn_result_invalid_argument;
	const size_t n = positions->count;
	if (!n)
		return vn_result_success;
	const vn_allocator heap = vn_heap(options ? &options->allocator : NULL);
	if (epsilon == 0.0) {
		const vn_work reader = vn_position_reader(positions, stride);
		return weld_exact(remap, &reader, n, heap);
	}
	if (n > SIZE_MAX / (2 * sizeof(weld_point)))
		return vn_result_out_of_memory;
	weld_point* block = (weld_point*)heap.allocate(heap.user, 2 * n * sizeof(weld_point));
	if (!block)
		return vn_result_out_of_memory;

	welder wd = {block, 0, remap, vn_position_reader(positions, stride), epsilon};
	int exponent;
	frexp(epsilon, &exponent); /* epsilon = m 2^exponent, m in [0.5, 1): s = 2^(exponent - 1) */
	const int shift = 1 - exponent;
	for (uint32_t i = 0; i < (uint32_t)n; ++i) {
		remap[i] = i;
		double p[3];
		vn_load(&wd.reader, wd.reader.type, i, p);
		if (isnan(p[0]) || isnan(p[1]) || isnan(p[2]))
			continue;
		weld_point* q = &block[wd.count++];
		q->id = i;
		q->exact = q->fine = 0;
		for (int a = 0; a < 3; ++a)
			set_key(q, a, p[a], shift);
	}
	wd.pts = sort_points(block, block + n, wd.count);
	join_neighbours(&wd);
	for (uint32_t i = 0; i < (uint32_t)n; ++i)
		remap[i] = vn_find(remap, i);
	heap.deallocate(heap.user, block);
	return vn_result_success;
}
