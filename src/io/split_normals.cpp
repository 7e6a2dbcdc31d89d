/*
 * The normals plan of split_normals.h: welding, hard edges from the input
 * normals, crease splitting, and the normals libvn computes on it.
 */
#include "split_normals.h"

#include <algorithm>
#include <map>
#include <type_traits>

namespace vn_split {

/* Small on purpose: exporters give the copies along UV seams the same
 * normal, and converting vn's output again must find its hard edges again
 * (a larger angle would smooth those whose two sides' normals came out
 * closer than it). See README.md, "glTF". */
const double default_hard_edge_angle = 0.1 * M_PI / 180;

namespace {

template <typename T>
vn_vectors vectors(T* data)
{
	return {data, 0, std::is_same<T, float>::value ? vn_scalar_float32 : vn_scalar_float64};
}

/* The corner after corner k in its face. */
struct next_corner {
	const faces& f;
	std::vector<uint32_t> next; /* polygons only */
	explicit next_corner(const faces& faces_) : f(faces_)
	{
		if (!f.offsets)
			return;
		next.resize(f.corner_count);
		for (size_t i = 0; i < f.face_count; ++i)
			for (uint32_t k = f.offsets[i]; k < f.offsets[i + 1]; ++k)
				next[k] = k + 1 < f.offsets[i + 1] ? k + 1 : f.offsets[i];
	}
	size_t operator()(size_t k) const { return f.offsets ? next[k] : k - k % 3 + (k + 1) % 3; }
};

/* Welded vertex normals of positions q into v, copied to every vertex of
 * each group (the representative is the group's lowest index, so it is
 * final by the time the others copy it). */
template <typename T>
vn_result vertex_normals(const plan& g, const vn_positions& q, T* v, vn_stats* stats)
{
	const vn_vectors vv = vectors(v);
	const vn_result r =
	    g.f.offsets ? vn_polygon_normals(&vv, &q, g.welded, g.f.offsets, g.f.face_count, g.method, &g.options, stats)
	                : vn_triangle_normals(&vv, &q, g.welded, g.f.corner_count, g.method, &g.options, stats);
	if (r != vn_result_success)
		return r;
	for (size_t i = 0; i < g.n; ++i)
		if (g.remap[i] != i)
			std::copy_n(&v[3 * g.remap[i]], 3, &v[3 * i]);
	return r;
}

/* Per-corner normals of positions q on the welded faces into c. */
template <typename T>
vn_result corner_normals(const plan& g, const vn_positions& q, T* c, vn_stats* stats)
{
	const vn_vectors cv = vectors(c);
	const uint8_t* sharp = g.sharp.empty() ? nullptr : g.sharp.data();
	return g.f.offsets ? vn_polygon_corner_normals(&cv, &q, g.welded, g.f.offsets, g.f.face_count, g.method, g.crease,
	                                               sharp, &g.options, stats)
	                   : vn_corner_normals(&cv, &q, g.welded, g.f.corner_count, g.method, g.crease, sharp, &g.options,
	                                       stats);
}

/* Per vertex: whether it represents copies welding merged into it. */
std::vector<uint8_t> merged_representatives(const plan& g)
{
	std::vector<uint8_t> merged(g.n, 0);
	for (size_t i = 0; i < g.n; ++i)
		if (g.remap[i] != i)
			merged[g.remap[i]] = 1;
	return merged;
}

/* Flags the corners whose edge joins welded copies with input normals more
 * than `angle` apart at either end; returns how many edges that makes (an
 * edge is flagged from both sides). */
size_t flag_hard_edges(plan& g, double angle)
{
	if (g.input_normals.count == 0)
		return 0;
	const double limit = std::cos(angle);
	auto differ = [&](uint32_t a, uint32_t b) {
		double x[3], y[3];
		load(g.input_normals, a, x);
		load(g.input_normals, b, y);
		double lx = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
		double ly = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
		return a != b && lx > 0 && ly > 0 && (x[0] * y[0] + x[1] * y[1] + x[2] * y[2]) < limit * lx * ly;
	};
	const next_corner next(g.f);
	const uint32_t* w = g.welded;
	const uint32_t* in = g.f.corners;
	/* Only an edge with an end where welding merged copies can join copies
	 * with different input normals: the others need no search (on a file
	 * without split vertices, that is every edge). */
	const std::vector<uint8_t> merged = merged_representatives(g);
	auto candidate = [&](size_t k) { return merged[w[k]] || merged[w[next(k)]]; };
	std::vector<std::pair<uint64_t, uint32_t>> edges;
	for (size_t k = 0; k < g.f.corner_count; ++k)
		if (candidate(k))
			edges.push_back({(uint64_t)w[k] << 32 | w[next(k)], (uint32_t)k});
	std::sort(edges.begin(), edges.end());
	g.sharp.assign(g.f.corner_count, 0);
	size_t flagged = 0;
	for (size_t k = 0; k < g.f.corner_count; ++k) {
		if (!candidate(k) || w[k] == w[next(k)])
			continue; /* no merged end, or a repeated vertex (no edge) */
		const uint64_t opposite = (uint64_t)w[next(k)] << 32 | w[k];
		auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(opposite, (uint32_t)0));
		for (; it != edges.end() && it->first == opposite && !g.sharp[k]; ++it) {
			const size_t j = it->second;
			g.sharp[k] = differ(in[k], in[next(j)]) || differ(in[next(k)], in[j]);
		}
		flagged += g.sharp[k] && w[k] < w[next(k)];
	}
	return flagged;
}

/* Welded copies whose input normals are opposed are the two sides of a
 * double-sided surface (a face and its reverse, each on its own copies, as
 * exporters write them), not copies split along a seam: welded, every edge
 * between them would have four faces and each vertex's sum would cancel
 * to rounding noise. So each copy, in index order, joins the first side
 * of its position (the copies welded so far) whose unit input normals'
 * sum it is not opposed to, more than 120 degrees from it; else it starts
 * one, with itself as representative (the lowest index of its side, as
 * vertex_normals needs). A copy without a usable input normal joins the
 * first side. A position has at most MAX_SIDES sides (a later copy opposed
 * to them all joins the first): more than three directions cannot be
 * pairwise that far apart, so only a crafted file would reach it. */
void separate_sides(plan& g)
{
	constexpr size_t MAX_SIDES = 4;
	struct side {
		uint32_t rep, next;
		double sum[3];
	};
	const std::vector<uint8_t> merged = merged_representatives(g);
	std::vector<side> sides;
	std::vector<uint32_t> first(g.n, UINT32_MAX); /* a representative's first side */
	for (uint32_t i = 0; i < g.n; ++i) {
		const uint32_t r = g.remap[i];
		if (!merged[r])
			continue;
		double x[3];
		load(g.input_normals, i, x);
		const double len = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
		for (double& c : x)
			c = len > 0 && std::isfinite(len) ? c / len : 0;
		uint32_t* link = &first[r];
		size_t count = 0;
		uint32_t k = first[r];
		for (; k != UINT32_MAX; link = &sides[k].next, k = sides[k].next, ++count) {
			const double* m = sides[k].sum;
			const double d = x[0] * m[0] + x[1] * m[1] + x[2] * m[2];
			if (d >= -0.5 * std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]))
				break;
		}
		if (k == UINT32_MAX && count >= MAX_SIDES)
			k = first[r];
		if (k == UINT32_MAX) {
			*link = (uint32_t)sides.size();
			sides.push_back({i, UINT32_MAX, {x[0], x[1], x[2]}});
			g.remap[i] = i;
		} else {
			for (int d = 0; d < 3; ++d)
				sides[k].sum[d] += x[d];
			g.remap[i] = sides[k].rep;
		}
	}
}

