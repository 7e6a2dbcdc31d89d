/*
 * glTF 2.0 reading and writing: the C++ glue behind gltf.h.
 *
 * tinygltf only LOADS (it checks the document and resolves the buffers:
 * GLB BIN chunk, data URIs, external .bin files). Everything else works on
 * the original JSON, kept as an nlohmann::ordered_json so that key order,
 * extras and unknown extensions survive, and on copies of the buffers in
 * which only NORMAL bytes change.
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
	case 5125: { uint32_t v; memcpy(&v, p, 4); return v; }
	default: { float v; memcpy(&v, p, 4); return v; }
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
	bool ok = d.glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, u, (unsigned)size, d.folder)
	                : loader.LoadASCIIFromString(&model, &err, &warn, file.data(), (unsigned)size, d.folder);
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

/* ------------------------------------------------------------------ normals */

struct primitive {
	size_t mesh, index;
	long long position, normal = -1;
	bool tangent = false;
	std::vector<double> positions;  /* 3 per vertex */
	std::vector<uint32_t> triangles; /* 3 per triangle */
	std::vector<double> input_normals; /* empty, or 3 per vertex */
	std::vector<float> normals;     /* result, 3 per vertex */
	size_t vertices() const { return positions.size() / 3; }
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
			if (prim.contains("extensions") && prim["extensions"].is_object() &&
			    prim["extensions"].contains("KHR_draco_mesh_compression"))
				fail(vn_io_error_unsupported, what + " is Draco-compressed (KHR_draco_mesh_compression), "
				                                     "which vn does not read yet");
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

/* Normals of a group of primitives computed together (one primitive, or a
 * whole mesh): welded, computed, copied back to every split vertex. */
void compute_group(std::vector<primitive*>& group, const vn_gltf_options& o, vn_gltf_stats& st)
{
	std::vector<double> positions;
	std::vector<uint32_t> triangles;
	for (primitive* p : group) {
		const uint32_t base = (uint32_t)(positions.size() / 3);
		if (positions.size() / 3 + p->vertices() > UINT32_MAX)
			fail(vn_io_error_unsupported, "a mesh has more than 2^32 vertices");
		positions.insert(positions.end(), p->positions.begin(), p->positions.end());
		for (uint32_t v : p->triangles)
			triangles.push_back(base + v);
	}
	const size_t n = positions.size() / 3;
	vn_options options;
	memset(&options, 0, sizeof options);
	options.threads = o.threads;
	const vn_positions pos = {positions.data(), n, 0, vn_scalar_float64};
	std::vector<uint32_t> remap(n);
	for (size_t i = 0; i < n; ++i)
		remap[i] = (uint32_t)i;
	if (!o.no_weld) {
		check(vn_weld_positions(remap.data(), &pos, o.weld_epsilon, &options));
		for (size_t i = 0; i < n; ++i)
			st.welded_vertices += remap[i] != i;
		for (uint32_t& v : triangles)
			v = remap[v];
	}
	std::vector<double> normals(3 * n);
	const vn_vectors out = {normals.data(), 0, vn_scalar_float64};
	vn_stats s;
	check(vn_triangle_normals(&out, &pos, triangles.data(), triangles.size(), o.method, &options, &s));

	size_t at = 0;
	for (primitive* p : group) {
		p->normals.resize(3 * p->vertices());
		for (size_t i = 0; i < p->vertices(); ++i) {
			const double* v = &normals[3 * remap[at + i]];
			double x = v[0], y = v[1], z = v[2];
			if (x == 0 && y == 0 && z == 0) {
				/* No face contributed: the input's unit normal, else +Z. */
				++st.zero_normals;
				z = 1;
				if (!p->input_normals.empty()) {
					const double* w = &p->input_normals[3 * i];
					double l = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
					if (std::isfinite(l) && std::fabs(l - 1) < 1e-3)
						x = w[0] / l, y = w[1] / l, z = w[2] / l;
				}
			}
			p->normals[3 * i] = (float)x;
			p->normals[3 * i + 1] = (float)y;
			p->normals[3 * i + 2] = (float)z;
		}
		at += p->vertices();
		st.vertices += p->vertices();
		st.triangles += p->triangles.size() / 3;
		++st.primitives;
		st.tangent_primitives += p->tangent;
	}
}

json& mesh_primitive(document& d, const primitive& p)
{
	return d.j["meshes"][p.mesh]["primitives"][p.index];
}

/* Appends a float32 VEC3 accessor holding p's normals and points p at it. */
void append_normals(document& d, const primitive& p, vn_gltf_stats& st)
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
	const size_t length = p.normals.size() * sizeof(float);
	buffer.resize(offset + length);
	memcpy(buffer.data() + offset, p.normals.data(), length);
	d.j["buffers"][b]["byteLength"] = buffer.size();
	if (!d.j.contains("bufferViews"))
		d.j["bufferViews"] = json::array();
	if (!d.j.contains("accessors"))
		d.j["accessors"] = json::array();
	d.j["bufferViews"].push_back(json{{"buffer", b}, {"byteOffset", offset}, {"byteLength", length}, {"target", 34962}});
	d.j["accessors"].push_back(json{{"bufferView", d.j["bufferViews"].size() - 1},
	                                {"componentType", 5126},
	                                {"count", p.vertices()},
	                                {"type", "VEC3"}});
	mesh_primitive(d, p)["attributes"]["NORMAL"] = d.j["accessors"].size() - 1;
	++st.appended_accessors;
}

