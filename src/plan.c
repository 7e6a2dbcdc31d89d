/* Per-frame plans: the topology work of a normal computation done once.
 *
 * vn_plan_create checks the indices once, copies them and lists the corners
 * of every vertex in 8 fixed slots (in input face order; unused slots name
 * a zero corner; vertices with more corners continue in an overflow list).
 * vn_plan_normals on float32 positions then gathers, for the weighted
 * family on triangles, in float arithmetic:
 *  - faces, eight per AVX2 step: each corner's contribution n * w_k (n the
 *    unnormalized normal, w_k the corner's weight as vn_triangle_weights
 *    defines it) as x, y, z, 0; zeros when the face contributes nothing;
 *  - vertices: each adds its slots' corners in order, normalizes, stores.
 * The passes are interleaved in chunks of CHUNK faces, so the corners are
 * read back from cache: each worker writes its faces' corners to a ring,
 * and after each chunk sums the vertices whose last face it held (a
 * schedule built at create). A vertex whose faces span more than the ring,
 * or two workers, or none, is far: its corners are also copied to a far
 * buffer and it is summed after all faces. When most vertices would be far
 * (input without locality), the faces are taken in a breadth-first order
 * instead, the slots still in input order. Each vertex's sum is formed in
 * one fixed order whatever the split and the face order, so results are
 * bit-identical for any thread count; the scalar and AVX2 kernels do the
 * same IEEE operations (fused ones with fmaf), so they agree bit for bit
 * too.
 *
 * float64 positions take vn_triangle_normals' scatter kernels (MWA with
 * vn_atan2_poly's angles), whose results a double gather would have to
 * reproduce bit for bit anyway, and which were as fast here
 * (docs/PERFORMANCE.md); everything else (polygons, the other schemes,
 * per-corner normals) runs the existing entry points on the plan's copy of
 * the indices, with the plan's memory as workspace. */
#include <stdlib.h>

#include "plan.h"
#include "simd.h"
#include "weights.h"

/* ---------------------------------------------------------------- entry points */

/* The bytes vn_polygon_corner_normals (and vn_corner_normals) need as a
 * workspace: vn.h's bound. */
static size_t corner_work_bytes(size_t corners, size_t faces, size_t nv, unsigned threads)
{
	return 36 * corners + 24 * faces + 4 * nv + 64 * (size_t)(threads ? threads : 1) + 64;
}

VN_INLINE size_t round64(size_t n)
{
	return (n + 63) & ~(size_t)63;
}

/* Scratch of vn_plan_create for the gather table, 6 arrays of nv; place
 * (each vertex's place in order[]) reuses first, which only buckets() reads.
 * With a locality order (locality_sort), perm and rank. */
typedef struct build {
	uint32_t *count, *ordinal, *first, *last, *bucket, *far, *place;
	uint32_t* perm; /* the gather's face g is input face perm[g] */
	uint32_t* rank; /* input corner c is corner rank[c] of its vertex, in input order */
	size_t from[MAX_WORKERS + 1]; /* worker t's faces are [from[t], from[t + 1]) */
} build;

/* The bucket of every vertex: the chunk after which it is summed, when its
 * faces are all in one worker's range and still in its ring then, else
 * `chunks` (a far vertex; so are isolated ones and those with more corners
 * than slots); far[] the first far corner of the far ones. Returns the
 * number of far corners. */
