/*
 * The KHR_draco_mesh_compression bridge (gltf_primitive.h): a primitive's
 * Draco data decoded with draco.h and checked against its accessors;
 * --draco off (decoded data into new bufferViews), keep (re-encoded with
 * the new normals, the input's attributes, unique ids and bits) and on
 * (every triangle primitive compressed); the --stats normal quantization
 * error.
 */
#include "gltf_primitive.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace vn_gltf {

/* Decodes primitive prim's Draco data (ext: its extension object; through
 * cache, when not null, so that primitives with the same extension share
 * one decoding) and checks it against the primitive: indexed TRIANGLES,
 * POSITION in the data, accessors of the decoded types. Attributes outside
 * the Draco data and morph targets follow the decoded points' order. */
std::shared_ptr<const draco_mesh> decode_draco(const document& d, const json& prim, const json& ext, const std::string& what,
                                               draco_cache* cache)
{
	const std::string ew = what + ".extensions." + draco_name;
	if (!ext.is_object() || !ext.contains("attributes") || !ext["attributes"].is_object())
		fail(vn_io_error_parse, ew + " is malformed");
	if (get_int(prim, "mode", 4, what) != 4 || !prim.contains("indices"))
		fail(vn_io_error_unsupported, what + " is Draco-compressed and not indexed TRIANGLES, which vn does not read");
	std::shared_ptr<const draco_mesh> decoded;
	if (cache)
		decoded = (*cache)[ext.dump()];
	if (!decoded) {
		const long long view = get_int(ext, "bufferView", -1, ew);
		const size_t length =
		    (size_t)get_int(element(d.j, "bufferViews", view, ew), "byteLength", 0, str("bufferViews[%lld]", view));
		const span s = view_span(d, view, 0, length, 1, ew);
		auto m = std::make_shared<draco_mesh>();
		vn_io_error e;
		const vn_io_result r = vn_drc_decode(element_at(d, s, 0), length, what.c_str(), &m->g, &e);
		if (r != vn_io_success)
			fail(r, e.message);
		for (auto& kv : ext["attributes"].items()) {
			const long long id = get_int(ext["attributes"], kv.key().c_str(), 0, ew + ".attributes");
			for (size_t i = 0; i < m->g.attribute_count; ++i)
				if (m->g.attributes[i].unique_id == id)
					m->by_name[kv.key()] = &m->g.attributes[i];
			if (!m->by_name.count(kv.key()))
				fail(vn_io_error_parse, str("%s.attributes.%s is Draco attribute %lld, which the data does not have",
				                            ew.c_str(), kv.key().c_str(), id));
		}
		decoded = m;
		if (cache)
			(*cache)[ext.dump()] = decoded;
	}
	const draco_mesh& m = *decoded;
	const json& attributes = prim["attributes"];
	for (auto& kv : m.by_name)
		if (!attributes.contains(kv.first))
			fail(vn_io_error_parse, str("%s.attributes has no %s", what.c_str(), kv.first.c_str()));
	if (!m.by_name.count("POSITION"))
		fail(vn_io_error_unsupported, what + ": POSITION is not in the Draco data, which vn does not handle");
	for (auto& kv : m.by_name)
		if (kv.second->component_type == vn_drc_float64)
			fail(vn_io_error_parse, str("%s: the Draco data's %s is float64, which no glTF accessor describes", what.c_str(),
			                            kv.first.c_str()));
	/* The accessors of the Draco data only give type and count, and the
	 * decoded data are what loaders use: a count that differs (Draco may
	 * split points, as in Cesium's DracoCompressed/CesiumMilkTruck) is
	 * written anew with the data. Other accessors and morph targets must
	 * follow the decoded points. */
	for (auto& kv : attributes.items()) {
		const accessor a = get_accessor(d, get_int(attributes, kv.key().c_str(), 0, what + ".attributes"));
		auto in = m.by_name.find(kv.key());
		if (in != m.by_name.end() ? (int)a.components != in->second->components : (size_t)a.count != m.g.point_count)
			fail(vn_io_error_parse, str("%s: the %s accessor's count or type does not match the Draco data (%zu points)",
			                            what.c_str(), kv.key().c_str(), m.g.point_count));
	}
	for (const char* name : {"POSITION", "NORMAL"}) {
		auto it = m.by_name.find(name);
		if (it != m.by_name.end() && it->second->components != 3)
			fail(vn_io_error_parse, str("%s: the Draco %s is not VEC3", what.c_str(), name));
	}
	return decoded;
}

