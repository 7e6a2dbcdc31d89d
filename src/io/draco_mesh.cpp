/*
 * Draco and vn_io_mesh (draco.h), on the bitstream in draco.cpp: a mesh
 * as Draco attributes and back (the "drc" format: vn_drc_read_file,
 * vn_io_drc_read, vn_io_drc_write), .drc to .drc keeping everything but
 * NORMAL (vn_drc_convert), and the angle normal quantization adds
 * (vn_drc_normal_error_of, vn_drc_triangle_normal_error).
 */
#include "draco.h"
#include "draco_internal.h"

#include <draco/metadata/geometry_metadata.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <new>
#include <string>
#include <vector>

namespace vn_drc {
namespace {

/* A vn_drc_geometry over arrays this object owns. */
struct geometry_builder {
	vn_drc_geometry g{};
	std::vector<uint32_t> indices;
	std::vector<uint32_t> kept; /* the mesh vertex of each point; empty: point i is vertex i */
	std::vector<vn_drc_attribute> attributes;
	std::vector<std::vector<char>> storage;
	std::unique_ptr<draco::GeometryMetadata> metadata;

	void add_bytes(int semantic, int type, int components, int normalized, int bits, std::vector<char> bytes)
	{
		storage.push_back(std::move(bytes));
		vn_drc_attribute a{};
		a.unique_id = uint32_t(attributes.size());
		a.semantic = semantic;
		a.component_type = type;
		a.components = components;
		a.normalized = normalized;
		a.quantization_bits = bits;
		a.data = storage.back().data();
		attributes.push_back(a);
	}

	template <typename T>
	void add(int semantic, int type, int components, int normalized, int bits, const std::vector<T>& values)
	{
		add_bytes(semantic, type, components, normalized, bits,
		          std::vector<char>(reinterpret_cast<const char*>(values.data()),
		                            reinterpret_cast<const char*>(values.data() + values.size())));
	}