static size_t buckets(const vn_plan* plan, build* b)
{
	const unsigned nt = plan->workers;
	const uint32_t chunks = plan->base[nt];
	size_t far = 0;
	for (uint32_t v = 0; v < plan->vertex_count; ++v) {
		uint32_t bucket = chunks;
		if (b->count[v] && b->count[v] <= SLOTS) {
			unsigned lo = 0, hi = nt; /* the worker of the last face: the last range starting at or before it */
			while (hi - lo > 1) {
				const unsigned mid = (lo + hi) / 2;
				if (b->from[mid] <= b->last[v])
					lo = mid;
				else
					hi = mid;
			}
			const size_t chunk = (b->last[v] - b->from[lo]) / CHUNK;
			size_t end = b->from[lo] + (chunk + 1) * CHUNK;
			end = end < b->from[lo + 1] ? end : b->from[lo + 1];
			if (b->first[v] >= b->from[lo] && b->first[v] + (size_t)plan->ring_faces >= end)
				bucket = plan->base[lo] + (uint32_t)chunk;
		}
		b->bucket[v] = bucket;
		if (bucket == chunks) {
			b->far[v] = (uint32_t)far;
			far += b->count[v];
		}
	}
	return far;
}

/* Each vertex's first and last face in the gather's order: input face
 * b->perm[g] (b->perm NULL: g) is its face g. */
static void face_span(const uint32_t* idx, size_t nf, build* b)
{
	for (size_t g = nf; g-- > 0;) {
		const uint32_t* face = idx + 3 * (size_t)(b->perm ? b->perm[g] : g);
		b->first[face[0]] = b->first[face[1]] = b->first[face[2]] = (uint32_t)g;
	}
	for (size_t g = 0; g < nf; ++g) {
		const uint32_t* face = idx + 3 * (size_t)(b->perm ? b->perm[g] : g);
		b->last[face[0]] = b->last[face[1]] = b->last[face[2]] = (uint32_t)g;
	}
}

/* A locality order for faces whose input order has none: breadth first over
 * shared vertices from face 0 (then from the first face not reached, for
 * each further component), so that the faces around a vertex come close
 * together. Sets b->perm and b->rank (from b->count, the corners of each
 * vertex) in one block from the allocator (returned; NULL when it fails);
 * b->bucket and b->far serve as scratch. */
static void* locality_sort(const uint32_t* idx, size_t nf, uint32_t nv, const vn_allocator* heap, build* b)
{
	const size_t ni = 3 * nf;
	/* perm, rank, each vertex's faces (CSR: vface from vstart), reached faces */
	uint32_t* block = (uint32_t*)heap->allocate(heap->user, sizeof(uint32_t) * (nf + 2 * ni + nv + 1) + nf);
	if (!block)
		return NULL;
	uint32_t *perm = block, *rank = perm + nf, *vface = rank + ni, *vstart = vface + ni;
	unsigned char* reached = (unsigned char*)(vstart + nv + 1);
	uint32_t *cursor = b->bucket, *done = b->far;
	vstart[0] = 0;
	for (uint32_t v = 0; v < nv; ++v)
		vstart[v + 1] = vstart[v] + b->count[v], cursor[v] = vstart[v], done[v] = 0;
	for (size_t c = 0; c < ni; ++c) {
		const uint32_t v = idx[c], i = cursor[v]++;
		vface[i] = (uint32_t)(c / 3);
		rank[c] = i - vstart[v];
	}
	memset(reached, 0, nf);
	size_t head = 0, tail = 0;
	for (size_t seed = 0; seed < nf; ++seed) {
		if (reached[seed])
			continue;
		reached[seed] = 1, perm[tail++] = (uint32_t)seed;
		while (head < tail) {
			const uint32_t f = perm[head++];
			for (int k = 0; k < 3; ++k) {
				const uint32_t v = idx[3 * (size_t)f + k];
				for (uint32_t i = vstart[v]; !done[v] && i < vstart[v + 1]; ++i)
					if (!reached[vface[i]])
						reached[vface[i]] = 1, perm[tail++] = vface[i];
				done[v] = 1;
			}
		}
	}
	b->perm = perm, b->rank = rank;
	return block;
}

/* The order in which the vertices are summed: a counting sort by bucket,
 * ascending vertex numbers within one; and each vertex's place in it. */