/* Writes p's normals over accessor a (float32, or normalized byte/short),
 * and its min/max when it has them. */
void overwrite_normals(document& d, long long index, const accessor& a, const primitive& p)
{
	std::vector<double> lo(3, INFINITY), hi(3, -INFINITY);
	for (size_t i = 0; i < p.vertices(); ++i) {
		unsigned char* e = d.buffers[(size_t)a.data.buffer].data() + a.data.offset + i * a.data.stride;
		for (size_t c = 0; c < 3; ++c) {
			double v = p.normals[3 * i + c], stored;
			if (a.component == 5126) {
				float f = p.normals[3 * i + c];
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

void write_normals(document& d, std::vector<primitive>& prims, vn_gltf_stats& st)
{
	std::map<long long, const primitive*> written;
	for (primitive& p : prims) {
		bool in_place = false;
		accessor a;
		if (p.normal >= 0) {
			a = get_accessor(d, p.normal);
			in_place = a.data.buffer >= 0 && a.sparse_count == 0 &&
			           (a.component == 5126 || (a.normalized && (a.component == 5120 || a.component == 5122)));
		}
		if (in_place) {
			auto it = written.find(p.normal);
			if (it == written.end()) {
				overwrite_normals(d, p.normal, a, p);
				written[p.normal] = &p;
				continue;
			}
			if (it->second->normals == p.normals)
				continue; /* shared, and the same result */
		}
		append_normals(d, p, st);
	}
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
		write_normals(d, prims, st);
		if (options->drop_tangents)
			for (const primitive& p : prims)
				if (p.tangent) {
					/* Morph targets may not displace an attribute the base lacks. */
					json& prim = mesh_primitive(d, p);
					prim["attributes"].erase("TANGENT");
					if (prim.contains("targets") && prim["targets"].is_array())
						for (json& target : prim["targets"])
							if (target.is_object())
								target.erase("TANGENT");
				}
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

extern "C" vn_io_result vn_io_gltf_write(FILE* out, const char* path, const vn_io_mesh* mesh, vn_io_error* error)
{
	return write_stream(out, path, mesh, false, error);
}

extern "C" vn_io_result vn_io_glb_write(FILE* out, const char* path, const vn_io_mesh* mesh, vn_io_error* error)
{
	return write_stream(out, path, mesh, true, error);
}
