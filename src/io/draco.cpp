/*
 * Draco (.drc) for vn_io: see draco.h. Everything goes through the plain
 * vn_drc_geometry structs, so the vn_io format and the API that glTF's
 * KHR_draco_mesh_compression (gltf.cpp) uses are the same code.
 */
#include "draco.h"

#include <draco/attributes/attribute_octahedron_transform.h>
#include <draco/attributes/attribute_quantization_transform.h>
#include <draco/compression/decode.h>
#include <draco/compression/point_cloud/point_cloud_decoder.h>
#include <draco/core/varint_decoding.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/metadata/metadata_decoder.h>
#include <draco/compression/expert_encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

namespace {

static_assert(int(vn_drc_position) == int(draco::GeometryAttribute::POSITION) &&
                  int(vn_drc_normal) == int(draco::GeometryAttribute::NORMAL) &&
                  int(vn_drc_color) == int(draco::GeometryAttribute::COLOR) &&
                  int(vn_drc_texcoord) == int(draco::GeometryAttribute::TEX_COORD) &&
                  int(vn_drc_generic) == int(draco::GeometryAttribute::GENERIC),
              "vn_drc_semantic mirrors draco::GeometryAttribute::Type");

struct type_pair {
	int gl;
	draco::DataType draco;
};
const type_pair types[] = {
    {vn_drc_int8, draco::DT_INT8},   {vn_drc_uint8, draco::DT_UINT8},   {vn_drc_int16, draco::DT_INT16},
    {vn_drc_uint16, draco::DT_UINT16}, {vn_drc_int32, draco::DT_INT32}, {vn_drc_uint32, draco::DT_UINT32},
    {vn_drc_float32, draco::DT_FLOAT32},
};

int gl_type(draco::DataType t)
{
	for (const type_pair& p : types)
		if (p.draco == t)
			return p.gl;
	return 0;
}

draco::DataType draco_type(int gl)
{
	for (const type_pair& p : types)
		if (p.gl == gl)
			return p.draco;
	return draco::DT_INVALID;
}

size_t value_bytes(const vn_drc_attribute& a)
{
	return size_t(a.components) * size_t(draco::DataTypeLength(draco_type(a.component_type)));
}

/* The bits each attribute (by unique id) was quantized with. Draco keeps the
 * transform parameters only on its portable (still quantized) attributes,
 * which a decode hands out when told to skip the inverse transform: so a
 * second decode with every transform skipped reads them back. */
std::vector<std::pair<uint32_t, int>> quantization_bits(const void* data, size_t size)
{
	std::vector<std::pair<uint32_t, int>> bits;
	draco::DecoderBuffer buffer;
	buffer.Init(static_cast<const char*>(data), size);
	draco::Decoder decoder;
	for (int t = draco::GeometryAttribute::POSITION; t < draco::GeometryAttribute::NAMED_ATTRIBUTES_COUNT; ++t)
		decoder.SetSkipAttributeTransform(static_cast<draco::GeometryAttribute::Type>(t));
	auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
	if (!decoded.ok())
		return bits;
	const draco::Mesh& mesh = *decoded.value();
	for (int i = 0; i < mesh.num_attributes(); ++i) {
		const draco::PointAttribute& a = *mesh.attribute(i);
		draco::AttributeQuantizationTransform q;
		draco::AttributeOctahedronTransform o;
		if (q.InitFromAttribute(a))
			bits.emplace_back(a.unique_id(), q.quantization_bits());
		else if (o.InitFromAttribute(a))
			bits.emplace_back(a.unique_id(), o.quantization_bits());
	}
	return bits;
}

/* libdraco sizes its connectivity tables from the counts a stream declares,
 * before it reads the data that would contradict them: a 163-byte stream
 * found by fuzzing made it allocate 4.6 GB. So the counts are read first, as
 * libdraco's mesh decoders read them for each bitstream version (fixed
 * 32-bit before 2.2, varints from 2.2; edgebreaker's vertex count varint
 * from 2.0), and a stream declaring more faces or points than max_per_byte
 * per byte of itself is refused: edgebreaker's best ratios on real meshes are
 * a few triangles per byte. Returns why a stream is refused, or an empty
 * string (also when the counts cannot be read: the decoder then says why). */
constexpr uint64_t max_per_byte = 4096;

std::string implausible(const void* data, size_t size)
{
	draco::DecoderBuffer b;
	b.Init(static_cast<const char*>(data), size);
	draco::DracoHeader h;
	if (!draco::PointCloudDecoder::DecodeHeader(&b, &h).ok())
		return "";
	const unsigned version = unsigned(h.version_major) << 8 | h.version_minor;
	if (h.flags & METADATA_FLAG_MASK) {
		draco::GeometryMetadata metadata;
		draco::MetadataDecoder reader;
		if (!reader.DecodeGeometryMetadata(&b, &metadata))
			return "";
	}
	auto count = [&](unsigned varint_from, uint32_t* out) {
		return version < varint_from ? b.Decode(out) : draco::DecodeVarint(out, &b);
	};
	uint32_t faces = 0, points = 0, new_vertices = 0;
	uint8_t traversal;
	if (h.encoder_method == draco::MESH_SEQUENTIAL_ENCODING) {
		if (!count(0x0202, &faces) || !count(0x0202, &points))
			return "";
	} else if (h.encoder_method == draco::MESH_EDGEBREAKER_ENCODING) {
		if (!b.Decode(&traversal) || (version < 0x0202 && !b.Decode(&new_vertices)) || !count(0x0200, &points) ||
		    !count(0x0202, &faces))
			return "";
	}
	if (faces > max_per_byte * size || points > max_per_byte * size)
		return "the stream declares " + std::to_string(faces) + " faces and " + std::to_string(points) +
		       " points in " + std::to_string(size) + " bytes: corrupt or hostile";
	return "";
}

vn_io_result decode(const void* data, size_t size, const char* name, vn_drc_geometry* g, vn_io_error* error)
{
	const std::string refused = implausible(data, size);
	if (!refused.empty())
		return vn_io_fail(error, vn_io_error_parse, "%s: %s", name, refused.c_str());
	draco::DecoderBuffer buffer;
	buffer.Init(static_cast<const char*>(data), size);
	auto kind = draco::Decoder::GetEncodedGeometryType(&buffer);
	if (!kind.ok())
		return vn_io_fail(error, vn_io_error_parse, "%s: not a Draco stream (%s)", name,
		                  kind.status().error_msg());
	if (kind.value() == draco::POINT_CLOUD)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: a Draco point cloud, not a mesh", name);
	if (kind.value() != draco::TRIANGULAR_MESH)
		return vn_io_fail(error, vn_io_error_parse, "%s: not a Draco mesh", name);
	draco::Decoder decoder;
	auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
	if (!decoded.ok())
		return vn_io_fail(error, vn_io_error_parse, "%s: corrupt Draco stream (%s)", name,
		                  decoded.status().error_msg());
	const draco::Mesh& mesh = *decoded.value();
	const auto bits = quantization_bits(data, size);

	g->point_count = mesh.num_points();
	g->triangle_count = mesh.num_faces();
	g->indices = static_cast<uint32_t*>(std::malloc(3 * g->triangle_count * sizeof(uint32_t) + 1));
	g->attributes =
	    static_cast<vn_drc_attribute*>(std::calloc(size_t(mesh.num_attributes()) + 1, sizeof(vn_drc_attribute)));
	if (!g->indices || !g->attributes)
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f)
		for (int k = 0; k < 3; ++k) {
			const uint32_t v = mesh.face(f)[k].value();
			if (v >= g->point_count)
				return vn_io_fail(error, vn_io_error_parse, "%s: face %u has point %u of %zu", name, f.value(), v,
				                  g->point_count);
			g->indices[3 * f.value() + k] = v;
		}
	for (int i = 0; i < mesh.num_attributes(); ++i) {
		const draco::PointAttribute& a = *mesh.attribute(i);
		vn_drc_attribute& out = g->attributes[g->attribute_count];
		out.unique_id = a.unique_id();
		out.semantic = a.attribute_type();
		out.component_type = gl_type(a.data_type());
		out.components = a.num_components();
		out.normalized = a.normalized();
		if (out.semantic < vn_drc_position || out.semantic > vn_drc_generic || !out.component_type ||
		    out.components < 1 || out.components > 4)
			return vn_io_fail(error, vn_io_error_unsupported,
			                  "%s: attribute %u has a type or size vn does not handle", name, out.unique_id);
		for (const auto& b : bits)
			if (b.first == out.unique_id)
				out.quantization_bits = b.second;
		const size_t n = value_bytes(out);
		if (a.byte_stride() < int64_t(n))
			return vn_io_fail(error, vn_io_error_parse, "%s: attribute %u is shorter than its type", name,
			                  out.unique_id);
		out.data = std::malloc(n * g->point_count + 1);
		if (!out.data)
			return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
		++g->attribute_count;
		for (draco::PointIndex p(0); p < mesh.num_points(); ++p)
			std::memcpy(static_cast<char*>(out.data) + n * p.value(), a.GetAddress(a.mapped_index(p)), n);
	}
	return vn_io_success;
}