	const vn_drc_geometry* get()
	{
		g.indices = indices.data();
		g.triangle_count = indices.size() / 3;
		for (size_t i = 0; i < attributes.size(); ++i)
			attributes[i].data = storage[i].data();
		g.attributes = attributes.data();
		g.attribute_count = attributes.size();
		g.metadata = metadata.get();
		return &g;
	}
};

} // namespace

/* The mesh as Draco attributes: positions, normals, texcoords, colours (bytes
 * when the source had bytes: lossless), then every attribute of
 * mesh->attributes (TEXCOORD_n and COLOR_n as TEX_COORD and COLOR, floats
 * quantized with the texcoord and colour bits; the others GENERIC, named in
 * their attribute metadata as "name" without the leading underscore, and
 * lossless, as are integers), polygons fan-triangulated. Draco's decoders
 * refuse more points than 3 per triangle, so a mesh with that many keeps
 * only the vertices faces use (in their order; b->kept lists them). A mesh
 * without faces is a point cloud: every vertex, and normals only where some
 * is not zero (vn computes none for it, and Draco would decode a zero
 * normal as (1, 0, 0)). */
static void build(const vn_io_mesh* mesh, const vn_drc_options& o, geometry_builder* b)
{
	const size_t n = mesh->vertex_count;
	b->g.point_cloud = mesh->face_count == 0;
	for (size_t f = 0; f < mesh->face_count; ++f)
		for (uint32_t c = mesh->face_offsets[f] + 2; c < mesh->face_offsets[f + 1]; ++c)
			b->indices.insert(b->indices.end(),
			                  {mesh->indices[mesh->face_offsets[f]], mesh->indices[c - 1], mesh->indices[c]});
	if (!b->g.point_cloud && n > b->indices.size()) {
		std::vector<uint32_t> to(n, UINT32_MAX);
		for (uint32_t v : b->indices)
			to[v] = 0;
		for (size_t v = 0; v < n; ++v)
			if (to[v] == 0)
				to[v] = uint32_t(b->kept.size()), b->kept.push_back(uint32_t(v));
		for (uint32_t& v : b->indices)
			v = to[v];
	}
	b->g.point_count = b->kept.empty() ? n : b->kept.size();
	/* k values per written vertex, as floats. */
	auto rows = [&](const auto* values, size_t k) {
		std::vector<float> out;
		out.reserve(k * b->g.point_count);
		for (size_t i = 0; i < b->g.point_count; ++i) {
			const size_t v = b->kept.empty() ? i : b->kept[i];
			out.insert(out.end(), values + k * v, values + k * v + k);
		}
		return out;
	};
	b->add(vn_drc_position, vn_drc_float32, 3, 0, o.position_bits, rows(mesh->positions, 3));
	if (mesh->normals && (!b->g.point_cloud || std::any_of(mesh->normals, mesh->normals + 3 * n,
	                                                         [](double x) { return x != 0.0; })))
		b->add(vn_drc_normal, vn_drc_float32, 3, 0, o.normal_bits, rows(mesh->normals, 3));
	if (mesh->texcoords)
		b->add(vn_drc_texcoord, vn_drc_float32, 2, 0, o.texcoord_bits, rows(mesh->texcoords, 2));
	if (mesh->colors && mesh->colors_are_bytes) {
		const std::vector<float> colors = rows(mesh->colors, 4);
		std::vector<uint8_t> bytes(colors.size());
		for (size_t i = 0; i < bytes.size(); ++i)
			bytes[i] = uint8_t(std::lround(std::clamp(colors[i], 0.0f, 1.0f) * 255));
		b->add(vn_drc_color, vn_drc_uint8, 4, 1, 0, bytes);
	} else if (mesh->colors) {
		b->add(vn_drc_color, vn_drc_float32, 4, 0, o.color_bits, rows(mesh->colors, 4));
	}
	for (size_t i = 0; i < mesh->attribute_count; ++i) {
		const vn_io_attribute& a = mesh->attributes[i];
		const size_t size = vn_io_component_size(a.component_type) * size_t(a.components);
		if (!size || a.components < 1 || a.components > 4 || !a.data)
			continue;
		std::vector<char> bytes(size * b->g.point_count);
		for (size_t p = 0; p < b->g.point_count; ++p)
			std::memcpy(&bytes[size * p], static_cast<const char*>(a.data) + size * (b->kept.empty() ? p : b->kept[p]),
			            size);
		const bool real = a.component_type == vn_drc_float32;
		const int semantic = a.semantic == vn_io_semantic_texcoord ? vn_drc_texcoord
		                     : a.semantic == vn_io_semantic_color  ? vn_drc_color
		                                                           : vn_drc_generic;
		const int bits = !real ? 0 : semantic == vn_drc_texcoord ? o.texcoord_bits : semantic == vn_drc_color ? o.color_bits : 0;
		b->add_bytes(semantic, a.component_type, a.components, a.normalized != 0, bits, std::move(bytes));
		if (semantic == vn_drc_generic && a.name[0] == '_' && a.name[1]) {
			if (!b->metadata)
				b->metadata.reset(new draco::GeometryMetadata());
			std::unique_ptr<draco::AttributeMetadata> m(new draco::AttributeMetadata());
			m->set_att_unique_id(b->attributes.back().unique_id);
			m->AddEntryString("name", a.name + 1);
			b->metadata->AddAttributeMetadata(std::move(m));
		}
	}
}

/* Integer colours scaled to [0, 1]; 0 for a type colours do not come in. */
static double color_scale(int type)
{
	switch (type) {
	case vn_drc_uint8: return 1.0 / 255;
	case vn_drc_uint16: return 1.0 / 65535;
	case vn_drc_float32: return 1;
	default: return 0;
	}
}

/* The largest value of a signed integer component type; 0 for the others. */
static double signed_max(int type)
{
	switch (type) {
	case vn_drc_int8: return 127;
	case vn_drc_int16: return 32767;
	case vn_drc_int32: return 2147483647;
	default: return 0;
	}
}

/* A NORMAL vn reads as the input's normals: 3 float components (float32 or
 * float64), or 3 signed integer ones (quantized normals, as glTF's
 * KHR_mesh_quantization and gltfpack store them). Any other NORMAL is kept
 * as an attribute. */
static bool readable_normal(const vn_drc_attribute* a)
{
	return a && a->components == 3 &&
	       (a->component_type == vn_drc_float32 || a->component_type == vn_drc_float64 ||
	        signed_max(a->component_type) > 0);
}

/* The n normals of a readable_normal() attribute into out (3 per point):
 * floats as decoded; integers as the unit vector they stand for (a
 * normalized type's minimum read as -1, as glTF reads it; (0, 0, 0) stays). */
template <typename T>
static void read_normals(const vn_drc_attribute& a, size_t n, T* out)
{
	const double limit = signed_max(a.component_type);
	for (size_t i = 0; i < n; ++i) {
		double v[3];
		for (int k = 0; k < 3; ++k)
			v[k] = a.normalized && limit > 0 ? std::max(component(a, 3 * i + k), -limit) : component(a, 3 * i + k);
		const double len = limit > 0 ? std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) : 1;
		for (int k = 0; k < 3; ++k)
			out[3 * i + k] = T(len > 0 ? v[k] / len : 0);
	}
}

