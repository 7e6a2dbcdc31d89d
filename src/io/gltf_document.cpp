/*
 * The glTF document (gltf_document.h): loading a .gltf or .glb (the GLB's
 * chunks, the JSON, buffers from the BIN chunk, data URIs or files beside
 * it), reading accessors (bufferViews checked against their buffers,
 * components, sparse substitution), appending bufferViews and accessors,
 * and the failures every stage throws.
 */
#include "gltf_document.h"

extern "C" {
#include "text.h"
}

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <map>
#include <strings.h> /* strcasecmp */

namespace vn_gltf {

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
{
	char text[512];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(text, sizeof text, fmt, ap);
	va_end(ap);
	return text;
}

static uint32_t le32(const unsigned char* p)
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

bool is_data_uri(const std::string& uri)
{
	return uri.size() >= 5 && strncasecmp(uri.c_str(), "data:", 5) == 0;
}

/* The value of base64 digit c (RFC 4648, and its URL-safe alphabet), or -1. */
static int base64_digit(unsigned char c)
{
	if (c >= 'A' && c <= 'Z')
		return c - 'A';
	if (c >= 'a' && c <= 'z')
		return c - 'a' + 26;
	if (c >= '0' && c <= '9')
		return c - '0' + 52;
	return c == '+' || c == '-' ? 62 : c == '/' || c == '_' ? 63 : -1;
}

bool decode_data_uri(const std::string& uri, bytes& data, std::string& media_type)
{
	const size_t comma = uri.find(',');
	if (!is_data_uri(uri) || comma == std::string::npos)
		return false;
	/* The header: [type/subtype][;attribute=value]*[;base64]. */
	std::string header = uri.substr(5, comma - 5);
	bool base64 = false;
	if (header.size() >= 7 && strcasecmp(header.c_str() + header.size() - 7, ";base64") == 0) {
		base64 = true;
		header.resize(header.size() - 7);
	}
	media_type = header.substr(0, header.find(';'));
	/* The data are URL-encoded (RFC 2397 section 3), also when base64. */
	const std::string text = uri_decode(uri.substr(comma + 1));
	data.clear();
	if (!base64) {
		data.assign(text.begin(), text.end());
		return true;
	}
	data.reserve(text.size() / 4 * 3);
	uint32_t bits = 0;
	int have = 0;
	size_t padding = 0;
	for (unsigned char c : text) {
		if (isspace(c))
			continue;
		if (c == '=') {
			++padding;
			continue;
		}
		const int v = base64_digit(c);
		if (v < 0 || padding)
			return false; /* not a base64 digit, or a digit after the padding */
		bits = bits << 6 | (uint32_t)v;
		if ((have += 6) >= 8) {
			have -= 8;
			data.push_back((unsigned char)(bits >> have));
		}
	}
	return padding <= 2;
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

long long index_or_none(const json& o, const char* key)
{
	auto it = o.find(key);
	return it != o.end() && it->is_number_integer() && it->get<long long>() >= 0 ? it->get<long long>() : -1;
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

static size_t component_count(const std::string& type)
{
	static const std::map<std::string, size_t> n = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
	                                                {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}};
	auto it = n.find(type);
	return it == n.end() ? 0 : it->second;
}

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
	const char* name;
	if (b.absent && !(b.base && meshopt_extension(v, &name, vw)))
		fail(vn_io_error_parse, str("%s is in buffers[%lld], which has no data: no uri, and no extension "
		                            "(such as EXT_meshopt_compression) that gives it", vw.c_str(), buffer));
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
	case 5130: { double v; memcpy(&v, p, 8); return v; } /* a PLY double, a Draco float64: never an accessor's */
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
 * file has none), a data URI or an external file; absent without uri
 * otherwise (a view of it fails when read, see view_span). A file read
 * joins d.buffer_files. */
static buffer load_buffer(document& d, size_t i, const std::shared_ptr<unsigned char>& file, const unsigned char* bin,
                          size_t bin_length)
{
	const std::string what = str("buffers[%zu]", i);
	const json& b = element(d.j, "buffers", (long long)i, what);
	const long long length = get_int(b, "byteLength", -1, what);
	if (length < 0)
		fail(vn_io_error_parse, what + " has no byteLength");
	buffer out;
	auto uri = b.find("uri");
	if (uri == b.end()) {
		if (!d.glb || i != 0 || !bin) {
			out.absent = true;
			return out;
		}
		if ((size_t)length > bin_length)
			fail(vn_io_error_parse, str("%s.byteLength %lld exceeds the BIN chunk (%zu bytes)", what.c_str(), length, bin_length));
		out.size = (size_t)length;
		out.owner = file;
		out.base = const_cast<unsigned char*>(bin);
		return out;
	}
	if (!uri->is_string())
		fail(vn_io_error_parse, what + ".uri is not a string");
	out.size = (size_t)length;
	const std::string& text = uri->get_ref<const std::string&>();
	size_t have;
	if (is_data_uri(text)) {
		bytes data;
		std::string type;
		if (!decode_data_uri(text, data, type))
			fail(vn_io_error_parse, what + ": its data URI is malformed (RFC 2397: data:[type][;base64],data)");
		have = data.size();
		out.owner = block(have);
		if (have) /* "data:," has no bytes, and data() may be null */
			memcpy(out.owner.get(), data.data(), have);
	} else {
		/* "" would name the glTF's own folder. */
		if (text.empty())
			fail(vn_io_error_parse, what + ".uri is empty: it names no file");
		const std::string path = d.folder + uri_decode(text);
		d.buffer_files.push_back(path);
		char* raw;
		vn_io_error e;
		if (vn_io_read_all(path.c_str(), &raw, &have, &e) != vn_io_success)
			fail(vn_io_error_open, str("%s: %s", what.c_str(), e.message));
		out.owner = std::shared_ptr<unsigned char>((unsigned char*)raw, free);
		if (have < out.size && vn_io_refuse_lfs_pointer(raw, have, path.c_str(), &e) != vn_io_success)
			fail(vn_io_error_parse, str("%s: %s", what.c_str(), e.message));
	}
	if (have < out.size)
		fail(vn_io_error_parse, str("%s has %zu bytes, fewer than its byteLength %lld", what.c_str(), have, length));
	out.base = out.owner.get();
	return out;
}

/* JSON has one number type, and a glTF index may be written 1.0 or 1e0
 * (valid: the validator's integer_written_as_float). Such values of the
 * properties glTF defines as integers (and of extensions that reuse their
 * names) become integers, so that every stage can treat indices as the
 * integers they are. extras are the application's and stay as they are. */
static void integral(json& v)
{
	if (v.is_number_float()) {
		const double x = v.get<double>();
		if (x >= 0 && x <= 9007199254740992.0 && x == std::floor(x))
			v = (long long)x;
	} else if (v.is_array()) {
		for (json& e : v)
			if (e.is_number_float())
				integral(e);
	}
}

static void canonical_integers(json& j)
{
	static const char* const integers[] = {"buffer", "bufferView", "byteOffset", "byteLength", "byteStride", "count",
	                                       "componentType", "target", "mesh", "skin", "camera", "material", "indices",
	                                       "mode", "source", "sampler", "index", "texCoord", "node", "input", "output",
	                                       "scene", "skeleton", "inverseBindMatrices", "children", "nodes", "joints"};
	auto members = [](json& o) {
		if (o.is_object())
			for (auto& kv : o.items())
				integral(kv.value());
	};
	if (j.is_object()) {
		for (auto& kv : j.items()) {
			if (kv.key() == "extras")
				continue;
			json& v = kv.value();
			if (std::any_of(std::begin(integers), std::end(integers), [&](const char* k) { return kv.key() == k; }))
				integral(v);
			else if (kv.key() == "attributes")
				members(v); /* name -> accessor (Draco: -> unique id) */
			else if (kv.key() == "targets" && v.is_array())
				for (json& t : v)
					members(t);
			canonical_integers(v);
		}
	} else if (j.is_array()) {
		for (json& e : j)
			canonical_integers(e);
	}
}

/* An external resource's URI (not a data URI, not another scheme's URL such
 * as https://, which vn neither reads nor copies), decoded; "" otherwise. */
std::string file_uri(const json& o)
{
	auto it = o.find("uri");
	if (it == o.end() || !it->is_string() || is_data_uri(it->get_ref<const std::string&>()))
		return "";
	const std::string& uri = it->get_ref<const std::string&>();
	const size_t colon = uri.find(':'), slash = uri.find('/');
	if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
		return ""; /* a scheme */
	return uri_decode(uri);
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

	if (vn_io_refuse_lfs_pointer(raw, size, path.c_str(), &e) != vn_io_success)
		fail_named(vn_io_error_parse, e.message);
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
		if (le32(u + 8) > size)
			fail(vn_io_error_parse, str("truncated GLB: the header says %u bytes, the file has %zu", le32(u + 8), size));
		if (le32(u + 8) < size) {
			/* The validator's GLB_EXTRA_DATA: a warning, and readers stop where the header says. */
			d.warnings.push_back(str("the GLB header says %u bytes, the file has %zu: the %zu bytes after them are "
			                         "ignored, and not written", le32(u + 8), size, size - le32(u + 8)));
			size = le32(u + 8);
			if (size < 20)
				fail(vn_io_error_parse, str("truncated GLB: the header says %zu bytes, less than a header and a chunk header", size));
		}
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
	} catch (const json::out_of_range& x) {
		/* 1e309: JSON's grammar, but no double (JavaScript reads Infinity,
		 * which the validator then reports as out of range). */
		const std::string why = x.what();
		const size_t quote = why.find('\'');
		fail(vn_io_error_parse, str("the glTF JSON has a number beyond the range of a double%s%s: glTF's numbers are finite",
		                            quote == std::string::npos ? "" : ", ",
		                            quote == std::string::npos ? "" : why.c_str() + quote));
	} catch (const json::exception& x) {
		fail(vn_io_error_parse, std::string("the glTF JSON is malformed: ") + x.what());
	}
	if (!d.j.is_object())
		fail(vn_io_error_parse, "invalid JSON: the document is not an object");
	canonical_integers(d.j);
	/* glTF 1.0 has asset.version "1.0" (early files the number 1, or none)
	 * and keeps its buffers, meshes and accessors in objects, not arrays. */
	auto asset = d.j.find("asset");
	const json* version = asset != d.j.end() && asset->is_object() && asset->contains("version") ? &(*asset)["version"] : nullptr;
	auto jb = d.j.find("buffers");
	if ((version && version->is_string() && version->get<std::string>().rfind("1.", 0) == 0) ||
	    (version && version->is_number() && version->get<double>() < 2) ||
	    (!version && jb != d.j.end() && jb->is_object()))
		fail(vn_io_error_unsupported, "glTF 1.0 (vn reads glTF 2.0): convert it first, e.g. with gltf-pipeline "
		                              "(npm): gltf-pipeline -i IN -o OUT");
	if (jb != d.j.end() && !jb->is_array())
		fail(vn_io_error_parse, "buffers is not an array");
	for (size_t i = 0; jb != d.j.end() && i < jb->size(); ++i)
		d.buffers.push_back(load_buffer(d, i, file, bin, bin_length));
	auto views = d.j.find("bufferViews");
	d.input_views = views != d.j.end() && views->is_array() ? views->size() : 0;
	/* Views past their buffer's end (read lazily: an error only when read). */
	size_t past = 0, first = 0, first_buffer = 0, furthest = 0;
	for (size_t v = 0; v < d.input_views; ++v) {
		const json& view = (*views)[v];
		if (!view.is_object())
			continue;
		const long long b = index_or_none(view, "buffer"), length = index_or_none(view, "byteLength");
		const long long begin = view.contains("byteOffset") ? index_or_none(view, "byteOffset") : 0;
		if (b < 0 || (size_t)b >= d.buffers.size() || d.buffers[(size_t)b].absent || begin < 0 || length < 0 ||
		    begin > PTRDIFF_MAX - length)
			continue;
		buffer& to = d.buffers[(size_t)b];
		const size_t end = (size_t)(begin + length);
		if (end > to.size) {
			if (!past++)
				first = v, first_buffer = (size_t)b, furthest = end;
			to.reserved = std::max(to.reserved, end);
		}
	}
	if (past) {
		const size_t b = first_buffer;
		d.warnings.push_back(str("bufferViews[%zu] ends at byte %zu, past the end of buffers[%zu] (%zu bytes)%s: an "
		                         "invalid file (the validator's BUFFER_VIEW_TOO_LONG); views that fit are read, and "
		                         "new data goes after byte %zu, zeros before it",
		                         first, furthest, b, d.buffers[b].size,
		                         past > 1 ? str(", and %zu more views end past their buffer's", past - 1).c_str() : "",
		                         d.buffers[b].reserved));
	}
	/* An image whose file is not there (a .gltf fetched without its
	 * textures) stays referred to by its URI: vn does not read images, and
	 * refusing would leave the normals unfixed for want of a texture. */
	auto images = d.j.find("images");
	for (size_t i = 0; images != d.j.end() && images->is_array() && i < images->size(); ++i) {
		const std::string name = (*images)[i].is_object() ? file_uri((*images)[i]) : "";
		if (name.empty())
			continue;
		if (FILE* f = fopen((d.folder + name).c_str(), "rb"))
			fclose(f);
		else
			d.missing_images.insert(i);
	}
	if (!d.missing_images.empty()) {
		const size_t i = *d.missing_images.begin();
		d.warnings.push_back(str("images[%zu] ('%s') cannot be read beside the input%s: the output refers to %s by URI, "
		                         "as the input does", i, file_uri((*images)[i]).c_str(),
		                         d.missing_images.size() > 1 ? str(", nor %zu more images", d.missing_images.size() - 1).c_str() : "",
		                         d.missing_images.size() > 1 ? "them" : "it"));
	}
	return d;
}