vn_io_result encode(const vn_drc_geometry* g, int level, bool keep_order, const char* name, std::vector<char>* bytes,
                    vn_io_error* error)
{
	if (level < 0 || level > 10)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: compression level %d is not 0 to 10", name, level);
	if (g->point_count > UINT32_MAX / 2)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: too many points for Draco", name);
	/* Draco 1.5.5's decoders refuse such a stream (sequential connectivity):
	 * writing one would make a file nobody can read. */
	if (g->point_count > 3 * g->triangle_count)
		return vn_io_fail(error, vn_io_error_unsupported,
		                  "%s: %zu points and %zu triangles: Draco cannot store more points than 3 per triangle "
		                  "(remove the unused vertices)", name, g->point_count, g->triangle_count);
	draco::Mesh mesh;
	mesh.set_num_points(static_cast<uint32_t>(g->point_count));
	for (size_t t = 0; t < g->triangle_count; ++t) {
		draco::Mesh::Face face;
		for (int k = 0; k < 3; ++k) {
			const uint32_t v = g->indices[3 * t + k];
			if (v >= g->point_count)
				return vn_io_fail(error, vn_io_error_unsupported, "%s: triangle %zu has point %u of %zu", name, t,
				                  v, g->point_count);
			face[k] = draco::PointIndex(v);
		}
		mesh.AddFace(face);
	}
	std::vector<std::pair<int, int>> quantize; // Draco attribute id, bits
	for (size_t i = 0; i < g->attribute_count; ++i) {
		const vn_drc_attribute& a = g->attributes[i];
		const draco::DataType type = draco_type(a.component_type);
		if (type == draco::DT_INVALID || a.semantic < vn_drc_position || a.semantic > vn_drc_generic ||
		    a.components < 1 || a.components > 4 || a.quantization_bits < 0 || a.quantization_bits > VN_DRC_MAX_BITS)
			return vn_io_fail(error, vn_io_error_unsupported, "%s: attribute %u has a type, size or bits Draco does not take",
			                  name, a.unique_id);
		if (a.semantic == vn_drc_normal && a.quantization_bits == 1)
			return vn_io_fail(error, vn_io_error_unsupported, "%s: normals need 2 to %d quantization bits", name,
			                  VN_DRC_MAX_BITS);
		for (size_t j = 0; j < i; ++j)
			if (g->attributes[j].unique_id == a.unique_id)
				return vn_io_fail(error, vn_io_error_unsupported, "%s: two attributes have unique id %u", name,
				                  a.unique_id);
		const size_t n = value_bytes(a);
		draco::GeometryAttribute ga;
		ga.Init(static_cast<draco::GeometryAttribute::Type>(a.semantic), nullptr, uint8_t(a.components), type,
		        a.normalized != 0, int64_t(n), 0);
		const int id = mesh.AddAttribute(ga, true, static_cast<uint32_t>(g->point_count));
		draco::PointAttribute* pa = mesh.attribute(id);
		pa->set_unique_id(a.unique_id); // AddAttribute numbers them 0, 1, ...
		for (size_t p = 0; p < g->point_count; ++p)
			pa->SetAttributeValue(draco::AttributeValueIndex(uint32_t(p)), static_cast<const char*>(a.data) + n * p);
		if (type == draco::DT_FLOAT32 && a.quantization_bits > 0)
			quantize.emplace_back(id, a.quantization_bits);
	}
	/* Levels below 10 pick edgebreaker, which splits non-manifold vertices
	 * and drops degenerate triangles; the sequential method keeps every point
	 * and triangle, so it is the fallback when edgebreaker changed a count. */
	for (const bool sequential : {level == 10 || keep_order, true}) {
		draco::ExpertEncoder encoder(mesh);
		for (const auto& q : quantize)
			encoder.SetAttributeQuantization(q.first, q.second);
		encoder.SetSpeedOptions(10 - level, 10 - level);
		if (sequential)
			encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
		draco::EncoderBuffer out;
		const draco::Status status = encoder.EncodeToBuffer(&out);
		if (!status.ok())
			return vn_io_fail(error, vn_io_error_unsupported, "%s: Draco cannot encode this mesh (%s)", name,
			                  status.error_msg());
		bytes->assign(out.data(), out.data() + out.size());
		if (sequential)
			break;
		draco::DecoderBuffer check;
		check.Init(bytes->data(), bytes->size());
		auto decoded = draco::Decoder().DecodeMeshFromBuffer(&check);
		if (decoded.ok() && decoded.value()->num_points() == g->point_count &&
		    decoded.value()->num_faces() == g->triangle_count)
			break;
	}
	return vn_io_success;
}