static void schedule(vn_plan* plan, build* b)
{
	const uint32_t chunks = plan->base[plan->workers], nv = plan->vertex_count;
	uint32_t* start = plan->start;
	memset(start, 0, sizeof(uint32_t) * ((size_t)chunks + 2));
	for (uint32_t v = 0; v < nv; ++v)
		++start[b->bucket[v] + 1];
	for (uint32_t k = 0; k <= chunks; ++k)
		start[k + 1] += start[k];
	for (uint32_t v = 0; v < nv; ++v)
		plan->order[start[b->bucket[v]]++] = v;
	for (uint32_t k = chunks + 1; k > 0; --k)
		start[k] = start[k - 1];
	start[0] = 0;
	b->place = b->first;
	for (uint32_t i = 0; i < nv; ++i)
		b->place[plan->order[i]] = i;
}

/* The slots and overflow codes (ring corners, or far corners for far
 * vertices), the far copies of each chunk, faces in order, and the chunks
 * with the last vertex. */
static void corner_table(vn_plan* plan, build* b)
{
	const uint32_t nv = plan->vertex_count, chunks = plan->base[plan->workers];
	const uint32_t ring_pad = (uint32_t)(sizeof(float) * CORNER(3 * plan->ring_faces));
	const uint32_t far_pad = (uint32_t)(sizeof(float) * CORNER(plan->far_count));
	/* The far vertices come last in the order. */
	const size_t first_far = SLOTS * (size_t)plan->start[chunks];
	for (size_t i = 0; i < SLOTS * (size_t)nv; ++i)
		plan->slots[i] = i < first_far ? ring_pad : far_pad;
	memset(plan->last_in_chunk, 0, chunks);
	uint32_t start = 0;
	for (uint32_t v = 0; v < nv; ++v)
		if (b->count[v] > SLOTS) {
			const uint32_t k = b->ordinal[v];
			plan->over_vertex[k] = v;
			plan->over_start[k] = start;
			start += b->count[v] - SLOTS;
		}
	plan->over_start[plan->over_count] = start;
	memset(b->count, 0, sizeof(uint32_t) * nv);
	unsigned t = 0;
	uint32_t e = 0, next = 0;
	for (size_t f = 0; f < plan->face_count; ++f) { /* f in the gather's order */
		while (f >= b->from[t + 1])
			++t;
		const size_t local = f - b->from[t];
		const uint32_t chunk = plan->base[t] + (uint32_t)(local / CHUNK);
		const uint32_t place = (uint32_t)(local % plan->ring_faces);
		const uint32_t* face = plan->faces + 3 * f;
		const uint32_t* rank = b->rank ? b->rank + 3 * (size_t)b->perm[f] : NULL;
		while (next <= chunk)
			plan->far_start[next++] = e;
		plan->last_in_chunk[chunk] |= (face[0] == nv - 1) | (face[1] == nv - 1) | (face[2] == nv - 1);
		for (uint32_t k = 0; k < 3; ++k) {
			const uint32_t v = face[k], j = rank ? rank[k] : b->count[v]++;
			const uint32_t ring = k * plan->ring_faces + place;
			uint32_t code = (uint32_t)(sizeof(float) * CORNER(ring));
			if (b->bucket[v] == chunks) {
				plan->far_from[e] = ring;
				plan->far_to[e] = b->far[v] + j;
				code = (uint32_t)(sizeof(float) * CORNER(plan->far_to[e++]));
			}
			if (j < SLOTS)
				plan->slots[SLOTS * (size_t)b->place[v] + j] = code;
			else
				plan->over_code[plan->over_start[b->ordinal[v]] + j - SLOTS] = code;
		}
	}
	while (next <= chunks)
		plan->far_start[next++] = e;
}

/* Whether the gather's loads may take plan->words for the stride, made
 * first when they are for another: not when the stride is no multiple of
 * 4 bytes, nor when the last position's 16-byte load ends beyond 2^32
 * words (such loads multiply index by stride). */