/* --draco off: values (`count` elements of a Draco attribute, or the
 * triangles' corners) in component type `component` into a new bufferView,
 * under the accessor `ref` points at the first time; primitives sharing
 * accessors (valid with Draco: they only carry count and type) may have
 * other values for it, which then go under a copy `ref` is pointed at, or
 * the same, which are not written again. held: per input accessor, the
 * accessors holding its values so far. */
/* How many points indices of a component type can number: its largest
 * value is its primitive restart value, which glTF forbids
 * (ACCESSOR_INDEX_PRIMITIVE_RESTART). */
static size_t points_numbered(long long component)
{
	return component == 5121 ? 255u : component == 5123 ? 65535u : UINT32_MAX;
}

static void store_decoded(document& d, json& ref, long long component, const vn_drc_attribute& a, size_t count, int target,
                          std::map<long long, std::vector<long long>>& held)
{
	const long long index = ref.get<long long>();
	accessor info = get_accessor(d, index);
	info.component = component;
	info.element = component_size(component) * info.components;
	const size_t stride = target == 34962 ? (info.element + 3) / 4 * 4 : info.element;
	const size_t csize = component_size(component), dsize = vn_io_component_size(a.component_type);
	bytes data(stride * count, 0);
	for (size_t i = 0; i < count; ++i)
		for (size_t c = 0; c < info.components; ++c) {
			const double v = read_component((const unsigned char*)a.data + dsize * (i * info.components + c), a.component_type, false);
			write_component(&data[i * stride + c * csize], component, v);
		}
	std::vector<long long>& same = held[index];
	for (long long h : same) {
		const json& j = d.j["accessors"][(size_t)h];
		const long long view = j["bufferView"].get<long long>();
		if (j["componentType"] == component && (size_t)d.j["bufferViews"][(size_t)view]["byteLength"] == data.size() &&
		    !memcmp(element_at(d, view_span(d, view, 0, data.size(), 1, "bufferViews"), 0), data.data(), data.size())) {
			ref = h;
			return;
		}
	}
	json j = d.j["accessors"][(size_t)index];
	j["componentType"] = component;
	j["count"] = count;
	j.erase("byteOffset");
	j.erase("sparse");
	set_bounds(j, data, stride, info, count);
	j["bufferView"] = append_view(d, std::move(data), stride == info.element ? 0 : stride, target);
	if (same.empty())
		d.j["accessors"][(size_t)index] = std::move(j);
	else
		ref = append_accessor(d, std::move(j));
	same.push_back(ref.get<long long>());
}

/* --draco off: every Draco-compressed primitive's decoded data go into new
 * bufferViews under its accessors, the extension is removed, and so is
 * KHR_draco_mesh_compression from extensionsUsed and extensionsRequired.
 * The primitives are then read as any other. */
