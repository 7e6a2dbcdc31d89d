/*
 * EXT_meshopt_compression and KHR_meshopt_compression (gltf_document.h):
 * a bufferView whose data are compressed names, in its extension, where
 * the compressed bytes lie and how to decode them (mode, filter, count,
 * byteStride); the view itself is where the decoded data belong, in a
 * fallback buffer that has them (for loaders without the extension) or
 * has no data at all. On load every such view is decoded with
 * meshoptimizer into that place (an absent fallback gets memory for it),
 * so that every other stage reads plain data through the view. After the
 * normals, --meshopt keep encodes again only the views whose decoded data
 * changed (the others keep their compressed bytes, as filters are lossy),
 * and --meshopt off leaves every view plain and the extensions gone.
 */
#include "gltf_document.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace vn_gltf {
namespace {

enum class codec { attributes, triangles, indices };
enum class filter { none, octahedral, quaternion, exponential };

const char* const codec_names[] = {"ATTRIBUTES", "TRIANGLES", "INDICES"};
const char* const filter_names[] = {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"};

/* A compressed bufferView, checked: its compressed data (source) and the
 * view's own range (target, count x stride bytes). */
struct stream {
	size_t view;
	const char* name; /* the extension's */
	std::string what; /* "bufferViews[N]" */
	codec mode;
	filter method;
	size_t count, stride;
	size_t source, source_offset, source_length;
	size_t target, target_offset;
	size_t size() const { return count * stride; }
};

/* The index of string property key of o among names (def when absent). */
template <size_t N> size_t enumerated(const json& o, const char* key, const char* const (&names)[N], long long def,
                                      const std::string& what)
{
	auto it = o.find(key);
	if (it == o.end() && def >= 0)
		return (size_t)def;
	for (size_t i = 0; it != o.end() && it->is_string() && i < N; ++i)
		if (*it == names[i])
			return i;
	if (it == o.end())
		fail(vn_io_error_parse, str("%s has no %s", what.c_str(), key));
	if (*it == "COLOR")
		fail(vn_io_error_unsupported, str("%s.%s is COLOR, which vn's meshoptimizer %d.%d cannot decode", what.c_str(), key,
		                                  MESHOPTIMIZER_VERSION / 1000, MESHOPTIMIZER_VERSION % 1000 / 10));
	fail(vn_io_error_parse, str("%s.%s is %s, which the extension does not define", what.c_str(), key, it->dump().c_str()));
}

/* Whether bufferViews[v] is compressed; s describes it, checked against the
 * specification's rules and the buffers. */
bool compressed(const document& d, size_t v, stream& s)
{
	s.view = v;
	s.what = str("bufferViews[%zu]", v);
	const json& view = d.j["bufferViews"][v];
	const json* ext = view.is_object() ? meshopt_extension(view, &s.name, s.what) : nullptr;
	if (!ext)
		return false;
	const std::string what = s.what + ".extensions." + s.name;
	if (!ext->is_object())
		fail(vn_io_error_parse, what + " is not an object");
	const long long buffer = get_int(*ext, "buffer", -1, what), offset = get_int(*ext, "byteOffset", 0, what),
	                length = get_int(*ext, "byteLength", -1, what), stride = get_int(*ext, "byteStride", -1, what),
	                count = get_int(*ext, "count", -1, what);
	if (buffer < 0 || length < 0 || stride < 0 || count < 0)
		fail(vn_io_error_parse, what + " lacks buffer, byteLength, byteStride or count");
	s.mode = (codec)enumerated(*ext, "mode", codec_names, -1, what);
	s.method = (filter)enumerated(*ext, "filter", filter_names, 0, what);
	/* The specification's rules, which meshoptimizer asserts. */
	const bool attributes = s.mode == codec::attributes;
	const bool valid = count >= 1 && count <= (1LL << 40) &&
	                   (attributes ? stride >= 4 && stride <= 256 && stride % 4 == 0
	                               : (stride == 2 || stride == 4) && s.method == filter::none) &&
	                   (s.mode != codec::triangles || count % 3 == 0) &&
	                   (s.method != filter::octahedral || stride == 4 || stride == 8) &&
	                   (s.method != filter::quaternion || stride == 8);
	if (!valid)
		fail(vn_io_error_parse, str("%s: byteStride %lld and count %lld do not suit mode %s, filter %s", what.c_str(),
		                            stride, count, codec_names[(int)s.mode], filter_names[(int)s.method]));
	s.count = (size_t)count, s.stride = (size_t)stride;
	if ((size_t)buffer >= d.buffers.size() || d.buffers[(size_t)buffer].absent)
		fail(vn_io_error_parse, str("%s: its data are in buffers[%lld], which %s", what.c_str(), buffer,
		                            (size_t)buffer >= d.buffers.size() ? "does not exist" : "has no data"));
	if ((unsigned long long)offset + (unsigned long long)length > d.buffers[(size_t)buffer].size)
		fail(vn_io_error_parse, str("%s overflows buffers[%lld]: it ends at byte %llu, the buffer has %zu", what.c_str(),
		                            buffer, (unsigned long long)(offset + length), d.buffers[(size_t)buffer].size));
	s.source = (size_t)buffer, s.source_offset = (size_t)offset, s.source_length = (size_t)length;
	/* Every mode stores at least 2 bits per 16 decoded bytes (the attribute
	 * codec's group headers): fewer bytes are a damaged stream, and this
	 * bounds the memory a small file may ask for. */
	if (s.size() / 64 > s.source_length)
		fail(vn_io_error_parse, str("%s: its %zu bytes of data are too few for %zu elements of %zu bytes: the stream "
		                            "is damaged", what.c_str(), s.source_length, s.count, s.stride));
	const long long target = get_int(view, "buffer", -1, s.what), target_offset = get_int(view, "byteOffset", 0, s.what);
	if (target < 0 || (size_t)target >= d.buffers.size())
		fail(vn_io_error_parse, s.what + " refers to a buffer that does not exist");
	if (get_int(view, "byteLength", -1, s.what) != (long long)s.size() ||
	    get_int(view, "byteStride", stride, s.what) != stride)
		fail(vn_io_error_parse, str("%s: its byteLength and byteStride are not those of %s (%zu elements of %zu bytes)",
		                            s.what.c_str(), s.name, s.count, s.stride));
	const size_t bound = d.buffers[(size_t)target].absent
	                         ? (size_t)get_int(d.j["buffers"][(size_t)target], "byteLength", 0, "buffers")
	                         : d.buffers[(size_t)target].size;
	if ((unsigned long long)target_offset + s.size() > bound)
		fail(vn_io_error_parse, str("%s overflows buffers[%lld]: it ends at byte %llu, the buffer has %zu", s.what.c_str(),
		                            target, (unsigned long long)target_offset + s.size(), bound));
	s.target = (size_t)target, s.target_offset = (size_t)target_offset;
	return true;
}

/* The n bytes of a stream s's mode and `method` at data decoded into out
 * (s.size() bytes, malloc-aligned for the filters' wider types). */
void decode(const stream& s, filter method, const unsigned char* data, size_t n, unsigned char* out)
{
	const int r = s.mode == codec::attributes  ? meshopt_decodeVertexBuffer(out, s.count, s.stride, data, n)
	              : s.mode == codec::triangles ? meshopt_decodeIndexBuffer(out, s.count, s.stride, data, n)
	                                           : meshopt_decodeIndexSequence(out, s.count, s.stride, data, n);
	if (r != 0) {
		/* -1: a header meshoptimizer does not know; the bitstream version in
		 * its low 4 bits when the high ones name the mode's codec. */
		const unsigned char header = s.mode == codec::attributes ? 0xa0 : s.mode == codec::triangles ? 0xe0 : 0xd0;
		if (r == -1 && n > 0 && (data[0] & 0xf0) == header)
			fail(vn_io_error_unsupported,
			     str("%s: %s %s data of bitstream version %d, which vn's meshoptimizer %d.%d cannot decode", s.what.c_str(),
			         s.name, s.mode == codec::attributes ? "vertex" : "index", data[0] & 15, MESHOPTIMIZER_VERSION / 1000,
			         MESHOPTIMIZER_VERSION % 1000 / 10));
		fail(vn_io_error_parse, str("%s: its %s data are damaged (meshoptimizer cannot decode them as %s)", s.what.c_str(),
		                            s.name, codec_names[(int)s.mode]));
	}
	if (method == filter::octahedral)
		meshopt_decodeFilterOct(out, s.count, s.stride);
	else if (method == filter::quaternion)
		meshopt_decodeFilterQuat(out, s.count, s.stride);
	else if (method == filter::exponential)
		meshopt_decodeFilterExp(out, s.count, s.stride);
}

/* The input's compressed views. */
std::vector<stream> streams(const document& d)
{
	std::vector<stream> out;
	stream s;
	for (size_t v = 0; v < d.input_views; ++v)
		if (compressed(d, v, s))
			out.push_back(s);
	return out;
}

unsigned char* target(const document& d, const stream& s)
{
	return d.buffers[s.target].base + s.target_offset;
}

/* The data of a view the normals changed (`now`; `was`: as decoded on
 * load) encoded again with its mode and a filter for normals: octahedral
 * at the most bits its stride holds, exponential with 24-bit mantissas
 * when that gives back every 4 bytes that did not change (else none),
 * none for quaternion (which would normalize them as rotations). Returns
 * the compressed bytes; `now` becomes what they decode to, and *method the
 * filter used. */
bytes encode(const stream& s, unsigned char* now, const unsigned char* was, filter* method)
{
	const size_t n = s.size();
	std::shared_ptr<unsigned char> input = block(n), back = block(n);
	std::vector<float> values(s.count * std::max<size_t>(4, s.stride / 4)); /* octahedral: 4 per element */
	bytes out;
	for (filter f : {*method == filter::quaternion ? filter::none : *method, filter::none}) {
		if (f == filter::octahedral) {
			const double one = s.stride == 4 ? 127 : 32767;
			for (size_t i = 0; i < 4 * s.count; ++i)
				values[i] = (float)(read_component(now + i * s.stride / 4, s.stride == 4 ? 5120 : 5122, false) / one);
			meshopt_encodeFilterOct(input.get(), s.count, s.stride, (int)s.stride * 2, values.data());
		} else if (f == filter::exponential) {
			memcpy(values.data(), now, n);
			if (!std::all_of(values.begin(), values.begin() + n / 4, [](float x) { return std::isfinite(x); }))
				continue; /* the filter holds finite values only */
			meshopt_encodeFilterExp(input.get(), s.count, s.stride, 24, values.data());
		} else {
			memcpy(input.get(), now, n);
		}
		out.resize(meshopt_encodeVertexBufferBound(s.count, s.stride));
		out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), input.get(), s.count, s.stride));
		decode(s, f, out.data(), out.size(), back.get());
		bool kept = true;
		for (size_t i = 0; f == filter::exponential && i < n; i += 4)
			kept = kept && (memcmp(now + i, was + i, 4) != 0 || memcmp(back.get() + i, was + i, 4) == 0);
		if (kept) {
			memcpy(now, back.get(), n);
			*method = f;
			break;
		}
	}
	return out;
}