static const vn_drc_attribute* first(const vn_drc_geometry& g, int s)
{
	for (size_t i = 0; i < g.attribute_count; ++i)
		if (g.attributes[i].semantic == s)
			return &g.attributes[i];
	return nullptr;
}

/* The n * components values of a into a new array, as they are (integers
 * too: a standalone stream's integer POSITION is in its own units). */
template <typename T>
static bool copy_values(const vn_drc_attribute* a, int components, size_t n, T** out)
{
	*out = static_cast<T*>(std::malloc(sizeof(T) * components * n + 1));
	if (!*out)
		return false;
	for (size_t i = 0; i < components * n; ++i)
		(*out)[i] = T(component(*a, i));
	return true;
}

/* POSITION as vn reads it: 3 components of any type (float32, or integers
 * as quantizing tools such as gltfpack store them). */
static bool readable_position(const vn_drc_attribute* a)
{
	return a && a->components == 3;
}

/* What glTF can hold as TEXCOORD_n (2 floats, or normalized unsigned
 * bytes or shorts) and COLOR_n (3 or 4 of those). */
static bool gltf_texcoord(const vn_drc_attribute& a)
{
	return a.components == 2 && (a.component_type == vn_drc_float32 ||
	                             (a.normalized && (a.component_type == vn_drc_uint8 || a.component_type == vn_drc_uint16)));
}

static bool gltf_color(const vn_drc_attribute& a)
{
	return (a.components == 3 || a.components == 4) &&
	       (a.component_type == vn_drc_float32 ||
	        (a.normalized && (a.component_type == vn_drc_uint8 || a.component_type == vn_drc_uint16)));
}

/* "_" and the attribute's metadata "name" in upper case, characters other
 * than letters, digits and '_' as '_'; without a name "_GENERIC_<unique id>"
 * (or the Draco type's name). */
static std::string application_name(const vn_drc_geometry& g, const vn_drc_attribute& a)
{
	std::string given;
	if (const auto* metadata = static_cast<const draco::GeometryMetadata*>(g.metadata))
		if (const draco::AttributeMetadata* m = metadata->GetAttributeMetadataByUniqueId(int32_t(a.unique_id)))
			m->GetEntryString("name", &given);
	std::string name = "_";
	for (char c : given)
		name += std::isalnum(static_cast<unsigned char>(c)) ? char(std::toupper(static_cast<unsigned char>(c))) : '_';
	if (name.size() == 1)
		name += std::string(semantic_names[a.semantic]) + "_" + std::to_string(a.unique_id);
	return name.substr(0, sizeof(vn_io_attribute{}.name) - 1);
}

