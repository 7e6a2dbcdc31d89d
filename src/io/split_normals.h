/*
 * Normals of a mesh as files split it (C++ only, internal to vn_io): the
 * plan every conversion follows, glTF primitives (gltf_normals.cpp) and
 * vn_io_mesh (mesh_normals.cpp) alike. Vertices are welded by position,
 * edges between welded copies whose input normals differ stay hard,
 * --crease-angle adds hard edges and splits the vertices whose corners
 * need different normals; a face and its reverse on the same vertices
 * (a two-sided sheet) are computed apart and the vertices split between
 * them; the result is one normal per output vertex (the input's, then the
 * split ones). Triangles, or polygons through face
 * offsets, on plain arrays; normals as float or double (T).
 */
#ifndef VN_IO_SPLIT_NORMALS_H
#define VN_IO_SPLIT_NORMALS_H

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "vn.h"

namespace vn_split {

/* Vector i of v (float32 or float64, any stride) as doubles. */
inline void load(const vn_positions& v, size_t i, double out[3])
{
	const size_t stride = v.stride ? v.stride : v.type == vn_scalar_float32 ? 12 : 24;
	const unsigned char* p = (const unsigned char*)v.data + i * stride;
	if (v.type == vn_scalar_float32) {
		float f[3];
		memcpy(f, p, sizeof f);
		out[0] = f[0], out[1] = f[1], out[2] = f[2];
	} else {
		memcpy(out, p, 3 * sizeof(double));
	}
}

/* Without a crease angle, welded copies whose input normals differ by more
 * than this keep a hard edge between them (see split_normals.cpp). */
extern const double default_hard_edge_angle;

struct settings {
	vn_method method = vn_method_mwa;
	unsigned threads = 0;
	bool weld = true;
	double weld_epsilon = 0;    /* vn_weld_positions' */
	bool crease = false;        /* split at crease_angle (radians) */
	double crease_angle = 0;
};

/* The faces on the input vertices: triangles (offsets null, 3 corners
 * each) or polygons (face f is corners offsets[f] .. offsets[f + 1]). */
struct faces {
	const uint32_t* corners = nullptr;
	size_t corner_count = 0;
	const uint32_t* offsets = nullptr;
	size_t face_count = 0;
};

/* How a mesh gets its normals (make_plan): the same plan serves other
 * positions of the same mesh (glTF morph targets). */
struct plan {
	size_t n = 0;                       /* input vertices */
	faces f;                            /* on input vertices */
	std::vector<uint32_t> remap;        /* input vertex -> welded representative */
	const uint32_t* welded = nullptr;   /* corners on welded vertices (and backs, from n on) */
	std::vector<uint32_t> welded_corners; /* what `welded` points at, when welding merged vertices */
	vn_positions input_normals = {nullptr, 0, 0, vn_scalar_float64}; /* count 0, or one per input vertex */
	bool corner_normals = false;        /* per-corner normals (hard edges or a crease angle) */
	double crease = M_PI;               /* radians; pi: no crease */
	std::vector<uint8_t> sharp;         /* per corner: edges whose input normals differ */
	std::vector<uint32_t> corner_output; /* per corner: output vertex, when splitting */
	std::vector<uint32_t> extra_source; /* output vertex n + k -> input vertex */
	std::vector<uint32_t> back_source;  /* welded vertex n + k (a two-sided vertex's back) -> its front */
	bool crease_split = false;          /* corner_output follows the corner normals at a crease angle */
	vn_method method = vn_method_mwa;
	vn_options options{};
	size_t welded_vertices = 0, hard_edges = 0;

	size_t outputs() const { return n + extra_source.size(); }
	/* The vertices the normals are computed on: the input's, then the backs. */
	size_t computed() const { return n + back_source.size(); }
	/* The input vertex output vertex k copies. */
	size_t source(size_t k) const { return k < n ? k : extra_source[k - n]; }
	/* The faces on the output vertices: corner_output when split, else the input's. */
	const uint32_t* output_corners() const { return extra_source.empty() ? f.corners : corner_output.data(); }
};

/* Plans g (new) for the pos.count vertices at pos with faces f (every
 * index < pos.count) and input normals (count 0: none); the plan keeps
 * views of f and input_normals. With a crease angle, c receives the corner
 * normals the split follows, for normals() to reuse, and stats (may be
 * null) the faces and degenerate faces. */
template <typename T>
vn_result make_plan(plan& g, const vn_positions& pos, const faces& f, const vn_positions& input_normals,
                    const settings& s, std::vector<T>& c, vn_stats* stats);

/* The plan's normals for positions q (q.count == g.n): one unit vector per
 * output vertex into out (3 each), or (0, 0, 0) for a vertex no face
 * contributes to (the caller chooses what those get). computed: c from
 * make_plan for the same positions, else null. stats (may be null): the
 * faces and degenerate faces, when this call computes (computed null). */
template <typename T>
vn_result normals(const plan& g, const vn_positions& q, std::vector<T>& out, const std::vector<T>* computed,
                  vn_stats* stats);

} // namespace vn_split

#endif /* VN_IO_SPLIT_NORMALS_H */
