/*
 * glTF 2.0 reading and writing: the C++ glue behind gltf.h.
 *
 * tinygltf only LOADS (it checks the document and resolves the buffers:
 * GLB BIN chunk, data URIs, external .bin files). Everything else works on
 * the original JSON, kept as an nlohmann::ordered_json so that key order,
 * extras and unknown extensions survive, and on copies of the buffers in
 * which only NORMAL bytes change (new data, when any, is appended; Draco
 * data are decoded and encoded again with draco.h).
 */
#include "gltf.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <tiny_gltf.h>
#include <vector>

namespace {

using json = nlohmann::ordered_json;
using bytes = std::vector<unsigned char>;

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

void put32(bytes& out, uint32_t v)
{
	for (int i = 0; i < 4; ++i)
		out.push_back((unsigned char)(v >> (8 * i)));
}

std::string folder_of(const std::string& path)
{
	size_t slash = path.rfind('/');
	return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string first_line(std::string s)
{
	while (!s.empty() && (s[0] == '\n' || s[0] == ' '))
		s.erase(0, 1);
	size_t nl = s.find('\n');
	return nl == std::string::npos ? s : s.substr(0, nl);
}

/* ------------------------------------------------------------------ loading */

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*)
{
	return true; /* images are copied as files or bytes, never decoded */
}

struct document {
	bool glb = false;
	std::string folder;
	json j;
	std::vector<bytes> buffers;
};

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
	if ((unsigned long long)begin + (unsigned long long)length > d.buffers[(size_t)buffer].size())
		fail(vn_io_error_parse, str("%s overflows buffers[%lld]: it ends at byte %llu, the buffer has %zu",
		                            vw.c_str(), buffer, (unsigned long long)(begin + length),
		                            d.buffers[(size_t)buffer].size()));
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
		const unsigned char* p = d.buffers[(size_t)s.buffer].data() + s.offset + i * s.stride;
		for (size_t c = 0; c < a.components; ++c)
			to[c] = read_component(p + c * csize, a.component, a.normalized);
	};
	if (a.data.buffer >= 0)
		for (size_t i = 0; i < (size_t)a.count; ++i)
			read_element(a.data, i, &out[i * a.components]);
	for (size_t k = 0; k < (size_t)a.sparse_count; ++k) {
		const unsigned char* p =
		    d.buffers[(size_t)a.sparse_indices.buffer].data() + a.sparse_indices.offset + k * a.sparse_indices.stride;
		double index = read_component(p, a.sparse_index_component, false);
		if (index >= (double)a.count)
			fail(vn_io_error_parse, str("a sparse index (%.0f) is out of range (count %lld)", index, a.count));
		read_element(a.sparse_values, k, &out[(size_t)index * a.components]);
	}
	return out;
}

const json* draco_extension(const json& prim);

/* The file as tinygltf gets it: tinygltf insists on a bufferView for every
 * primitive's indices accessor, which Draco-compressed primitives lack, so
 * their "indices" are left out (vn reads them itself). json_length: the
 * GLB's JSON chunk length. */
std::string for_tinygltf(const std::string& file, const json& j, bool glb, size_t json_length)
{
	json copy = j;
	bool changed = false;
	auto meshes = copy.find("meshes");
	if (meshes != copy.end() && meshes->is_array())
		for (json& mesh : *meshes)
			if (mesh.is_object() && mesh.contains("primitives") && mesh["primitives"].is_array())
				for (json& prim : mesh["primitives"])
					if (prim.is_object() && draco_extension(prim) && prim.contains("indices"))
						changed = prim.erase("indices") != 0;
	if (!changed)
		return file;
	std::string text = copy.dump();
	if (!glb)
		return text;
	text.resize((text.size() + 3) / 4 * 4, ' ');
	const std::string rest = file.substr(20 + json_length);
	bytes head;
	put32(head, glb_magic);
	put32(head, 2);
	put32(head, (uint32_t)(20 + text.size() + rest.size()));
	put32(head, (uint32_t)text.size());
	put32(head, chunk_json);
	return std::string(head.begin(), head.end()) + text + rest;
}

document load(const std::string& path)
{
	char* raw;
	size_t size;
	vn_io_error e;
	if (vn_io_read_all(path.c_str(), &raw, &size, &e) != vn_io_success)
		fail_named(vn_io_error_open, e.message);
	std::string file(raw, size);
	free(raw);

	document d;
	d.folder = folder_of(path);
	const unsigned char* u = (const unsigned char*)file.data();
	std::string text = file;
	size_t json_length = 0;
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
		text = file.substr(20, length);
		json_length = length;
		size_t at = 20 + (size_t)length;
		if (at < size) {
			if (size - at < 8)
				fail(vn_io_error_parse, "malformed GLB: truncated chunk header after the JSON chunk");
			uint32_t bin_length = le32(u + at);
			if (bin_length > size - at - 8)
				fail(vn_io_error_parse, str("malformed GLB: the chunk length %u exceeds the file", bin_length));
		}
	}
	try {
		d.j = json::parse(text);
	} catch (const json::exception& x) {
		fail(vn_io_error_parse, std::string("invalid JSON: ") + x.what());
	}
	if (!d.j.is_object())
		fail(vn_io_error_parse, "invalid JSON: the document is not an object");

	tinygltf::TinyGLTF loader;
	loader.SetImageLoader(skip_image, nullptr);
	tinygltf::Model model;
	std::string err, warn;
	const std::string given = for_tinygltf(file, d.j, d.glb, json_length);
	bool ok = d.glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, (const unsigned char*)given.data(),
	                                              (unsigned)given.size(), d.folder)
	                : loader.LoadASCIIFromString(&model, &err, &warn, given.data(), (unsigned)given.size(), d.folder);
	if (!ok)
		fail(vn_io_error_parse, first_line(err.empty() ? "tinygltf cannot load the file" : err));
	for (auto& b : model.buffers)
		d.buffers.push_back(std::move(b.data));
	auto jb = d.j.find("buffers");
	if (d.buffers.size() != (jb != d.j.end() && jb->is_array() ? jb->size() : 0))
		fail(vn_io_error_parse, "the buffers could not all be loaded");
	for (size_t i = 0; i < d.buffers.size(); ++i) {
		long long declared = get_int((*jb)[i], "byteLength", 0, str("buffers[%zu]", i));
		if ((size_t)declared > d.buffers[i].size())
			fail(vn_io_error_parse, str("buffers[%zu] has %zu bytes, fewer than its byteLength %lld", i,
			                            d.buffers[i].size(), declared));
	}
	return d;
}