/* Decoded geometry into a vn_io_mesh; records the bits found in *found. */
static vn_io_result to_mesh(const vn_drc_geometry& g, const char* name, vn_io_mesh* mesh, vn_drc_options* found,
                            vn_io_error* error)
{
	const vn_drc_attribute* position = first(g, vn_drc_position);
	const vn_drc_attribute* normal = first(g, vn_drc_normal);
	const vn_drc_attribute* color = nullptr;
	const vn_drc_attribute* texcoord = nullptr;
	for (size_t i = 0; i < g.attribute_count; ++i) {
		const vn_drc_attribute& a = g.attributes[i];
		if (!texcoord && a.semantic == vn_drc_texcoord && a.components == 2 && a.component_type == vn_drc_float32)
			texcoord = &a;
		if (!color && a.semantic == vn_drc_color && a.components >= 3 && color_scale(a.component_type))
			color = &a;
	}
	if (!readable_position(position))
		return vn_io_fail(error, vn_io_error_unsupported, "%s: no 3-component POSITION", name);
	if (!readable_normal(normal))
		normal = nullptr; /* kept as an attribute below */

	const size_t n = g.point_count;
	mesh->vertex_count = n;
	mesh->face_count = g.triangle_count;
	mesh->face_offsets = static_cast<uint32_t*>(std::malloc(sizeof(uint32_t) * (g.triangle_count + 1)));
	mesh->indices = static_cast<uint32_t*>(std::malloc(sizeof(uint32_t) * 3 * g.triangle_count + 1));
	if (!mesh->face_offsets || !mesh->indices || !copy_values(position, 3, n, &mesh->positions) ||
	    (normal && !(mesh->normals = static_cast<double*>(std::malloc(sizeof(double) * 3 * n + 1)))) ||
	    (texcoord && !copy_values(texcoord, 2, n, &mesh->texcoords)) ||
	    (color && !(mesh->colors = static_cast<float*>(std::malloc(sizeof(float) * 4 * n + 1)))))
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	std::memcpy(mesh->indices, g.indices, sizeof(uint32_t) * 3 * g.triangle_count);
	if (normal)
		read_normals(*normal, n, mesh->normals);
	for (size_t f = 0; f <= g.triangle_count; ++f)
		mesh->face_offsets[f] = uint32_t(3 * f);
	if (color) {
		const double scale = color_scale(color->component_type);
		for (size_t i = 0; i < n; ++i)
			for (int k = 0; k < 4; ++k)
				mesh->colors[4 * i + k] =
				    k < color->components ? float(component(*color, color->components * i + k) * scale) : 1.0f;
		mesh->colors_are_bytes = color->component_type == vn_drc_uint8 || vn_io_colors_are_bytes(mesh->colors, n);
	}
	/* Every other attribute: TEXCOORD_n and COLOR_n numbered after the
	 * ones above, the rest application-specific ("_NAME"). */
	int texcoords = texcoord ? 1 : 0, colors = color ? 1 : 0;
	for (size_t i = 0; i < g.attribute_count; ++i) {
		const vn_drc_attribute& a = g.attributes[i];
		if (&a == position || &a == normal || &a == texcoord || &a == color)
			continue;
		std::string label;
		int semantic = vn_io_semantic_generic;
		if (a.semantic == vn_drc_texcoord && gltf_texcoord(a))
			label = "TEXCOORD_" + std::to_string(texcoords++), semantic = vn_io_semantic_texcoord;
		else if (a.semantic == vn_drc_color && gltf_color(a))
			label = "COLOR_" + std::to_string(colors++), semantic = vn_io_semantic_color;
		else
			label = application_name(g, a);
		for (size_t j = 0; j < mesh->attribute_count; ++j)
			if (label == mesh->attributes[j].name)
				label = label.substr(0, sizeof(vn_io_attribute{}.name) - 12) + "_" + std::to_string(a.unique_id);
		vn_io_attribute* out =
		    vn_io_mesh_add_attribute(mesh, label.c_str(), semantic, a.component_type, a.components, a.normalized);
		if (!out)
			return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
		std::memcpy(out->data, a.data, value_bytes(a) * n);
	}
	if (found) {
		const struct {
			const vn_drc_attribute* a;
			int* bits;
		} fields[] = {{position, &found->position_bits},
		              {normal, &found->normal_bits},
		              {texcoord, &found->texcoord_bits},
		              {color, &found->color_bits}};
		for (const auto& f : fields)
			if (f.a && f.a->quantization_bits > 0)
				*f.bits = f.a->quantization_bits;
	}
	return vn_io_success;
}

namespace {

/* Owns a decoded geometry. */
struct decoded_geometry {
	vn_drc_geometry g{};
	decoded_geometry() = default;
	decoded_geometry(const decoded_geometry&) = delete;
	decoded_geometry& operator=(const decoded_geometry&) = delete;
	~decoded_geometry() { vn_drc_geometry_free(&g); }
};

} // namespace

static double now()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/* vn_io_write_file's writer for bytes encoded beforehand (its settings). */
static vn_io_result write_bytes(FILE* out, const char* path, const vn_io_mesh*, const void* settings, vn_io_error* error)
{
	const auto& bytes = *static_cast<const std::vector<char>*>(settings);
	if (std::fwrite(bytes.data(), 1, bytes.size(), out) != bytes.size())
		return vn_io_fail(error, vn_io_error_write, "%s: cannot write", path);
	return vn_io_success;
}

