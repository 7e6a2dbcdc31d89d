/* Per-corner normals with hard edges (vn.h, "welding and split normals").
 *
 * 1. Each triangle's unit normal, for the crease test. A triangle that
 *    contributes nothing (not vn_usable: zero or non-finite area, a repeated
 *    index) is no part of the surface: its edges join nothing (a face beside
 *    it sees a boundary there; a welded pole's collapsed triangles thus leave
 *    the pole's fan intact), and its corners get their vertex's normal over
 *    all its usable triangles, as vn.h says.
 * 2. Edge adjacency without hashing: the corners of usable triangles, each
 *    standing for its edge corner -> next corner, sorted by (lower, higher
 *    vertex, corner): a counting sort by the lower vertex, then each
 *    vertex's few edges in place; O(n log n) at worst, O(n + V) on meshes of
 *    bounded valence. An edge of exactly two uses in opposite directions is
 *    manifold, and smooth unless flagged or creased; every other edge is
 *    sharp.
 * 3. Wedges: union-find over corners. A smooth edge a -> b of t, b -> a of
 *    t', joins t's and t''s corners at a, and those at b.
 * 4. Sums: triangles in index order add their corner contributions (the
 *    kernels' own arithmetic, vn_triangle_fn) to their wedges; each wedge is
 *    normalized as parallel.c's finalize does. So a closed manifold mesh with
 *    no sharp edge gets, at every corner, its vertex's vn_triangle_normals
 *    normal bit for bit, whatever the simd option.
 *
 * Single-threaded: options->threads and the workspace are not used. Work
 * memory, from the options' allocator: 20 bytes a corner, 4 a vertex and 24
 * a wedge (a vertex's share of a smooth region). */
#include <stdlib.h>

#include "fastmath.h" /* VN_PI */
#include "internal.h"

#define NONE UINT32_MAX

VN_INLINE uint32_t next_corner(uint32_t c)
{
	return c % 3 == 2 ? c - 2 : c + 1;
}

/* Whether the angle theta between unit normals a and b exceeds the crease
 * angle c in [0, pi), given cos c and sin c. With s = |a x b| = sin theta
 * and d = a . b = cos theta, theta > c <=> sin(theta - c) = s cos c - d sin c
 * > 0 for theta and c in [0, pi], except at theta = pi, c = 0 (s = 0, d < 0).
 * No trigonometry per edge. */
static int creased(const double a[3], const double b[3], double cos_c, double sin_c)
{
	double x[3];
	vn_cross(a, b, x);
	const double s = sqrt(vn_dot(x, x)), d = vn_dot(a, b);
	return s * cos_c - d * sin_c > 0.0 || (s == 0.0 && d < 0.0);
}

/* The work of one call. */
typedef struct corners {
	const uint32_t* idx;
	uint32_t nv;
	uint32_t n;       /* corners */
	double* unit;     /* 3 per triangle: its unit normal, or 0 when it is not usable */
	uint64_t* edges;  /* per usable corner: high << 32 | corner, bucketed by low vertex */
	uint32_t* count;  /* nv + 1: where each vertex's bucket ends, then its slot for degenerate corners */
	uint32_t* parent; /* n: the union-find, then each corner's wedge */
	uint32_t wedges;
} corners;

VN_INLINE int usable(const corners* k, uint32_t t)
{
	const double* u = k->unit + 3 * (size_t)t;
	return u[0] != 0.0 || u[1] != 0.0 || u[2] != 0.0;
}

/* Step 1; returns the number of triangles that are not usable. */
static size_t unit_normals(corners* k, const vn_work* reader)
{
	size_t degenerate = 0;
	for (uint32_t t = 0; t < k->n / 3; ++t) {
		double p0[3], p1[3], p2[3], e01[3], e12[3], e20[3];
		double* n = k->unit + 3 * (size_t)t;
		vn_load(reader, reader->type, k->idx[3 * t], p0);
		vn_load(reader, reader->type, k->idx[3 * t + 1], p1);
		vn_load(reader, reader->type, k->idx[3 * t + 2], p2);
		const double l2 = vn_triangle_edges(p0, p1, p2, e01, e12, e20, n);
		if (vn_usable(l2)) {
			const double inv = 1.0 / sqrt(l2);
			n[0] *= inv, n[1] *= inv, n[2] *= inv;
		} else {
			n[0] = n[1] = n[2] = 0.0;
			++degenerate;
		}
	}
	return degenerate;
}

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