/* ------------------------------------------------------------------ Draco */

const char* const draco_name = "KHR_draco_mesh_compression";

/* A primitive's KHR_draco_mesh_compression object, or null. */
const json* draco_extension(const json& prim)
{
	auto e = prim.find("extensions");
	if (e == prim.end() || !e->is_object())
		return nullptr;
	auto k = e->find(draco_name);
	return k == e->end() ? nullptr : &*k;
}

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
 * checks it against the primitive: every attribute compressed, accessors
 * with the decoded counts and sizes, TRIANGLES with indices, no targets. */
std::shared_ptr<draco_mesh> decode_draco(const document& d, const json& prim, const json& ext, const std::string& what)
{
	const std::string ew = what + ".extensions." + draco_name;
	if (!ext.is_object() || !ext.contains("attributes") || !ext["attributes"].is_object())
		fail(vn_io_error_parse, ew + " is malformed");
	if (get_int(prim, "mode", 4, what) != 4 || !prim.contains("indices") || prim.contains("targets"))
		fail(vn_io_error_unsupported,
		     what + " is Draco-compressed and not indexed TRIANGLES without morph targets, which vn does not read");
	const long long view = get_int(ext, "bufferView", -1, ew);
	const size_t length = (size_t)get_int(element(d.j, "bufferViews", view, ew), "byteLength", 0, str("bufferViews[%lld]", view));
	const span s = view_span(d, view, 0, length, 1, ew);
	auto m = std::make_shared<draco_mesh>();
	vn_io_error e;
	const vn_io_result r = vn_drc_decode(d.buffers[(size_t)s.buffer].data() + s.offset, length, what.c_str(), &m->g, &e);
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
	for (auto& kv : attributes.items()) {
		if (!m->by_name.count(kv.key()))
			fail(vn_io_error_unsupported, str("%s: %s is not in the Draco data, which vn does not handle", what.c_str(),
			                                  kv.key().c_str()));
		const accessor a = get_accessor(d, get_int(attributes, kv.key().c_str(), 0, what + ".attributes"));
		if ((size_t)a.count != m->g.point_count || (int)a.components != m->by_name[kv.key()]->components)
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

/* A Draco attribute's values in a new bufferView, in the component type of
 * accessor `index`, which is pointed at it (its min/max recomputed). */
void store_decoded(document& d, long long index, const vn_drc_attribute& a, size_t points, int target)
{
	const accessor info = get_accessor(d, index);
	const size_t csize = component_size(info.component), stride = target == 34962 ? (info.element + 3) / 4 * 4 : info.element;
	const size_t dsize = (size_t)component_size(a.component_type == 5124 ? 5125 : a.component_type);
	bytes data(stride * points, 0);
	std::vector<double> lo(info.components, INFINITY), hi(info.components, -INFINITY);
	for (size_t i = 0; i < points; ++i)
		for (size_t c = 0; c < info.components; ++c) {
			const double v = read_component((const unsigned char*)a.data + dsize * (i * info.components + c), a.component_type, false);
			write_component(&data[i * stride + c * csize], info.component, v);
			const double stored = read_component(&data[i * stride + c * csize], info.component, false);
			lo[c] = std::min(lo[c], stored);
			hi[c] = std::max(hi[c], stored);
		}
	json& j = d.j["accessors"][(size_t)index];
	j.erase("byteOffset");
	j.erase("sparse");
	j["bufferView"] = append_view(d, data, stride == info.element ? 0 : stride, target);
	for (auto bound : {std::make_pair("min", &lo), std::make_pair("max", &hi)})
		if (j.contains(bound.first)) {
			j[bound.first] = json::array();
			for (double v : *bound.second)
				j[bound.first].push_back(info.component == 5126 ? json(v) : json((long long)v));
		}
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
			const vn_drc_attribute corners = {0, 0, 5125, 1, 0, 0, dm->g.indices};
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

struct primitive {
	size_t mesh, index;
	long long position, normal = -1;
	bool tangent = false;
	std::vector<double> positions;  /* 3 per vertex */
	std::vector<uint32_t> triangles; /* 3 per triangle */
	std::vector<double> input_normals; /* empty, or 3 per vertex */
	std::vector<float> normals;     /* result, 3 per output vertex */
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
	 * above come from it. */
	std::shared_ptr<const draco_mesh> draco;
	size_t vertices() const { return positions.size() / 3; }
	size_t output_vertices() const { return vertices() + split_source.size(); }
};

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
			if (const json* ext = draco_extension(prim)) {
				r.draco = decode_draco(d, prim, *ext, what);
				const vn_drc_geometry& g = r.draco->g;
				const float* q = (const float*)r.draco->by_name.at("POSITION")->data;
				r.positions.assign(q, q + 3 * g.point_count);
				r.triangles.assign(g.indices, g.indices + 3 * g.triangle_count);
				auto normal = r.draco->by_name.find("NORMAL");
				if (normal != r.draco->by_name.end()) {
					r.normal = get_int(attributes, "NORMAL", 0, what + ".attributes");
					q = (const float*)normal->second->data;
					r.input_normals.assign(q, q + 3 * g.point_count);
				}
				r.tangent = attributes.contains("TANGENT");
				out.push_back(std::move(r));
				continue;
			}
			accessor pa = get_accessor(d, r.position);
			if (pa.components != 3 || pa.count > (long long)UINT32_MAX)
				fail(vn_io_error_parse, what + ": POSITION is not VEC3");
			r.positions = read_accessor(d, pa);
			const size_t n = (size_t)pa.count;
			if (attributes.contains("NORMAL")) {
				r.normal = get_int(attributes, "NORMAL", 0, what + ".attributes");
				accessor na = get_accessor(d, r.normal);
				if (na.components != 3 || na.count != pa.count)
					fail(vn_io_error_parse, what + ": NORMAL is not VEC3 with one element per vertex");
				r.input_normals = read_accessor(d, na);
			}
			r.tangent = attributes.contains("TANGENT");
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
						if (ta.components != 3 || ta.count != pa.count)
							fail(vn_io_error_parse, tw + ": POSITION is not VEC3 with one element per vertex");
						morphed = read_accessor(d, ta);
						for (size_t i = 0; i < morphed.size(); ++i)
							morphed[i] += r.positions[i];
					}
					long long normal = target.contains("NORMAL") ? get_int(target, "NORMAL", 0, tw) : -1;
					if (normal >= 0) {
						accessor tn = get_accessor(d, normal);
						if (tn.components != 3 || tn.count != pa.count)
							fail(vn_io_error_parse, tw + ": NORMAL is not VEC3 with one element per vertex");
					}
					r.target_positions.push_back(std::move(morphed));
					r.target_normal.push_back(normal);
				}
			}

			std::vector<uint32_t> order;
			if (prim.contains("indices")) {
				accessor ia = get_accessor(d, get_int(prim, "indices", 0, what));
				if (ia.components != 1 || (ia.component != 5121 && ia.component != 5123 && ia.component != 5125))
					fail(vn_io_error_parse, what + ": indices are not unsigned integer scalars");
				for (double v : read_accessor(d, ia)) {
					if (v >= (double)n)
						fail(vn_io_error_parse,
						     str("%s: index %.0f is out of range (%zu vertices)", what.c_str(), v, n));
					order.push_back((uint32_t)v);
				}
			} else {
				for (size_t i = 0; i < n; ++i)
					order.push_back((uint32_t)i);
			}
			const size_t k = order.size();
			if (mode == 4) {
				r.triangles.assign(order.begin(), order.begin() + (long)(k / 3 * 3));
			} else {
				for (size_t i = 0; i + 2 < k; ++i) {
					uint32_t a = mode == 5 ? order[i + (i & 1)] : order[0];
					uint32_t b = mode == 5 ? order[i + 1 - (i & 1)] : order[i + 1];
					r.triangles.insert(r.triangles.end(), {a, b, order[i + 2]});
				}
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
 * normals: the same plan serves the base shape and every morph target. */
struct group_plan {
	std::vector<primitive*> prims;
	std::vector<size_t> first;          /* first input vertex of each primitive */
	std::vector<size_t> extra_first;    /* first split vertex of each primitive, counted from n */
	size_t n = 0;                       /* input vertices */
	std::vector<uint32_t> remap;        /* input vertex -> welded representative */
	std::vector<uint32_t> corner_input; /* input vertex of each corner */
	std::vector<uint32_t> triangles;    /* corners on welded vertices */
	std::vector<double> input_normals;  /* 3 per input vertex; 0 0 0 when none */
	bool corners = false;               /* per-corner normals (sharp edges or a crease angle) */
	double crease = M_PI;               /* radians; pi: no crease */
	std::vector<uint8_t> sharp;         /* per corner: edges whose input normals differ */
	std::vector<uint32_t> corner_output; /* per corner: output vertex, when splitting */
	std::vector<uint32_t> extra_source; /* output vertex n + k -> input vertex */
	vn_method method = vn_method_mwa;
	vn_options options;
};

/* The plan's normals for input positions q (3 per input vertex): one unit
 * vector per output vertex (input vertices, then split ones). A vertex no
 * face contributes to gets its input normal when that is a unit vector,
 * else +Z; *zeros counts them. */
std::vector<double> plan_normals(const group_plan& g, const std::vector<double>& q, size_t* zeros)
{
	const size_t n = g.n, outputs = n + g.extra_source.size();
	const vn_positions pos = {q.data(), n, 0, vn_scalar_float64};
	std::vector<double> out(3 * outputs, 0.0);
	auto vertex_normals = [&] {
		std::vector<double> v(3 * n);
		const vn_vectors vv = {v.data(), 0, vn_scalar_float64};
		check(vn_triangle_normals(&vv, &pos, g.triangles.data(), g.triangles.size(), g.method, &g.options, nullptr));
		return v;
	};
	if (!g.corners) {
		std::vector<double> v = vertex_normals();
		for (size_t i = 0; i < n; ++i)
			std::copy_n(&v[3 * g.remap[i]], 3, &out[3 * i]);
	} else {
		std::vector<double> c(g.triangles.size() * 3);
		const vn_vectors cv = {c.data(), 0, vn_scalar_float64};
		check(vn_corner_normals(&cv, &pos, g.triangles.data(), g.triangles.size(), g.method, g.crease,
		                        g.sharp.empty() ? nullptr : g.sharp.data(), &g.options, nullptr));
		if (!g.corner_output.empty()) {
			for (size_t k = 0; k < g.corner_output.size(); ++k)
				std::copy_n(&c[3 * k], 3, &out[3 * g.corner_output[k]]);
		} else {
			/* No splitting: a vertex whose corners disagree (its fans are
			 * not separated in the file) gets the smooth normal. */
			std::vector<uint32_t> seen(n, UINT32_MAX);
			std::vector<uint8_t> conflict(n, 0);
			for (size_t k = 0; k < g.corner_input.size(); ++k) {
				const uint32_t i = g.corner_input[k];
				if (seen[i] == UINT32_MAX)
					seen[i] = (uint32_t)k, std::copy_n(&c[3 * k], 3, &out[3 * i]);
				else if (!std::equal(&c[3 * k], &c[3 * k] + 3, &c[3 * seen[i]]))
					conflict[i] = 1;
			}
			if (std::find(conflict.begin(), conflict.end(), 1) != conflict.end()) {
				std::vector<double> v = vertex_normals();
				for (size_t i = 0; i < n; ++i)
					if (conflict[i])
						std::copy_n(&v[3 * g.remap[i]], 3, &out[3 * i]);
			}
		}
	}
	for (size_t k = 0; k < outputs; ++k) {
		double* v = &out[3 * k];
		if (v[0] != 0 || v[1] != 0 || v[2] != 0)
			continue;
		++*zeros;
		const double* w = &g.input_normals[3 * (k < n ? k : g.extra_source[k - n])];
		double l = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
		if (std::isfinite(l) && std::fabs(l - 1) < 1e-3)
			v[0] = w[0] / l, v[1] = w[1] / l, v[2] = w[2] / l;
		else
			v[2] = 1;
	}
	return out;
}

/* Flags the corners whose edge joins split copies with input normals more
 * than `angle` apart at either end; returns how many. */
size_t flag_hard_edges(group_plan& g, double angle)
{
	const double limit = std::cos(angle);
	auto differ = [&](uint32_t a, uint32_t b) {
		const double* x = &g.input_normals[3 * a];
		const double* y = &g.input_normals[3 * b];
		double lx = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
		double ly = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
		return a != b && lx > 0 && ly > 0 && (x[0] * y[0] + x[1] * y[1] + x[2] * y[2]) < limit * lx * ly;
	};
	auto next = [](size_t k) { return k - k % 3 + (k + 1) % 3; };
	const size_t corners = g.triangles.size();
	/* Only an edge with an end where welding merged copies can join copies
	 * with different input normals: the others need no search (on a file
	 * without split vertices, that is every edge). */
	std::vector<uint8_t> merged(g.n, 0);
	for (size_t i = 0; i < g.n; ++i)
		if (g.remap[i] != i)
			merged[g.remap[i]] = 1;
	auto candidate = [&](size_t k) { return merged[g.triangles[k]] || merged[g.triangles[next(k)]]; };
	std::vector<std::pair<uint64_t, uint32_t>> edges;
	for (size_t k = 0; k < corners; ++k)
		if (candidate(k))
			edges.push_back({(uint64_t)g.triangles[k] << 32 | g.triangles[next(k)], (uint32_t)k});
	std::sort(edges.begin(), edges.end());
	g.sharp.assign(corners, 0);
	size_t flagged = 0;
	for (size_t k = 0; k < corners; ++k) {
		if (!candidate(k) || g.triangles[k] == g.triangles[next(k)])
			continue; /* no merged end, or a degenerate triangle (no edges) */
		const uint64_t opposite = (uint64_t)g.triangles[next(k)] << 32 | g.triangles[k];
		auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(opposite, (uint32_t)0));
		for (; it != edges.end() && it->first == opposite && !g.sharp[k]; ++it) {
			const size_t j = it->second;
			g.sharp[k] = differ(g.corner_input[k], g.corner_input[next(j)]) ||
			             differ(g.corner_input[next(k)], g.corner_input[j]);
		}
		flagged += g.sharp[k];
	}
	return flagged;
}