static vn_io_result convert(const char* in, const char* out, const vn_drc_convert_options& o, vn_drc_convert_stats& st,
                            vn_io_error* error)
{
	const double t0 = now();
	decoded_geometry d;
	{
		char* data;
		size_t size;
		vn_io_result r = vn_io_read_all(in, &data, &size, error);
		if (r != vn_io_success)
			return r;
		r = vn_drc_decode_any(data, size, in, &d.g, error);
		std::free(data);
		if (r != vn_io_success)
			return r;
	}
	const vn_drc_geometry& g = d.g;
	const vn_drc_attribute* position = first(g, vn_drc_position);
	if (!readable_position(position))
		return vn_io_fail(error, vn_io_error_unsupported, "%s: no 3-component POSITION", in);
	const bool real = position->component_type == vn_drc_float32 || position->component_type == vn_drc_float64;
	vn_positions positions = {position->data, g.point_count, 0,
	                          position->component_type == vn_drc_float64 ? vn_scalar_float64 : vn_scalar_float32};
	std::vector<double> integral; /* an integer POSITION as doubles */
	if (!real) {
		integral.resize(3 * g.point_count);
		for (size_t i = 0; i < integral.size(); ++i)
			integral[i] = component(*position, i);
		positions = {integral.data(), g.point_count, 0, vn_scalar_float64};
	}
	for (size_t i = 0; real && i < g.point_count; ++i) {
		const double x = component(*position, 3 * i), y = component(*position, 3 * i + 1),
		             z = component(*position, 3 * i + 2);
		if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
			return vn_io_fail(error, vn_io_error_unsupported,
			                  "%s: point %zu has a non-finite position (%g, %g, %g), which no output can hold", in, i, x,
			                  y, z);
	}
	const double t1 = now();

	/* A point no face gives a normal keeps the input's (keep_existing): a
	 * float normal as decoded (re-encoded on the same bits it decodes the
	 * same), an integer one as the unit vector it stands for. */
	std::vector<float> normals(g.point_cloud ? 0 : 3 * g.point_count + 3); /* a point cloud's are kept as they are */
	const vn_drc_attribute* input_normal = first(g, vn_drc_normal);
	st.input_normals = readable_normal(input_normal);
	st.point_cloud = g.point_cloud;
	if (st.input_normals && !g.point_cloud)
		read_normals(*input_normal, g.point_count, normals.data());
	const vn_vectors vectors = {normals.data(), 0, vn_scalar_float32};
	vn_options vo;
	std::memset(&vo, 0, sizeof vo);
	vo.threads = o.threads;
	vo.keep_existing = st.input_normals;
	const vn_result vr = g.point_cloud ? vn_result_success
	                                   : vn_triangle_normals(&vectors, &positions, g.indices, 3 * g.triangle_count,
	                                                         o.method, &vo, &st.normals);
	if (vr != vn_result_success)
		return vn_io_fail(error, vr == vn_result_out_of_memory ? vn_io_error_memory : vn_io_error_unsupported,
		                  "%s: %s", in, vn_result_string(vr));
	const double t2 = now();

	/* Every attribute as decoded, NORMAL replaced (or added; a point
	 * cloud's kept), bits given for a semantic replacing the stream's. */
	vn_drc_options defaults;
	vn_drc_default_options(&defaults);
	const vn_drc_options& given = o.given;
	std::vector<vn_drc_attribute> attributes(g.attributes, g.attributes + g.attribute_count);
	vn_drc_attribute* normal = nullptr;
	for (vn_drc_attribute& a : attributes)
		if (a.semantic == vn_drc_normal) {
			normal = &a;
			break;
		}
	if (!normal && !g.point_cloud) {
		vn_drc_attribute a{};
		for (const vn_drc_attribute& b : attributes)
			a.unique_id = std::max(a.unique_id, b.unique_id + 1);
		a.semantic = vn_drc_normal;
		attributes.push_back(a);
		normal = &attributes.back();
	}
	const int normal_bits = given.normal_bits >= 0 ? given.normal_bits
	                        : normal && normal->component_type == vn_drc_float32 && normal->quantization_bits > 0
	                            ? normal->quantization_bits
	                            : defaults.normal_bits;
	if (!g.point_cloud) {
		normal->component_type = vn_drc_float32;
		normal->components = 3;
		normal->normalized = 0;
		normal->quantization_bits = normal_bits;
		normal->grid = vn_drc_grid{};
		normal->data = normals.data();
	}
	for (vn_drc_attribute& a : attributes) {
		const int bits = vn_drc_given_bits(&given, a.semantic, a.component_type);
		if (bits >= 0)
			a.quantization_bits = bits;
	}
	st.points = g.point_count;
	st.triangles = g.triangle_count;
	st.attributes = attributes.size();
	st.used = defaults;
	st.used.normal_bits = normal_bits;
	st.used.compression_level = given.compression_level >= 0 ? given.compression_level : defaults.compression_level;
	const struct {
		int semantic;
		int* bits;
	} used[] = {{vn_drc_position, &st.used.position_bits},
	            {vn_drc_texcoord, &st.used.texcoord_bits},
	            {vn_drc_color, &st.used.color_bits}};
	for (const auto& u : used) {
		bool seen = false;
		for (const vn_drc_attribute& a : attributes)
			if (!seen && a.semantic == u.semantic && a.component_type == vn_drc_float32) {
				seen = true;
				if (a.quantization_bits > 0)
					*u.bits = a.quantization_bits;
			}
	}
	for (const auto& u : {std::make_pair(given.position_bits, &st.used.position_bits),
	                      std::make_pair(given.texcoord_bits, &st.used.texcoord_bits),
	                      std::make_pair(given.color_bits, &st.used.color_bits)})
		if (u.first >= 0)
			*u.second = u.first;

	vn_drc_geometry h = g;
	h.attributes = attributes.data();
	h.attribute_count = attributes.size();
	std::vector<char> bytes;
	vn_io_result r = encode(&h, st.used.compression_level, false, out, &bytes, error);
	if (r != vn_io_success)
		return r;
	vn_io_format writer{}; /* the bytes as they are, through vn_io_write_file's atomic output */
	writer.name = "drc";
	writer.write = write_bytes;
	vn_io_mesh none;
	std::memset(&none, 0, sizeof none);
	if ((r = vn_io_write_file(out, &writer, &none, &bytes, error)) != vn_io_success)
		return r;
	const double t3 = now();
	st.read_seconds = t1 - t0;
	st.normals_seconds = t2 - t1;
	st.write_seconds = t3 - t2;

	if (o.normal_error && !g.point_cloud) {
		std::vector<double> xyz(3 * g.point_count);
		for (size_t i = 0; i < xyz.size(); ++i)
			xyz[i] = component(*position, i);
		const std::vector<double> nxyz(normals.begin(), normals.begin() + 3 * g.point_count);
		if ((r = vn_drc_triangle_normal_error(xyz.data(), nxyz.data(), g.point_count, g.indices, g.triangle_count,
		                                      &st.used, out, &st.normal_error, error)) != vn_io_success)
			return r;
	}
	return vn_io_success;
}

} // namespace vn_drc

