/* Per-frame plans' layout, private to plan.c (create, the corner table,
 * the entry points) and plan_gather.c (vn_plan_normals' float32 gather);
 * plan.c's opening comment describes both. */
#ifndef VN_PLAN_H
#define VN_PLAN_H

#include "internal.h"

#define SLOTS 8
#define MAX_WORKERS 256 /* vn_parallel's limit */
/* Faces per chunk (48 KB of corners), and the largest ring: the faces whose
 * corners a worker keeps (768 KB, within a core's L2; vertices whose faces
 * span more are far). */
#define CHUNK 2048
#define WINDOW 16384
/* Slots hold byte offsets of corners (16 bytes each), so far corners must
 * be fewer than 2^28. */
#define MAX_FAR (1u << 28)
/* Corner c's x, y, z, 0 in a corner buffer, in floats. */
#define CORNER(c) (4 * (size_t)(c))

struct vn_plan {
	vn_options opt; /* the caller's, workspace set to the plan's memory */
	uint32_t vertex_count;
	size_t face_count, index_count;
	uint32_t* indices;
	uint32_t* offsets; /* NULL for triangles */
	/* The gather's faces: indices, or their locality order when the input
	 * has none (vn_plan_create); the slots keep each vertex's corners in
	 * input order either way. */
	uint32_t* faces;
	/* For the gather's position loads (one instruction fewer than index
	 * times stride): indices[i] * words_stride / 4, the position's offset
	 * in 4-byte words for that stride (0: none yet), in faces' order; made for packed
	 * float32 at create, again for another stride when a call brings one. */
	uint32_t* words;
	size_t words_stride;
	int gather;        /* triangles with the corner table below */
	int simd;
	unsigned workers;
	uint32_t* slots; /* SLOTS corners of each vertex in order[], as byte offsets into its buffer */
	size_t over_count;
	uint32_t* over_vertex; /* vertices with more than SLOTS corners (all far), ascending */
	uint32_t* over_start;  /* over_count + 1 offsets into over_code */
	uint32_t* over_code;
	/* Vertices in the order they are summed: worker t's chunk k's vertices
	 * are order[start[base[t] + k] .. start[base[t] + k + 1]), then the
	 * far vertices from start[chunks] to the end. */
	uint32_t* order;
	uint32_t* start;
	uint32_t base[MAX_WORKERS + 1];
	/* Each worker writes its faces' corners to a ring of ring_faces faces
	 * (3 planes of ring_faces corners, then a zero corner and padding to 64
	 * bytes), corner k of face f at k ring_faces + (f - first face) mod
	 * ring_faces. A vertex summed after a chunk names ring corners
	 * (its faces are all still there); any other (far) vertex names
	 * corners of the far buffer (far_count and a zero one), in which its
	 * corners are consecutive: chunk k copies ring corner far_from[e] to
	 * far_to[e] for e in far_start[k] .. far_start[k + 1]. */
	uint32_t ring_faces;
	size_t far_count;
	uint32_t* far_start;
	uint32_t* far_from;
	uint32_t* far_to;
	uint8_t* last_in_chunk; /* whether a face of chunk k has the last vertex */
	float* corners; /* the rings, then the far buffer, 4 floats a corner, 64-byte aligned; also the workspace */
};

/* The floats of a worker's ring, its zero corner and padding: rings stay
 * 64-byte aligned for the face pass's 32-byte stores. */
#define RING(plan) CORNER(3 * (size_t)(plan)->ring_faces + 4)

/* The range of worker t of n when items are split into multiples of 8. */
VN_INLINE void split(size_t n, unsigned t, unsigned nt, size_t* lo, size_t* hi)
{
	*lo = t ? ((uint64_t)n * t / nt) & ~(size_t)7 : 0;
	*hi = t + 1 < nt ? ((uint64_t)n * (t + 1) / nt) & ~(size_t)7 : n;
}

/* vn_plan_normals on the gather path (float32 positions with the given
 * byte stride, a scheme of the weighted family, triangles): both passes on
 * the plan's workers; words is plan->words when it holds that stride's
 * offsets, else NULL; stats may be NULL. */
void vn_plan_gather(const vn_plan* plan, const vn_positions* positions, size_t stride, const uint32_t* words,
                    vn_method method, const vn_vectors* normals, vn_stats* stats);

#endif