std::string warning_lines(const document& d)
{
	std::string text;
	for (const std::string& w : d.warnings)
		text += (text.empty() ? "" : "\n") + w;
	return text;
}

/* ------------------------------------------------------------------ appending */

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

size_t append_bytes(document& d, size_t b, bytes data)
{
	buffer& to = d.buffers[b];
	const size_t offset = (to.tail_size() + 3) / 4 * 4;
	to.tail.emplace_back(offset, std::move(data));
	d.j["buffers"][b]["byteLength"] = to.total();
	return to.tail_start() + offset;
}

/* Appends data as a new bufferView at the end of the last buffer (in a
 * GLB, the BIN chunk) and returns its index. stride, target: 0 for none. */
size_t append_view(document& d, bytes data, size_t stride, int target)
{
	/* The last buffer with data, but in a GLB the BIN chunk's (buffer 0
	 * without uri); a new one when there is none. */
	size_t b = d.buffers.size();
	while (b > 0 && d.buffers[b - 1].absent)
		--b;
	if (b == 0) {
		if (!d.j.contains("buffers"))
			d.j["buffers"] = json::array();
		d.j["buffers"].push_back(json{{"byteLength", 0}});
		d.buffers.emplace_back();
		b = d.buffers.size();
	}
	--b;
	if (d.glb && !d.buffers[0].absent && !d.j["buffers"][0].contains("uri"))
		b = 0;
	const size_t length = data.size(), offset = append_bytes(d, b, std::move(data));
	if (!d.j.contains("bufferViews"))
		d.j["bufferViews"] = json::array();
	json view = {{"buffer", b}, {"byteOffset", offset}, {"byteLength", length}};
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

json with_indices_label(const document& d, const json& prim, json a)
{
	const auto at = prim.find("indices");
	if (at == prim.end() || !at->is_number_integer() || !d.j.contains("accessors"))
		return a;
	const long long old = at->get<long long>();
	const json& accessors = d.j["accessors"];
	if (old < 0 || (size_t)old >= accessors.size() || !accessors[(size_t)old].is_object())
		return a;
	for (const char* key : {"name", "extras"})
		if (accessors[(size_t)old].contains(key))
			a[key] = accessors[(size_t)old][key];
	return a;
}

vn_io_result to_error(const failure& f, const char* path, vn_io_error* error)
{
	if (f.names_file)
		return vn_io_fail(error, f.result, "%s", f.msg.c_str());
	return vn_io_fail(error, f.result, "%s: %s", path, f.msg.c_str());
}

} // namespace vn_gltf