/* Split vertices for per-corner normals c: a corner whose normal differs
 * from the first one of its input vertex gets a new vertex, shared by the
 * vertex's corners with the same normal. */
void split_corners(group_plan& g, const std::vector<double>& c)
{
	const size_t corners = g.corner_input.size();
	std::vector<uint32_t> owner(g.n, UINT32_MAX);
	g.extra_first.assign(1, 0);
	std::map<uint32_t, std::vector<uint32_t>> extras; /* input vertex -> its split vertices' first corner */
	g.corner_output.assign(corners, 0);
	size_t p = 0;
	for (size_t k = 0; k < corners; ++k) {
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
	std::vector<double> positions;
	for (primitive* p : prims) {
		g.first.push_back(positions.size() / 3);
		if (positions.size() / 3 + p->vertices() > UINT32_MAX)
			fail(vn_io_error_unsupported, "a mesh has more than 2^32 vertices");
		positions.insert(positions.end(), p->positions.begin(), p->positions.end());
		if (p->input_normals.empty())
			g.input_normals.resize(positions.size(), 0.0);
		else
			g.input_normals.insert(g.input_normals.end(), p->input_normals.begin(), p->input_normals.end());
		for (uint32_t v : p->triangles)
			g.corner_input.push_back((uint32_t)(g.first.back() + v));
	}
	g.n = positions.size() / 3;
	const vn_positions pos = {positions.data(), g.n, 0, vn_scalar_float64};
	g.remap.resize(g.n);
	for (size_t i = 0; i < g.n; ++i)
		g.remap[i] = (uint32_t)i;
	if (!o.no_weld) {
		check(vn_weld_positions(g.remap.data(), &pos, o.weld_epsilon, &g.options));
		for (size_t i = 0; i < g.n; ++i)
			st.welded_vertices += g.remap[i] != i;
	}
	g.triangles.resize(g.corner_input.size());
	for (size_t k = 0; k < g.triangles.size(); ++k)
		g.triangles[k] = g.remap[g.corner_input[k]];
	if (!o.no_weld && !flag_hard_edges(g, o.crease ? o.crease_angle : default_hard_edge_angle))
		g.sharp.clear();
	g.corners = o.crease || !g.sharp.empty();
	if (o.crease) {
		g.crease = o.crease_angle;
		std::vector<double> c(g.triangles.size() * 3);
		const vn_vectors cv = {c.data(), 0, vn_scalar_float64};
		check(vn_corner_normals(&cv, &pos, g.triangles.data(), g.triangles.size(), g.method, g.crease,
		                        g.sharp.empty() ? nullptr : g.sharp.data(), &g.options, nullptr));
		split_corners(g, c);
	}
	size_t zeros = 0;
	const std::vector<double> base = plan_normals(g, positions, &zeros);
	st.zero_normals += zeros;

	/* Each primitive's output vertices: its input ones, then its split ones. */
	auto gather = [&](const std::vector<double>& all, size_t p, std::vector<float>& out, const std::vector<double>* minus) {
		const primitive& pr = *prims[p];
		out.resize(3 * pr.output_vertices());
		for (size_t i = 0; i < out.size(); ++i) {
			const size_t k = i < 3 * pr.vertices() ? 3 * g.first[p] + i : 3 * (g.n + g.extra_first[p]) + i - 3 * pr.vertices();
			out[i] = (float)(minus ? all[k] - (*minus)[k] : all[k]);
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
		gather(base, p, pr.normals, nullptr);
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
			const bool moves = t < p->target_positions.size() && !p->target_positions[t].empty();
			const std::vector<double>& q = moves ? p->target_positions[t] : p->positions;
			morphed.insert(morphed.end(), q.begin(), q.end());
		}
		size_t ignored = 0;
		const std::vector<double> normals = plan_normals(g, morphed, &ignored);
		for (size_t p = 0; p < prims.size(); ++p) {
			primitive& pr = *prims[p];
			if (t >= pr.target_positions.size())
				continue;
			pr.target_normals.emplace_back();
			if (!pr.target_positions[t].empty() || pr.target_normal[t] >= 0)
				gather(normals, p, pr.target_normals.back(), &base);
		}
	}
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
	bytes& buffer = d.buffers[b];
	buffer.resize((buffer.size() + 3) / 4 * 4, 0);
	const size_t offset = buffer.size();
	buffer.insert(buffer.end(), data.begin(), data.end());
	d.j["buffers"][b]["byteLength"] = buffer.size();
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
		unsigned char* e = d.buffers[(size_t)a.data.buffer].data() + a.data.offset + i * a.data.stride;
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
	auto element = [&](const span& s, size_t i) {
		return d.buffers[(size_t)s.buffer].data() + s.offset + i * s.stride;
	};
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
	j.erase("sparse");
	j.erase("byteOffset");
	j["bufferView"] = append_view(d, data, stride == a.element ? 0 : stride, 34962);
	j["count"] = p.output_vertices();
	return append_accessor(d, j);
}

/* Points a split primitive's every attribute (and its morph targets') at
 * copies with the split vertices, and its indices at the new triangles. */
void write_split(document& d, const primitive& p)
{
	json& prim = mesh_primitive(d, p);
	std::map<long long, long long> copies;
	auto copy_all = [&](json& attributes) {
		for (auto& kv : attributes.items()) {
			if (kv.key() == "NORMAL")
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

/* g Draco-encoded at `level` into a new bufferView; returns its index. */
size_t append_draco(document& d, const vn_drc_geometry& g, int level, const std::string& what)
{
	void* data;
	size_t size;
	vn_io_error e;
	const vn_io_result r = vn_drc_encode(&g, level, what.c_str(), &data, &size, &e);
	if (r != vn_io_success)
		fail(r, e.message);
	const bytes encoded((unsigned char*)data, (unsigned char*)data + size);
	free(data);
	return append_view(d, encoded, 0, 0);
}

/* Adds p's output vertices (positions, new normals) and triangles. */
void record_normals(quantized_normals& q, const primitive& p)
{
	const size_t first = q.positions.size() / 3;
	for (uint32_t v : p.split_source.empty() ? p.triangles : p.split_triangles)
		q.indices.push_back((uint32_t)(first + v));
	q.positions.insert(q.positions.end(), p.positions.begin(), p.positions.end());
	for (uint32_t v : p.split_source)
		q.positions.insert(q.positions.end(), &p.positions[3 * v], &p.positions[3 * v] + 3);
	q.normals.insert(q.normals.end(), p.normals.begin(), p.normals.end());
}

/* Encodes Draco primitive p again with its new normals: the same attributes
 * (but a dropped TANGENT), unique ids and bits (normals: --draco-qn when given; a NORMAL the data
 * lacked gets the next unique id and a bufferView-less accessor), in a new
 * bufferView the extension points at. */
void write_draco(document& d, const primitive& p, const vn_gltf_options& o, vn_gltf_stats& st,
                 std::map<int, quantized_normals>& quantized)
{
	const std::string what = str("meshes[%zu].primitives[%zu]", p.mesh, p.index);
	if (!p.split_source.empty())
		fail(vn_io_error_unsupported,
		     str("%s: --crease-angle would split %zu vertices of this Draco-compressed primitive, which vn does not "
		         "do inside Draco data (--draco off writes it uncompressed)", what.c_str(), p.split_source.size()));
	json& prim = mesh_primitive(d, p);
	json& ext = prim["extensions"][draco_name];
	const vn_drc_geometry& in = p.draco->g;
	std::vector<vn_drc_attribute> attributes;
	for (size_t i = 0; i < in.attribute_count; ++i)
		if (!o.drop_tangents || !p.draco->by_name.count("TANGENT") || p.draco->by_name.at("TANGENT") != &in.attributes[i])
			attributes.push_back(in.attributes[i]);
	std::vector<float> normals(p.normals);
	auto normal = std::find_if(attributes.begin(), attributes.end(), [&](const vn_drc_attribute& a) {
		return p.draco->by_name.count("NORMAL") && a.unique_id == p.draco->by_name.at("NORMAL")->unique_id;
	});
	if (normal == attributes.end()) {
		vn_drc_attribute a = {0, vn_drc_normal, vn_drc_float32, 3, 0, 0, nullptr};
		for (const vn_drc_attribute& b : attributes)
			a.unique_id = std::max(a.unique_id, b.unique_id + 1);
		a.quantization_bits = -1; /* set below */
		ext["attributes"]["NORMAL"] = a.unique_id;
		prim["attributes"]["NORMAL"] = append_accessor(d, json{{"componentType", 5126}, {"count", in.point_count}, {"type", "VEC3"}});
		++st.appended_accessors;
		attributes.push_back(a);
		normal = attributes.end() - 1;
	}
	normal->data = normals.data();
	const vn_drc_options bits = draco_bits(o);
	if (o.draco_options.normal_bits >= 0 || normal->quantization_bits < 0)
		normal->quantization_bits = bits.normal_bits;
	vn_drc_geometry g = in;
	g.attributes = attributes.data();
	g.attribute_count = attributes.size();
	ext["bufferView"] = append_draco(d, g, bits.compression_level, what);
	++st.draco_primitives;
	record_normals(quantized[normal->quantization_bits], p);
}

/* --draco on: p (not Draco-compressed on input, normals written, split
 * when it had to be) gets its attributes and triangles Draco-encoded with
 * o's bits (semantics by name: POSITION, NORMAL, TEXCOORD_n, COLOR_n, the
 * rest generic and lossless), new bufferView-less accessors and indices,
 * and the extension. The old accessors stay (unused). A primitive with
 * morph targets is left uncompressed: Draco renumbers the vertices that
 * the targets' accessors follow. */
void compress_draco(document& d, const primitive& p, const vn_gltf_options& o, vn_gltf_stats& st,
                    std::map<int, quantized_normals>& quantized)
{
	json& prim = mesh_primitive(d, p);
	if (prim.contains("targets"))
		return;
	const std::string what = str("meshes[%zu].primitives[%zu]", p.mesh, p.index);
	const vn_drc_options bits = draco_bits(o);
	const size_t n = p.output_vertices();
	std::vector<bytes> storage;
	std::vector<vn_drc_attribute> attributes;
	json ext_attributes = json::object();
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
		storage.emplace_back(values.size() * csize);
		for (size_t i = 0; i < values.size(); ++i)
			write_component(&storage.back()[i * csize], a.component, values[i]);
		const bool texcoord = name.rfind("TEXCOORD_", 0) == 0, color = name.rfind("COLOR_", 0) == 0;
		vn_drc_attribute da = {(uint32_t)attributes.size(),
		                       name == "POSITION" ? vn_drc_position : name == "NORMAL" ? vn_drc_normal
		                       : texcoord ? vn_drc_texcoord : color ? vn_drc_color : vn_drc_generic,
		                       (int)a.component, (int)a.components, get_accessor(d, index).normalized, 0, nullptr};
		da.quantization_bits = da.semantic == vn_drc_position ? bits.position_bits : da.semantic == vn_drc_normal ? bits.normal_bits
		                       : texcoord ? bits.texcoord_bits : color ? bits.color_bits : 0;
		attributes.push_back(da);
		ext_attributes[name] = da.unique_id;
		json copy = d.j["accessors"][(size_t)index];
		copy.erase("bufferView");
		copy.erase("byteOffset");
		copy.erase("sparse");
		kv.value() = append_accessor(d, copy);
	}
	for (size_t i = 0; i < attributes.size(); ++i)
		attributes[i].data = storage[i].data();
	const std::vector<uint32_t>& triangles = p.split_source.empty() ? p.triangles : p.split_triangles;
	vn_drc_geometry g = {n, triangles.size() / 3, const_cast<uint32_t*>(triangles.data()), attributes.size(), attributes.data()};
	const size_t view = append_draco(d, g, bits.compression_level, what);
	prim["indices"] = append_accessor(d, json{{"componentType", n <= 256 ? 5121 : n <= 65536 ? 5123 : 5125},
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
		std::vector<uint32_t> offsets(q.indices.size() / 3 + 1);
		for (size_t f = 0; f < offsets.size(); ++f)
			offsets[f] = (uint32_t)(3 * f);
		vn_io_mesh mesh;
		memset(&mesh, 0, sizeof mesh);
		mesh.vertex_count = q.positions.size() / 3;
		mesh.positions = const_cast<double*>(q.positions.data());
		mesh.normals = const_cast<double*>(q.normals.data());
		mesh.face_count = q.indices.size() / 3;
		mesh.face_offsets = offsets.data();
		mesh.indices = const_cast<uint32_t*>(q.indices.data());
		vn_drc_options options = draco_bits(o);
		options.normal_bits = kv.first;
		vn_io_error e;
		const vn_io_result r = vn_drc_normal_error_of(&mesh, &options, "Draco normals", &st.draco_normal_error[kv.first], &e);
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
		if (p.draco) {
			write_draco(d, p, o, st, quantized);
			continue;
		}
		const bool split = !p.split_source.empty();
		if (split)
			write_split(d, p);
		json& prim = mesh_primitive(d, p);
		prim["attributes"]["NORMAL"] = put_vec3(d, split ? -1 : p.normal, p.normals, written, st);
		for (size_t t = 0; t < p.target_normals.size(); ++t)
			if (!p.target_normals[t].empty())
				prim["targets"][t]["NORMAL"] = put_vec3(d, split ? -1 : p.target_normal[t], p.target_normals[t], written, st);
		if (o.draco == vn_gltf_draco_on)
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

bytes glb_file(const json& j, const bytes* bin)
{
	std::string text = j.dump();
	text.resize((text.size() + 3) / 4 * 4, ' ');
	size_t bin_padded = bin ? (bin->size() + 3) / 4 * 4 : 0;
	bytes out;
	put32(out, glb_magic);
	put32(out, 2);
	put32(out, (uint32_t)(12 + 8 + text.size() + (bin ? 8 + bin_padded : 0)));
	put32(out, (uint32_t)text.size());
	put32(out, chunk_json);
	out.insert(out.end(), text.begin(), text.end());
	if (bin) {
		put32(out, (uint32_t)bin_padded);
		put32(out, chunk_bin);
		out.insert(out.end(), bin->begin(), bin->end());
		out.resize(out.size() + bin_padded - bin->size(), 0);
	}
	if (out.size() > UINT32_MAX)
		fail(vn_io_error_unsupported, "the GLB would exceed 4 GiB");
	return out;
}

/* Output files written as temporaries beside their final paths, then all
 * renamed; the temporaries of an unfinished set are removed. */
struct file_set {
	std::vector<std::pair<std::string, std::string>> files; /* temporary, final */
	~file_set()
	{
		for (auto& f : files)
			unlink(f.first.c_str());
	}
	void add(const std::string& path, const unsigned char* data, size_t size)
	{
		const size_t slash = path.rfind('/') == std::string::npos ? 0 : path.rfind('/') + 1;
		std::string temporary = path.substr(0, slash) + "." + path.substr(slash) + ".XXXXXX";
		int fd = mkstemp(&temporary[0]);
		if (fd < 0)
			fail_named(vn_io_error_write,
			     str("%s: cannot create a temporary file next to it: %s", path.c_str(), strerror(errno)));
		files.emplace_back(temporary, path);
		mode_t mask = umask(0);
		umask(mask);
		bool ok = fchmod(fd, 0644 & ~mask) == 0;
		for (size_t done = 0; ok && done < size;) {
			ssize_t n = write(fd, data + done, size - done);
			if (n < 0 && errno == EINTR)
				continue;
			ok = n > 0;
			done += ok ? (size_t)n : 0;
		}
		ok = ok && fsync(fd) == 0;
		ok = close(fd) == 0 && ok;
		if (!ok)
			fail_named(vn_io_error_write, str("%s: cannot write: %s", path.c_str(), strerror(errno)));
	}
	void commit()
	{
		for (auto& f : files) {
			if (rename(f.first.c_str(), f.second.c_str()) != 0)
				fail_named(vn_io_error_write, str("%s: cannot replace the file: %s", f.second.c_str(), strerror(errno)));
			f.first.clear();
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

void save(document& d, const std::string& path, bool glb)
{
	file_set files;
	const std::string folder = folder_of(path);
	json& jb = d.j["buffers"];
	if (glb) {
		/* Buffer 0 becomes the BIN chunk; any other buffer with an external
		 * file becomes a data URI, so that the GLB stands alone. */
		for (size_t i = 0; i < d.buffers.size(); ++i) {
			if (i == 0)
				jb[i].erase("uri");
			else
				jb[i]["uri"] = data_uri(jb[i], d.buffers[i]);
		}
	} else {
		std::string stem = path.substr(folder.size());
		size_t dot = stem.rfind('.');
		if (dot != std::string::npos && dot > 0)
			stem.resize(dot);
		size_t k = 0;
		for (size_t i = 0; i < d.buffers.size(); ++i) {
			if (is_data_uri(jb[i])) {
				jb[i]["uri"] = data_uri(jb[i], d.buffers[i]);
				continue;
			}
			std::string name = stem + (k ? str("_%zu", k) : "") + ".bin";
			++k;
			jb[i]["uri"] = uri_encode(name);
			files.add(folder + name, d.buffers[i].data(), d.buffers[i].size());
		}
	}
	/* External images: same URIs, so the files go next to the output. */
	if (d.j.contains("images") && d.j["images"].is_array() && !same_folder(d.folder, folder)) {
		for (const json& image : d.j["images"]) {
			if (!image.is_object() || !image.contains("uri") || !image["uri"].is_string() || is_data_uri(image))
				continue;
			const std::string name = uri_decode(image["uri"].get<std::string>());
			bytes data, existing;
			if (!read_file(d.folder + name, data))
				fail_named(vn_io_error_open, str("%s: cannot read the image '%s'", (d.folder + name).c_str(), name.c_str()));
			if (read_file(folder + name, existing)) {
				if (existing != data)
					fail_named(vn_io_error_write, str("%s exists and differs from the input's image; not overwritten",
					                            (folder + name).c_str()));
				continue;
			}
			files.add(folder + name, data.data(), data.size());
		}
	}
	if (glb) {
		bytes file = glb_file(d.j, d.buffers.empty() ? nullptr : &d.buffers[0]);
		files.add(path, file.data(), file.size());
	} else {
		std::string text = d.j.dump(2) + "\n";
		files.add(path, (const unsigned char*)text.data(), text.size());
	}
	files.commit();
}

/* ------------------------------------------------------------------ vn_io_mesh */

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
		std::copy(p.positions.begin(), p.positions.end(), mesh->positions + 3 * v);
		for (uint32_t i : p.triangles)
			mesh->indices[t++] = (uint32_t)(v + i);
		v += p.vertices();
	}
	for (size_t f = 0; f <= triangles; ++f)
		mesh->face_offsets[f] = (uint32_t)(3 * f);
}

/* A minimal document for mesh: one node, one mesh, one primitive. */
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
	std::vector<float> positions(3 * n), normals(3 * n);
	std::vector<double> lo(3, INFINITY), hi(3, -INFINITY);
	for (size_t i = 0; i < 3 * n; ++i) {
		positions[i] = (float)mesh->positions[i];
		lo[i % 3] = std::min(lo[i % 3], (double)positions[i]);
		hi[i % 3] = std::max(hi[i % 3], (double)positions[i]);
	}
	for (size_t i = 0; i < n; ++i) {
		const double* v = mesh->normals ? &mesh->normals[3 * i] : nullptr;
		bool zero = !v || (v[0] == 0 && v[1] == 0 && v[2] == 0);
		for (size_t c = 0; c < 3; ++c)
			normals[3 * i + c] = zero ? (c == 2 ? 1.0f : 0.0f) : (float)v[c];
	}
	bytes bin(12 * n * 2 + 4 * indices.size());
	memcpy(bin.data(), positions.data(), 12 * n);
	memcpy(bin.data() + 12 * n, normals.data(), 12 * n);
	memcpy(bin.data() + 24 * n, indices.data(), 4 * indices.size());
	j = json{{"asset", {{"version", "2.0"}, {"generator", "vn"}}},
	         {"scene", 0},
	         {"scenes", json::array({json{{"nodes", {0}}}})},
	         {"nodes", json::array({json{{"mesh", 0}}})},
	         {"meshes", json::array({json{{"primitives", json::array({json{
	                                           {"attributes", {{"POSITION", 0}, {"NORMAL", 1}}},
	                                           {"indices", 2},
	                                           {"mode", 4}}})}}})},
	         {"accessors", json::array({json{{"bufferView", 0}, {"componentType", 5126}, {"count", n},
	                                          {"type", "VEC3"}, {"min", lo}, {"max", hi}},
	                                     json{{"bufferView", 1}, {"componentType", 5126}, {"count", n},
	                                          {"type", "VEC3"}},
	                                     json{{"bufferView", 2}, {"componentType", 5125},
	                                          {"count", indices.size()}, {"type", "SCALAR"}}})},
	         {"bufferViews", json::array({json{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 12 * n}, {"target", 34962}},
	                                       json{{"buffer", 0}, {"byteOffset", 12 * n}, {"byteLength", 12 * n}, {"target", 34962}},
	                                       json{{"buffer", 0}, {"byteOffset", 24 * n}, {"byteLength", 4 * indices.size()},
	                                            {"target", 34963}}})},
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
		bytes file;
		if (glb) {
			file = glb_file(j, &bin);
		} else {
			j["buffers"][0]["uri"] = data_uri(json::object(), bin);
			std::string text = j.dump(2) + "\n";
			file.assign(text.begin(), text.end());
		}
		if (fwrite(file.data(), 1, file.size(), out) != file.size())
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
		save(d, out, out_glb != 0);
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
