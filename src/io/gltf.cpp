/*
 * glTF 2.0 reading and writing: the C++ glue behind gltf.h.
 *
 * The original JSON is kept as an nlohmann::ordered_json so that key order,
 * extras and unknown extensions survive; only NORMAL data change (in place
 * where the accessor allows, else appended; Draco data are decoded and
 * encoded again with draco.h). Buffers are read once and written once, in
 * place: a GLB's BIN chunk stays in the memory the file was read into, and
 * the output is written from it piece by piece. tinygltf 2.7's loader is not
 * used for this because it copies every buffer into its model (twice the
 * file in memory, half the time of a conversion: docs/PERFORMANCE.md);
 * vn checks everything it reads itself, and takes tinygltf's data-URI
 * decoding. The document and buffer types are in gltf_document.h;
 * gltf_prune.cpp removes what the edits leave unused.
 */
#include "gltf.h"
#include "gltf_document.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <tiny_gltf.h>
#include <vector>

namespace {

using namespace vn_gltf;

/* Every failure is thrown as one of these and turned into a vn_io_error at
 * the C boundary. msg never names the file: the boundary prefixes it. */
struct failure {
	vn_io_result result;
	std::string msg;
	bool names_file; /* msg starts with the file it is about */
};

/* A failure about the file being read (the caller prefixes its name). */
[[noreturn]] void fail(vn_io_result r, const std::string& msg)
{
	throw failure{r, msg, false};
}

/* A failure whose message names its own file ("out.bin: cannot write"). */
[[noreturn]] void fail_named(vn_io_result r, const std::string& msg)
{
	throw failure{r, msg, true};
}

std::string str(const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

std::string str(const char* fmt, ...)
{
	char text[512];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(text, sizeof text, fmt, ap);
	va_end(ap);
	return text;
}

const uint32_t glb_magic = 0x46546C67, chunk_json = 0x4E4F534A, chunk_bin = 0x004E4942;

uint32_t le32(const unsigned char* p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

std::string folder_of(const std::string& path)
{
	size_t slash = path.rfind('/');
	return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string uri_decode(const std::string& s)
{
	std::string out;
	for (size_t i = 0; i < s.size(); ++i) {
		if (s[i] == '%' && i + 2 < s.size() && isxdigit((unsigned char)s[i + 1]) && isxdigit((unsigned char)s[i + 2])) {
			out += (char)std::stoi(s.substr(i + 1, 2), nullptr, 16);
			i += 2;
		} else {
			out += s[i];
		}
	}
	return out;
}

/* ------------------------------------------------------------------ loading */

/* Integer property `key` of o, or def when absent; anything but a
 * non-negative integer is malformed. */
long long get_int(const json& o, const char* key, long long def, const std::string& what)
{
	auto it = o.find(key);
	if (it == o.end())
		return def;
	if (!it->is_number_integer() || it->get<long long>() < 0)
		fail(vn_io_error_parse, what + "." + key + " is not a non-negative integer");
	return it->get<long long>();
}

const json& element(const json& doc, const char* array, long long i, const std::string& what)
{
	auto it = doc.find(array);
	if (it == doc.end() || !it->is_array() || i < 0 || (size_t)i >= it->size())
		fail(vn_io_error_parse, str("%s refers to %s[%lld], which does not exist", what.c_str(), array, i));
	const json& e = (*it)[(size_t)i];
	if (!e.is_object())
		fail(vn_io_error_parse, str("%s[%lld] is not an object", array, i));
	return e;
}

size_t component_size(long long type)
{
	switch (type) {
	case 5120: case 5121: return 1;
	case 5122: case 5123: return 2;
	case 5125: case 5126: return 4;
	default: return 0;
	}
}

size_t component_count(const std::string& type)
{
	static const std::map<std::string, size_t> n = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
	                                                {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}};
	auto it = n.find(type);
	return it == n.end() ? 0 : it->second;
}

/* Where an accessor's or sparse part's elements lie in a buffer. */
struct span {
	int buffer = -1; /* -1: no bufferView (zeros) */
	size_t offset = 0, stride = 0;
};

struct accessor {
	long long count = 0, component = 0;
	size_t components = 0, element = 0;
	bool normalized = false;
	span data;
	/* sparse */
	long long sparse_count = 0, sparse_index_component = 0;
	span sparse_indices, sparse_values;
};

/* Element i of s. */
unsigned char* element_at(const document& d, const span& s, size_t i)
{
	return d.buffers[(size_t)s.buffer].at(s.offset + i * s.stride);
}

/* The bufferView `view` checked against its buffer; needed bytes from the
 * view's start must fit in it. */
span view_span(const document& d, long long view, size_t offset, size_t needed, size_t element_size,
               const std::string& what)
{
	const std::string vw = str("bufferViews[%lld]", view);
	const json& v = element(d.j, "bufferViews", view, what);
	long long buffer = get_int(v, "buffer", -1, vw);
	if (buffer < 0 || (size_t)buffer >= d.buffers.size())
		fail(vn_io_error_parse, vw + " refers to a buffer that does not exist");
	long long begin = get_int(v, "byteOffset", 0, vw), length = get_int(v, "byteLength", -1, vw);
	if (length < 0)
		fail(vn_io_error_parse, vw + " has no byteLength");
	const auto& b = d.buffers[(size_t)buffer];
	const size_t bound = (size_t)view < d.input_views ? b.size : b.total();
	if ((unsigned long long)begin + (unsigned long long)length > bound)
		fail(vn_io_error_parse, str("%s overflows buffers[%lld]: it ends at byte %llu, the buffer has %zu",
		                            vw.c_str(), buffer, (unsigned long long)(begin + length), bound));
	span s;
	s.buffer = (int)buffer;
	s.offset = (size_t)begin + offset;
	s.stride = (size_t)get_int(v, "byteStride", 0, vw);
	if (s.stride > 252)
		fail(vn_io_error_parse, vw + ".byteStride is over 252");
	if (s.stride == 0)
		s.stride = element_size;
	if (offset > (size_t)length || needed > (size_t)length - offset)
		fail(vn_io_error_parse, str("%s is out of bounds: it reads up to byte %zu of %s, which has %lld",
		                            what.c_str(), offset + needed, vw.c_str(), length));
	return s;
}

accessor get_accessor(const document& d, long long index)
{
	const std::string what = str("accessors[%lld]", index);
	const json& a = element(d.j, "accessors", index, what);
	accessor r;
	r.count = get_int(a, "count", 0, what);
	r.component = get_int(a, "componentType", 0, what);
	auto type = a.find("type");
	r.components = type != a.end() && type->is_string() ? component_count(type->get<std::string>()) : 0;
	size_t csize = component_size(r.component);
	if (r.count < 1 || !csize || !r.components)
		fail(vn_io_error_parse, what + " has an invalid count, componentType or type");
	r.element = csize * r.components;
	auto norm = a.find("normalized");
	r.normalized = norm != a.end() && norm->is_boolean() && norm->get<bool>();
	if (r.count > (long long)UINT32_MAX)
		fail(vn_io_error_unsupported, what + " has more than 2^32 elements");
	if (a.contains("bufferView")) {
		long long view = get_int(a, "bufferView", 0, what);
		size_t offset = (size_t)get_int(a, "byteOffset", 0, what);
		const json& v = element(d.j, "bufferViews", view, what);
		size_t stride = std::min<size_t>((size_t)get_int(v, "byteStride", 0, str("bufferViews[%lld]", view)), 253);
		if (!stride)
			stride = r.element;
		r.data = view_span(d, view, offset, stride * (size_t)(r.count - 1) + r.element, r.element, what);
	}
	else if (r.count > (1 << 24))
		/* Data that is not in the file (zeros plus sparse values): a size
		 * limit, so that a small file cannot ask for gigabytes. */
		fail(vn_io_error_unsupported, what + " has no bufferView and more than 2^24 elements");
	auto sp = a.find("sparse");
	if (sp != a.end()) {
		const std::string sw = what + ".sparse";
		if (!sp->is_object() || !sp->contains("indices") || !sp->contains("values") ||
		    !(*sp)["indices"].is_object() || !(*sp)["values"].is_object())
			fail(vn_io_error_parse, sw + " is malformed");
		r.sparse_count = get_int(*sp, "count", 0, sw);
		const json& ind = (*sp)["indices"];
		const json& val = (*sp)["values"];
		r.sparse_index_component = get_int(ind, "componentType", 0, sw + ".indices");
		size_t isize = component_size(r.sparse_index_component);
		if (r.sparse_count < 1 || r.sparse_count > r.count || !isize || r.sparse_index_component == 5120 ||
		    r.sparse_index_component == 5122 || r.sparse_index_component == 5126)
			fail(vn_io_error_parse, sw + " has an invalid count or index type");
		r.sparse_indices = view_span(d, get_int(ind, "bufferView", -1, sw + ".indices"),
		                             (size_t)get_int(ind, "byteOffset", 0, sw + ".indices"),
		                             isize * (size_t)r.sparse_count, isize, sw + ".indices");
		r.sparse_indices.stride = isize;
		r.sparse_values = view_span(d, get_int(val, "bufferView", -1, sw + ".values"),
		                            (size_t)get_int(val, "byteOffset", 0, sw + ".values"),
		                            r.element * (size_t)r.sparse_count, r.element, sw + ".values");
		r.sparse_values.stride = r.element;
	}
	return r;
}

double read_component(const unsigned char* p, long long type, bool normalized)
{
	switch (type) {
	case 5120: { int8_t v; memcpy(&v, p, 1); return normalized ? std::max(v / 127.0, -1.0) : v; }
	case 5121: { uint8_t v; memcpy(&v, p, 1); return normalized ? v / 255.0 : v; }
	case 5122: { int16_t v; memcpy(&v, p, 2); return normalized ? std::max(v / 32767.0, -1.0) : v; }
	case 5123: { uint16_t v; memcpy(&v, p, 2); return normalized ? v / 65535.0 : v; }
	case 5124: { int32_t v; memcpy(&v, p, 4); return v; } /* Draco's, never a glTF accessor's */
	case 5125: { uint32_t v; memcpy(&v, p, 4); return v; }
	default: { float v; memcpy(&v, p, 4); return v; }
	}
}

/* What a normalized integer component stored as v stands for. */
double normalized_value(double v, long long type)
{
	switch (type) {
	case 5120: return std::max(v / 127.0, -1.0);
	case 5121: return v / 255.0;
	case 5122: return std::max(v / 32767.0, -1.0);
	case 5123: return v / 65535.0;
	default: return v;
	}
}

/* v (not normalized: integers are rounded) as a component of type. */
void write_component(unsigned char* p, long long type, double v)
{
	switch (type) {
	case 5120: { int8_t q = (int8_t)std::lround(v); memcpy(p, &q, 1); break; }
	case 5121: { uint8_t q = (uint8_t)std::lround(v); memcpy(p, &q, 1); break; }
	case 5122: { int16_t q = (int16_t)std::lround(v); memcpy(p, &q, 2); break; }
	case 5123: { uint16_t q = (uint16_t)std::lround(v); memcpy(p, &q, 2); break; }
	case 5125: { uint32_t q = (uint32_t)std::llround(v); memcpy(p, &q, 4); break; }
	default: { float f = (float)v; memcpy(p, &f, 4); break; }
	}
}

/* All count x components values, with the sparse substitution applied. */
std::vector<double> read_accessor(const document& d, const accessor& a)
{
	std::vector<double> out((size_t)a.count * a.components, 0.0);
	const size_t csize = component_size(a.component);
	auto read_element = [&](const span& s, size_t i, double* to) {
		const unsigned char* p = element_at(d, s, i);
		for (size_t c = 0; c < a.components; ++c)
			to[c] = read_component(p + c * csize, a.component, a.normalized);
	};
	if (a.data.buffer >= 0)
		for (size_t i = 0; i < (size_t)a.count; ++i)
			read_element(a.data, i, &out[i * a.components]);
	for (size_t k = 0; k < (size_t)a.sparse_count; ++k) {
		double index = read_component(element_at(d, a.sparse_indices, k), a.sparse_index_component, false);
		if (index >= (double)a.count)
			fail(vn_io_error_parse, str("a sparse index (%.0f) is out of range (count %lld)", index, a.count));
		read_element(a.sparse_values, k, &out[(size_t)index * a.components]);
	}
	return out;
}

/* Buffer i's bytes: the GLB's BIN chunk (bin: its first byte, null when the
 * file has none), a data URI or an external file. */
buffer load_buffer(const document& d, size_t i, const std::shared_ptr<unsigned char>& file, const unsigned char* bin,
                   size_t bin_length)
{
	const std::string what = str("buffers[%zu]", i);
	const json& b = element(d.j, "buffers", (long long)i, what);
	const long long length = get_int(b, "byteLength", -1, what);
	if (length < 0)
		fail(vn_io_error_parse, what + " has no byteLength");
	buffer out;
	out.size = (size_t)length;
	auto uri = b.find("uri");
	if (uri == b.end()) {
		if (!d.glb || i != 0)
			fail(vn_io_error_parse, what + " has no uri");
		if (!bin)
			fail(vn_io_error_parse, what + " is the GLB's BIN chunk, which the file does not have");
		if (out.size > bin_length)
			fail(vn_io_error_parse, str("%s.byteLength %lld exceeds the BIN chunk (%zu bytes)", what.c_str(), length, bin_length));
		out.owner = file;
		out.base = const_cast<unsigned char*>(bin);
		return out;
	}
	if (!uri->is_string())
		fail(vn_io_error_parse, what + ".uri is not a string");
	const std::string& text = uri->get_ref<const std::string&>();
	size_t have;
	if (tinygltf::IsDataURI(text)) {
		std::vector<unsigned char> data;
		std::string mime;
		if (!tinygltf::DecodeDataURI(&data, mime, text, 0, false))
			fail(vn_io_error_parse, what + ": cannot decode its data URI");
		have = data.size();
		out.owner = block(have);
		memcpy(out.owner.get(), data.data(), have);
	} else {
		const std::string path = d.folder + uri_decode(text);
		char* raw;
		vn_io_error e;
		if (vn_io_read_all(path.c_str(), &raw, &have, &e) != vn_io_success)
			fail(vn_io_error_open, str("%s: %s", what.c_str(), e.message));
		out.owner = std::shared_ptr<unsigned char>((unsigned char*)raw, free);
	}
	if (have < out.size)
		fail(vn_io_error_parse, str("%s has %zu bytes, fewer than its byteLength %lld", what.c_str(), have, length));
	out.base = out.owner.get();
	return out;
}

/* Reads the file in one piece and parses its JSON; the GLB's BIN chunk
 * becomes buffer 0 where it lies, other buffers are read from their URIs. */
document load(const std::string& path)
{
	char* raw;
	size_t size;
	vn_io_error e;
	if (vn_io_read_all(path.c_str(), &raw, &size, &e) != vn_io_success)
		fail_named(vn_io_error_open, e.message);
	const std::shared_ptr<unsigned char> file((unsigned char*)raw, free);

	document d;
	d.folder = folder_of(path);
	const unsigned char* u = file.get();
	const char* text = raw;
	size_t text_length = size;
	const unsigned char* bin = nullptr;
	size_t bin_length = 0;
	d.glb = size >= 4 && le32(u) == glb_magic;
	if (d.glb) {
		if (size < 20)
			fail(vn_io_error_parse, str("truncated GLB: %zu bytes, less than a header and a chunk header", size));
		if (le32(u + 4) != 2)
			fail(vn_io_error_unsupported, str("GLB version %u (vn reads version 2)", le32(u + 4)));
		if (le32(u + 8) != size)
			fail(vn_io_error_parse, str("%s GLB: the header says %u bytes, the file has %zu",
			                            le32(u + 8) > size ? "truncated" : "malformed", le32(u + 8), size));
		uint32_t length = le32(u + 12);
		if (le32(u + 16) != chunk_json)
			fail(vn_io_error_parse, "malformed GLB: the first chunk is not JSON");
		if (length > size - 20)
			fail(vn_io_error_parse, str("malformed GLB: the JSON chunk length %u exceeds the file", length));
		text = raw + 20;
		text_length = length;
		size_t at = 20 + (size_t)length;
		if (at < size) {
			if (size - at < 8)
				fail(vn_io_error_parse, "malformed GLB: truncated chunk header after the JSON chunk");
			uint32_t chunk_length = le32(u + at);
			if (chunk_length > size - at - 8)
				fail(vn_io_error_parse, str("malformed GLB: the chunk length %u exceeds the file", chunk_length));
			if (le32(u + at + 4) == chunk_bin) /* another chunk type: no BIN chunk */
				bin = u + at + 8, bin_length = chunk_length;
		}
	}
	if (size == 0)
		fail(vn_io_error_parse, "the file is empty, not glTF");
	if (!d.glb) {
		size_t at = size >= 3 && memcmp(raw, "\xef\xbb\xbf", 3) == 0 ? 3 : 0; /* a UTF-8 byte order mark */
		while (at < size && isspace((unsigned char)raw[at]))
			++at;
		if (at == size || raw[at] != '{')
			fail(vn_io_error_parse, "neither a GLB (which starts with the bytes 'glTF') nor glTF JSON (which starts with "
			                        "'{'): not a glTF file, or a damaged one");
	}
	try {
		d.j = json::parse(text, text + text_length);
	} catch (const json::parse_error& x) {
		/* nlohmann's text starts with its own error id and position. */
		const std::string why = x.what();
		const size_t dash = why.find(" - ");
		fail(vn_io_error_parse, str("the glTF JSON is malformed at byte %zu%s: %s", (size_t)x.byte,
		                            d.glb ? " of the JSON chunk" : "",
		                            dash == std::string::npos ? why.c_str() : why.c_str() + dash + 3));
	} catch (const json::exception& x) {
		fail(vn_io_error_parse, std::string("the glTF JSON is malformed: ") + x.what());
	}
	if (!d.j.is_object())
		fail(vn_io_error_parse, "invalid JSON: the document is not an object");
	auto jb = d.j.find("buffers");
	if (jb != d.j.end() && !jb->is_array())
		fail(vn_io_error_parse, "buffers is not an array");
	for (size_t i = 0; jb != d.j.end() && i < jb->size(); ++i)
		d.buffers.push_back(load_buffer(d, i, file, bin, bin_length));
	auto views = d.j.find("bufferViews");
	d.input_views = views != d.j.end() && views->is_array() ? views->size() : 0;
	return d;
}

/* ------------------------------------------------------------------ Draco */

/* A Draco-compressed primitive decoded: its geometry and, per glTF
 * attribute name, the Draco attribute the extension maps it to. */
struct draco_mesh {
	vn_drc_geometry g{};
	std::map<std::string, const vn_drc_attribute*> by_name;
	draco_mesh() = default;
	draco_mesh(const draco_mesh&) = delete;
	draco_mesh& operator=(const draco_mesh&) = delete;
	~draco_mesh() { vn_drc_geometry_free(&g); }
};

size_t append_view(document& d, const bytes& data, size_t stride, int target);

/* Decodes primitive prim's Draco data (ext: its extension object) and
 * checks it against the primitive: indexed TRIANGLES, POSITION in the
 * data, accessors with the decoded counts and sizes. Attributes outside the
 * Draco data and morph targets follow the decoded points' order. */
std::shared_ptr<draco_mesh> decode_draco(const document& d, const json& prim, const json& ext, const std::string& what)
{
	const std::string ew = what + ".extensions." + draco_name;
	if (!ext.is_object() || !ext.contains("attributes") || !ext["attributes"].is_object())
		fail(vn_io_error_parse, ew + " is malformed");
	if (get_int(prim, "mode", 4, what) != 4 || !prim.contains("indices"))
		fail(vn_io_error_unsupported, what + " is Draco-compressed and not indexed TRIANGLES, which vn does not read");
	const long long view = get_int(ext, "bufferView", -1, ew);
	const size_t length = (size_t)get_int(element(d.j, "bufferViews", view, ew), "byteLength", 0, str("bufferViews[%lld]", view));
	const span s = view_span(d, view, 0, length, 1, ew);
	auto m = std::make_shared<draco_mesh>();
	vn_io_error e;
	const vn_io_result r = vn_drc_decode(element_at(d, s, 0), length, what.c_str(), &m->g, &e);
	if (r != vn_io_success)
		fail(r, e.message);
	const json& attributes = prim["attributes"];
	for (auto& kv : ext["attributes"].items()) {
		const long long id = get_int(ext["attributes"], kv.key().c_str(), 0, ew + ".attributes");
		for (size_t i = 0; i < m->g.attribute_count; ++i)
			if (m->g.attributes[i].unique_id == id)
				m->by_name[kv.key()] = &m->g.attributes[i];
		if (!m->by_name.count(kv.key()))
			fail(vn_io_error_parse, str("%s.attributes.%s is Draco attribute %lld, which the data does not have",
			                            ew.c_str(), kv.key().c_str(), id));
		if (!attributes.contains(kv.key()))
			fail(vn_io_error_parse, str("%s.attributes has no %s", what.c_str(), kv.key().c_str()));
	}
	if (!m->by_name.count("POSITION"))
		fail(vn_io_error_unsupported, what + ": POSITION is not in the Draco data, which vn does not handle");
	for (auto& kv : attributes.items()) {
		const accessor a = get_accessor(d, get_int(attributes, kv.key().c_str(), 0, what + ".attributes"));
		auto in = m->by_name.find(kv.key());
		if ((size_t)a.count != m->g.point_count || (in != m->by_name.end() && (int)a.components != in->second->components))
			fail(vn_io_error_parse, str("%s: the %s accessor's count or type does not match the Draco data (%zu points)",
			                            what.c_str(), kv.key().c_str(), m->g.point_count));
	}
	if ((size_t)get_accessor(d, get_int(prim, "indices", 0, what)).count != 3 * m->g.triangle_count)
		fail(vn_io_error_parse, str("%s: the indices accessor's count does not match the Draco data (%zu triangles)",
		                            what.c_str(), m->g.triangle_count));
	for (const char* name : {"POSITION", "NORMAL"}) {
		auto it = m->by_name.find(name);
		if (it != m->by_name.end() && (it->second->component_type != 5126 || it->second->components != 3))
			fail(vn_io_error_unsupported, str("%s: the Draco %s is not 3 floats", what.c_str(), name));
	}
	return m;
}

/* Replaces accessor a's min and max, where it has them, with lo and hi
 * (integers unless the component type is float). */
void set_bounds(json& a, const std::vector<double>& lo, const std::vector<double>& hi, long long component)
{
	for (auto bound : {std::make_pair("min", &lo), std::make_pair("max", &hi)})
		if (a.contains(bound.first)) {
			a[bound.first] = json::array();
			for (double v : *bound.second)
				a[bound.first].push_back(component == 5126 ? json(v) : json((long long)v));
		}
}

/* Sets accessor j's min and max, where it has them, to those of count
 * elements of a's type at stride bytes in data. */
void set_bounds(json& j, const bytes& data, size_t stride, const accessor& a, size_t count)
{
	std::vector<double> lo(a.components, INFINITY), hi(a.components, -INFINITY);
	const size_t csize = component_size(a.component);
	for (size_t i = 0; i < count; ++i)
		for (size_t c = 0; c < a.components; ++c) {
			const double v = read_component(&data[i * stride + c * csize], a.component, false);
			lo[c] = std::min(lo[c], v);
			hi[c] = std::max(hi[c], v);
		}
	set_bounds(j, lo, hi, a.component);
}

/* A Draco attribute's values in a new bufferView, in the component type of
 * accessor `index`, which is pointed at it (its min/max recomputed). */
void store_decoded(document& d, long long index, const vn_drc_attribute& a, size_t points, int target)
{
	const accessor info = get_accessor(d, index);
	const size_t csize = component_size(info.component), stride = target == 34962 ? (info.element + 3) / 4 * 4 : info.element;
	const size_t dsize = (size_t)component_size(a.component_type == 5124 ? 5125 : a.component_type);
	bytes data(stride * points, 0);
	for (size_t i = 0; i < points; ++i)
		for (size_t c = 0; c < info.components; ++c) {
			const double v = read_component((const unsigned char*)a.data + dsize * (i * info.components + c), a.component_type, false);
			write_component(&data[i * stride + c * csize], info.component, v);
		}
	json& j = d.j["accessors"][(size_t)index];
	j.erase("byteOffset");
	j.erase("sparse");
	j["bufferView"] = append_view(d, data, stride == info.element ? 0 : stride, target);
	set_bounds(j, data, stride, info, points);
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
	std::map<long long, int> done;
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
			const std::shared_ptr<draco_mesh> dm = decode_draco(d, prim, *ext, what);
			std::vector<long long> accessors = {get_int(prim, "indices", 0, what)};
			for (const auto& kv : dm->by_name)
				accessors.push_back(get_int(prim["attributes"], kv.first.c_str(), 0, what));
			for (long long a : accessors)
				if (done[a]++)
					fail(vn_io_error_unsupported,
					     str("accessors[%lld] is used by more than one Draco-compressed primitive, which vn does not decompress", a));
			for (const auto& kv : dm->by_name)
				store_decoded(d, get_int(prim["attributes"], kv.first.c_str(), 0, what), *kv.second, dm->g.point_count, 34962);
			json& indices = d.j["accessors"][(size_t)accessors[0]];
			if (dm->g.point_count > (get_int(indices, "componentType", 0, what) == 5121 ? 256u : 65536u))
				indices["componentType"] = 5125;
			vn_drc_attribute corners{};
			corners.component_type = 5125;
			corners.components = 1;
			corners.data = dm->g.indices;
			store_decoded(d, accessors[0], corners, 3 * dm->g.triangle_count, 34963);
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

/* ------------------------------------------------------------------ normals */

/* 3-vectors (positions, normals) of float32 or float64: a view into a
 * buffer or Draco data, or decoded values owned here. Move-only: the view
 * may point into `owned`. */
struct vec3s {
	vn_positions view = {nullptr, 0, 0, vn_scalar_float64};
	std::vector<double> owned;
	vec3s() = default;
	vec3s(vec3s&&) = default;
	vec3s& operator=(vec3s&&) = default;
	vec3s(const vec3s&) = delete;
	vec3s& operator=(const vec3s&) = delete;
	explicit vec3s(std::vector<double> values) : owned(std::move(values))
	{
		view = {owned.data(), owned.size() / 3, 0, vn_scalar_float64};
	}
	vec3s(const void* data, size_t count, size_t stride, vn_scalar type) : view{data, count, stride, type} {}
	size_t size() const { return view.count; }
	bool empty() const { return view.count == 0; }
	void load(size_t i, double out[3]) const
	{
		const size_t stride = view.stride ? view.stride : view.type == vn_scalar_float32 ? 12 : 24;
		const unsigned char* p = (const unsigned char*)view.data + i * stride;
		if (view.type == vn_scalar_float32) {
			float f[3];
			memcpy(f, p, sizeof f);
			out[0] = f[0], out[1] = f[1], out[2] = f[2];
		} else {
			memcpy(out, p, 3 * sizeof(double));
		}
	}
	void append_to(std::vector<double>& to) const
	{
		const size_t first = to.size();
		to.resize(first + 3 * size());
		for (size_t i = 0; i < size(); ++i)
			load(i, &to[first + 3 * i]);
	}
};

/* Accessor a (VEC3) as vec3s: a view when it is plain aligned float32. */
vec3s read_vec3(const document& d, const accessor& a)
{
	if (a.component == 5126 && a.data.buffer >= 0 && a.sparse_count == 0) {
		const unsigned char* p = element_at(d, a.data, 0);
		if ((uintptr_t)p % 4 == 0 && a.data.stride % 4 == 0)
			return vec3s(p, (size_t)a.count, a.data.stride, vn_scalar_float32);
	}
	return vec3s(read_accessor(d, a));
}

/* Triangle corners: a view into a buffer or Draco data, or owned. Move-only. */
struct corners {
	const uint32_t* data_ = nullptr;
	size_t size_ = 0;
	std::vector<uint32_t> owned;
	corners() = default;
	corners(corners&&) = default;
	corners& operator=(corners&&) = default;
	corners(const corners&) = delete;
	corners& operator=(const corners&) = delete;
	explicit corners(std::vector<uint32_t> values) : data_(values.data()), size_(values.size()), owned(std::move(values)) {}
	corners(const uint32_t* data, size_t size) : data_(data), size_(size) {}
	const uint32_t* data() const { return data_; }
	size_t size() const { return size_; }
	const uint32_t* begin() const { return data_; }
	const uint32_t* end() const { return data_ + size_; }
	uint32_t operator[](size_t k) const { return data_[k]; }
};

struct primitive {
	size_t mesh, index;
	long long position, normal = -1;
	bool tangent = false;
	vec3s positions;
	corners triangles;           /* 3 per triangle */
	vec3s input_normals;         /* empty, or one per vertex */
	std::vector<float> normals;  /* result, 3 per output vertex */
	/* Morph targets: per target, the morphed positions P + dP (empty when
	 * the target has no POSITION), its NORMAL accessor (-1: none) and the
	 * resulting NORMAL displacement (3 per output vertex; empty when the
	 * target has neither POSITION nor NORMAL, and is left alone). */
	std::vector<std::vector<double>> target_positions;
	std::vector<long long> target_normal;
	std::vector<std::vector<float>> target_normals;
	/* Splitting (--crease-angle): output vertex -> input vertex for the
	 * vertices appended after the input's, and the rewritten triangles.
	 * Both empty when no vertex is split. */
	std::vector<uint32_t> split_source;
	std::vector<uint32_t> split_triangles;
	/* Draco-compressed (null: not): positions, triangles and input normals
	 * above are views into it. */
	std::shared_ptr<const draco_mesh> draco;
	size_t vertices() const { return positions.size(); }
	size_t output_vertices() const { return vertices() + split_source.size(); }
	/* The triangles on the output vertices. */
	corners output_triangles() const
	{
		return split_source.empty() ? corners(triangles.data(), triangles.size())
		                            : corners(split_triangles.data(), split_triangles.size());
	}
};

/* The vertex order of indices accessor ia (each checked < n). */
corners read_indices(const document& d, const accessor& ia, size_t n, bool whole_triangles, const std::string& what)
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
void check_finite(const vec3s& positions, const std::string& what)
{
	for (size_t i = 0; i < positions.size(); ++i) {
		double p[3];
		positions.load(i, p);
		if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
			fail(vn_io_error_parse, str("%s of vertex %zu is not finite (%g, %g, %g); vn does not write meshes with NaN or "
			                            "infinite positions: fix or remove that vertex", what.c_str(), i, p[0], p[1], p[2]));
	}
}

/* Reads the triangle primitives; counts the others. */
std::vector<primitive> triangle_primitives(const document& d, vn_gltf_stats* st)
{
	std::vector<primitive> out;
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
			if (mode == 0 || mode == 1 || mode == 2 || mode == 3) {
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
				r.draco = decode_draco(d, prim, *ext, what);
				const vn_drc_geometry& g = r.draco->g;
				r.positions = vec3s(r.draco->by_name.at("POSITION")->data, g.point_count, 0, vn_scalar_float32);
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
					r.input_normals = vec3s(compressed->data, n, 0, vn_scalar_float32);
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
			if (r.draco) {
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

void check(vn_result r)
{
	if (r != vn_result_success)
		fail(r == vn_result_out_of_memory ? vn_io_error_memory : vn_io_error_parse, vn_result_string(r));
}

/* Without --crease-angle, split copies whose input normals differ by more
 * than this keep a hard edge between them. Small on purpose: exporters give
 * the copies along UV seams the same normal, and converting vn's output
 * again must find its hard edges again (a larger angle would smooth those
 * whose two sides' normals came out closer than it). See README.md, "glTF". */
const double default_hard_edge_angle = 0.1 * M_PI / 180;

/* How a group of primitives (one primitive, or a whole mesh) gets its
 * normals: the same plan serves the base shape and every morph target. A
 * group of one primitive uses its data where they lie; a larger group
 * joins copies. */
struct group_plan {
	std::vector<primitive*> prims;
	std::vector<size_t> first;          /* first input vertex of each primitive */
	std::vector<size_t> extra_first;    /* first split vertex of each primitive, counted from n */
	size_t n = 0;                       /* input vertices */
	size_t corners = 0;                 /* 3 per triangle */
	std::vector<uint32_t> remap;        /* input vertex -> welded representative */
	const uint32_t* corner_input = nullptr; /* input vertex of each corner */
	const uint32_t* triangles = nullptr;    /* corners on welded vertices */
	std::vector<uint32_t> joined_corners, welded_corners; /* what those point at, when not a primitive's */
	vec3s input_normals;                /* one per input vertex, or empty */
	bool corner_normals = false;        /* per-corner normals (sharp edges or a crease angle) */
	double crease = M_PI;               /* radians; pi: no crease */
	std::vector<uint8_t> sharp;         /* per corner: edges whose input normals differ */
	std::vector<uint32_t> corner_output; /* per corner: output vertex, when splitting */
	std::vector<uint32_t> extra_source; /* output vertex n + k -> input vertex */
	vn_method method = vn_method_mwa;
	vn_options options;
};

/* The plan's normals for input positions q: one unit vector per output
 * vertex (input vertices, then split ones), 3 floats each. A vertex no face
 * contributes to gets its input normal when that is a unit vector, else +Z;
 * *zeros counts them. */
std::vector<float> plan_normals(const group_plan& g, const vn_positions& q, size_t* zeros)
{
	const size_t n = g.n, outputs = n + g.extra_source.size();
	std::vector<float> out(3 * outputs, 0.0f);
	/* Welded vertex normals into v, then copied to every vertex of each
	 * group (the representative is the group's lowest index, so it is
	 * final by the time the others copy it). */
	auto vertex_normals = [&](float* v) {
		const vn_vectors vv = {v, 0, vn_scalar_float32};
		check(vn_triangle_normals(&vv, &q, g.triangles, g.corners, g.method, &g.options, nullptr));
		for (size_t i = 0; i < n; ++i)
			if (g.remap[i] != i)
				std::copy_n(&v[3 * g.remap[i]], 3, &v[3 * i]);
	};
	if (!g.corner_normals) {
		vertex_normals(out.data());
	} else {
		std::vector<float> c(3 * g.corners);
		const vn_vectors cv = {c.data(), 0, vn_scalar_float32};
		check(vn_corner_normals(&cv, &q, g.triangles, g.corners, g.method, g.crease,
		                        g.sharp.empty() ? nullptr : g.sharp.data(), &g.options, nullptr));
		if (!g.corner_output.empty()) {
			for (size_t k = 0; k < g.corners; ++k)
				std::copy_n(&c[3 * k], 3, &out[3 * g.corner_output[k]]);
		} else {
			/* No splitting: a vertex whose corners disagree (its fans are
			 * not separated in the file) gets the smooth normal. */
			std::vector<uint32_t> seen(n, UINT32_MAX);
			std::vector<uint8_t> conflict(n, 0);
			for (size_t k = 0; k < g.corners; ++k) {
				const uint32_t i = g.corner_input[k];
				if (seen[i] == UINT32_MAX)
					seen[i] = (uint32_t)k, std::copy_n(&c[3 * k], 3, &out[3 * i]);
				else if (!std::equal(&c[3 * k], &c[3 * k] + 3, &c[3 * seen[i]]))
					conflict[i] = 1;
			}
			if (std::find(conflict.begin(), conflict.end(), 1) != conflict.end()) {
				std::vector<float> v(3 * n);
				vertex_normals(v.data());
				for (size_t i = 0; i < n; ++i)
					if (conflict[i])
						std::copy_n(&v[3 * i], 3, &out[3 * i]);
			}
		}
	}
	for (size_t k = 0; k < outputs; ++k) {
		float* v = &out[3 * k];
		if (v[0] != 0 || v[1] != 0 || v[2] != 0)
			continue;
		++*zeros;
		double w[3] = {0, 0, 0};
		if (!g.input_normals.empty())
			g.input_normals.load(k < n ? k : g.extra_source[k - n], w);
		double l = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
		if (std::isfinite(l) && std::fabs(l - 1) < 1e-3)
			v[0] = (float)(w[0] / l), v[1] = (float)(w[1] / l), v[2] = (float)(w[2] / l);
		else
			v[2] = 1;
	}
	return out;
}

/* Flags the corners whose edge joins split copies with input normals more
 * than `angle` apart at either end; returns how many edges that makes (an
 * edge is flagged from both sides). */
size_t flag_hard_edges(group_plan& g, double angle)
{
	if (g.input_normals.empty())
		return 0;
	const double limit = std::cos(angle);
	auto differ = [&](uint32_t a, uint32_t b) {
		double x[3], y[3];
		g.input_normals.load(a, x);
		g.input_normals.load(b, y);
		double lx = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
		double ly = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
		return a != b && lx > 0 && ly > 0 && (x[0] * y[0] + x[1] * y[1] + x[2] * y[2]) < limit * lx * ly;
	};
	auto next = [](size_t k) { return k - k % 3 + (k + 1) % 3; };
	/* Only an edge with an end where welding merged copies can join copies
	 * with different input normals: the others need no search (on a file
	 * without split vertices, that is every edge). */
	std::vector<uint8_t> merged(g.n, 0);
	for (size_t i = 0; i < g.n; ++i)
		if (g.remap[i] != i)
			merged[g.remap[i]] = 1;
	auto candidate = [&](size_t k) { return merged[g.triangles[k]] || merged[g.triangles[next(k)]]; };
	std::vector<std::pair<uint64_t, uint32_t>> edges;
	for (size_t k = 0; k < g.corners; ++k)
		if (candidate(k))
			edges.push_back({(uint64_t)g.triangles[k] << 32 | g.triangles[next(k)], (uint32_t)k});
	std::sort(edges.begin(), edges.end());
	g.sharp.assign(g.corners, 0);
	size_t flagged = 0;
	for (size_t k = 0; k < g.corners; ++k) {
		if (!candidate(k) || g.triangles[k] == g.triangles[next(k)])
			continue; /* no merged end, or a degenerate triangle (no edges) */
		const uint64_t opposite = (uint64_t)g.triangles[next(k)] << 32 | g.triangles[k];
		auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(opposite, (uint32_t)0));
		for (; it != edges.end() && it->first == opposite && !g.sharp[k]; ++it) {
			const size_t j = it->second;
			g.sharp[k] = differ(g.corner_input[k], g.corner_input[next(j)]) ||
			             differ(g.corner_input[next(k)], g.corner_input[j]);
		}
		flagged += g.sharp[k] && g.triangles[k] < g.triangles[next(k)];
	}
	return flagged;
}

/* Split vertices for per-corner normals c: a corner whose normal differs
 * from the first one of its input vertex gets a new vertex, shared by the
 * vertex's corners with the same normal. */
void split_corners(group_plan& g, const std::vector<float>& c)
{
	std::vector<uint32_t> owner(g.n, UINT32_MAX);
	g.extra_first.assign(1, 0);
	std::map<uint32_t, std::vector<uint32_t>> extras; /* input vertex -> its split vertices' first corner */
	g.corner_output.assign(g.corners, 0);
	size_t p = 0;
	for (size_t k = 0; k < g.corners; ++k) {
		const uint32_t i = g.corner_input[k];
		while (p + 1 < g.prims.size() && i >= g.first[p + 1])
			g.extra_first.push_back(g.extra_source.size()), ++p;
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
	while (g.extra_first.size() < g.prims.size())
		g.extra_first.push_back(g.extra_source.size());
}

/* Normals of a group of primitives computed together (one primitive, or a
 * whole mesh): welded, computed (per corner where edges are hard), copied
 * back to every split vertex; then every morph target's NORMAL
 * displacement, by the same computation on the morphed positions. */
void compute_group(std::vector<primitive*>& prims, const vn_gltf_options& o, vn_gltf_stats& st)
{
	group_plan g;
	g.prims = prims;
	g.method = o.method;
	memset(&g.options, 0, sizeof g.options);
	g.options.threads = o.threads;
	std::vector<double> joined;
	vn_positions pos = prims[0]->positions.view;
	bool any_normals = false;
	for (primitive* p : prims) {
		g.first.push_back(g.n);
		if (g.n + p->vertices() > UINT32_MAX)
			fail(vn_io_error_unsupported, "a mesh has more than 2^32 vertices");
		g.n += p->vertices();
		g.corners += p->triangles.size();
		any_normals = any_normals || !p->input_normals.empty();
	}
	if (prims.size() == 1) {
		g.corner_input = prims[0]->triangles.data();
		g.input_normals = vec3s(prims[0]->input_normals.view.data, prims[0]->input_normals.size(),
		                        prims[0]->input_normals.view.stride, prims[0]->input_normals.view.type);
	} else {
		std::vector<double> joined_normals;
		for (size_t k = 0; k < prims.size(); ++k) {
			const primitive* p = prims[k];
			p->positions.append_to(joined);
			if (any_normals && p->input_normals.empty())
				joined_normals.resize(joined.size(), 0.0);
			else if (any_normals)
				p->input_normals.append_to(joined_normals);
			for (uint32_t v : p->triangles)
				g.joined_corners.push_back((uint32_t)(g.first[k] + v));
		}
		pos = {joined.data(), g.n, 0, vn_scalar_float64};
		g.corner_input = g.joined_corners.data();
		g.input_normals = vec3s(std::move(joined_normals));
	}
	g.remap.resize(g.n);
	for (size_t i = 0; i < g.n; ++i)
		g.remap[i] = (uint32_t)i;
	size_t welded = 0;
	if (!o.no_weld) {
		check(vn_weld_positions(g.remap.data(), &pos, o.weld_epsilon, &g.options));
		for (size_t i = 0; i < g.n; ++i)
			welded += g.remap[i] != i;
		st.welded_vertices += welded;
	}
	g.triangles = g.corner_input;
	if (welded) {
		g.welded_corners.resize(g.corners);
		for (size_t k = 0; k < g.corners; ++k)
			g.welded_corners[k] = g.remap[g.corner_input[k]];
		g.triangles = g.welded_corners.data();
	}
	/* Hard edges join welded copies: none without welding. */
	const size_t hard = welded ? flag_hard_edges(g, o.crease ? o.crease_angle : default_hard_edge_angle) : 0;
	if (!hard)
		g.sharp.clear();
	st.hard_edges += hard;
	g.corner_normals = o.crease || !g.sharp.empty();
	if (o.crease) {
		g.crease = o.crease_angle;
		std::vector<float> c(3 * g.corners);
		const vn_vectors cv = {c.data(), 0, vn_scalar_float32};
		check(vn_corner_normals(&cv, &pos, g.triangles, g.corners, g.method, g.crease,
		                        g.sharp.empty() ? nullptr : g.sharp.data(), &g.options, nullptr));
		split_corners(g, c);
		st.split_vertices += g.extra_source.size();
	}
	size_t zeros = 0;
	std::vector<float> base = plan_normals(g, pos, &zeros);
	st.zero_normals += zeros;

	/* Each primitive's output vertices: its input ones, then its split ones
	 * (a group of one primitive is laid out so already). */
	auto gather = [&](const std::vector<float>& all, size_t p, std::vector<float>& out, const std::vector<float>* minus) {
		const primitive& pr = *prims[p];
		out.resize(3 * pr.output_vertices());
		for (size_t i = 0; i < out.size(); ++i) {
			const size_t k = i < 3 * pr.vertices() ? 3 * g.first[p] + i : 3 * (g.n + g.extra_first[p]) + i - 3 * pr.vertices();
			out[i] = minus ? all[k] - (*minus)[k] : all[k];
		}
	};
	size_t corner_first = 0;
	for (size_t p = 0; p < prims.size(); ++p) {
		primitive& pr = *prims[p];
		const size_t end = g.extra_source.empty() ? 0 : p + 1 < prims.size() ? g.extra_first[p + 1] : g.extra_source.size();
		if (end > (g.extra_source.empty() ? 0 : g.extra_first[p])) {
			for (size_t e = g.extra_first[p]; e < end; ++e)
				pr.split_source.push_back((uint32_t)(g.extra_source[e] - g.first[p]));
			for (size_t k = 0; k < pr.triangles.size(); ++k) {
				const uint32_t v = g.corner_output[corner_first + k];
				pr.split_triangles.push_back(v < g.n ? (uint32_t)(v - g.first[p])
				                                     : (uint32_t)(pr.vertices() + v - g.n - g.extra_first[p]));
			}
		}
		corner_first += pr.triangles.size();
		st.vertices += pr.vertices();
		st.triangles += pr.triangles.size() / 3;
		++st.primitives;
		st.tangent_primitives += pr.tangent;
	}

	size_t targets = 0;
	for (primitive* p : prims)
		targets = std::max(targets, p->target_positions.size());
	for (size_t t = 0; t < targets; ++t) {
		std::vector<double> morphed;
		for (primitive* p : prims) {
			if (t < p->target_positions.size() && !p->target_positions[t].empty())
				morphed.insert(morphed.end(), p->target_positions[t].begin(), p->target_positions[t].end());
			else
				p->positions.append_to(morphed);
		}
		size_t ignored = 0;
		const vn_positions q = {morphed.data(), g.n, 0, vn_scalar_float64};
		const std::vector<float> normals = plan_normals(g, q, &ignored);
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

json& mesh_primitive(document& d, const primitive& p)
{
	return d.j["meshes"][p.mesh]["primitives"][p.index];
}

/* Appends data as a new bufferView at the end of the last buffer (in a
 * GLB, the BIN chunk) and returns its index. stride, target: 0 for none. */
size_t append_view(document& d, const bytes& data, size_t stride, int target)
{
	if (d.buffers.empty()) {
		d.j["buffers"] = json::array({json{{"byteLength", 0}}});
		d.buffers.emplace_back();
	}
	/* The last buffer, but in a GLB the BIN chunk's (buffer 0 without uri). */
	size_t b = d.buffers.size() - 1;
	if (d.glb && !d.j["buffers"][0].contains("uri"))
		b = 0;
	buffer& to = d.buffers[b];
	to.tail.resize((to.tail.size() + 3) / 4 * 4, 0);
	const size_t offset = to.tail_start() + to.tail.size();
	to.tail.insert(to.tail.end(), data.begin(), data.end());
	d.j["buffers"][b]["byteLength"] = to.total();
	if (!d.j.contains("bufferViews"))
		d.j["bufferViews"] = json::array();
	json view = {{"buffer", b}, {"byteOffset", offset}, {"byteLength", data.size()}};
	if (stride)
		view["byteStride"] = stride;
	if (target)
		view["target"] = target;
	d.j["bufferViews"].push_back(view);
	return d.j["bufferViews"].size() - 1;
}

/* Appends accessor a and returns its index. */
long long append_accessor(document& d, json a)
{
	if (!d.j.contains("accessors"))
		d.j["accessors"] = json::array();
	d.j["accessors"].push_back(std::move(a));
	return (long long)d.j["accessors"].size() - 1;
}

/* Writes values (3 per element) over accessor a (float32, or normalized
 * byte/short), and its min/max when it has them. */
void overwrite_vec3(document& d, long long index, const accessor& a, const std::vector<float>& values)
{
	std::vector<double> lo(3, INFINITY), hi(3, -INFINITY);
	for (size_t i = 0; i < values.size() / 3; ++i) {
		unsigned char* e = element_at(d, a.data, i);
		for (size_t c = 0; c < 3; ++c) {
			double v = values[3 * i + c], stored;
			if (a.component == 5126) {
				float f = values[3 * i + c];
				memcpy(e + 4 * c, &f, 4);
				stored = f;
			} else if (a.component == 5120) {
				int8_t q = (int8_t)std::lround(std::max(-1.0, std::min(1.0, v)) * 127);
				memcpy(e + c, &q, 1);
				stored = q;
			} else {
				int16_t q = (int16_t)std::lround(std::max(-1.0, std::min(1.0, v)) * 32767);
				memcpy(e + 2 * c, &q, 2);
				stored = q;
			}
			lo[c] = std::min(lo[c], stored);
			hi[c] = std::max(hi[c], stored);
		}
	}
	json& j = d.j["accessors"][(size_t)index];
	if (j.contains("min"))
		j["min"] = lo;
	if (j.contains("max"))
		j["max"] = hi;
}

/* Where values (NORMAL data, 3 per vertex) go: over accessor `index` when it
 * is plain (float32, or normalized byte/short holding every value; not
 * sparse; as many elements) and not already written with other values;
 * otherwise into a new float32 accessor. Returns the accessor. */
long long put_vec3(document& d, long long index, const std::vector<float>& values,
                   std::map<long long, const std::vector<float>*>& written, vn_gltf_stats& st)
{
	if (index >= 0) {
		accessor a = get_accessor(d, index);
		const bool fits = a.component == 5126 ||
		                  (a.normalized && (a.component == 5120 || a.component == 5122) &&
		                   std::all_of(values.begin(), values.end(), [](float v) { return std::fabs(v) <= 1; }));
		if (a.data.buffer >= 0 && a.sparse_count == 0 && fits && (size_t)a.count * 3 == values.size()) {
			auto it = written.find(index);
			if (it == written.end()) {
				overwrite_vec3(d, index, a, values);
				written[index] = &values;
				return index;
			}
			if (*it->second == values)
				return index; /* shared, and the same result */
		}
	}
	bytes data(values.size() * sizeof(float));
	memcpy(data.data(), values.data(), data.size());
	++st.appended_accessors;
	return append_accessor(d, json{{"bufferView", append_view(d, data, 0, 34962)},
	                               {"componentType", 5126},
	                               {"count", values.size() / 3},
	                               {"type", "VEC3"}});
}

/* A copy of accessor `index` with p's split vertices appended (copies of
 * their input vertices), in a new bufferView; returns the new accessor. */
long long split_accessor(document& d, long long index, const primitive& p)
{
	const accessor a = get_accessor(d, index);
	const size_t stride = (a.element + 3) / 4 * 4;
	bytes data(stride * p.output_vertices(), 0);
	auto element = [&](const span& s, size_t i) { return element_at(d, s, i); };
	if (a.data.buffer >= 0)
		for (size_t i = 0; i < p.vertices(); ++i)
			memcpy(&data[i * stride], element(a.data, i), a.element);
	for (size_t k = 0; k < (size_t)a.sparse_count; ++k) {
		double i = read_component(element(a.sparse_indices, k), a.sparse_index_component, false);
		if (i >= (double)p.vertices())
			fail(vn_io_error_parse, str("a sparse index (%.0f) is out of range (count %lld)", i, a.count));
		memcpy(&data[(size_t)i * stride], element(a.sparse_values, k), a.element);
	}
	for (size_t e = 0; e < p.split_source.size(); ++e)
		memcpy(&data[(p.vertices() + e) * stride], &data[p.split_source[e] * stride], a.element);
	json j = d.j["accessors"][(size_t)index];
	set_bounds(j, data, stride, a, p.output_vertices());
	j.erase("sparse");
	j.erase("byteOffset");
	j["bufferView"] = append_view(d, data, stride == a.element ? 0 : stride, 34962);
	j["count"] = p.output_vertices();
	return append_accessor(d, j);
}

/* Points a split primitive's every attribute (and its morph targets') at
 * copies with the split vertices, and its indices at the new triangles.
 * A Draco-compressed primitive's attributes in the Draco data and its
 * indices are the Draco encoder's (write_draco): only the others are
 * copied here. */
void write_split(document& d, const primitive& p)
{
	json& prim = mesh_primitive(d, p);
	std::map<long long, long long> copies;
	auto copy_all = [&](json& attributes) {
		for (auto& kv : attributes.items()) {
			if (kv.key() == "NORMAL" || (p.draco && p.draco->by_name.count(kv.key()) && &attributes == &prim["attributes"]))
				continue;
			const long long old = get_int(attributes, kv.key().c_str(), 0, "attributes");
			if (!copies.count(old))
				copies[old] = split_accessor(d, old, p);
			kv.value() = copies[old];
		}
	};
	copy_all(prim["attributes"]);
	if (prim.contains("targets"))
		for (json& target : prim["targets"])
			copy_all(target);
	if (p.draco)
		return;
	bytes data(p.split_triangles.size() * 4);
	memcpy(data.data(), p.split_triangles.data(), data.size());
	prim["indices"] = append_accessor(d, json{{"bufferView", append_view(d, data, 0, 34963)},
	                                          {"componentType", 5125},
	                                          {"count", p.split_triangles.size()},
	                                          {"type", "SCALAR"}});
	if (prim.contains("mode"))
		prim["mode"] = 4; /* strips and fans become triangle lists */
}

/* Draco primitives written, per normal quantization bits: their positions,
 * new normals and triangles, for the --stats quantization error. */
struct quantized_normals {
	std::vector<double> positions, normals;
	std::vector<uint32_t> indices;
};

/* The Draco bits and level given in o, vn_drc_default_options' for the others. */
vn_drc_options draco_bits(const vn_gltf_options& o)
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

/* g Draco-encoded (keep_order: as vn_drc_encode) into a new bufferView;
 * returns its index. When position >= 0, that accessor (g's attribute
 * position_id) gets the min/max of the positions a decoder gets back when
 * they are floats: quantizing anew may move them outside the bounds of the
 * input's (integer positions are lossless). */
size_t append_draco(document& d, const vn_drc_geometry& g, int level, bool keep_order, long long position,
                    uint32_t position_id, const std::string& what)
{
	void* data;
	size_t size;
	vn_io_error e;
	vn_io_result r = vn_drc_encode(&g, level, keep_order, what.c_str(), &data, &size, &e);
	if (r != vn_io_success)
		fail(r, e.message);
	const bytes encoded((unsigned char*)data, (unsigned char*)data + size);
	free(data);
	if (position >= 0) {
		draco_mesh back;
		if ((r = vn_drc_decode(encoded.data(), encoded.size(), what.c_str(), &back.g, &e)) != vn_io_success)
			fail(r, e.message);
		for (size_t i = 0; i < back.g.attribute_count; ++i)
			if (back.g.attributes[i].unique_id == position_id && back.g.attributes[i].component_type == vn_drc_float32) {
				const float* q = (const float*)back.g.attributes[i].data;
				json lo = json::array(), hi = json::array();
				for (int c = 0; c < 3; ++c) {
					float l = INFINITY, h = -INFINITY;
					for (size_t k = 0; k < back.g.point_count; ++k)
						l = std::min(l, q[3 * k + c]), h = std::max(h, q[3 * k + c]);
					lo.push_back(l), hi.push_back(h);
				}
				d.j["accessors"][(size_t)position]["min"] = lo;
				d.j["accessors"][(size_t)position]["max"] = hi;
			}
	}
	return append_view(d, encoded, 0, 0);
}

/* The vertices of [0, n) that triangles use (every one when `all`), in
 * order; renumbered[v] becomes v's index among them. */
std::vector<uint32_t> kept_vertices(const corners& triangles, size_t n, bool all, std::vector<uint32_t>& renumbered)
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
void record_normals(quantized_normals& q, const primitive& p)
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
 * --draco-qp/qn/qt/qc (a NORMAL the data lacked gets the next unique id, a
 * bufferView-less accessor and --draco-qn or default bits), in a new bufferView
 * the extension points at. Points keep their order when morph targets or
 * attributes outside the Draco data follow it. */
void write_draco(document& d, const primitive& p, const vn_gltf_options& o, vn_gltf_stats& st,
                 std::map<int, quantized_normals>& quantized)
{
	const std::string what = str("meshes[%zu].primitives[%zu]", p.mesh, p.index);
	json& prim = mesh_primitive(d, p);
	json& ext = prim["extensions"][draco_name];
	const vn_drc_options bits = draco_bits(o);
	const vn_drc_geometry& in = p.draco->g;
	const auto& by_name = p.draco->by_name;
	const size_t n = p.output_vertices();
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
				memcpy(&grown.back()[size * (in.point_count + e)], (const unsigned char*)a.data + size * p.split_source[e], size);
			attributes.back().data = grown.back().data();
		}
	if (!p.split_source.empty()) {
		/* The accessors of the Draco data get the new count (a copy: the
		 * old one may be shared); the indices a type that holds it. */
		for (auto& kv : prim["attributes"].items())
			if (by_name.count(kv.key())) {
				json copy = d.j["accessors"][(size_t)get_int(prim["attributes"], kv.key().c_str(), 0, what)];
				copy["count"] = n;
				kv.value() = append_accessor(d, copy);
			}
		json indices = d.j["accessors"][(size_t)get_int(prim, "indices", 0, what)];
		if (n > (get_int(indices, "componentType", 0, what) == 5121 ? 256u : 65536u)) {
			indices["componentType"] = 5125;
			prim["indices"] = append_accessor(d, indices);
		}
	}
	const bool keep_order = prim.contains("targets") || prim["attributes"].size() > by_name.size() -
	                        (o.drop_tangents && by_name.count("TANGENT"));
	auto normal = std::find_if(attributes.begin(), attributes.end(), [&](const vn_drc_attribute& a) {
		return by_name.count("NORMAL") && a.unique_id == by_name.at("NORMAL")->unique_id;
	});
	if (normal == attributes.end()) {
		vn_drc_attribute a{};
		a.semantic = vn_drc_normal;
		a.component_type = vn_drc_float32;
		a.components = 3;
		a.quantization_bits = bits.normal_bits;
		for (const vn_drc_attribute& b : attributes)
			a.unique_id = std::max(a.unique_id, b.unique_id + 1);
		ext["attributes"]["NORMAL"] = a.unique_id;
		prim["attributes"]["NORMAL"] = append_accessor(d, json{{"componentType", 5126}, {"count", n}, {"type", "VEC3"}});
		++st.appended_accessors;
		attributes.push_back(a);
		normal = attributes.end() - 1;
	}
	normal->data = const_cast<float*>(p.normals.data());
	bool moved = false; /* positions quantized with other bits than the stream's */
	for (vn_drc_attribute& a : attributes) {
		const int given = vn_drc_given_bits(&o.draco_options, a.semantic, a.component_type);
		if (given >= 0 && given != a.quantization_bits) {
			moved = moved || a.semantic == vn_drc_position;
			a.quantization_bits = given;
		}
	}
	vn_drc_geometry g = in;
	g.attributes = attributes.data();
	g.attribute_count = attributes.size();
	g.point_count = n;
	g.indices = const_cast<uint32_t*>(p.output_triangles().data());
	ext["bufferView"] = append_draco(d, g, bits.compression_level, keep_order, moved ? p.position : -1,
	                                 by_name.at("POSITION")->unique_id, what);
	++st.draco_primitives;
	record_normals(quantized[normal->quantization_bits], p);
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
void compress_draco(document& d, const primitive& p, const vn_gltf_options& o, vn_gltf_stats& st,
                    std::map<int, quantized_normals>& quantized)
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
	std::vector<uint32_t> corners_kept(triangles.size());
	for (size_t k = 0; k < triangles.size(); ++k)
		corners_kept[k] = renumbered[triangles[k]];
	std::vector<bytes> storage;
	std::vector<vn_drc_attribute> attributes;
	json ext_attributes = json::object();
	long long position = -1;
	for (auto& kv : prim["attributes"].items()) {
		const std::string& name = kv.key();
		const long long index = get_int(prim["attributes"], name.c_str(), 0, what + ".attributes");
		accessor a = get_accessor(d, index);
		if (a.components > 4 || (size_t)a.count != n)
			fail(vn_io_error_unsupported, str("%s: %s cannot be Draco-compressed (more than 4 components, or not one per vertex)",
			                                  what.c_str(), name.c_str()));
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
		da.quantization_bits = da.semantic == vn_drc_position ? bits.position_bits : da.semantic == vn_drc_normal ? bits.normal_bits
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
	const size_t view = append_draco(d, g, bits.compression_level, targets, position,
	                                 ext_attributes["POSITION"].get<uint32_t>(), what);
	const size_t points = kept.size();
	prim["indices"] = append_accessor(d, json{{"componentType", points <= 256 ? 5121 : points <= 65536 ? 5123 : 5125},
	                                          {"count", triangles.size()},
	                                          {"type", "SCALAR"}});
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
	record_normals(quantized[bits.normal_bits], p);
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

/* Writes every primitive's normals and morph targets' NORMAL displacements
 * (and, for split primitives, copies of all their vertex data). */
void write_normals(document& d, std::vector<primitive>& prims, const vn_gltf_options& o, vn_gltf_stats& st)
{
	std::map<long long, const std::vector<float>*> written;
	std::map<int, quantized_normals> quantized;
	for (primitive& p : prims) {
		const bool split = !p.split_source.empty();
		if (split)
			write_split(d, p);
		if (p.draco) {
			write_draco(d, p, o, st, quantized);
		} else {
			const long long normal = put_vec3(d, split ? -1 : p.normal, p.normals, written, st);
			mesh_primitive(d, p)["attributes"]["NORMAL"] = normal;
		}
		/* Morph targets are never Draco-compressed. */
		for (size_t t = 0; t < p.target_normals.size(); ++t)
			if (!p.target_normals[t].empty()) {
				const long long normal = put_vec3(d, split ? -1 : p.target_normal[t], p.target_normals[t], written, st);
				mesh_primitive(d, p)["targets"][t]["NORMAL"] = normal;
			}
		if (!p.draco && o.draco == vn_gltf_draco_on)
			compress_draco(d, p, o, st, quantized);
	}
	if (o.draco_normal_error)
		normal_errors(quantized, o, st);
}

/* ------------------------------------------------------------------ writing */

std::string base64(const bytes& data)
{
	static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
	std::string out;
	out.reserve((data.size() + 2) / 3 * 4);
	for (size_t i = 0; i < data.size(); i += 3) {
		uint32_t v = (uint32_t)data[i] << 16;
		if (i + 1 < data.size())
			v |= (uint32_t)data[i + 1] << 8;
		if (i + 2 < data.size())
			v |= data[i + 2];
		out += digits[v >> 18 & 63];
		out += digits[v >> 12 & 63];
		out += i + 1 < data.size() ? digits[v >> 6 & 63] : '=';
		out += i + 2 < data.size() ? digits[v & 63] : '=';
	}
	return out;
}

std::string uri_encode(const std::string& s)
{
	std::string out;
	for (unsigned char c : s) {
		if (isalnum(c) || strchr("-._~", c))
			out += (char)c;
		else
			out += str("%%%02X", c);
	}
	return out;
}

bool is_data_uri(const json& o)
{
	auto it = o.find("uri");
	return it != o.end() && it->is_string() && it->get<std::string>().rfind("data:", 0) == 0;
}

std::string data_uri(const json& buffer, const bytes& data)
{
	std::string prefix = "data:application/octet-stream;base64,";
	if (is_data_uri(buffer)) {
		std::string old = buffer["uri"].get<std::string>();
		size_t comma = old.find(',');
		if (comma != std::string::npos)
			prefix = old.substr(0, comma + 1);
	}
	return prefix + base64(data);
}

/* A file's contents: byte ranges written one after the other, and the
 * small pieces (headers, JSON, padding) they include, owned here. */
struct pieces {
	std::vector<std::pair<const unsigned char*, size_t>> list;
	std::vector<std::unique_ptr<std::string>> owned;
	void add(const void* data, size_t n)
	{
		if (n)
			list.emplace_back((const unsigned char*)data, n);
	}
	void add(std::string text)
	{
		owned.emplace_back(new std::string(std::move(text)));
		add(owned.back()->data(), owned.back()->size());
	}
	/* Buffer b, padded with zeros to a multiple of 4 bytes when `pad`. */
	void add(const buffer& b, bool pad)
	{
		add(b.base, b.size);
		if (!b.tail.empty()) {
			add(std::string(b.tail_start() - b.size, '\0'));
			add(b.tail.data(), b.tail.size());
		}
		if (pad)
			add(std::string((4 - b.total() % 4) % 4, '\0'));
	}
	/* The pieces in one block (for a data URI). */
	bytes joined() const
	{
		bytes out;
		for (const auto& piece : list)
			out.insert(out.end(), piece.first, piece.first + piece.second);
		return out;
	}
};

std::string le32_text(std::initializer_list<size_t> values)
{
	std::string out;
	for (size_t v : values)
		for (int i = 0; i < 4; ++i)
			out.push_back((char)(v >> (8 * i) & 0xff));
	return out;
}

/* A GLB of JSON j and the BIN chunk bin (null: none). */
pieces glb_file(const json& j, const buffer* bin)
{
	std::string text = j.dump();
	text.resize((text.size() + 3) / 4 * 4, ' ');
	const size_t bin_padded = bin ? (bin->total() + 3) / 4 * 4 : 0;
	const size_t total = 12 + 8 + text.size() + (bin ? 8 + bin_padded : 0);
	if (total > UINT32_MAX)
		fail(vn_io_error_unsupported, "the GLB would exceed 4 GiB");
	pieces out;
	out.add(le32_text({glb_magic, 2, total, text.size(), chunk_json}));
	out.add(std::move(text));
	if (bin) {
		out.add(le32_text({bin_padded, chunk_bin}));
		out.add(*bin, true);
	}
	return out;
}

/* Output files written as temporaries beside their final paths, then all
 * renamed; the temporaries of an unfinished set are removed. vn_io_output
 * does what every output file needs: links followed, devices refused, mode
 * and owner kept, temporaries removed on a fatal signal too. */
struct file_set {
	std::vector<vn_io_output> files;
	~file_set()
	{
		for (vn_io_output& f : files)
			vn_io_output_discard(&f);
	}
	void add(const std::string& path, const pieces& contents)
	{
		files.reserve(files.size() + 1); /* push_back below cannot throw with the temporary open */
		vn_io_output output;
		vn_io_error e;
		vn_io_result r = vn_io_output_open(&output, path.c_str(), &e);
		if (r != vn_io_success)
			fail_named(r, e.message);
		files.push_back(output);
		vn_io_output& f = files.back();
		bool ok = true;
		for (const auto& piece : contents.list)
			for (size_t done = 0; ok && done < piece.second;) {
				ssize_t n = write(f.fd, piece.first + done, piece.second - done);
				if (n < 0 && errno == EINTR)
					continue;
				ok = n > 0;
				done += ok ? (size_t)n : 0;
			}
		if (!ok)
			fail_named(vn_io_error_write, str("%s: cannot write: %s", path.c_str(), strerror(errno)));
		if ((r = vn_io_output_close(&f, &e)) != vn_io_success)
			fail_named(r, e.message);
	}
	void add(const std::string& path, const std::string& text)
	{
		pieces p;
		p.add(text.data(), text.size());
		add(path, p);
	}
	void commit()
	{
		for (vn_io_output& f : files) {
			vn_io_error e;
			vn_io_result r = vn_io_output_commit(&f, &e);
			if (r != vn_io_success)
				fail_named(r, e.message);
		}
		files.clear();
	}
};

bool read_file(const std::string& path, bytes& out)
{
	char* raw;
	size_t size;
	vn_io_error e;
	if (vn_io_read_all(path.c_str(), &raw, &size, &e) != vn_io_success)
		return false;
	out.assign(raw, raw + size);
	free(raw);
	return true;
}

bool same_folder(const std::string& a, const std::string& b)
{
	struct stat sa, sb;
	return stat(a.empty() ? "." : a.c_str(), &sa) == 0 && stat(b.empty() ? "." : b.c_str(), &sb) == 0 &&
	       sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* An external resource's URI (not a data URI, not another scheme's URL such
 * as https://, which vn neither reads nor copies), decoded; "" otherwise. */
std::string file_uri(const json& o)
{
	auto it = o.find("uri");
	if (it == o.end() || !it->is_string() || is_data_uri(o))
		return "";
	const std::string& uri = it->get_ref<const std::string&>();
	const size_t colon = uri.find(':'), slash = uri.find('/');
	if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
		return ""; /* a scheme */
	return uri_decode(uri);
}

/* True when relative path `name` stays inside its folder: not absolute, no
 * ".." component. */
bool stays_inside(const std::string& name)
{
	if (name.empty() || name[0] == '/')
		return false;
	for (size_t at = 0; at <= name.size();) {
		size_t end = name.find('/', at);
		if (end == std::string::npos)
			end = name.size();
		if (name.compare(at, end - at, "..") == 0)
			return false;
		at = end + 1;
	}
	return true;
}

/* An image's media type from its first bytes, "" when not one glTF uses. */
std::string image_type(const bytes& data)
{
	auto starts = [&](const char* magic, size_t n, size_t at = 0) {
		return data.size() >= at + n && memcmp(data.data() + at, magic, n) == 0;
	};
	if (starts("\x89PNG\r\n\x1a\n", 8))
		return "image/png";
	if (starts("\xff\xd8\xff", 3))
		return "image/jpeg";
	if (starts("RIFF", 4) && starts("WEBP", 4, 8))
		return "image/webp";
	if (starts("\xabKTX 20\xbb\r\n\x1a\n", 12))
		return "image/ktx2";
	if (starts("ftypavif", 8, 4))
		return "image/avif";
	if (starts("DDS ", 4))
		return "image/vnd-ms.dds";
	return "";
}

/* A GLB holds its data in the BIN chunk: every buffer is appended to it
 * (each at a multiple of 4, so views keep their alignment) and every image
 * the GLB can hold goes into a bufferView with its mimeType. A document
 * using an extension that may refer to buffers (e.g. EXT_meshopt_compression)
 * keeps its buffers apart, the others as data URIs. */
void merge_for_glb(document& d, const std::string& unknown)
{
	json& jb = d.j["buffers"];
	auto whole = [](const buffer& b) {
		pieces p;
		p.add(b, false);
		return p.joined();
	};
	if (!unknown.empty()) {
		for (size_t i = 0; i < d.buffers.size(); ++i) {
			if (i == 0)
				jb[i].erase("uri");
			else
				jb[i]["uri"] = data_uri(jb[i], whole(d.buffers[i]));
		}
		return;
	}
	std::vector<size_t> start(d.buffers.size());
	size_t size = 0;
	for (size_t b = 0; b < d.buffers.size(); ++b) {
		start[b] = (size + 3) / 4 * 4;
		size = start[b] + d.buffers[b].total();
	}
	/* Images: read first, so the block is allocated once. */
	std::vector<std::pair<size_t, bytes>> images;
	auto ji = d.j.find("images");
	for (size_t i = 0; ji != d.j.end() && ji->is_array() && i < ji->size(); ++i) {
		json& image = (*ji)[i];
		if (!image.is_object() || !image.contains("uri"))
			continue;
		bytes data;
		std::string type;
		if (is_data_uri(image)) {
			const std::string& text = image["uri"].get_ref<const std::string&>();
			std::vector<unsigned char> decoded;
			if (!tinygltf::DecodeDataURI(&decoded, type, text, 0, false))
				fail(vn_io_error_parse, str("images[%zu]: cannot decode its data URI", i));
			data.assign(decoded.begin(), decoded.end());
			const size_t semicolon = text.find(';');
			type = text.substr(5, semicolon == std::string::npos ? 0 : semicolon - 5);
		} else {
			const std::string name = file_uri(image);
			if (name.empty())
				continue; /* a URL: stays one */
			if (!read_file(d.folder + name, data))
				fail_named(vn_io_error_open, str("%s: cannot read images[%zu] ('%s') to put it into the GLB",
				                                 (d.folder + name).c_str(), i, name.c_str()));
		}
		if (type.empty() || type == "application/octet-stream")
			type = image_type(data);
		if (type.empty() && image.contains("mimeType") && image["mimeType"].is_string())
			type = image["mimeType"].get<std::string>();
		if (type.empty())
			fail(vn_io_error_unsupported,
			     str("images[%zu] is neither PNG, JPEG, WebP, KTX2, AVIF nor DDS and has no mimeType, which a GLB "
			         "needs to hold it (write .gltf instead)", i));
		image["mimeType"] = type;
		images.emplace_back(i, std::move(data));
	}
	std::vector<size_t> image_start;
	for (const auto& im : images) {
		image_start.push_back((size + 3) / 4 * 4);
		size = image_start.back() + im.second.size();
	}
	if (d.buffers.size() <= 1 && images.empty()) {
		if (!d.buffers.empty())
			jb[0].erase("uri");
		return;
	}
	buffer merged;
	merged.owner = block(size);
	merged.base = merged.owner.get();
	merged.size = size;
	memset(merged.base, 0, size);
	for (size_t b = 0; b < d.buffers.size(); ++b) {
		const buffer& from = d.buffers[b];
		memcpy(merged.base + start[b], from.base, from.size);
		if (!from.tail.empty())
			memcpy(merged.base + start[b] + from.tail_start(), from.tail.data(), from.tail.size());
	}
	auto views = d.j.find("bufferViews");
	for (size_t v = 0; views != d.j.end() && views->is_array() && v < views->size(); ++v) {
		json& view = (*views)[v];
		const long long b = get_int(view, "buffer", -1, str("bufferViews[%zu]", v));
		if (b >= 0 && (size_t)b < start.size()) {
			view["buffer"] = 0;
			view["byteOffset"] = start[(size_t)b] + (size_t)get_int(view, "byteOffset", 0, "bufferView");
		}
	}
	json first = d.buffers.empty() ? json::object() : jb[0];
	first.erase("uri");
	first["byteLength"] = size;
	d.j["buffers"] = json::array({first});
	d.buffers.assign(1, std::move(merged));
	for (size_t k = 0; k < images.size(); ++k) {
		memcpy(d.buffers[0].base + image_start[k], images[k].second.data(), images[k].second.size());
		if (!d.j.contains("bufferViews"))
			d.j["bufferViews"] = json::array();
		d.j["bufferViews"].push_back(json{{"buffer", 0}, {"byteOffset", image_start[k]}, {"byteLength", images[k].second.size()}});
		json& image = d.j["images"][images[k].first];
		image.erase("uri");
		image["bufferView"] = d.j["bufferViews"].size() - 1;
	}
}

/* Creates the folders of relative path `name` below `folder` that are
 * missing. */
void make_folders(const std::string& folder, const std::string& name)
{
	for (size_t slash = name.find('/'); slash != std::string::npos; slash = name.find('/', slash + 1)) {
		const std::string sub = folder + name.substr(0, slash);
		if (mkdir(sub.c_str(), 0777) != 0 && errno != EEXIST)
			fail_named(vn_io_error_write, str("%s: cannot create the folder: %s", sub.c_str(), strerror(errno)));
	}
}

/* Writes the document to path: a GLB with everything in its BIN chunk, or a
 * .gltf with its buffers in files beside it (the input's own names when
 * writing in place, else OUTSTEM.bin, OUTSTEM_1.bin, ...) and its external
 * images copied next to it when the folder differs, never outside path's
 * folder. unknown: an extension vn does not know, or "". */
void save(document& d, const std::string& path, bool glb, bool in_place, const std::string& unknown)
{
	file_set files;
	const std::string folder = folder_of(path);
	if (glb) {
		merge_for_glb(d, unknown);
		files.add(path, glb_file(d.j, d.buffers.empty() ? nullptr : &d.buffers[0]));
		files.commit();
		return;
	}
	json& jb = d.j["buffers"];
	/* The input's files, which a new buffer file must not replace. */
	std::vector<std::string> inputs;
	for (size_t i = 0; i < d.buffers.size(); ++i)
		if (!file_uri(jb[i]).empty())
			inputs.push_back(d.folder + file_uri(jb[i]));
	auto is_input = [&](const std::string& p) {
		return std::any_of(inputs.begin(), inputs.end(), [&](const std::string& q) { return vn_io_same_file(p.c_str(), q.c_str()); });
	};
	std::string stem = path.substr(folder.size());
	size_t dot = stem.rfind('.');
	if (dot != std::string::npos && dot > 0)
		stem.resize(dot);
	size_t k = 0;
	for (size_t i = 0; i < d.buffers.size(); ++i) {
		if (is_data_uri(jb[i])) {
			pieces p;
			p.add(d.buffers[i], false);
			jb[i]["uri"] = data_uri(jb[i], p.joined());
			continue;
		}
		std::string name = in_place ? file_uri(jb[i]) : "";
		while (name.empty() || (!in_place && is_input(folder + name)))
			name = stem + (k ? str("_%zu", k) : "") + ".bin", ++k;
		if (!in_place)
			jb[i]["uri"] = uri_encode(name);
		pieces contents;
		contents.add(d.buffers[i], false);
		files.add(folder + name, contents);
	}
	/* External images keep their URIs when they stay inside the output's
	 * folder (copied there, folders made as needed); one that would land
	 * outside it ("../tex/a.png") is copied into it under its own name. */
	auto images = d.j.find("images");
	if (images != d.j.end() && images->is_array() && !same_folder(d.folder, folder)) {
		std::map<std::string, bytes> placed; /* name in the output folder -> contents */
		for (json& image : *images) {
			const std::string name = image.is_object() ? file_uri(image) : "";
			if (name.empty())
				continue;
			bytes data, existing;
			if (!read_file(d.folder + name, data))
				fail_named(vn_io_error_open, str("%s: cannot read the image '%s'", (d.folder + name).c_str(), name.c_str()));
			std::string to = name;
			if (!stays_inside(name)) {
				const std::string base = name.substr(name.rfind('/') == std::string::npos ? 0 : name.rfind('/') + 1);
				const size_t ext = base.rfind('.');
				to = base;
				for (size_t n = 1; placed.count(to) && placed[to] != data; ++n)
					to = (ext == std::string::npos || ext == 0 ? base : base.substr(0, ext)) + str("_%zu", n) +
					     (ext == std::string::npos || ext == 0 ? "" : base.substr(ext));
				image["uri"] = uri_encode(to);
			}
			if (placed.count(to))
				continue;
			placed[to] = data;
			if (read_file(folder + to, existing)) {
				if (existing != data)
					fail_named(vn_io_error_write, str("%s exists and differs from the input's image; not overwritten",
					                                  (folder + to).c_str()));
				continue;
			}
			make_folders(folder, to);
			files.add(folder + to, std::string(data.begin(), data.end()));
		}
	}
	files.add(path, d.j.dump(2) + "\n");
	files.commit();
}

/* ------------------------------------------------------------------ vn_io_mesh */

/* The values of attribute `name` of primitive p (decoded Draco data or its
 * accessor), as doubles, with its type; false when p lacks it. */
bool attribute_values(const document& d, const primitive& p, const std::string& name, std::vector<double>& values,
                      accessor& type)
{
	const json& attributes = d.j["meshes"][p.mesh]["primitives"][p.index]["attributes"];
	if (!attributes.contains(name))
		return false;
	if (p.draco && p.draco->by_name.count(name)) {
		const vn_drc_attribute& a = *p.draco->by_name.at(name);
		type = accessor{};
		type.count = (long long)p.vertices();
		type.component = a.component_type;
		type.components = (size_t)a.components;
		type.normalized = a.normalized != 0;
		const size_t csize = vn_io_component_size(a.component_type);
		values.resize(p.vertices() * type.components);
		for (size_t i = 0; i < values.size(); ++i)
			values[i] = read_component((const unsigned char*)a.data + i * csize, a.component_type, false);
		return true;
	}
	type = get_accessor(d, get_int(attributes, name.c_str(), 0, "attributes"));
	if ((size_t)type.count != p.vertices() || type.components > 4)
		return false;
	const bool normalized = type.normalized;
	type.normalized = false; /* the stored values */
	values = read_accessor(d, type);
	type.normalized = normalized;
	return true;
}

/* Every triangle primitive merged into one mesh: positions, triangles, the
 * first colour set (COLOR_0) into colors, TEXCOORD_0 into texcoords, every
 * other vertex attribute (TEXCOORD_n, COLOR_n, JOINTS_n, WEIGHTS_n,
 * TANGENT, _NAME) into attributes in its own type; a primitive without an
 * attribute another one has gets zeros there. */
void mesh_from_document(const document& d, vn_io_mesh* mesh)
{
	std::vector<primitive> prims = triangle_primitives(d, nullptr);
	size_t vertices = 0, triangles = 0;
	for (const primitive& p : prims) {
		vertices += p.vertices();
		triangles += p.triangles.size() / 3;
	}
	if (vertices > UINT32_MAX || 3 * triangles > UINT32_MAX)
		fail(vn_io_error_unsupported, "the meshes have more than 2^32 vertices or indices");
	mesh->vertex_count = vertices;
	mesh->face_count = triangles;
	mesh->positions = (double*)malloc(3 * sizeof(double) * (vertices ? vertices : 1));
	mesh->indices = (uint32_t*)malloc(3 * sizeof(uint32_t) * (triangles ? triangles : 1));
	mesh->face_offsets = (uint32_t*)malloc(sizeof(uint32_t) * (triangles + 1));
	if (!mesh->positions || !mesh->indices || !mesh->face_offsets)
		fail(vn_io_error_memory, "out of memory");
	size_t v = 0, t = 0;
	for (const primitive& p : prims) {
		for (size_t i = 0; i < p.vertices(); ++i)
			p.positions.load(i, mesh->positions + 3 * (v + i));
		for (uint32_t i : p.triangles)
			mesh->indices[t++] = (uint32_t)(v + i);
		v += p.vertices();
	}
	for (size_t f = 0; f <= triangles; ++f)
		mesh->face_offsets[f] = (uint32_t)(3 * f);

	/* Attribute names in first-seen order. */
	std::vector<std::string> names;
	for (const primitive& p : prims)
		for (auto& kv : d.j["meshes"][p.mesh]["primitives"][p.index]["attributes"].items())
			if (kv.key() != "POSITION" && kv.key() != "NORMAL" &&
			    std::find(names.begin(), names.end(), kv.key()) == names.end())
				names.push_back(kv.key());
	for (const std::string& name : names) {
		/* Each primitive's values (read once), and the type: the first
		 * primitive's, or floats, as they stand for, where primitives
		 * disagree. */
		std::vector<std::vector<double>> values(prims.size());
		std::vector<accessor> types(prims.size());
		std::vector<bool> has(prims.size(), false);
		accessor type;
		bool any = false;
		for (size_t k = 0; k < prims.size(); ++k) {
			has[k] = attribute_values(d, prims[k], name, values[k], types[k]);
			if (!has[k])
				continue;
			const accessor& here = types[k];
			if (!any) {
				type = here;
			} else if (here.component != type.component || here.normalized != type.normalized ||
			           here.components > type.components) {
				type.component = 5126;
				type.normalized = false;
				type.components = std::max(here.components, type.components);
			}
			any = true;
		}
		if (!any)
			continue;
		const bool color = name == "COLOR_0" && (type.components == 3 || type.components == 4);
		const bool texcoord = name == "TEXCOORD_0" && type.components == 2;
		const int semantic = name.rfind("TEXCOORD_", 0) == 0 ? vn_io_semantic_texcoord
		                     : name.rfind("COLOR_", 0) == 0  ? vn_io_semantic_color
		                                                     : vn_io_semantic_generic;
		float* floats = nullptr;
		vn_io_attribute* a = nullptr;
		if (color) {
			floats = mesh->colors = (float*)calloc(4 * (vertices ? vertices : 1), sizeof(float));
			mesh->colors_are_bytes = type.component == 5121;
		} else if (texcoord) {
			floats = mesh->texcoords = (float*)calloc(2 * (vertices ? vertices : 1), sizeof(float));
		} else {
			a = vn_io_mesh_add_attribute(mesh, name.c_str(), semantic, (int)type.component, (int)type.components,
			                             type.normalized);
		}
		if (!floats && !a)
			fail(vn_io_error_memory, "out of memory");
		const size_t k = color ? 4 : texcoord ? 2 : type.components, csize = component_size(type.component);
		v = 0;
		for (size_t j = 0; j < prims.size(); ++j) {
			const primitive& p = prims[j];
			const accessor& here = types[j];
			if (has[j])
				for (size_t i = 0; i < p.vertices(); ++i)
					for (size_t c = 0; c < k; ++c) {
						/* Colours and texture coordinates as the floats they
						 * stand for; other attributes in their own type. */
						const bool have = c < here.components;
						double x = have ? values[j][i * here.components + c] : 1.0; /* missing alpha: opaque */
						if ((floats || type.component == 5126) && have && here.normalized)
							x = normalized_value(x, here.component);
						if (floats)
							floats[(v + i) * k + c] = (float)x;
						else if (have)
							write_component((unsigned char*)a->data + ((v + i) * k + c) * csize, type.component, x);
					}
			else if (color)
				for (size_t i = 0; i < p.vertices(); ++i)
					std::fill_n(&floats[(v + i) * 4], 4, 1.0f); /* white where a primitive has no colours */
			v += p.vertices();
		}
	}
}

/* glTF's name for mesh attribute a, given the TEXCOORD_n and COLOR_n sets
 * already written (numbered on from them: glTF wants them consecutive), or
 * "" when glTF cannot hold it as such: TEXCOORD is VEC2, COLOR VEC3/VEC4,
 * of float or normalized unsigned byte/short; an application-specific name
 * starts with '_'. */
std::string gltf_name(const vn_io_attribute& a, int* texcoords, int* colors)
{
	const bool allowed = a.component_type == 5126 || (a.normalized && (a.component_type == 5121 || a.component_type == 5123));
	if (a.semantic == vn_io_semantic_texcoord && a.components == 2 && allowed)
		return str("TEXCOORD_%d", (*texcoords)++);
	if (a.semantic == vn_io_semantic_color && (a.components == 3 || a.components == 4) && allowed)
		return str("COLOR_%d", (*colors)++);
	return a.name[0] == '_' ? std::string(a.name) : "_" + std::string(a.name);
}

/* A minimal document for mesh: one node, one mesh, one primitive with
 * POSITION, NORMAL, COLOR_0 (vertex colours), TEXCOORD_0 and every other
 * attribute (in its type; 32-bit integers, which glTF allows only for
 * indices, as floats). */
bytes document_from_mesh(const vn_io_mesh* mesh, json& j)
{
	if (mesh->vertex_count == 0 || mesh->face_count == 0)
		fail(vn_io_error_unsupported, "glTF needs at least one vertex and one face");
	std::vector<uint32_t> indices;
	for (size_t f = 0; f < mesh->face_count; ++f)
		for (uint32_t c = mesh->face_offsets[f] + 1; c + 1 < mesh->face_offsets[f + 1]; ++c)
			indices.insert(indices.end(), {mesh->indices[mesh->face_offsets[f]], mesh->indices[c], mesh->indices[c + 1]});
	if (indices.empty())
		fail(vn_io_error_unsupported, "glTF needs at least one face with 3 or more corners");
	const size_t n = mesh->vertex_count;
	bytes bin;
	json accessors = json::array(), views = json::array(), attributes = json::object();
	/* One bufferView per accessor, each element padded to 4 bytes (vertex
	 * attributes need it). */
	auto add = [&](const std::string& name, int component, size_t components, bool normalized, size_t count,
	               const std::function<double(size_t, size_t)>& value, bool bounds, int target) {
		const size_t csize = component_size(component), element = csize * components;
		const size_t stride = target == 34962 ? (element + 3) / 4 * 4 : element;
		bin.resize((bin.size() + 3) / 4 * 4, 0);
		const size_t offset = bin.size();
		bin.resize(offset + stride * count, 0);
		for (size_t i = 0; i < count; ++i)
			for (size_t c = 0; c < components; ++c)
				write_component(&bin[offset + i * stride + c * csize], component, value(i, c));
		json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", stride * count}};
		if (stride != element)
			view["byteStride"] = stride;
		view["target"] = target;
		views.push_back(view);
		json a = {{"bufferView", views.size() - 1}, {"componentType", component}, {"count", count},
		          {"type", components == 1 ? "SCALAR" : str("VEC%zu", components)}};
		if (normalized)
			a["normalized"] = true;
		if (bounds) {
			a["min"] = json::array(), a["max"] = json::array();
			accessor info;
			info.component = component;
			info.components = components;
			set_bounds(a, bytes(bin.begin() + (long)offset, bin.end()), stride, info, count);
		}
		accessors.push_back(a);
		if (!name.empty())
			attributes[name] = accessors.size() - 1;
	};
	add("POSITION", 5126, 3, false, n, [&](size_t i, size_t c) { return mesh->positions[3 * i + c]; }, true, 34962);
	add("NORMAL", 5126, 3, false, n, [&](size_t i, size_t c) {
		const double* v = mesh->normals ? &mesh->normals[3 * i] : nullptr;
		const bool zero = !v || (v[0] == 0 && v[1] == 0 && v[2] == 0);
		return zero ? (c == 2 ? 1.0 : 0.0) : v[c]; }, false, 34962);
	int texcoords = 0, colors = 0;
	if (mesh->texcoords)
		add(str("TEXCOORD_%d", texcoords++), 5126, 2, false, n, [&](size_t i, size_t c) { return mesh->texcoords[2 * i + c]; },
		    false, 34962);
	if (mesh->colors) {
		bool alpha = false;
		for (size_t i = 0; i < n && !alpha; ++i)
			alpha = mesh->colors[4 * i + 3] != 1.0f;
		add(str("COLOR_%d", colors++), mesh->colors_are_bytes ? 5121 : 5126, alpha ? 4 : 3, mesh->colors_are_bytes != 0, n,
		    [&](size_t i, size_t c) {
			    const double v = mesh->colors[4 * i + c];
			    return mesh->colors_are_bytes ? std::lround(std::min(1.0, std::max(0.0, v)) * 255) : v; },
		    false, 34962);
	}
	for (size_t k = 0; k < mesh->attribute_count; ++k) {
		const vn_io_attribute& a = mesh->attributes[k];
		const size_t csize = vn_io_component_size(a.component_type);
		const bool wide = a.component_type == 5124 || a.component_type == 5125; /* glTF: indices only */
		add(gltf_name(a, &texcoords, &colors), wide ? 5126 : a.component_type, (size_t)a.components,
		    a.normalized && !wide, n, [&](size_t i, size_t c) {
			    return read_component((const unsigned char*)a.data + (i * a.components + c) * csize, a.component_type, false); },
		    false, 34962);
	}
	add("", 5125, 1, false, indices.size(), [&](size_t i, size_t) { return (double)indices[i]; }, false, 34963);
	j = json{{"asset", {{"version", "2.0"}, {"generator", "vn"}}},
	         {"scene", 0},
	         {"scenes", json::array({json{{"nodes", {0}}}})},
	         {"nodes", json::array({json{{"mesh", 0}}})},
	         {"meshes", json::array({json{{"primitives", json::array({json{
	                                           {"attributes", attributes},
	                                           {"indices", accessors.size() - 1},
	                                           {"mode", 4}}})}}})},
	         {"accessors", accessors},
	         {"bufferViews", views},
	         {"buffers", json::array({json{{"byteLength", bin.size()}}})}};
	return bin;
}

vn_io_result to_error(const failure& f, const char* path, vn_io_error* error)
{
	if (f.names_file)
		return vn_io_fail(error, f.result, "%s", f.msg.c_str());
	return vn_io_fail(error, f.result, "%s: %s", path, f.msg.c_str());
}

/* Runs body, turning every failure and exception into a vn_io_result. */
template <typename F> vn_io_result guarded(const char* path, vn_io_error* error, F body)
{
	try {
		body();
		return vn_io_success;
	} catch (const failure& f) {
		return to_error(f, path, error);
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	} catch (const std::exception& x) {
		return vn_io_fail(error, vn_io_error_parse, "%s: %s", path, x.what());
	}
}

vn_io_result write_stream(FILE* out, const char* path, const vn_io_mesh* mesh, bool glb, vn_io_error* error)
{
	return guarded(path, error, [&] {
		json j;
		bytes bin = document_from_mesh(mesh, j);
		buffer b;
		b.base = bin.data();
		b.size = bin.size();
		pieces file;
		if (glb) {
			file = glb_file(j, &b);
		} else {
			j["buffers"][0]["uri"] = data_uri(json::object(), bin);
			file.add(j.dump(2) + "\n");
		}
		for (const auto& piece : file.list)
			if (fwrite(piece.first, 1, piece.second, out) != piece.second)
				fail_named(vn_io_error_write, str("%s: cannot write: %s", path, strerror(errno)));
	});
}

} // namespace

extern "C" vn_io_result vn_gltf_convert(const char* in, const char* out, int out_glb, const vn_gltf_options* options,
                                        vn_gltf_stats* stats, vn_io_error* error)
{
	vn_gltf_stats st;
	memset(&st, 0, sizeof st);
	vn_io_result r = guarded(in, error, [&] {
		document d = load(in);
		const usage before = used(d.j);
		if (options->draco == vn_gltf_draco_off)
			decompress_draco(d);
		std::vector<primitive> prims = triangle_primitives(d, &st);
		if (options->weld_mesh && !options->no_weld) {
			for (size_t i = 0; i < prims.size();) {
				std::vector<primitive*> group;
				size_t m = prims[i].mesh;
				for (; i < prims.size() && prims[i].mesh == m; ++i)
					group.push_back(&prims[i]);
				compute_group(group, *options, st);
			}
		} else {
			for (primitive& p : prims) {
				std::vector<primitive*> group = {&p};
				compute_group(group, *options, st);
			}
		}
		if (options->drop_tangents)
			for (const primitive& p : prims)
				if (p.tangent) {
					/* Morph targets may not displace an attribute the base lacks. */
					json& prim = mesh_primitive(d, p);
					prim["attributes"].erase("TANGENT");
					if (p.draco)
						prim["extensions"][draco_name]["attributes"].erase("TANGENT");
					if (prim.contains("targets") && prim["targets"].is_array())
						for (json& target : prim["targets"])
							if (target.is_object())
								target.erase("TANGENT");
				}
		write_normals(d, prims, *options, st);
		std::string unknown;
		prune(d, before, st, &unknown);
		snprintf(st.unpruned_extension, sizeof st.unpruned_extension, "%s", unknown.c_str());
		/* OUT may be a link: the buffers and images go beside what it
		 * points at, where the .gltf itself lands. */
		char* target = nullptr;
		vn_io_error e;
		if (vn_io_output_check(out, &target, &e) != vn_io_success)
			fail_named(vn_io_error_write, e.message);
		const std::string resolved = target;
		free(target);
		save(d, resolved, out_glb != 0, vn_io_same_file(in, out), unknown_extension(d.j));
	});
	if (stats)
		*stats = st;
	return r;
}

extern "C" vn_io_result vn_io_gltf_read(const char* path, vn_io_mesh* mesh, vn_io_error* error)
{
	memset(mesh, 0, sizeof *mesh);
	vn_io_result r = guarded(path, error, [&] { mesh_from_document(load(path), mesh); });
	if (r != vn_io_success)
		vn_io_mesh_free(mesh);
	return r;
}

extern "C" vn_io_result vn_io_gltf_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error)
{
	(void)settings; /* a glTF written from a mesh has none */
	return write_stream(out, path, mesh, false, error);
}

extern "C" vn_io_result vn_io_glb_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error)
{
	(void)settings;
	return write_stream(out, path, mesh, true, error);
}
