/*
 * The normals plan (gltf_primitive.h): the triangle primitives read from
 * the document (TRIANGLES, strips and fans as triangle lists, indices,
 * morph targets, Draco data through gltf_draco.cpp), grouped (one
 * primitive, primitives on one vertex array, or a whole mesh with
 * --weld-scope mesh), and their normals and
 * morph targets' NORMAL displacements computed by the plan of
 * split_normals.h (welded, hard edges kept, split at a crease angle).
 */
#include "gltf_primitive.h"

#include <algorithm>
#include <cmath>

namespace vn_gltf {

/* Accessor a (VEC3) as vec3s: a view when it is plain aligned float32. */
static vec3s read_vec3(const document& d, const accessor& a)
{
	if (a.component == 5126 && a.data.buffer >= 0 && a.sparse_count == 0) {
		const unsigned char* p = element_at(d, a.data, 0);
		if ((uintptr_t)p % 4 == 0 && a.data.stride % 4 == 0)
			return vec3s(p, (size_t)a.count, a.data.stride, vn_scalar_float32);
	}
	return vec3s(read_accessor(d, a));
}

/* A Draco attribute's n 3-vectors as its accessor a reads them: a view of
 * float32 data, else the integers dequantized through a's component type
 * and normalized flag (KHR_mesh_quantization), as read_vec3 reads them. */
static vec3s draco_vec3(const vn_drc_attribute& v, const accessor& a, size_t n)
{
	if (v.component_type == vn_drc_float32)
		return vec3s(v.data, n, 0, vn_scalar_float32);
	std::vector<double> values(3 * n);
	const size_t size = vn_io_component_size(v.component_type);
	for (size_t i = 0; i < values.size(); ++i) {
		const double stored = read_component((const unsigned char*)v.data + i * size, v.component_type, false);
		values[i] = a.normalized ? normalized_value(stored, a.component) : stored;
	}
	return vec3s(std::move(values));
}

/* The vertex order of indices accessor ia (each checked < n). */
static corners read_indices(const document& d, const accessor& ia, size_t n, bool whole_triangles, const std::string& what)
{
	if (ia.components != 1 || (ia.component != 5121 && ia.component != 5123 && ia.component != 5125))
		fail(vn_io_error_parse, what + ": indices are not unsigned integer scalars");
	auto checked = [&](uint32_t v) {
		if (v >= n)
			fail(vn_io_error_parse, str("%s: index %u is out of range (%zu vertices)", what.c_str(), v, n));
		return v;
	};
	const size_t count = whole_triangles ? (size_t)ia.count / 3 * 3 : (size_t)ia.count;
	if (ia.component == 5125 && ia.sparse_count == 0 && ia.data.buffer >= 0 && ia.data.stride == 4) {
		const unsigned char* p = element_at(d, ia.data, 0);
		if ((uintptr_t)p % 4 == 0) {
			const uint32_t* v = (const uint32_t*)p;
			for (size_t k = 0; k < count; ++k)
				checked(v[k]);
			return corners(v, count);
		}
	}
	std::vector<uint32_t> order((size_t)ia.count, 0);
	if (ia.data.buffer >= 0)
		for (size_t k = 0; k < order.size(); ++k)
			order[k] = (uint32_t)read_component(element_at(d, ia.data, k), ia.component, false);
	for (size_t k = 0; k < (size_t)ia.sparse_count; ++k) {
		const double i = read_component(element_at(d, ia.sparse_indices, k), ia.sparse_index_component, false);
		if (i >= (double)ia.count)
			fail(vn_io_error_parse, str("a sparse index (%.0f) is out of range (count %lld)", i, ia.count));
		order[(size_t)i] = (uint32_t)read_component(element_at(d, ia.sparse_values, k), ia.component, false);
	}
	for (uint32_t v : order)
		checked(v);
	order.resize(count);
	return corners(std::move(order));
}

/* Fails on the first non-finite position: no file vn writes may hold one
 * (glTF's validator rejects them, Draco's encoder crashes on them). */
static void check_finite(const vec3s& positions, const std::string& what)
{
	for (size_t i = 0; i < positions.size(); ++i) {
		double p[3];
		positions.load(i, p);
		if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
			fail(vn_io_error_parse, str("%s of vertex %zu is not finite (%g, %g, %g); vn does not write meshes with NaN or "
			                            "infinite positions: fix or remove that vertex", what.c_str(), i, p[0], p[1], p[2]));
	}
}

/* Reads the triangle primitives (and the POINTS ones where points is set);
 * counts the others. */
std::vector<primitive> triangle_primitives(const document& d, vn_gltf_stats* st, bool points)
{
	std::vector<primitive> out;
	draco_cache decoded;
	auto meshes = d.j.find("meshes");
	if (meshes == d.j.end())
		return out;
	if (!meshes->is_array())
		fail(vn_io_error_parse, "meshes is not an array");
	for (size_t m = 0; m < meshes->size(); ++m) {
		const json& mesh = (*meshes)[m];
		if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
			fail(vn_io_error_parse, str("meshes[%zu] has no primitives array", m));
		for (size_t p = 0; p < mesh["primitives"].size(); ++p) {
			const json& prim = mesh["primitives"][p];
			const std::string what = str("meshes[%zu].primitives[%zu]", m, p);
			if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object())
				fail(vn_io_error_parse, what + " has no attributes object");
			long long mode = get_int(prim, "mode", 4, what);
			if (mode > 6)
				fail(vn_io_error_parse, what + " has an invalid mode");
			const json& attributes = prim["attributes"];
			/* A POINTS primitive compressed with Draco (which the extension
			 * does not define for it) stays out. */
			const bool cloud = mode == 0 && points && !draco_extension(prim);
			if ((mode == 0 && !cloud) || mode == 1 || mode == 2 || mode == 3) {
				if (st)
					++(mode == 0 ? st->skipped_points : st->skipped_lines);
				continue;
			}
			if (!attributes.contains("POSITION")) {
				if (st)
					++st->skipped_no_position;
				continue;
			}
			primitive r;
			r.mesh = m;
			r.index = p;
			r.position = get_int(attributes, "POSITION", 0, what + ".attributes");
			r.tangent = attributes.contains("TANGENT");
			if (const json* ext = draco_extension(prim)) {
				r.draco = decode_draco(d, prim, *ext, what, &decoded);
				const vn_drc_geometry& g = r.draco->g;
				r.positions = draco_vec3(*r.draco->by_name.at("POSITION"), get_accessor(d, r.position), g.point_count);
				r.triangles = corners(g.indices, 3 * g.triangle_count);
			} else {
				accessor pa = get_accessor(d, r.position);
				if (pa.components != 3 || pa.count > (long long)UINT32_MAX)
					fail(vn_io_error_parse, what + ": POSITION is not VEC3");
				r.positions = read_vec3(d, pa);
			}
			const size_t n = r.vertices();
			check_finite(r.positions, what + ": POSITION");
			if (attributes.contains("NORMAL")) {
				r.normal = get_int(attributes, "NORMAL", 0, what + ".attributes");
				const vn_drc_attribute* compressed = nullptr;
				if (r.draco && r.draco->by_name.count("NORMAL"))
					compressed = r.draco->by_name.at("NORMAL");
				if (compressed) {
					r.input_normals = draco_vec3(*compressed, get_accessor(d, r.normal), n);
				} else {
					accessor na = get_accessor(d, r.normal);
					if (na.components != 3 || (size_t)na.count != n)
						fail(vn_io_error_parse, what + ": NORMAL is not VEC3 with one element per vertex");
					r.input_normals = read_vec3(d, na);
				}
			}
			if (prim.contains("targets")) {
				if (!prim["targets"].is_array())
					fail(vn_io_error_parse, what + ".targets is not an array");
				for (size_t t = 0; t < prim["targets"].size(); ++t) {
					const json& target = prim["targets"][t];
					const std::string tw = str("%s.targets[%zu]", what.c_str(), t);
					if (!target.is_object())
						fail(vn_io_error_parse, tw + " is not an object");
					std::vector<double> morphed;
					if (target.contains("POSITION")) {
						accessor ta = get_accessor(d, get_int(target, "POSITION", 0, tw));
						if (ta.components != 3 || (size_t)ta.count != n)
							fail(vn_io_error_parse, tw + ": POSITION is not VEC3 with one element per vertex");
						morphed = read_accessor(d, ta);
						for (size_t i = 0; i < n; ++i) {
							double q[3];
							r.positions.load(i, q);
							for (int c = 0; c < 3; ++c)
								morphed[3 * i + c] += q[c];
						}
						check_finite(vec3s(morphed.data(), n, 0, vn_scalar_float64), tw + ": POSITION");
					}
					long long normal = target.contains("NORMAL") ? get_int(target, "NORMAL", 0, tw) : -1;
					if (normal >= 0) {
						accessor tn = get_accessor(d, normal);
						if (tn.components != 3 || (size_t)tn.count != n)
							fail(vn_io_error_parse, tw + ": NORMAL is not VEC3 with one element per vertex");
					}
					r.target_positions.push_back(std::move(morphed));
					r.target_normal.push_back(normal);
				}
			}
			if (r.draco || cloud) { /* Draco's triangles are read; POINTS have none */
				out.push_back(std::move(r));
				continue;
			}

			corners order;
			if (prim.contains("indices")) {
				order = read_indices(d, get_accessor(d, get_int(prim, "indices", 0, what)), n, mode == 4, what);
			} else {
				std::vector<uint32_t> all(mode == 4 ? n / 3 * 3 : n);
				for (size_t i = 0; i < all.size(); ++i)
					all[i] = (uint32_t)i;
				order = corners(std::move(all));
			}
			if (mode == 4) {
				r.triangles = std::move(order);
			} else {
				std::vector<uint32_t> triangles;
				for (size_t i = 0; i + 2 < order.size(); ++i) {
					uint32_t a = mode == 5 ? order[i + (i & 1)] : order[0];
					uint32_t b = mode == 5 ? order[i + 1 - (i & 1)] : order[i + 1];
					triangles.insert(triangles.end(), {a, b, order[i + 2]});
				}
				r.triangles = corners(std::move(triangles));
			}
			out.push_back(std::move(r));
		}
	}
	return out;
}