/* Split vertices for per-corner normals c: a corner whose normal differs
 * from the first one of its input vertex gets a new vertex, shared by the
 * vertex's corners with the same normal. */
template <typename T>
void split_corners(plan& g, const std::vector<T>& c)
{
	std::vector<uint32_t> owner(g.n, UINT32_MAX);
	std::map<uint32_t, std::vector<uint32_t>> extras; /* input vertex -> its split vertices' first corner */
	g.corner_output.assign(g.f.corner_count, 0);
	for (size_t k = 0; k < g.f.corner_count; ++k) {
		const uint32_t i = g.f.corners[k];
		if (owner[i] == UINT32_MAX || std::equal(&c[3 * k], &c[3 * k] + 3, &c[3 * owner[i]])) {
			if (owner[i] == UINT32_MAX)
				owner[i] = (uint32_t)k;
			g.corner_output[k] = i;
			continue;
		}
		std::vector<uint32_t>& mine = extras[i];
		size_t e = 0;
		while (e < mine.size() && !std::equal(&c[3 * k], &c[3 * k] + 3, &c[3 * mine[e]]))
			++e;
		if (e == mine.size()) {
			mine.push_back((uint32_t)k);
			g.extra_source.push_back(i);
			g.corner_output[k] = (uint32_t)(g.n + g.extra_source.size() - 1);
		} else {
			g.corner_output[k] = g.corner_output[mine[e]];
		}
	}
}

} // namespace