using namespace vn_drc;

extern "C" {

vn_io_result vn_drc_read_file(const char* path, vn_io_mesh* mesh, vn_drc_options* found, vn_io_error* error)
{
	std::memset(mesh, 0, sizeof *mesh);
	char* data;
	size_t size;
	vn_io_result r = vn_io_read_all(path, &data, &size, error);
	if (r != vn_io_success)
		return r;
	vn_drc_geometry g;
	r = vn_drc_decode_any(data, size, path, &g, error);
	std::free(data);
	if (r != vn_io_success)
		return r;
	try {
		r = to_mesh(g, path, mesh, found, error);
	} catch (const std::bad_alloc&) {
		r = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	}
	vn_drc_geometry_free(&g);
	if (r != vn_io_success)
		vn_io_mesh_free(mesh);
	return r;
}

vn_io_result vn_io_drc_read(const char* path, vn_io_mesh* mesh, vn_io_error* error)
{
	return vn_drc_read_file(path, mesh, nullptr, error);
}

vn_io_result vn_io_drc_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error)
{
	vn_drc_options defaults;
	vn_drc_default_options(&defaults);
	const vn_drc_options& o = settings ? *static_cast<const vn_drc_options*>(settings) : defaults;
	try {
		geometry_builder b;
		build(mesh, o, &b);
		std::vector<char> bytes;
		const vn_io_result r = encode(b.get(), o.compression_level, false, path, &bytes, error);
		if (r != vn_io_success)
			return r;
		if (std::fwrite(bytes.data(), 1, bytes.size(), out) != bytes.size())
			return vn_io_fail(error, vn_io_error_write, "%s: cannot write", path);
		return vn_io_success;
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	}
}