/* Accessors of bufferView v with min or max get them from its data again
 * (a lossy filter moved the values a little). */
void bounds_again(document& d, size_t v)
{
	auto accessors = d.j.find("accessors");
	for (size_t i = 0; accessors != d.j.end() && accessors->is_array() && i < accessors->size(); ++i) {
		json& j = (*accessors)[i];
		auto view = j.is_object() ? j.find("bufferView") : j.end();
		if (view == j.end() || *view != v || !(j.contains("min") || j.contains("max")))
			continue;
		const accessor a = get_accessor(d, (long long)i);
		if (a.sparse_count)
			continue; /* its bounds include the sparse values */
		const unsigned char* first = element_at(d, a.data, 0);
		set_bounds(j, bytes(first, first + a.data.stride * (size_t)(a.count - 1) + a.element), a.data.stride, a,
		           (size_t)a.count);
	}
}

/* json o's member `key`, erased, and o's "extensions" with it when that is
 * left empty. */
void erase_extension(json& o, const char* key)
{
	auto ext = o.find("extensions");
	if (ext == o.end() || !ext->is_object())
		return;
	ext->erase(key);
	if (ext->empty())
		o.erase("extensions");
}

} // namespace

std::set<std::string> decode_meshopt(document& d, vn_gltf_stats* st)
{
	const std::vector<stream> all = streams(d);
	std::set<std::string> names;
	for (const stream& s : all)
		names.insert(s.name);
	if (all.empty())
		return names;
	/* An absent fallback gets memory up to the end of its last view; as
	 * decoded data are at most 64 times the compressed ones, more than 64
	 * times the file's data is not a fallback's but a damaged file's. */
	std::vector<size_t> need(d.buffers.size(), 0);
	size_t data = 0;
	for (const buffer& b : d.buffers)
		data += b.absent ? 0 : b.size;
	for (const stream& s : all)
		if (d.buffers[s.target].absent)
			need[s.target] = std::max(need[s.target], s.target_offset + s.size());
	for (size_t b = 0; b < d.buffers.size(); ++b) {
		if (!need[b])
			continue;
		if (need[b] / 64 > data)
			fail(vn_io_error_parse, str("buffers[%zu]: its meshopt views end at byte %zu, more than the file's %zu bytes of "
			                            "data could fill", b, need[b], data));
		buffer& to = d.buffers[b];
		to.owner = block(need[b]);
		to.base = to.owner.get();
		to.size = need[b];
		memset(to.base, 0, to.size);
	}
	/* Decoded data written over compressed data would damage what is read
	 * next and what --meshopt keep writes back. */
	std::vector<std::pair<std::pair<size_t, size_t>, size_t>> sources; /* (buffer, begin), end */
	for (const stream& s : all)
		sources.push_back({{s.source, s.source_offset}, s.source_offset + s.source_length});
	std::sort(sources.begin(), sources.end());
	for (size_t k = 1; k < sources.size(); ++k)
		if (sources[k].first.first == sources[k - 1].first.first)
			sources[k].second = std::max(sources[k].second, sources[k - 1].second); /* the furthest end so far */
	for (const stream& s : all) {
		auto after = std::lower_bound(sources.begin(), sources.end(),
		                              std::make_pair(std::make_pair(s.target, s.target_offset + s.size()), (size_t)0));
		if (after != sources.begin() && (after - 1)->first.first == s.target && (after - 1)->second > s.target_offset)
			fail(vn_io_error_parse, str("%s: its data in buffers[%zu] overlap compressed data", s.what.c_str(), s.target));
	}
	for (const stream& s : all) {
		std::shared_ptr<unsigned char> out = block(s.size());
		decode(s, s.method, d.buffers[s.source].base + s.source_offset, s.source_length, out.get());
		memcpy(target(d, s), out.get(), s.size());
	}
	if (st)
		st->meshopt_views += all.size();
	return names;
}

