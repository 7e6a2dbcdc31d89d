/*
 * Removing what vn's edits of a glTF document left unused (gltf_document.h):
 * accessors and bufferViews that the input used and the output does not,
 * their bytes, and the renumbering of every reference to what stays.
 */
#include "gltf_document.h"

#include <algorithm>
#include <cstring>
#include <iterator>

namespace vn_gltf {
namespace {

/* Calls on_accessor(ref) for every place in the document that holds an
 * accessor index outside the accessors array (primitive attributes,
 * indices and targets, skins, animation samplers, GPU instancing), and
 * on_view(ref) for every bufferView index outside it (images, Draco,
 * EXT_structural_metadata's property tables). */
template <typename A, typename V> void visit_references(json& j, A on_accessor, V on_view)
{
	auto each = [&](const char* array, auto&& f) {
		auto it = j.find(array);
		if (it != j.end() && it->is_array())
			for (json& e : *it)
				if (e.is_object())
					f(e);
	};
	auto members = [&](json& o) {
		if (o.is_object())
			for (auto& kv : o.items())
				if (kv.value().is_number_integer())
					on_accessor(kv.value());
	};
	auto key = [](json& o, const char* k, auto&& f) {
		auto it = o.find(k);
		if (it != o.end() && it->is_number_integer())
			f(*it);
	};
	each("meshes", [&](json& mesh) {
		auto prims = mesh.find("primitives");
		if (prims == mesh.end() || !prims->is_array())
			return;
		for (json& prim : *prims) {
			if (!prim.is_object())
				continue;
			if (prim.contains("attributes"))
				members(prim["attributes"]);
			key(prim, "indices", on_accessor);
			if (prim.contains("targets") && prim["targets"].is_array())
				for (json& target : prim["targets"])
					members(target);
			if (const json* ext = draco_extension(prim))
				if (ext->is_object())
					key(prim["extensions"][draco_name], "bufferView", on_view);
		}
	});
	each("skins", [&](json& skin) { key(skin, "inverseBindMatrices", on_accessor); });
	each("animations", [&](json& animation) {
		if (animation.contains("samplers") && animation["samplers"].is_array())
			for (json& sampler : animation["samplers"])
				if (sampler.is_object()) {
					key(sampler, "input", on_accessor);
					key(sampler, "output", on_accessor);
				}
	});
	each("nodes", [&](json& node) {
		auto ext = node.find("extensions");
		if (ext != node.end() && ext->is_object() && ext->contains("EXT_mesh_gpu_instancing") &&
		    (*ext)["EXT_mesh_gpu_instancing"].is_object() && (*ext)["EXT_mesh_gpu_instancing"].contains("attributes"))
			members((*ext)["EXT_mesh_gpu_instancing"]["attributes"]);
	});
	each("images", [&](json& image) { key(image, "bufferView", on_view); });
	/* A property table keeps each property's values, and its array and
	 * string offsets, in bufferViews (3D Tiles 1.1 content). */
	auto ext = j.find("extensions");
	if (ext == j.end() || !ext->is_object() || !ext->contains("EXT_structural_metadata"))
		return;
	json& metadata = (*ext)["EXT_structural_metadata"];
	auto tables = metadata.is_object() ? metadata.find("propertyTables") : metadata.end();
	if (tables != metadata.end() && tables->is_array())
		for (json& table : *tables)
			if (table.is_object() && table.contains("properties") && table["properties"].is_object())
				for (auto& property : table["properties"].items())
					if (property.value().is_object())
						for (const char* k : {"values", "arrayOffsets", "stringOffsets"})
							key(property.value(), k, on_view);
}

/* The bufferView indices an accessor holds: its data and sparse parts. */
template <typename V> void accessor_views(json& a, V on_view)
{
	if (!a.is_object())
		return;
	if (a.contains("bufferView") && a["bufferView"].is_number_integer())
		on_view(a["bufferView"]);
	auto sp = a.find("sparse");
	if (sp != a.end() && sp->is_object())
		for (const char* part : {"indices", "values"})
			if (sp->contains(part) && (*sp)[part].is_object() && (*sp)[part].contains("bufferView") &&
			    (*sp)[part]["bufferView"].is_number_integer())
				on_view((*sp)[part]["bufferView"]);
}

/* A reference visitor that flags v[index] for every index within v. */
auto marker(std::vector<bool>& v)
{
	return [&v](json& ref) {
		const long long i = ref.get<long long>();
		if (i >= 0 && (size_t)i < v.size())
			v[(size_t)i] = true;
	};
}

bool none(const std::vector<bool>& v)
{
	return std::find(v.begin(), v.end(), true) == v.end();
}

} // namespace

usage used(json& j)
{
	usage u;
	auto size = [&](const char* array) { return j.contains(array) && j[array].is_array() ? j[array].size() : 0; };
	u.accessors.assign(size("accessors"), false);
	u.views.assign(size("bufferViews"), false);
	visit_references(j, marker(u.accessors), marker(u.views));
	for (size_t i = 0; i < u.accessors.size(); ++i)
		if (u.accessors[i])
			accessor_views(j["accessors"][i], marker(u.views));
	return u;
}

namespace {

/* Extensions whose data hold no accessor, bufferView or buffer index beyond
 * those visit_references and extension_buffers know (prefix match for
 * KHR_materials_):
 * EXT_mesh_features and EXT_instance_features name feature-ID attributes
 * by set number, textures and property tables by index,
 * EXT_structural_metadata's textures, attributes and tables likewise
 * (its tables' bufferViews visit_references knows), CESIUM_RTC holds a
 * centre, KHR_animation_pointer and
 * KHR_interactivity JSON pointers of the glTF object model (nodes,
 * materials, meshes, cameras, skins, animations, scenes: nothing pruning
 * renumbers), KHR_node_visibility, _selectability and _hoverability a
 * flag on a node. */
bool prunable_with(const std::string& name)
{
	static const char* const known[] = {"KHR_draco_mesh_compression", "KHR_mesh_quantization", "KHR_texture_transform",
	                                    "KHR_lights_punctual", "KHR_texture_basisu", "EXT_texture_webp",
	                                    "EXT_texture_avif", "EXT_mesh_gpu_instancing", "KHR_xmp_json_ld",
	                                    "KHR_xmp", "EXT_mesh_features", "EXT_instance_features",
	                                    "EXT_structural_metadata", "CESIUM_RTC", "KHR_animation_pointer",
	                                    "KHR_node_visibility", "KHR_node_selectability", "KHR_node_hoverability",
	                                    "KHR_interactivity", "EXT_lights_image_based", "MSFT_lod",
	                                    "MSFT_texture_dds", "EXT_meshopt_compression", "KHR_meshopt_compression"};
	return name.rfind("KHR_materials_", 0) == 0 ||
	       std::find_if(std::begin(known), std::end(known), [&](const char* k) { return name == k; }) != std::end(known);
}

} // namespace

std::string unknown_extension(const json& j)
{
	for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
		auto it = j.find(list);
		if (it != j.end() && it->is_array())
			for (const json& name : *it)
				if (!name.is_string() || !prunable_with(name.get<std::string>()))
					return name.is_string() ? name.get<std::string>() : name.dump();
	}
	return "";
}