void decompress_draco(document& d)
{
	auto meshes = d.j.find("meshes");
	if (meshes == d.j.end() || !meshes->is_array())
		return; /* reported by triangle_primitives */
	std::map<long long, std::vector<long long>> held;
	for (size_t m = 0; m < meshes->size(); ++m) {
		json& mesh = (*meshes)[m];
		if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
			continue;
		for (size_t p = 0; p < mesh["primitives"].size(); ++p) {
			json& prim = mesh["primitives"][p];
			const json* ext = prim.is_object() && prim.contains("attributes") && prim["attributes"].is_object()
			                      ? draco_extension(prim) : nullptr;
			if (!ext)
				continue;
			const std::string what = str("meshes[%zu].primitives[%zu]", m, p);
			/* Each primitive decoded anew: its decoded data are then freed
			 * before the next one's. */
			const std::shared_ptr<const draco_mesh> dm = decode_draco(d, prim, *ext, what, nullptr);
			for (const auto& kv : dm->by_name) {
				json& ref = prim["attributes"][kv.first];
				store_decoded(d, ref, get_accessor(d, get_int(prim["attributes"], kv.first.c_str(), 0, what)).component,
				              *kv.second, dm->g.point_count, 34962, held);
			}
			const long long component = get_accessor(d, get_int(prim, "indices", 0, what)).component;
			const size_t limit = points_numbered(component);
			vn_drc_attribute corners{};
			corners.component_type = 5125;
			corners.components = 1;
			corners.data = dm->g.indices;
			store_decoded(d, prim["indices"], dm->g.point_count > limit ? 5125 : component, corners, 3 * dm->g.triangle_count,
			              34963, held);
			prim["extensions"].erase(draco_name);
			if (prim["extensions"].empty())
				prim.erase("extensions");
		}
	}
	for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
		auto it = d.j.find(list);
		if (it == d.j.end() || !it->is_array())
			continue;
		it->erase(std::remove(it->begin(), it->end(), json(draco_name)), it->end());
		if (it->empty())
			d.j.erase(list);
	}
}

/* The Draco bits and level given in o, vn_drc_default_options' for the others. */
static vn_drc_options draco_bits(const vn_gltf_options& o)
{
	vn_drc_options bits;
	vn_drc_default_options(&bits);
	const vn_drc_options& given = o.draco_options;
	for (auto f : {std::make_pair(&bits.position_bits, given.position_bits), std::make_pair(&bits.normal_bits, given.normal_bits),
	               std::make_pair(&bits.texcoord_bits, given.texcoord_bits), std::make_pair(&bits.color_bits, given.color_bits),
	               std::make_pair(&bits.compression_level, given.compression_level)})
		if (f.second >= 0)
			*f.first = f.second;
	return bits;
}

/* vn_drc_encoder_new's encoder, freed with vn_drc_encoder_free. */
using draco_encoder = std::unique_ptr<vn_drc_encoder, void (*)(vn_drc_encoder*)>;

/* g checked and copied into a Draco encoder: what g points at may be freed
 * once this returns, before Draco needs several times as much to encode. */
static draco_encoder new_encoder(const vn_drc_geometry& g, const std::string& what)
{
	vn_drc_encoder* e;
	vn_io_error error;
	const vn_io_result r = vn_drc_encoder_new(&g, what.c_str(), &e, &error);
	if (r != vn_io_success)
		fail(r, error.message);
	return draco_encoder(e, vn_drc_encoder_free);
}

/* The encoder's geometry Draco-encoded (keep_order: as vn_drc_encode) into
 * a new bufferView; returns its index. When position >= 0, that accessor
 * (the geometry's attribute position_id) gets the min/max of the positions
 * a decoder gets back when they are floats: quantizing anew may move them
 * outside the bounds of the input's (integer positions are lossless). An
 * accessor in `bounded` already got those of another primitive sharing
 * it: it gets the bounds of both. */