static void check(vn_result r)
{
	if (r != vn_result_success)
		fail(r == vn_result_out_of_memory ? vn_io_error_memory : vn_io_error_parse, vn_result_string(r));
}

/* The plan's normals for input positions q, as vn_split::normals gives
 * them, but a vertex no face contributes to gets its input normal when that
 * is a unit vector, else +Z; *zeros counts them. */
static std::vector<float> plan_normals(const vn_split::plan& g, const vn_positions& q, size_t* zeros,
                                       const std::vector<float>* computed)
{
	std::vector<float> out;
	check(vn_split::normals(g, q, out, computed, nullptr));
	for (size_t k = 0; k < g.outputs(); ++k) {
		float* v = &out[3 * k];
		if (v[0] != 0 || v[1] != 0 || v[2] != 0)
			continue;
		++*zeros;
		double w[3] = {0, 0, 0};
		if (g.input_normals.count)
			vn_split::load(g.input_normals, g.source(k), w);
		double l = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
		if (std::isfinite(l) && std::fabs(l - 1) < 1e-3)
			v[0] = (float)(w[0] / l), v[1] = (float)(w[1] / l), v[2] = (float)(w[2] / l);
		else
			v[2] = 1;
	}
	return out;
}

/* Normals of a group of primitives computed together (one primitive, a
 * whole mesh, or primitives on one vertex array): welded, computed (per
 * corner where edges are hard), copied back to every split vertex; then
 * every morph target's NORMAL displacement, by the same computation on the
 * morphed positions. */