namespace {

/* Calls f(holder) for every byte range of buffer b, holder the json of its
 * byteOffset and byteLength: the bufferViews in b, and the meshopt data in
 * b that bufferViews' extensions refer to. */
template <typename F> void ranges_in(json& views, size_t b, F f)
{
	for (json& v : views) {
		if (!v.is_object())
			continue;
		if (index_or_none(v, "buffer") == (long long)b)
			f(v);
		extension_buffers(v, [&](json& ref, json& ext) {
			if (ref == b)
				f(ext);
		});
	}
}

/* Packs buffer b to the bytes its bufferViews and the extensions' data
 * cover: overlapping ranges stay together, each keeps its offset modulo 4
 * (what accessor alignment needs), gaps go. The file's part is copied; the
 * blocks vn appended (a view each) are moved, not copied. A buffer with a
 * malformed range is left as it is. Returns false when nothing is left in b (it can go). */
bool pack_buffer(document& d, size_t b)
{
	json& views = d.j["bufferViews"];
	struct range {
		size_t begin, end, to;
	};
	std::vector<range> ranges;
	bool malformed = false;
	ranges_in(views, b, [&](json& holder) {
		const long long begin = holder.contains("byteOffset") ? index_or_none(holder, "byteOffset") : 0;
		const long long length = index_or_none(holder, "byteLength");
		/* Within the file's part or within vn's appended part (never across). */
		const buffer& from = d.buffers[b];
		const unsigned long long end = (unsigned long long)begin + (unsigned long long)length;
		if (begin < 0 || length < 0 || !(end <= from.size || ((size_t)begin >= from.tail_start() && end <= from.total())))
			malformed = true;
		else
			ranges.push_back({(size_t)begin, (size_t)(begin + length), 0});
	});
	if (malformed)
		return true;
	if (ranges.empty())
		return false;
	std::sort(ranges.begin(), ranges.end(), [](const range& x, const range& y) { return x.begin < y.begin; });
	std::vector<range> merged;
	for (const range& r : ranges)
		if (!merged.empty() && r.begin < merged.back().end)
			merged.back().end = std::max(merged.back().end, r.end);
		else
			merged.push_back(r);
	buffer& from = d.buffers[b];
	size_t size = 0, file_size = 0;
	for (range& m : merged) {
		m.to = (size + 3) / 4 * 4 + m.begin % 4;
		size = m.to + (m.end - m.begin);
		if (m.end <= from.size)
			file_size = size;
	}
	buffer packed;
	packed.owner = block(file_size);
	packed.base = packed.owner.get();
	packed.size = file_size;
	packed.absent = from.absent; /* a meshopt fallback's decoded data stay unwritten */
	memset(packed.base, 0, file_size);
	for (const range& m : merged) {
		if (m.end <= from.size) {
			memcpy(packed.base + m.to, from.at(m.begin), m.end - m.begin);
			continue;
		}
		const size_t offset = m.begin - from.tail_start(), length = m.end - m.begin;
		auto appended = std::lower_bound(from.tail.begin(), from.tail.end(), offset,
		                                 [](const std::pair<size_t, bytes>& a, size_t o) { return a.first < o; });
		bytes data;
		if (appended != from.tail.end() && appended->first == offset && appended->second.size() == length)
			data = std::move(appended->second);
		else
			data.assign(from.at(m.begin), from.at(m.begin) + length);
		packed.tail.emplace_back(m.to - packed.tail_start(), std::move(data));
	}
	ranges_in(views, b, [&](json& holder) {
		const size_t begin = holder.contains("byteOffset") ? (size_t)index_or_none(holder, "byteOffset") : 0;
		/* The last range starting at or before it (sorted, disjoint). */
		const range& m = *(std::upper_bound(merged.begin(), merged.end(), begin,
		                                    [](size_t x, const range& r) { return x < r.begin; }) - 1);
		holder["byteOffset"] = m.to + (begin - m.begin);
	});
	d.buffers[b] = std::move(packed);
	d.j["buffers"][b]["byteLength"] = size;
	return true;
}

/* Removes the buffers flagged in gone (nothing refers to them) and
 * renumbers the bufferViews' (and their extensions') references to the
 * others. */
void remove_buffers(document& d, const std::vector<bool>& gone)
{
	if (none(gone))
		return;
	std::vector<long long> to(gone.size());
	std::vector<buffer> kept;
	json kept_json = json::array();
	for (size_t b = 0; b < gone.size(); ++b) {
		to[b] = gone[b] ? -1 : (long long)kept.size();
		if (!gone[b]) {
			kept.push_back(std::move(d.buffers[b]));
			kept_json.push_back(std::move(d.j["buffers"][b]));
		}
	}
	d.buffers = std::move(kept);
	if (kept_json.empty())
		d.j.erase("buffers");
	else
		d.j["buffers"] = std::move(kept_json);
	auto renumber = [&](json& ref) {
		if (ref.is_number_integer() && ref.get<long long>() >= 0 && ref.get<size_t>() < to.size())
			ref = to[ref.get<size_t>()];
	};
	for (json& v : d.j["bufferViews"])
		if (v.is_object()) {
			if (v.contains("buffer"))
				renumber(v["buffer"]);
			extension_buffers(v, [&](json& ref, json&) { renumber(ref); });
		}
}

} // namespace