static int words_for(vn_plan* plan, size_t stride)
{
	if (stride % 4 || (uint64_t)plan->vertex_count * (stride / 4) + 4 > UINT32_MAX)
		return 0;
	if (plan->words_stride != stride) {
		const uint32_t k = (uint32_t)(stride / 4);
		for (size_t i = 0; i < plan->index_count; ++i)
			plan->words[i] = plan->faces[i] * k;
		plan->words_stride = stride;
	}
	return 1;
}

vn_result vn_plan_create(const uint32_t* indices, const uint32_t* face_offsets, size_t face_count,
                         size_t vertex_count, const vn_options* options, vn_plan** out)
{
	if (!out || !vn_options_valid(options) || vertex_count > UINT32_MAX)
		return vn_result_invalid_argument;
	static const vn_options defaults;
	const vn_options* o = options ? options : &defaults;
	size_t ni;
	if (face_offsets) {
		if (face_count > UINT32_MAX - 1)
			return vn_result_invalid_argument;
		for (size_t f = 0; f < face_count; ++f)
			if (face_offsets[f + 1] < face_offsets[f])
				return vn_result_invalid_argument;
		ni = face_offsets[face_count];
	} else {
		if (face_count > UINT32_MAX / 3)
			return vn_result_invalid_argument;
		ni = 3 * face_count;
	}
	if (ni && !indices)
		return vn_result_invalid_argument;
	const uint32_t nv = (uint32_t)vertex_count;
	vn_result r = vn_check_indices(indices, ni, nv);
	if (r != vn_result_success)
		return r;

	const vn_allocator heap = vn_heap(&o->allocator);
	int gather = !face_offsets && nv;
	const unsigned workers = vn_worker_count(nv, o->threads);
	/* The chunks of each worker, and the ring: a window of faces, fewer when
	 * every worker has fewer. */
	build b;
	memset(&b, 0, sizeof(b));
	uint32_t chunks = 0, base[MAX_WORKERS + 1], ring_faces = CHUNK;
	for (unsigned t = 0; t < workers; ++t) {
		size_t hi;
		split(face_count, t, workers, &b.from[t], &hi);
		b.from[t + 1] = hi;
		base[t] = chunks;
		const size_t k = (hi - b.from[t] + CHUNK - 1) / CHUNK;
		chunks += gather ? (uint32_t)k : 0;
		ring_faces = k * CHUNK > ring_faces ? (uint32_t)(k * CHUNK < WINDOW ? k * CHUNK : WINDOW) : ring_faces;
	}
	base[workers] = chunks;

	/* Scratch: corners, overflow ordinal, first and last face, bucket, far
	 * corner of each vertex; with a locality order, its scratch and faces. */
	size_t over_count = 0, over_codes = 0, far = 0;
	void* sort = NULL;
	vn_plan shape; /* what buckets() reads */
	memset(&shape, 0, sizeof(shape));
	if (gather) {
		if (!(b.count = (uint32_t*)heap.allocate(heap.user, 6 * sizeof(uint32_t) * nv)))
			return vn_result_out_of_memory;
		b.ordinal = b.count + nv, b.first = b.ordinal + nv, b.last = b.first + nv;
		b.bucket = b.last + nv, b.far = b.bucket + nv;
		memset(b.count, 0, sizeof(uint32_t) * nv);
		for (size_t i = 0; i < ni; ++i)
			++b.count[indices[i]];
		for (uint32_t v = 0; v < nv; ++v)
			if (b.count[v] > SLOTS)
				b.ordinal[v] = (uint32_t)over_count++, over_codes += b.count[v] - SLOTS;
		shape.vertex_count = nv;
		shape.workers = workers;
		shape.ring_faces = ring_faces;
		memcpy(shape.base, base, sizeof(uint32_t) * (workers + 1));
		face_span(indices, face_count, &b);
		far = buckets(&shape, &b);
		/* More than a quarter of the corners far: the input's order has no
		 * locality (a shuffled file), so the gather takes faces in a
		 * locality order; a good order stays as it is. */
		if (far > ni / 4) {
			if (!(sort = locality_sort(indices, face_count, nv, &heap, &b))) {
				heap.deallocate(heap.user, b.count);
				return vn_result_out_of_memory;
			}
			face_span(indices, face_count, &b);
			far = buckets(&shape, &b);
		}
		if (far >= MAX_FAR) { /* no locality at all: the existing entry points */
			heap.deallocate(heap.user, b.count);
			if (sort)
				heap.deallocate(heap.user, sort);
			memset(&b, 0, sizeof(b));
			sort = NULL;
			gather = 0, far = 0, over_count = over_codes = 0, chunks = 0;
			memset(base, 0, sizeof(base));
		}
	}

	const size_t record_bytes = gather ? 16 * ((3 * (size_t)ring_faces + 4) * workers + far + 1) : 0;
	size_t work = vn_workspace_size(nv, o);
	const size_t corner_bytes = corner_work_bytes(ni, face_count, nv, o->threads);
	work = work > corner_bytes ? work : corner_bytes;
	work = work > record_bytes ? work : record_bytes;
	const size_t head = round64(sizeof(vn_plan));
	const size_t idx_bytes = round64(sizeof(uint32_t) * ni);
	const size_t word_bytes = gather ? idx_bytes : 0, sorted_bytes = sort ? idx_bytes : 0;
	const size_t off_bytes = face_offsets ? round64(sizeof(uint32_t) * (face_count + 1)) : 0;
	const size_t slot_bytes = gather ? round64(sizeof(uint32_t) * SLOTS * (size_t)nv) : 0;
	const size_t over_bytes = round64(sizeof(uint32_t) * (2 * over_count + 1 + over_codes));
	const size_t order_bytes = gather ? round64(sizeof(uint32_t) * ((size_t)nv + chunks + 2)) : 0;
	const size_t far_bytes = gather ? round64(sizeof(uint32_t) * (chunks + 1 + 2 * far)) + round64(chunks) : 0;
	const size_t total =
	    head + idx_bytes + word_bytes + sorted_bytes + off_bytes + slot_bytes + over_bytes + order_bytes + far_bytes +
	    round64(work) + 64;
	unsigned char* block = (unsigned char*)heap.allocate(heap.user, total);
	if (!block) {
		if (sort)
			heap.deallocate(heap.user, sort);
		if (b.count)
			heap.deallocate(heap.user, b.count);
		return vn_result_out_of_memory;
	}
	vn_plan* plan = (vn_plan*)block;
	memset(plan, 0, sizeof(*plan));
	unsigned char* at = block + head;
	plan->opt = *o;
	plan->vertex_count = nv;
	plan->face_count = face_count;
	plan->index_count = ni;
	plan->gather = gather;
	plan->simd = o->simd == vn_simd_auto && vn_cpu_has_avx2_fma();
	plan->workers = workers;
	plan->indices = (uint32_t*)at;
	if (ni)
		memcpy(plan->indices, indices, sizeof(uint32_t) * ni);
	at += idx_bytes;
	plan->words = (uint32_t*)at;
	at += word_bytes;
	plan->faces = plan->indices;
	if (sort) {
		plan->faces = (uint32_t*)at;
		for (size_t f = 0; f < face_count; ++f)
			memcpy(plan->faces + 3 * f, indices + 3 * (size_t)b.perm[f], 3 * sizeof(uint32_t));
		at += sorted_bytes;
	}
	if (face_offsets) {
		plan->offsets = (uint32_t*)at;
		memcpy(plan->offsets, face_offsets, sizeof(uint32_t) * (face_count + 1));
		at += off_bytes;
	}
	plan->slots = (uint32_t*)at;
	at += slot_bytes;
	plan->over_count = over_count;
	plan->over_vertex = (uint32_t*)at;
	plan->over_start = plan->over_vertex + over_count;
	plan->over_code = plan->over_start + over_count + 1;
	at += over_bytes;
	plan->order = (uint32_t*)at;
	plan->start = plan->order + nv;
	memcpy(plan->base, base, sizeof(uint32_t) * (workers + 1));
	at += order_bytes;
	plan->ring_faces = ring_faces;
	plan->far_count = far;
	plan->far_start = (uint32_t*)at;
	plan->far_from = plan->far_start + chunks + 1;
	plan->far_to = plan->far_from + far;
	plan->last_in_chunk = (uint8_t*)(at + round64(sizeof(uint32_t) * (chunks + 1 + 2 * far)));
	at += far_bytes;
	/* 64-byte alignment: 8 faces' corners k are 2 cache lines. */
	plan->corners = (float*)(block + ((((uintptr_t)at + 63) & ~(uintptr_t)63) - (uintptr_t)block));
	plan->opt.workspace = plan->corners;
	plan->opt.workspace_size = work;

	if (gather) {
		schedule(plan, &b);
		corner_table(plan, &b);
		heap.deallocate(heap.user, b.count);
		if (sort)
			heap.deallocate(heap.user, sort);
		words_for(plan, 3 * sizeof(float)); /* packed float32, the common layout */
	}
	*out = plan;
	return vn_result_success;
}