/* Sorts one vertex's bucket in place: insertion sort for the usual handful
 * of edges, heapsort (O(k log k)) for a vertex that starts very many. */
static void sort_bucket(uint64_t* a, size_t count)
{
	if (count <= 16) {
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

/* Step 2: each usable corner's edge, corner -> next corner, as (low, high,
 * corner): a counting sort by low vertex (O(n + V)), then each bucket by
 * high << 32 | corner. Bucket v ends at count[v]. */
static void sort_edges(corners* k)
{
	uint32_t* count = k->count;
	memset(count, 0, ((size_t)k->nv + 1) * sizeof(uint32_t));
	for (uint32_t t = 0; t < k->n / 3; ++t)
		if (usable(k, t))
			for (uint32_t c = 3 * t; c < 3 * t + 3; ++c) {
				const uint32_t a = k->idx[c], b = k->idx[next_corner(c)];
				++count[(a < b ? a : b) + 1];
			}
	for (uint32_t v = 0; v < k->nv; ++v)
		count[v + 1] += count[v];
	for (uint32_t t = 0; t < k->n / 3; ++t)
		if (usable(k, t))
			for (uint32_t c = 3 * t; c < 3 * t + 3; ++c) {
				const uint32_t a = k->idx[c], b = k->idx[next_corner(c)];
				k->edges[count[a < b ? a : b]++] = (uint64_t)(a < b ? b : a) << 32 | c;
			}
	for (uint32_t v = 0, begin = 0; v < k->nv; begin = count[v++])
		sort_bucket(k->edges + begin, count[v] - begin);
}

/* Step 3: joins the corners across every smooth edge. */
static void join_wedges(corners* k, const uint8_t* sharp, double crease_angle)
{
	const int crease = crease_angle < VN_PI;
	const double cos_c = cos(crease_angle), sin_c = sin(crease_angle);
	const uint64_t* edges = k->edges;
	for (uint32_t c = 0; c < k->n; ++c)
		k->parent[c] = c;
	for (uint32_t v = 0, begin = 0; v < k->nv; begin = k->count[v++])
		for (uint32_t i = begin, j; i < k->count[v]; i = j) {
			for (j = i + 1; j < k->count[v] && edges[j] >> 32 == edges[i] >> 32;)
				++j;
			if (j - i != 2)
				continue;
			const uint32_t c0 = (uint32_t)edges[i], c1 = (uint32_t)edges[i + 1];
			const int opposite = k->idx[c0] == k->idx[next_corner(c1)];
			const double* u0 = k->unit + 3 * (size_t)(c0 / 3);
			const double* u1 = k->unit + 3 * (size_t)(c1 / 3);
			if (opposite && !(sharp && (sharp[c0] || sharp[c1])) && !(crease && creased(u0, u1, cos_c, sin_c))) {
				vn_unite(k->parent, c0, next_corner(c1));
				vn_unite(k->parent, next_corner(c0), c1);
			}
		}
}

/* Step 3, labels: parent[c] becomes corner c's wedge, numbered in order of
 * first corner; the degenerate corners of a vertex share one wedge, which
 * gathers all of the vertex's usable triangles. */
static void label_wedges(corners* k)
{
	uint32_t* slot = k->count;
	for (uint32_t v = 0; v < k->nv; ++v)
		slot[v] = NONE;
	uint32_t w = 0;
	for (uint32_t t = 0; t < k->n / 3; ++t) {
		const int real = usable(k, t);
		for (uint32_t c = 3 * t; c < 3 * t + 3; ++c) {
			uint32_t* s = slot + k->idx[c];
			if (!real) {
				if (*s == NONE)
					*s = w++;
				k->parent[c] = *s;
				continue;
			}
			/* parent[c] <= c, and every corner below c already holds its label. */
			const uint32_t p = k->parent[c];
			k->parent[c] = p == c ? w++ : k->parent[p];
		}
	}
	k->wedges = w;
}

/* Step 4: acc (3 per wedge, zeroed) receives each wedge's sum. */
static void accumulate(const corners* k, const vn_work* reader, vn_method method, double* acc)
{
	const vn_triangle_fn contribute = method == vn_method_mewcsa ? vn_cotangent_triangle : vn_weighted_triangle;
	const uint32_t* slot = k->count;
	for (uint32_t t = 0; t < k->n / 3; ++t) {
		double p[3][3], c[3][3];
		for (int i = 0; i < 3; ++i)
			vn_load(reader, reader->type, k->idx[3 * t + i], p[i]);
		if (!contribute(method, p[0], p[1], p[2], c))
			continue;
		for (int i = 0; i < 3; ++i) {
			const uint32_t corner = 3 * t + (uint32_t)i, s = slot[k->idx[corner]];
			double* a = acc + 3 * (size_t)k->parent[corner];
			a[0] += c[i][0], a[1] += c[i][1], a[2] += c[i][2];
			if (s != NONE) {
				double* b = acc + 3 * (size_t)s;
				b[0] += c[i][0], b[1] += c[i][1], b[2] += c[i][2];
			}
		}
	}
}

vn_result vn_corner_normals(const vn_vectors* normals, const vn_positions* positions, const uint32_t* indices,
                            size_t index_count, vn_method method, double crease_angle, const uint8_t* sharp_edges,
                            const vn_options* options, vn_stats* stats)
{
	const size_t in_stride = vn_positions_stride(positions), out_stride = vn_vectors_stride(normals);
	if (!in_stride || !out_stride || index_count % 3 || index_count > UINT32_MAX ||
	    (index_count && (!indices || !normals->data)) || !(crease_angle >= 0.0) || !vn_options_valid(options))
		return vn_result_invalid_argument;
	if ((unsigned)method >= vn_method_count)
		return vn_result_unknown_method;
	const uint32_t nv = (uint32_t)positions->count;
	for (size_t i = 0; i < index_count; ++i)
		if (indices[i] >= nv)
			return vn_result_index_out_of_range;

	const vn_work reader = vn_position_reader(positions, in_stride);
	const vn_allocator heap = vn_heap(options ? &options->allocator : NULL);
	corners k;
	memset(&k, 0, sizeof(k));
	k.idx = indices;
	k.nv = nv;
	k.n = (uint32_t)index_count;
	if (index_count > SIZE_MAX / 64) /* the sizes below would wrap (32-bit size_t) */
		return vn_result_out_of_memory;
	/* One block: unit normals, edges, then the two index arrays. */
	const size_t unit_bytes = 3 * sizeof(double) * (k.n / 3), edge_bytes = sizeof(uint64_t) * k.n;
	const size_t block = unit_bytes + edge_bytes + sizeof(uint32_t) * ((size_t)nv + 1 + (size_t)k.n);
	unsigned char* mem = (unsigned char*)heap.allocate(heap.user, block);
	if (!mem)
		return vn_result_out_of_memory;
	k.unit = (double*)mem;
	k.edges = (uint64_t*)(mem + unit_bytes);
	k.count = (uint32_t*)(mem + unit_bytes + edge_bytes);
	k.parent = k.count + nv + 1;

	const size_t degenerate = unit_normals(&k, &reader);
	sort_edges(&k);
	join_wedges(&k, sharp_edges, crease_angle);
	label_wedges(&k);
	double* acc = (double*)heap.allocate(heap.user, 3 * sizeof(double) * (k.wedges ? k.wedges : 1));
	if (!acc) {
		heap.deallocate(heap.user, mem);
		return vn_result_out_of_memory;
	}
	memset(acc, 0, 3 * sizeof(double) * k.wedges);
	accumulate(&k, &reader, method, acc);

	size_t zero = 0;
	for (uint32_t w = 0; w < k.wedges; ++w)
		vn_normalize(acc + 3 * (size_t)w);
	vn_vectors out = *normals;
	out.stride = out_stride;
	for (uint32_t c = 0; c < k.n; ++c) {
		const double* a = acc + 3 * (size_t)k.parent[c];
		zero += a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0;
		vn_store(&out, c, a);
	}
	heap.deallocate(heap.user, acc);
	heap.deallocate(heap.user, mem);
	if (stats) {
		stats->faces = k.n / 3;
		stats->degenerate_faces = degenerate;
		stats->zero_normals = zero;
		stats->nonfinite_vertices = vn_count_nonfinite(&reader, 0, reader.vertex_count);
	}
	return vn_result_success;
}