template <typename T>
vn_result make_plan(plan& g, const vn_positions& pos, const faces& f, const vn_positions& input_normals,
                    const settings& s, std::vector<T>& c, vn_stats* stats)
{
	g.n = pos.count;
	g.f = f;
	g.input_normals = input_normals;
	g.method = s.method;
	memset(&g.options, 0, sizeof g.options);
	g.options.threads = s.threads;
	g.remap.resize(g.n);
	for (size_t i = 0; i < g.n; ++i)
		g.remap[i] = (uint32_t)i;
	if (s.weld) {
		const vn_result r = vn_weld_positions(g.remap.data(), &pos, s.weld_epsilon, &g.options);
		if (r != vn_result_success)
			return r;
		if (input_normals.count)
			separate_sides(g);
		for (size_t i = 0; i < g.n; ++i)
			g.welded_vertices += g.remap[i] != i;
	}
	g.welded = f.corners;
	if (g.welded_vertices) {
		g.welded_corners.resize(f.corner_count);
		for (size_t k = 0; k < f.corner_count; ++k)
			g.welded_corners[k] = g.remap[f.corners[k]];
		g.welded = g.welded_corners.data();
	}
	/* Hard edges join welded copies: none without welding. */
	g.hard_edges = g.welded_vertices ? flag_hard_edges(g, s.crease ? s.crease_angle : default_hard_edge_angle) : 0;
	if (!g.hard_edges)
		g.sharp.clear();
	g.corner_normals = s.crease || !g.sharp.empty();
	if (s.crease) {
		g.crease = s.crease_angle;
		c.resize(3 * f.corner_count);
		const vn_result r = corner_normals(g, pos, c.data(), stats);
		if (r != vn_result_success)
			return r;
		split_corners(g, c);
	}
	return vn_result_success;
}

template <typename T>
vn_result normals(const plan& g, const vn_positions& q, std::vector<T>& out, const std::vector<T>* computed,
                  vn_stats* stats)
{
	out.assign(3 * g.outputs(), 0);
	if (!g.corner_normals)
		return vertex_normals(g, q, out.data(), stats);
	std::vector<T> own;
	if (!computed) {
		own.resize(3 * g.f.corner_count);
		const vn_result r = corner_normals(g, q, own.data(), stats);
		if (r != vn_result_success)
			return r;
		stats = nullptr;
	}
	const std::vector<T>& c = computed ? *computed : own;
	if (!g.corner_output.empty()) {
		for (size_t k = 0; k < g.f.corner_count; ++k)
			std::copy_n(&c[3 * k], 3, &out[3 * g.corner_output[k]]);
		return vn_result_success;
	}
	/* No splitting: a vertex whose corners disagree (its fans are not
	 * separated in the file) gets the smooth normal. */
	std::vector<uint32_t> seen(g.n, UINT32_MAX);
	std::vector<uint8_t> conflict(g.n, 0);
	for (size_t k = 0; k < g.f.corner_count; ++k) {
		const uint32_t i = g.f.corners[k];
		if (seen[i] == UINT32_MAX)
			seen[i] = (uint32_t)k, std::copy_n(&c[3 * k], 3, &out[3 * i]);
		else if (!std::equal(&c[3 * k], &c[3 * k] + 3, &c[3 * seen[i]]))
			conflict[i] = 1;
	}
	if (std::find(conflict.begin(), conflict.end(), 1) != conflict.end()) {
		std::vector<T> v(3 * g.n);
		const vn_result r = vertex_normals(g, q, v.data(), stats);
		if (r != vn_result_success)
			return r;
		for (size_t i = 0; i < g.n; ++i)
			if (conflict[i])
				std::copy_n(&v[3 * i], 3, &out[3 * i]);
	}
	return vn_result_success;
}

template vn_result make_plan<float>(plan&, const vn_positions&, const faces&, const vn_positions&, const settings&,
                                   std::vector<float>&, vn_stats*);
template vn_result make_plan<double>(plan&, const vn_positions&, const faces&, const vn_positions&, const settings&,
                                    std::vector<double>&, vn_stats*);
template vn_result normals<float>(const plan&, const vn_positions&, std::vector<float>&, const std::vector<float>*,
                                  vn_stats*);
template vn_result normals<double>(const plan&, const vn_positions&, std::vector<double>&, const std::vector<double>*,
                                   vn_stats*);

} // namespace vn_split