void vn_plan_destroy(vn_plan* plan)
{
	if (!plan)
		return;
	const vn_allocator heap = vn_heap(&plan->opt.allocator);
	heap.deallocate(heap.user, plan);
}

/* The positions' stride when they fit the plan, else 0. */
static size_t plan_positions(const vn_plan* plan, const vn_positions* positions, const vn_vectors* normals)
{
	const size_t stride = vn_positions_stride(positions);
	if (!plan || !stride || positions->count != plan->vertex_count || !vn_vectors_stride(normals) ||
	    (positions->count && !normals->data))
		return 0;
	return stride;
}

vn_result vn_plan_normals(vn_plan* plan, const vn_positions* positions, vn_method method, const vn_vectors* normals,
                          vn_stats* stats)
{
	const size_t stride = plan_positions(plan, positions, normals);
	if (!stride)
		return vn_result_invalid_argument;
	if ((unsigned)method >= vn_method_count)
		return vn_result_unknown_method;
	if (!plan->gather || method > vn_method_mwrelr || positions->type != vn_scalar_float32) {
		if (plan->offsets)
			return vn_polygon_normals(normals, positions, plan->indices, plan->offsets, plan->face_count, method,
			                          &plan->opt, stats);
		if (method == vn_method_mwa && positions->type == vn_scalar_float64)
			return vn_triangle_normals_mwa_poly(normals, positions, plan->indices, plan->index_count, &plan->opt,
			                                    stats);
		return vn_triangle_normals(normals, positions, plan->indices, plan->index_count, method, &plan->opt, stats);
	}

	vn_plan_gather(plan, positions, stride, words_for(plan, stride) ? plan->words : NULL, method, normals, stats);
	return vn_result_success;
}

vn_result vn_plan_corner_normals(vn_plan* plan, const vn_positions* positions, vn_method method, double crease_angle,
                                 const uint8_t* sharp_edges, const vn_vectors* normals, vn_stats* stats)
{
	if (!plan_positions(plan, positions, normals))
		return vn_result_invalid_argument;
	if (plan->offsets)
		return vn_polygon_corner_normals(normals, positions, plan->indices, plan->offsets, plan->face_count, method,
		                                 crease_angle, sharp_edges, &plan->opt, stats);
	return vn_corner_normals(normals, positions, plan->indices, plan->index_count, method, crease_angle, sharp_edges,
	                         &plan->opt, stats);
}