/* Removes what vn's changes left unused: accessors and bufferViews the
 * input used and the output does not (old NORMAL data, re-encoded Draco
 * data, primitives --draco on compressed), renumbering every reference,
 * and their bytes, packing each such buffer (other views keep their
 * offsets modulo 4). What the input itself left unused stays. A document
 * using an extension vn does not know (it may hold indices) is left as
 * is, and *unknown names it. */
void prune(document& d, const usage& before, vn_gltf_stats& st, std::string* unknown)
{
	usage after = used(d.j);
	/* Used by the input, or appended by vn (past the input's arrays), and
	 * unused now. */
	auto orphaned = [](const std::vector<bool>& was, const std::vector<bool>& is) {
		std::vector<bool> out(is.size(), false);
		for (size_t i = 0; i < is.size(); ++i)
			out[i] = (i >= was.size() || was[i]) && !is[i];
		return out;
	};
	std::vector<bool> gone_accessors = orphaned(before.accessors, after.accessors);
	if (none(gone_accessors) && none(orphaned(before.views, after.views)) && d.repack.empty())
		return;
	if (!(*unknown = unknown_extension(d.j)).empty())
		return;
	/* New index of each kept element; removal of the others. */
	auto renumber = [](json& array, const std::vector<bool>& gone) {
		std::vector<long long> to(gone.size());
		long long next = 0;
		for (size_t i = 0; i < gone.size(); ++i)
			to[i] = gone[i] ? -1 : next++;
		json kept = json::array();
		for (size_t i = 0; i < array.size(); ++i)
			if (i >= gone.size() || !gone[i])
				kept.push_back(std::move(array[i]));
		array = std::move(kept);
		return [to](json& ref) {
			const long long i = ref.get<long long>();
			if (i >= 0 && (size_t)i < to.size())
				ref = to[(size_t)i];
		};
	};
	auto nothing = [](json&) {};
	if (d.j.contains("accessors")) {
		const auto to = renumber(d.j["accessors"], gone_accessors);
		visit_references(d.j, to, nothing);
		st.pruned_accessors += (size_t)std::count(gone_accessors.begin(), gone_accessors.end(), true);
	}
	after = used(d.j);
	/* Views no accessor points at any more (used or not: an accessor the
	 * input left unused keeps its view). */
	std::vector<bool> pointed(after.views.size(), false);
	if (d.j.contains("accessors"))
		for (json& a : d.j["accessors"])
			accessor_views(a, marker(pointed));
	std::vector<bool> gone_views = orphaned(before.views, after.views);
	for (size_t i = 0; i < gone_views.size(); ++i)
		gone_views[i] = gone_views[i] && !pointed[i];
	/* The buffers that lose bytes: those of the views that go (with their
	 * meshopt data), and those the meshopt stage left bytes unused in. */
	std::vector<bool> packed(d.buffers.size(), false);
	auto mark = marker(packed);
	for (size_t b : d.repack)
		if (b < packed.size())
			packed[b] = true;
	for (size_t i = 0; i < gone_views.size(); ++i)
		if (gone_views[i]) {
			json& view = d.j["bufferViews"][i];
			if (index_or_none(view, "buffer") >= 0)
				mark(view["buffer"]);
			extension_buffers(view, [&](json& ref, json&) { mark(ref); });
		}
	if (!none(gone_views)) {
		const auto to = renumber(d.j["bufferViews"], gone_views);
		visit_references(d.j, nothing, to);
		if (d.j.contains("accessors"))
			for (json& a : d.j["accessors"])
				accessor_views(a, to);
		st.pruned_views += (size_t)std::count(gone_views.begin(), gone_views.end(), true);
	}
	std::vector<bool> gone_buffers(d.buffers.size(), false);
	for (size_t b = 0; b < d.buffers.size(); ++b)
		if (packed[b])
			gone_buffers[b] = !pack_buffer(d, b);
	remove_buffers(d, gone_buffers);
}

} // namespace vn_gltf