void write_meshopt(document& d, vn_gltf_meshopt mode, vn_gltf_stats& st)
{
	const std::vector<stream> all = streams(d);
	for (const stream& s : all) {
		if (mode == vn_gltf_meshopt_off) {
			erase_extension(d.j["bufferViews"][s.view], s.name);
			d.repack.insert(s.source);
			continue;
		}
		std::shared_ptr<unsigned char> was = block(s.size());
		decode(s, s.method, d.buffers[s.source].base + s.source_offset, s.source_length, was.get());
		unsigned char* now = target(d, s);
		if (memcmp(now, was.get(), s.size()) == 0)
			continue; /* its compressed bytes stay as they are */
		if (s.mode != codec::attributes)
			fail(vn_io_error_unsupported, str("%s: new normals are in it, and %s compresses it as %s, which holds indices "
			                                  "only: use --meshopt off", s.what.c_str(), s.name, codec_names[(int)s.mode]));
		filter method = s.method;
		const bytes data = encode(s, now, was.get(), &method);
		json& ext = d.j["bufferViews"][s.view]["extensions"][s.name];
		ext["byteOffset"] = append_bytes(d, s.source, data);
		ext["byteLength"] = data.size();
		if (method != s.method)
			ext.erase("filter"); /* none */
		d.repack.insert(s.source);
		if (method != filter::none)
			bounds_again(d, s.view);
		++st.meshopt_encoded;
	}
	if (mode == vn_gltf_meshopt_off)
		for (buffer& b : d.buffers)
			if (b.absent && b.base) {
				/* A fallback without data holds them now. */
				b.absent = false;
				d.j["buffers"][(size_t)(&b - d.buffers.data())]["byteLength"] = b.size;
			}
}

void tidy_meshopt(document& d, const std::set<std::string>& names)
{
	auto views = d.j.find("bufferViews");
	for (const std::string& name : names) {
		const bool used = views != d.j.end() && views->is_array() &&
		                  std::any_of(views->begin(), views->end(), [&](const json& v) {
			                  return v.is_object() && v.contains("extensions") && v["extensions"].is_object() &&
			                         v["extensions"].contains(name);
		                  });
		if (used)
			continue;
		for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
			auto it = d.j.find(list);
			if (it == d.j.end() || !it->is_array())
				continue;
			it->erase(std::remove(it->begin(), it->end(), name), it->end());
			if (it->empty())
				d.j.erase(list);
		}
		auto buffers = d.j.find("buffers");
		for (size_t b = 0; buffers != d.j.end() && buffers->is_array() && b < buffers->size(); ++b)
			if ((*buffers)[b].is_object())
				erase_extension((*buffers)[b], name.c_str());
	}
}

} // namespace vn_gltf
