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

/* Per computed vertex: whether it represents copies welding merged into
 * it (a back: whether its front does). */
std::vector<uint8_t> merged_representatives(const plan& g)
{
	std::vector<uint8_t> merged(g.computed(), 0);
	for (size_t i = 0; i < g.n; ++i)
		if (g.remap[i] != i)
			merged[g.remap[i]] = 1;
	for (size_t k = 0; k < g.back_source.size(); ++k)
		merged[g.n + k] = merged[g.back_source[k]];
	return merged;
}

/* Positions q (q.count == g.n) for the computed vertices: q itself, or with
 * each back's front position appended (into store). */
vn_positions computed_positions(const plan& g, const vn_positions& q, std::vector<double>& store)
{
	if (g.back_source.empty())
		return q;
	store.resize(3 * g.computed());
	for (size_t i = 0; i < g.n; ++i)
		load(q, i, &store[3 * i]);
	for (size_t k = 0; k < g.back_source.size(); ++k)
		std::copy_n(&store[3 * g.back_source[k]], 3, &store[3 * (g.n + k)]);
	return {store.data(), g.computed(), 0, vn_scalar_float64};
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

/* Whether the k vertices at v repeat one (scratch: a work vector). */
bool repeats(const uint32_t* v, size_t k, std::vector<uint32_t>& scratch)
{
	if (k <= 8) {
		for (size_t i = 1; i < k; ++i)
			for (size_t j = 0; j < i; ++j)
				if (v[i] == v[j])
					return true;
		return false;
	}
	scratch.assign(v, v + k);
	std::sort(scratch.begin(), scratch.end());
	return std::adjacent_find(scratch.begin(), scratch.end()) != scratch.end();
}

/* A hash of the directed edge a -> b, not symmetric (nor linear: a linear
 * one would telescope around every face). */
inline uint64_t edge_hash(uint32_t a, uint32_t b)
{
	uint64_t x = (uint64_t)a << 32 | b;
	x = (x ^ x >> 31) * 0x7fb5d329728ea185ull;
	x = (x ^ x >> 27) * 0x81dadef4bc2dd44dull;
	return x ^ x >> 33;
}

/* Whether some vertex may be two-sided (separate_two_sided), in one pass:
 * a face's sum of h(a, b) - h(b, a) over its edges a -> b changes sign with
 * its orientation, so at a vertex whose faces all have their reverses
 * there the sums cancel exactly (mod 2^64); elsewhere they cancel only by
 * accident (then separate_two_sided looks, and finds nothing). */
template <typename B, typename E>
bool maybe_two_sided(const plan& g, size_t nf, B begin, E end, std::vector<uint32_t>& scratch)
{
	std::vector<uint64_t> sum(g.n, 0);
	std::vector<uint8_t> used(g.n, 0);
	const uint32_t* w = g.welded;
	for (size_t f = 0; f < nf; ++f) {
		const size_t b = begin(f), k = end(f) - b;
		if (k < 3 || repeats(w + b, k, scratch))
			continue;
		uint64_t h = 0;
		for (size_t i = 0, j = k - 1; i < k; j = i++)
			h += edge_hash(w[b + j], w[b + i]) - edge_hash(w[b + i], w[b + j]);
		for (size_t i = 0; i < k; ++i)
			sum[w[b + i]] += h, used[w[b + i]] = 1;
	}
	for (size_t v = 0; v < g.n; ++v)
		if (used[v] && sum[v] == 0)
			return true;
	return false;
}

/* A face and its reverse on the same (welded) vertices are the two sides of
 * a sheet whose copies were shared or welded: summed at one vertex, they
 * cancel to rounding noise. A vertex every one of whose faces (but those
 * repeating a vertex) has its reverse among them is two-sided: its faces
 * facing away from its first face with a nonzero normal (Newell's) are
 * moved to a back, a computed vertex of its own (n + k). A vertex where
 * some face has no reverse (a wall two closed cells share, on their
 * boundary) is left as it is: there the pairs cancel and the others give
 * the normal. Faces pair by their vertex cycles, compared among the faces
 * of the same lowest vertex. */
void separate_two_sided(plan& g, const vn_positions& pos)
{
	const size_t nf = g.f.offsets ? g.f.face_count : g.f.corner_count / 3;
	auto begin = [&](size_t f) -> size_t { return g.f.offsets ? g.f.offsets[f] : 3 * f; };
	auto end = [&](size_t f) -> size_t { return g.f.offsets ? g.f.offsets[f + 1] : 3 * f + 3; };
	const uint32_t* w = g.welded;
	std::vector<uint32_t> sorted;
	if (!maybe_two_sided(g, nf, begin, end, sorted))
		return;
	/* Each face's cycle starts at its lowest vertex, corner `at`, and goes
	 * towards the lower of that corner's neighbours: side 1 in the face's
	 * own order, 2 against it, 0 for a face with a repeated vertex or under
	 * 3 corners (it pairs with nothing). */
	std::vector<uint32_t> at(nf, 0);
	std::vector<uint8_t> side(nf, 0);
	std::vector<uint32_t> start(g.n + 1, 0); /* faces by lowest vertex (counting sort) */
	for (size_t f = 0; f < nf; ++f) {
		const size_t b = begin(f), k = end(f) - b;
		if (k < 3 || repeats(w + b, k, sorted))
			continue;
		const size_t m = (size_t)(std::min_element(w + b, w + b + k) - (w + b));
		at[f] = (uint32_t)m;
		side[f] = w[b + (m + 1 == k ? 0 : m + 1)] < w[b + (m ? m - 1 : k - 1)] ? 1 : 2;
		++start[w[b + m] + 1];
	}
	for (size_t v = 0; v < g.n; ++v)
		start[v + 1] += start[v];
	std::vector<uint32_t> by_lowest(start[g.n]), fill(start.begin(), start.end() - 1);
	for (size_t f = 0; f < nf; ++f)
		if (side[f])
			by_lowest[fill[w[begin(f) + at[f]]]++] = (uint32_t)f;
	std::vector<uint32_t>().swap(fill);
	/* Vertex i of face f's cycle. */
	auto cycle = [&](size_t f, size_t i) {
		const size_t b = begin(f), k = end(f) - b, j = side[f] == 1 ? at[f] + i : at[f] + k - i;
		return w[b + (j < k ? j : j - k)];
	};
	/* Faces ordered by cycle (size, then vertices); -1, 0, 1. */
	auto compare = [&](uint32_t a, uint32_t c) {
		const size_t ka = end(a) - begin(a), kc = end(c) - begin(c);
		if (ka != kc)
			return ka < kc ? -1 : 1;
		for (size_t i = 1; i < ka; ++i)
			if (cycle(a, i) != cycle(c, i))
				return cycle(a, i) < cycle(c, i) ? -1 : 1;
		return 0;
	};
	/* Sorted by cycle, the faces of one lowest vertex come in runs of one
	 * cycle: a run with both sides is paired. */
	std::vector<uint8_t> paired(nf, 0);
	bool any = false;
	for (size_t v = 0; v < g.n; ++v) {
		uint32_t* b = by_lowest.data() + start[v];
		uint32_t* e = by_lowest.data() + start[v + 1];
		if (e - b < 2)
			continue;
		if (e - b > 2) /* two need no sorting */
			std::sort(b, e, [&](uint32_t a, uint32_t c) { return compare(a, c) < 0; });
		for (uint32_t* r = b; r < e;) {
			uint32_t* t = r + 1;
			uint8_t sides = side[*r];
			for (; t < e && compare(*r, *t) == 0; ++t)
				sides |= side[*t];
			if (sides == 3)
				for (any = true; r < t; ++r)
					paired[*r] = 1;
			r = t;
		}
	}
	if (!any)
		return;
	/* Two-sided vertices: a paired face and no unpaired one. */
	std::vector<uint8_t> state(g.n, 0); /* 1: a paired face; 2: an unpaired one */
	for (size_t f = 0; f < nf; ++f)
		if (side[f])
			for (size_t c = begin(f); c < end(f); ++c)
				state[w[c]] |= paired[f] ? 1 : 2;
	std::vector<double> first(3 * g.n, 0.0);
	std::vector<uint32_t> back(g.n, UINT32_MAX);
	std::vector<uint32_t>& out = g.welded_corners;
	if (out.empty())
		out.assign(w, w + g.f.corner_count);
	for (size_t f = 0; f < nf; ++f) {
		if (!paired[f])
			continue;
		double n[3] = {0, 0, 0}, p0[3], a[3], c[3];
		load(pos, w[begin(f)], p0);
		for (size_t i = begin(f) + 1; i + 1 < end(f); ++i) {
			load(pos, w[i], a);
			load(pos, w[i + 1], c);
			for (int d = 0; d < 3; ++d)
				a[d] -= p0[d], c[d] -= p0[d];
			n[0] += a[1] * c[2] - a[2] * c[1], n[1] += a[2] * c[0] - a[0] * c[2], n[2] += a[0] * c[1] - a[1] * c[0];
		}
		for (size_t i = begin(f); i < end(f); ++i) {
			const uint32_t v = w[i];
			if (state[v] != 1)
				continue;
			double* r = &first[3 * v];
			if (r[0] == 0 && r[1] == 0 && r[2] == 0)
				std::copy_n(n, 3, r);
			if (n[0] * r[0] + n[1] * r[1] + n[2] * r[2] >= 0)
				continue;
			if (back[v] == UINT32_MAX) {
				back[v] = (uint32_t)(g.n + g.back_source.size());
				g.back_source.push_back(v);
			}
			out[i] = back[v];
		}
	}
	g.welded = out.data();
}

/* Output vertices for the backs: a corner on another computed vertex than
 * the first corner of its input vertex gets a new output vertex (one per
 * input vertex: its corners are on its front or on that front's back). */
void split_back_corners(plan& g)
{
	std::vector<uint32_t> first(g.n, UINT32_MAX), extra(g.n, UINT32_MAX);
	g.corner_output.assign(g.f.corner_count, 0);
	for (size_t k = 0; k < g.f.corner_count; ++k) {
		const uint32_t i = g.f.corners[k];
		if (first[i] == UINT32_MAX)
			first[i] = g.welded[k];
		if (g.welded[k] == first[i]) {
			g.corner_output[k] = i;
			continue;
		}
		if (extra[i] == UINT32_MAX) {
			extra[i] = (uint32_t)(g.n + g.extra_source.size());
			g.extra_source.push_back(i);
		}
		g.corner_output[k] = extra[i];
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
	separate_two_sided(g, pos);
	/* Hard edges join welded copies: none without welding. */
	g.hard_edges = g.welded_vertices ? flag_hard_edges(g, s.crease ? s.crease_angle : default_hard_edge_angle) : 0;
	if (!g.hard_edges)
		g.sharp.clear();
	g.corner_normals = s.crease || !g.sharp.empty();
	if (s.crease) {
		g.crease = s.crease_angle;
		g.crease_split = true;
		c.resize(3 * f.corner_count);
		std::vector<double> store;
		const vn_result r = corner_normals(g, computed_positions(g, pos, store), c.data(), stats);
		if (r != vn_result_success)
			return r;
		split_corners(g, c);
	} else if (!g.back_source.empty()) {
		split_back_corners(g);
	}
	return vn_result_success;
}

template <typename T>
vn_result normals(const plan& g, const vn_positions& q, std::vector<T>& out, const std::vector<T>* computed,
                  vn_stats* stats)
{
	out.assign(3 * g.outputs(), 0);
	std::vector<double> store;
	const vn_positions p = computed_positions(g, q, store);
	if (!g.corner_normals && g.back_source.empty())
		return vertex_normals(g, p, out.data(), stats);
	std::vector<T> v;
	auto smooth = [&]() {
		v.resize(3 * g.computed());
		return vertex_normals(g, p, v.data(), stats);
	};
	if (!g.corner_normals) { /* two-sided: each corner its side's normal */
		const vn_result r = smooth();
		if (r != vn_result_success)
			return r;
		std::copy_n(v.begin(), 3 * g.n, out.begin());
		for (size_t k = 0; k < g.f.corner_count; ++k)
			std::copy_n(&v[3 * g.welded[k]], 3, &out[3 * g.corner_output[k]]);
		return vn_result_success;
	}
	std::vector<T> own;
	if (!computed) {
		own.resize(3 * g.f.corner_count);
		const vn_result r = corner_normals(g, p, own.data(), stats);
		if (r != vn_result_success)
			return r;
		stats = nullptr;
	}
	const std::vector<T>& c = computed ? *computed : own;
	if (g.crease_split) {
		for (size_t k = 0; k < g.f.corner_count; ++k)
			std::copy_n(&c[3 * k], 3, &out[3 * g.corner_output[k]]);
		return vn_result_success;
	}
	/* Hard edges, no crease: a vertex whose corners disagree (its fans are
	 * not separated in the file) gets the smooth normal. */
	const uint32_t* oc = g.corner_output.empty() ? g.f.corners : g.corner_output.data();
	std::vector<uint32_t> seen(g.outputs(), UINT32_MAX);
	std::vector<uint8_t> conflict(g.outputs(), 0);
	for (size_t k = 0; k < g.f.corner_count; ++k) {
		const uint32_t i = oc[k];
		if (seen[i] == UINT32_MAX)
			seen[i] = (uint32_t)k, std::copy_n(&c[3 * k], 3, &out[3 * i]);
		else if (!std::equal(&c[3 * k], &c[3 * k] + 3, &c[3 * seen[i]]))
			conflict[i] = 1;
	}
	if (std::find(conflict.begin(), conflict.end(), 1) != conflict.end()) {
		const vn_result r = smooth();
		if (r != vn_result_success)
			return r;
		for (size_t i = 0; i < g.outputs(); ++i)
			if (conflict[i])
				std::copy_n(&v[3 * g.welded[seen[i]]], 3, &out[3 * i]);
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