vn_io_result vn_drc_convert(const char* in, const char* out, const vn_drc_convert_options* options,
                            vn_drc_convert_stats* stats, vn_io_error* error)
{
	vn_drc_convert_stats ignored;
	vn_drc_convert_stats& st = stats ? *stats : ignored;
	st = vn_drc_convert_stats{};
	try {
		return convert(in, out, *options, st, error);
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", in);
	}
}

vn_io_result vn_drc_triangle_normal_error(const double* positions, const double* normals, size_t points,
                                          const uint32_t* indices, size_t triangles, const vn_drc_options* options,
                                          const char* name, vn_drc_normal_error* out, vn_io_error* error)
{
	try {
		std::vector<uint32_t> offsets(triangles + 1);
		for (size_t f = 0; f <= triangles; ++f)
			offsets[f] = uint32_t(3 * f);
		vn_io_mesh mesh;
		std::memset(&mesh, 0, sizeof mesh);
		mesh.vertex_count = points;
		mesh.positions = const_cast<double*>(positions);
		mesh.normals = const_cast<double*>(normals);
		mesh.face_count = triangles;
		mesh.face_offsets = offsets.data();
		mesh.indices = const_cast<uint32_t*>(indices);
		return vn_drc_normal_error_of(&mesh, options, name, out, error);
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	}
}

vn_io_result vn_drc_normal_error_of(const vn_io_mesh* mesh, const vn_drc_options* options, const char* name,
                                    vn_drc_normal_error* out, vn_io_error* error)
{
	*out = vn_drc_normal_error{};
	if (!mesh->normals)
		return vn_io_success;
	try {
		/* Edgebreaker renumbers points, so a GENERIC attribute carrying each
		 * vertex's index (integers: lossless) tells which vertex a decoded
		 * point is. Normal quantization is per value, so the normals come
		 * back exactly as from the file written with the same options. */
		geometry_builder b;
		build(mesh, *options, &b);
		std::vector<uint32_t> ids(b.g.point_count);
		for (size_t i = 0; i < ids.size(); ++i)
			ids[i] = b.kept.empty() ? uint32_t(i) : b.kept[i];
		b.add(vn_drc_generic, vn_drc_uint32, 1, 0, 0, ids);
		const uint32_t id_unique_id = b.attributes.back().unique_id; /* the mesh may have GENERIC ones of its own */
		std::vector<char> bytes;
		vn_io_result r = encode(b.get(), options->compression_level, false, name, &bytes, error);
		if (r != vn_io_success)
			return r;
		vn_drc_geometry g;
		/* A mesh without faces is encoded as a point cloud. */
		if ((r = vn_drc_decode_any(bytes.data(), bytes.size(), name, &g, error)) != vn_io_success)
			return r;
		const vn_drc_attribute* normal = first(g, vn_drc_normal);
		const vn_drc_attribute* id = nullptr;
		for (size_t i = 0; i < g.attribute_count; ++i)
			if (g.attributes[i].unique_id == id_unique_id)
				id = &g.attributes[i];
		std::vector<double> angles;
		for (size_t p = 0; normal && id && p < g.point_count; ++p) {
			const uint32_t v = static_cast<const uint32_t*>(id->data)[p];
			if (v >= mesh->vertex_count)
				continue;
			const double* a = mesh->normals + 3 * size_t(v);
			const float* q = static_cast<const float*>(normal->data) + 3 * p;
			const double cx = a[1] * q[2] - a[2] * q[1], cy = a[2] * q[0] - a[0] * q[2], cz = a[0] * q[1] - a[1] * q[0];
			if (a[0] != 0 || a[1] != 0 || a[2] != 0) // vn's zero normal: no direction to compare
				angles.push_back(std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), a[0] * q[0] + a[1] * q[1] + a[2] * q[2]) *
				                 (180 / std::acos(-1.0)));
		}
		vn_drc_geometry_free(&g);
		if (angles.empty())
			return vn_io_success;
		std::sort(angles.begin(), angles.end());
		const size_t m = angles.size();
		out->compared = m;
		out->median_degrees = m % 2 ? angles[m / 2] : (angles[m / 2 - 1] + angles[m / 2]) / 2;
		out->max_degrees = angles.back();
		return vn_io_success;
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	}
}

} // extern "C"