static size_t append_draco(document& d, draco_encoder encoder, int level, bool keep_order, long long position,
                           uint32_t position_id, std::set<long long>& bounded, const std::string& what)
{
	void* data;
	size_t size;
	vn_io_error e;
	vn_io_result r = vn_drc_encoder_encode(encoder.get(), level, keep_order, what.c_str(), &data, &size, &e);
	encoder.reset();
	if (r != vn_io_success)
		fail(r, e.message);
	bytes encoded((unsigned char*)data, (unsigned char*)data + size);
	free(data);
	if (position >= 0) {
		draco_mesh back;
		if ((r = vn_drc_decode(encoded.data(), encoded.size(), what.c_str(), &back.g, &e)) != vn_io_success)
			fail(r, e.message);
		for (size_t i = 0; i < back.g.attribute_count; ++i)
			if (back.g.attributes[i].unique_id == position_id && back.g.attributes[i].component_type == vn_drc_float32) {
				json& a = d.j["accessors"][(size_t)position];
				const bool shared = !bounded.insert(position).second;
				const float* q = (const float*)back.g.attributes[i].data;
				json lo = json::array(), hi = json::array();
				for (size_t c = 0; c < 3; ++c) {
					float l = shared ? a["min"][c].get<float>() : INFINITY, h = shared ? a["max"][c].get<float>() : -INFINITY;
					for (size_t k = 0; k < back.g.point_count; ++k)
						l = std::min(l, q[3 * k + c]), h = std::max(h, q[3 * k + c]);
					lo.push_back(l), hi.push_back(h);
				}
				a["min"] = lo;
				a["max"] = hi;
			}
	}
	return append_view(d, std::move(encoded), 0, 0);
}

/* The vertices of [0, n) that triangles use (every one when `all`), in
 * order; renumbered[v] becomes v's index among them. */
static std::vector<uint32_t> kept_vertices(const corners& triangles, size_t n, bool all, std::vector<uint32_t>& renumbered)
{
	std::vector<uint32_t> kept;
	renumbered.assign(n, UINT32_MAX);
	for (uint32_t v : triangles)
		renumbered[v] = 0;
	for (size_t v = 0; v < n; ++v)
		if (all || renumbered[v] == 0)
			renumbered[v] = (uint32_t)kept.size(), kept.push_back((uint32_t)v);
	return kept;
}

/* Adds p's output vertices that triangles use (positions, new normals) and
 * its triangles. */
static void record_normals(quantized_normals& q, const primitive& p)
{
	const corners triangles = p.output_triangles();
	std::vector<uint32_t> renumbered;
	const uint32_t first = (uint32_t)(q.positions.size() / 3);
	for (uint32_t v : kept_vertices(triangles, p.output_vertices(), false, renumbered)) {
		double x[3];
		p.positions.load(v < p.vertices() ? v : p.split_source[v - p.vertices()], x);
		q.positions.insert(q.positions.end(), x, x + 3);
		q.normals.insert(q.normals.end(), &p.normals[3 * v], &p.normals[3 * v] + 3);
	}
	for (uint32_t v : triangles)
		q.indices.push_back(first + renumbered[v]);
}

/* Encodes Draco primitive p again with its new normals: the same attributes
 * (but a dropped TANGENT), unique ids and bits, except the bits given with
 * --draco-qp/qn/qt/qc, in a new bufferView the extension points at. The
 * normals go into the Draco NORMAL in its type when that is float32, or a
 * byte or short its accessor reads as normalized (KHR_mesh_quantization);
 * a NORMAL of another type keeps its unique id but becomes float32, under a
 * new bufferView-less accessor, as does one the data lacked (with the next
 * free unique id), both with --draco-qn or default bits. Points keep their
 * order when morph targets or attributes outside the Draco data follow it.
 * p is released, its normals too, once the encoder has its copy. */