/* A vn_drc_geometry over arrays this object owns. */
struct geometry_builder {
	vn_drc_geometry g{};
	std::vector<uint32_t> indices;
	std::vector<uint32_t> kept; /* the mesh vertex of each point; empty: point i is vertex i */
	std::vector<vn_drc_attribute> attributes;
	std::vector<std::vector<char>> storage;

	template <typename T>
	void add(int semantic, int type, int components, int normalized, int bits, std::vector<T> values)
	{
		storage.emplace_back(reinterpret_cast<const char*>(values.data()),
		                     reinterpret_cast<const char*>(values.data() + values.size()));
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

	const vn_drc_geometry* get()
	{
		g.indices = indices.data();
		g.triangle_count = indices.size() / 3;
		g.attributes = attributes.data();
		g.attribute_count = attributes.size();
		return &g;
	}
};

/* The mesh as Draco attributes: positions, normals, texcoords, colours (bytes
 * when the source had bytes: lossless), polygons fan-triangulated. Draco's
 * decoders refuse more points than 3 per triangle, so a mesh with that many
 * keeps only the vertices faces use (in their order; b->kept lists them). */
void build(const vn_io_mesh* mesh, const vn_drc_options& o, geometry_builder* b)
{
	const size_t n = mesh->vertex_count;
	for (size_t f = 0; f < mesh->face_count; ++f)
		for (uint32_t c = mesh->face_offsets[f] + 2; c < mesh->face_offsets[f + 1]; ++c)
			b->indices.insert(b->indices.end(),
			                  {mesh->indices[mesh->face_offsets[f]], mesh->indices[c - 1], mesh->indices[c]});
	if (n > b->indices.size()) {
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
	if (mesh->normals)
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
}

/* Integer colours scaled to [0, 1]; 0 for a type colours do not come in. */
double color_scale(int type)
{
	switch (type) {
	case vn_drc_uint8: return 1.0 / 255;
	case vn_drc_uint16: return 1.0 / 65535;
	case vn_drc_float32: return 1;
	default: return 0;
	}
}

double component(const vn_drc_attribute& a, size_t i)
{
	switch (a.component_type) {
	case vn_drc_uint8: return static_cast<const uint8_t*>(a.data)[i];
	case vn_drc_uint16: return static_cast<const uint16_t*>(a.data)[i];
	default: return static_cast<const float*>(a.data)[i];
	}
}

const vn_drc_attribute* first(const vn_drc_geometry& g, int s)
{
	for (size_t i = 0; i < g.attribute_count; ++i)
		if (g.attributes[i].semantic == s)
			return &g.attributes[i];
	return nullptr;
}

template <typename T>
bool copy_floats(const vn_drc_attribute* a, int components, size_t n, T** out)
{
	*out = static_cast<T*>(std::malloc(sizeof(T) * components * n + 1));
	if (!*out)
		return false;
	for (size_t i = 0; i < components * n; ++i)
		(*out)[i] = T(static_cast<const float*>(a->data)[i]);
	return true;
}

/* Decoded geometry into a vn_io_mesh; records the bits found in *found. */
vn_io_result to_mesh(const vn_drc_geometry& g, const char* name, vn_io_mesh* mesh, vn_drc_options* found,
                     vn_io_error* error)
{
	const vn_drc_attribute* position = first(g, vn_drc_position);
	const vn_drc_attribute* normal = first(g, vn_drc_normal);
	const vn_drc_attribute* color = first(g, vn_drc_color);
	const vn_drc_attribute* texcoord = nullptr;
	for (size_t i = 0; i < g.attribute_count; ++i)
		if (!texcoord && g.attributes[i].semantic == vn_drc_texcoord && g.attributes[i].components == 2 &&
		    g.attributes[i].component_type == vn_drc_float32)
			texcoord = &g.attributes[i];
	if (!position || position->components != 3 || position->component_type != vn_drc_float32)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: no 3-component float POSITION", name);
	if (normal && (normal->components != 3 || normal->component_type != vn_drc_float32))
		return vn_io_fail(error, vn_io_error_unsupported, "%s: NORMAL is not 3 floats", name);
	if (color && (color->components < 3 || !color_scale(color->component_type)))
		return vn_io_fail(error, vn_io_error_unsupported, "%s: COLOR is not RGB(A) of float, uint8 or uint16", name);

	const size_t n = g.point_count;
	mesh->vertex_count = n;
	mesh->face_count = g.triangle_count;
	mesh->face_offsets = static_cast<uint32_t*>(std::malloc(sizeof(uint32_t) * (g.triangle_count + 1)));
	mesh->indices = static_cast<uint32_t*>(std::malloc(sizeof(uint32_t) * 3 * g.triangle_count + 1));
	if (!mesh->face_offsets || !mesh->indices || !copy_floats(position, 3, n, &mesh->positions) ||
	    (normal && !copy_floats(normal, 3, n, &mesh->normals)) ||
	    (texcoord && !copy_floats(texcoord, 2, n, &mesh->texcoords)) ||
	    (color && !(mesh->colors = static_cast<float*>(std::malloc(sizeof(float) * 4 * n + 1)))))
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	std::memcpy(mesh->indices, g.indices, sizeof(uint32_t) * 3 * g.triangle_count);
	for (size_t f = 0; f <= g.triangle_count; ++f)
		mesh->face_offsets[f] = uint32_t(3 * f);
	if (color) {
		const double scale = color_scale(color->component_type);
		for (size_t i = 0; i < n; ++i)
			for (int k = 0; k < 4; ++k)
				mesh->colors[4 * i + k] =
				    k < color->components ? float(component(*color, color->components * i + k) * scale) : 1.0f;
		mesh->colors_are_bytes = color->component_type == vn_drc_uint8;
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

} // namespace

extern "C" {

void vn_drc_geometry_free(vn_drc_geometry* g)
{
	if (!g)
		return;
	for (size_t i = 0; i < g->attribute_count; ++i)
		std::free(g->attributes[i].data);
	std::free(g->attributes);
	std::free(g->indices);
	*g = vn_drc_geometry{};
}

vn_io_result vn_drc_decode(const void* data, size_t size, const char* name, vn_drc_geometry* g, vn_io_error* error)
{
	*g = vn_drc_geometry{};
	vn_io_result r;
	try {
		r = decode(data, size, name, g, error);
	} catch (const std::bad_alloc&) {
		r = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	}
	if (r != vn_io_success)
		vn_drc_geometry_free(g);
	return r;
}

vn_io_result vn_drc_encode(const vn_drc_geometry* g, int compression_level, int keep_order, const char* name,
                           void** data, size_t* size, vn_io_error* error)
{
	*data = nullptr;
	*size = 0;
	try {
		std::vector<char> bytes;
		const vn_io_result r = encode(g, compression_level, keep_order != 0, name, &bytes, error);
		if (r != vn_io_success)
			return r;
		if (!(*data = std::malloc(bytes.size() + 1)))
			return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
		std::memcpy(*data, bytes.data(), bytes.size());
		*size = bytes.size();
		return vn_io_success;
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	}
}

void vn_drc_default_options(vn_drc_options* o)
{
	o->position_bits = 14;
	o->normal_bits = 10;
	o->texcoord_bits = 12;
	o->color_bits = 8;
	o->compression_level = 7;
}

vn_io_result vn_drc_read_file(const char* path, vn_io_mesh* mesh, vn_drc_options* found, vn_io_error* error)
{
	char* data;
	size_t size;
	vn_io_result r = vn_io_read_all(path, &data, &size, error);
	if (r != vn_io_success)
		return r;
	vn_drc_geometry g;
	r = vn_drc_decode(data, size, path, &g, error);
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
		std::vector<char> bytes;
		vn_io_result r = encode(b.get(), options->compression_level, false, name, &bytes, error);
		if (r != vn_io_success)
			return r;
		vn_drc_geometry g;
		if ((r = vn_drc_decode(bytes.data(), bytes.size(), name, &g, error)) != vn_io_success)
			return r;
		const vn_drc_attribute* normal = first(g, vn_drc_normal);
		const vn_drc_attribute* id = first(g, vn_drc_generic);
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