void compute_group(std::vector<primitive*>& prims, const vn_gltf_options& o, vn_gltf_stats& st)
{
	/* The group's vertex arrays joined one after another, each once:
	 * primitives on one array (same_vertex_array) share its range, which
	 * starts at their first[]. A primitive whose triangles are those of an
	 * earlier one on its array (meshes that draw one geometry with other
	 * materials) is that one (same_as[]): its triangles are not joined
	 * again, so the plan holds each geometry once. */
	std::vector<size_t> first(prims.size()), same_as(prims.size()), arrays; /* arrays: the primitive that brings each */
	size_t n = 0, distinct = 0;
	std::vector<double> joined, joined_normals;
	std::vector<uint32_t> joined_corners;
	vn_positions pos = prims[0]->positions.view;
	vn_positions input_normals = prims[0]->input_normals.view;
	vn_split::faces f;
	bool any_normals = false;
	for (size_t k = 0; k < prims.size(); ++k) {
		const primitive* p = prims[k];
		auto same = std::find_if(arrays.begin(), arrays.end(), [&](size_t a) { return same_vertex_array(*prims[a], *p); });
		same_as[k] = k;
		if (same != arrays.end()) {
			first[k] = first[*same];
			for (size_t j = *same; j < k && same_as[k] == k; ++j)
				if (same_as[j] == j && first[j] == first[k] &&
				    std::equal(p->triangles.begin(), p->triangles.end(), prims[j]->triangles.begin(), prims[j]->triangles.end()))
					same_as[k] = j;
		} else {
			if (n + p->vertices() > UINT32_MAX)
				fail(vn_io_error_unsupported, "a mesh has more than 2^32 vertices");
			first[k] = n;
			n += p->vertices();
			arrays.push_back(k);
			any_normals = any_normals || !p->input_normals.empty();
		}
		if (same_as[k] == k)
			f.corner_count += p->triangles.size(), ++distinct;
	}
	if (distinct == 1) {
		f.corners = prims[0]->triangles.data();
	} else {
		for (size_t k = 0; k < prims.size(); ++k)
			if (same_as[k] == k)
				for (uint32_t v : prims[k]->triangles)
					joined_corners.push_back((uint32_t)(first[k] + v));
		f.corners = joined_corners.data();
	}
	if (arrays.size() > 1) {
		for (size_t a : arrays) {
			const primitive* p = prims[a];
			p->positions.append_to(joined);
			if (any_normals && p->input_normals.empty())
				joined_normals.resize(joined.size(), 0.0);
			else if (any_normals)
				p->input_normals.append_to(joined_normals);
		}
		pos = {joined.data(), n, 0, vn_scalar_float64};
		input_normals = {joined_normals.data(), joined_normals.size() / 3, 0, vn_scalar_float64};
	}
	vn_split::settings s;
	s.method = o.method;
	s.threads = o.threads;
	s.weld = !o.no_weld;
	s.weld_epsilon = o.weld_epsilon;
	s.crease = o.crease;
	s.crease_angle = o.crease_angle;
	vn_split::plan g;
	std::vector<float> c; /* with a crease angle, the corner normals the split follows */
	check(vn_split::make_plan(g, pos, f, input_normals, s, c, nullptr));
	st.welded_vertices += g.welded_vertices;
	st.hard_edges += g.hard_edges;
	st.split_vertices += g.extra_source.size();
	size_t zeros = 0;
	std::vector<float> base = plan_normals(g, pos, &zeros, o.crease ? &c : nullptr);
	std::vector<float>().swap(c);
	st.zero_normals += zeros;
	/* Each primitive's split vertices, counted from n: those of its vertex
	 * array, which come together (the split vertices follow their input
	 * vertices). */
	std::vector<size_t> extra_first, extra_end;
	auto at = [&](size_t v) {
		return (size_t)(std::lower_bound(g.extra_source.begin(), g.extra_source.end(), v) - g.extra_source.begin());
	};
	for (size_t p = 0; p < prims.size(); ++p) {
		extra_first.push_back(at(first[p]));
		extra_end.push_back(at(first[p] + prims[p]->vertices()));
	}

	/* Each primitive's output vertices: its input ones, then its split ones
	 * (a group of one primitive is laid out so already). */
	auto gather = [&](const std::vector<float>& all, size_t p, std::vector<float>& out, const std::vector<float>* minus) {
		const primitive& pr = *prims[p];
		out.resize(3 * pr.output_vertices());
		for (size_t i = 0; i < out.size(); ++i) {
			const size_t k = i < 3 * pr.vertices() ? 3 * first[p] + i : 3 * (n + extra_first[p]) + i - 3 * pr.vertices();
			out[i] = minus ? all[k] - (*minus)[k] : all[k];
		}
	};
	size_t corner_first = 0;
	for (size_t p = 0; p < prims.size(); ++p) {
		primitive& pr = *prims[p];
		if (same_as[p] != p) {
			pr.split_source = prims[same_as[p]]->split_source;
			pr.split_triangles = prims[same_as[p]]->split_triangles;
		} else if (extra_end[p] > extra_first[p]) {
			pr.split_source.reserve(extra_end[p] - extra_first[p]);
			pr.split_triangles.reserve(pr.triangles.size());
			for (size_t e = extra_first[p]; e < extra_end[p]; ++e)
				pr.split_source.push_back((uint32_t)(g.extra_source[e] - first[p]));
			for (size_t k = 0; k < pr.triangles.size(); ++k) {
				const uint32_t v = g.corner_output[corner_first + k];
				pr.split_triangles.push_back(v < g.n ? (uint32_t)(v - first[p])
				                                     : (uint32_t)(pr.vertices() + v - g.n - extra_first[p]));
			}
		}
		if (same_as[p] == p)
			corner_first += pr.triangles.size();
		st.triangles += pr.triangles.size() / 3;
		++st.primitives;
		st.tangent_primitives += pr.tangent;
	}
	st.vertices += n;

	size_t targets = 0;
	for (primitive* p : prims)
		targets = std::max(targets, p->target_positions.size());
	for (size_t t = 0; t < targets; ++t) {
		std::vector<double> morphed;
		for (size_t a : arrays) {
			const primitive* p = prims[a];
			if (t < p->target_positions.size() && !p->target_positions[t].empty())
				morphed.insert(morphed.end(), p->target_positions[t].begin(), p->target_positions[t].end());
			else
				p->positions.append_to(morphed);
		}
		size_t ignored = 0;
		const vn_positions q = {morphed.data(), g.n, 0, vn_scalar_float64};
		const std::vector<float> normals = plan_normals(g, q, &ignored, nullptr);
		for (size_t p = 0; p < prims.size(); ++p) {
			primitive& pr = *prims[p];
			if (t >= pr.target_positions.size())
				continue;
			pr.target_normals.emplace_back();
			if (!pr.target_positions[t].empty() || pr.target_normal[t] >= 0)
				gather(normals, p, pr.target_normals.back(), &base);
		}
	}
	if (prims.size() == 1)
		prims[0]->normals = std::move(base);
	else
		for (size_t p = 0; p < prims.size(); ++p)
			gather(base, p, prims[p]->normals, nullptr);
}

} // namespace vn_gltf