void write_draco(document& d, primitive& p, const vn_gltf_options& o, vn_gltf_stats& st, draco_written& w)
{
	const std::string what = str("meshes[%zu].primitives[%zu]", p.mesh, p.index);
	json& prim = mesh_primitive(d, p);
	json& ext = prim["extensions"][draco_name];
	const vn_drc_options bits = draco_bits(o);
	const size_t n = p.output_vertices();
	const bool keep_order = prim.contains("targets") || prim["attributes"].size() > p.draco->by_name.size() -
	                        (o.drop_tangents && p.draco->by_name.count("TANGENT"));
	bool moved = false; /* positions quantized with other bits than the stream's */
	const uint32_t position_id = p.draco->by_name.at("POSITION")->unique_id;
	draco_encoder encoder(nullptr, vn_drc_encoder_free);
	{
		const vn_drc_geometry& in = p.draco->g;
		const auto& by_name = p.draco->by_name;
		std::vector<vn_drc_attribute> attributes;
		std::vector<bytes> grown; /* split: each attribute with the split vertices' copies */
		grown.reserve(in.attribute_count);
		for (size_t i = 0; i < in.attribute_count; ++i)
			if (!o.drop_tangents || !by_name.count("TANGENT") || by_name.at("TANGENT") != &in.attributes[i]) {
				attributes.push_back(in.attributes[i]);
				if (p.split_source.empty())
					continue;
				const vn_drc_attribute& a = in.attributes[i];
				const size_t size = (size_t)a.components * vn_io_component_size(a.component_type);
				grown.emplace_back(size * n);
				memcpy(grown.back().data(), a.data, size * in.point_count);
				for (size_t e = 0; e < p.split_source.size(); ++e)
					memcpy(&grown.back()[size * (in.point_count + e)], (const unsigned char*)a.data + size * p.split_source[e],
					       size);
				attributes.back().data = grown.back().data();
			}
		/* The accessors of the Draco data get the new count (split copies,
		 * or an input's count that was not the decoded one), as copies: the
		 * old ones may be shared; the indices a type that holds it. */
		for (auto& kv : prim["attributes"].items())
			if (by_name.count(kv.key())) {
				json copy = d.j["accessors"][(size_t)get_int(prim["attributes"], kv.key().c_str(), 0, what)];
				if (get_int(copy, "count", 0, what) != (long long)n) {
					copy["count"] = n;
					kv.value() = append_accessor(d, copy);
				}
			}
		json indices = d.j["accessors"][(size_t)get_int(prim, "indices", 0, what)];
		const bool wider = n > points_numbered(get_int(indices, "componentType", 0, what));
		if (wider || get_int(indices, "count", 0, what) != (long long)(3 * in.triangle_count)) {
			if (wider)
				indices["componentType"] = 5125;
			indices["count"] = 3 * in.triangle_count;
			prim["indices"] = append_accessor(d, indices);
		}
		auto in_normal = by_name.find("NORMAL");
		size_t normal = 0;
		while (normal < attributes.size() &&
		       (in_normal == by_name.end() || attributes[normal].unique_id != in_normal->second->unique_id))
			++normal;
		bool kept = false;
		if (normal < attributes.size()) {
			const int type = attributes[normal].component_type;
			const accessor a = get_accessor(d, get_int(prim["attributes"], "NORMAL", 0, what));
			kept = a.component == type &&
			       (type == vn_drc_float32 || ((type == vn_drc_int8 || type == vn_drc_int16) && a.normalized));
		}
		if (!kept) {
			vn_drc_attribute a{};
			a.semantic = vn_drc_normal;
			a.component_type = vn_drc_float32;
			a.components = 3;
			a.quantization_bits = bits.normal_bits;
			if (normal < attributes.size()) {
				a.unique_id = attributes[normal].unique_id;
				attributes[normal] = a;
			} else {
				for (const vn_drc_attribute& b : attributes)
					a.unique_id = std::max(a.unique_id, b.unique_id + 1);
				ext["attributes"]["NORMAL"] = a.unique_id;
				attributes.push_back(a);
			}
			prim["attributes"]["NORMAL"] = append_accessor(d, json{{"componentType", 5126}, {"count", n}, {"type", "VEC3"}});
			++st.appended_accessors;
		}
		vn_drc_attribute& normals = attributes[normal];
		bytes stored; /* the normals as normalized integers */
		if (normals.component_type == vn_drc_float32) {
			normals.data = const_cast<float*>(p.normals.data());
		} else {
			const size_t size = vn_io_component_size(normals.component_type);
			stored.resize(p.normals.size() * size);
			for (size_t k = 0; k < p.normals.size(); ++k)
				write_unit(&stored[k * size], normals.component_type, p.normals[k]);
			normals.data = stored.data();
		}
		for (vn_drc_attribute& a : attributes) {
			const int given = vn_drc_given_bits(&o.draco_options, a.semantic, a.component_type);
			if (given >= 0 && given != a.quantization_bits) {
				moved = moved || a.semantic == vn_drc_position;
				a.quantization_bits = given;
			}
		}
		/* Integer normals are not Draco-quantized: their error is not Draco's. */
		if (o.draco_normal_error && normals.component_type == vn_drc_float32)
			record_normals(w.quantized[normals.quantization_bits], p);
		vn_drc_geometry g = in;
		g.attributes = attributes.data();
		g.attribute_count = attributes.size();
		g.point_count = n;
		g.indices = const_cast<uint32_t*>(p.output_triangles().data());
		encoder = new_encoder(g, what);
	}
	/* Only the encoder's copy is needed now: Draco needs several times as
	 * much again to encode it. */
	p.release();
	std::vector<float>().swap(p.normals);
	ext["bufferView"] = append_draco(d, std::move(encoder), bits.compression_level, keep_order, moved ? p.position : -1,
	                                 position_id, w.bounded, what);
	++st.draco_primitives;
}

/* --draco on: p (not Draco-compressed on input, normals written, split
 * when it had to be) gets its attributes and triangles Draco-encoded with
 * o's bits (semantics by name: POSITION, NORMAL, TEXCOORD_n, COLOR_n, the
 * rest generic and lossless), new bufferView-less accessors and indices,
 * and the extension; POSITION's min/max are the decoded positions'.
 * Vertices no triangle uses are left out. A primitive with morph targets
 * keeps every point in order, which the targets' accessors follow; when
 * that is more than 3 points per triangle (which Draco 1.5.5's decoder refuses),
 * it stays uncompressed (counted). The old accessors become unused, for
 * prune() to remove. */
void compress_draco(document& d, const primitive& p, const vn_gltf_options& o, vn_gltf_stats& st, draco_written& w)
{
	json& prim = mesh_primitive(d, p);
	const std::string what = str("meshes[%zu].primitives[%zu]", p.mesh, p.index);
	const vn_drc_options bits = draco_bits(o);
	const size_t n = p.output_vertices();
	const bool targets = prim.contains("targets");
	const corners triangles = p.output_triangles();
	/* Vertices no triangle uses are left out (Draco 1.5.5's decoder refuses more
	 * points than 3 per triangle), unless morph targets follow the order. */
	std::vector<uint32_t> renumbered;
	const std::vector<uint32_t> kept = kept_vertices(triangles, n, targets, renumbered);
	if (kept.size() > triangles.size()) {
		++st.draco_uncompressed;
		return;
	}
	json ext_attributes = json::object();
	long long position = -1;
	draco_encoder encoder(nullptr, vn_drc_encoder_free);
	{
		std::vector<uint32_t> corners_kept(triangles.size());
		for (size_t k = 0; k < triangles.size(); ++k)
			corners_kept[k] = renumbered[triangles[k]];
		std::vector<bytes> storage;
		std::vector<vn_drc_attribute> attributes;
		for (auto& kv : prim["attributes"].items()) {
			const std::string& name = kv.key();
			const long long index = get_int(prim["attributes"], name.c_str(), 0, what + ".attributes");
			accessor a = get_accessor(d, index);
			if (a.components > 4 || (size_t)a.count != n)
				fail(vn_io_error_unsupported,
				     str("%s: %s cannot be Draco-compressed (more than 4 components, or not one per vertex)", what.c_str(),
				         name.c_str()));
			a.normalized = false; /* the stored integers, which Draco keeps with the flag */
			const std::vector<double> values = read_accessor(d, a);
			const size_t csize = component_size(a.component);
			storage.emplace_back(kept.size() * a.components * csize);
			std::vector<double> lo(a.components, INFINITY), hi(a.components, -INFINITY);
			for (size_t i = 0; i < kept.size(); ++i)
				for (size_t c = 0; c < a.components; ++c) {
					const double v = values[kept[i] * a.components + c];
					write_component(&storage.back()[(i * a.components + c) * csize], a.component, v);
					lo[c] = std::min(lo[c], v), hi[c] = std::max(hi[c], v);
				}
			const bool texcoord = name.rfind("TEXCOORD_", 0) == 0, color = name.rfind("COLOR_", 0) == 0;
			vn_drc_attribute da{};
			da.unique_id = (uint32_t)attributes.size();
			da.semantic = name == "POSITION" ? vn_drc_position : name == "NORMAL" ? vn_drc_normal
			              : texcoord ? vn_drc_texcoord : color ? vn_drc_color : vn_drc_generic;
			da.component_type = (int)a.component;
			da.components = (int)a.components;
			da.normalized = get_accessor(d, index).normalized;
			da.quantization_bits = da.semantic == vn_drc_position ? bits.position_bits
			                       : da.semantic == vn_drc_normal ? bits.normal_bits
			                       : texcoord ? bits.texcoord_bits : color ? bits.color_bits : 0;
			attributes.push_back(da);
			ext_attributes[name] = da.unique_id;
			json copy = d.j["accessors"][(size_t)index];
			copy.erase("bufferView");
			copy.erase("byteOffset");
			copy.erase("sparse");
			copy["count"] = kept.size();
			set_bounds(copy, lo, hi, a.component);
			kv.value() = append_accessor(d, copy);
			if (name == "POSITION")
				position = kv.value().get<long long>();
		}
		for (size_t i = 0; i < attributes.size(); ++i)
			attributes[i].data = storage[i].data();
		vn_drc_geometry g{};
		g.point_count = kept.size();
		g.triangle_count = corners_kept.size() / 3;
		g.indices = corners_kept.data();
		g.attribute_count = attributes.size();
		g.attributes = attributes.data();
		encoder = new_encoder(g, what);
	}
	if (o.draco_normal_error)
		record_normals(w.quantized[bits.normal_bits], p);
	const size_t view = append_draco(d, std::move(encoder), bits.compression_level, targets, position,
	                                 ext_attributes["POSITION"].get<uint32_t>(), w.bounded, what);
	const size_t points = kept.size();
	const int component = points <= points_numbered(5121) ? 5121 : points <= points_numbered(5123) ? 5123 : 5125;
	prim["indices"] = append_accessor(d, with_indices_label(d, prim,
	                                                        json{{"componentType", component},
	                                                             {"count", triangles.size()},
	                                                             {"type", "SCALAR"}}));
	if (prim.contains("mode"))
		prim["mode"] = 4;
	if (!prim.contains("extensions"))
		prim["extensions"] = json::object();
	prim["extensions"][draco_name] = json{{"bufferView", view}, {"attributes", ext_attributes}};
	for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
		json& names = d.j[list];
		if (std::find(names.begin(), names.end(), json(draco_name)) == names.end())
			names.push_back(draco_name);
	}
	++st.draco_primitives;
}

/* --stats: the angle normal quantization adds, per normal bits. */
void normal_errors(const std::map<int, quantized_normals>& quantized, const vn_gltf_options& o, vn_gltf_stats& st)
{
	for (const auto& kv : quantized) {
		const quantized_normals& q = kv.second;
		vn_drc_options options = draco_bits(o);
		options.normal_bits = kv.first;
		vn_io_error e;
		const vn_io_result r =
		    vn_drc_triangle_normal_error(q.positions.data(), q.normals.data(), q.positions.size() / 3, q.indices.data(),
		                                 q.indices.size() / 3, &options, "Draco normals", &st.draco_normal_error[kv.first], &e);
		if (r != vn_io_success)
			fail(r, e.message);
	}
}

} // namespace vn_gltf
