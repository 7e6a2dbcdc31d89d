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
#include <draco/core/options.h>
#include <draco/core/varint_decoding.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/metadata/metadata_decoder.h>
#include <draco/compression/expert_encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <cctype>
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

/* What each attribute (in the decoder's order) was quantized with: bits
 * (0: not quantized) and, for
 * Draco's AttributeQuantizationTransform, the grid. Draco keeps the
 * transform parameters only on its portable (still quantized) attributes,
 * which a decode hands out when told to skip the inverse transform: so a
 * second decode with every transform skipped reads them back. */
struct quantization {
	uint32_t unique_id;
	int bits;
	vn_drc_grid grid; /* bits 0: octahedral (normals) */
};

std::vector<quantization> quantizations(const void* data, size_t size)
{
	std::vector<quantization> found;
	draco::DecoderBuffer buffer;
	buffer.Init(static_cast<const char*>(data), size);
	draco::Decoder decoder;
	for (int t = draco::GeometryAttribute::POSITION; t < draco::GeometryAttribute::NAMED_ATTRIBUTES_COUNT; ++t)
		decoder.SetSkipAttributeTransform(static_cast<draco::GeometryAttribute::Type>(t));
	auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
	if (!decoded.ok())
		return found;
	const draco::Mesh& mesh = *decoded.value();
	for (int i = 0; i < mesh.num_attributes(); ++i) {
		const draco::PointAttribute& a = *mesh.attribute(i);
		draco::AttributeQuantizationTransform q;
		draco::AttributeOctahedronTransform o;
		quantization f{a.unique_id(), 0, vn_drc_grid{}};
		if (q.InitFromAttribute(a)) {
			f.bits = q.quantization_bits();
			if (q.min_values().size() >= 1 && q.min_values().size() <= 4) {
				f.grid.bits = f.bits;
				for (size_t c = 0; c < q.min_values().size(); ++c)
					f.grid.origin[c] = q.min_value(int(c));
				f.grid.range = q.range();
			}
		} else if (o.InitFromAttribute(a)) {
			f.bits = o.quantization_bits();
		}
		found.push_back(f);
	}
	return found;
}

/* The counts a mesh stream declares, read as Draco 1.5.5 reads them
 * (point_cloud_decoder.cc, mesh_sequential_decoder.cc,
 * mesh_edgebreaker_decoder.cc and mesh_edgebreaker_decoder_impl.cc):
 *
 *   header: "DRACO", major, minor, geometry type, method, uint16 flags;
 *   metadata from 1.3 when flagged;
 *   sequential: faces, points: uint32 before 2.2, varints from 2.2;
 *   edgebreaker: uint8 traversal decoder type; before 2.2 the new vertex
 *   count (uint32 before 2.0, varint in 2.0 and 2.1); encoded vertices,
 *   faces; uint8 attribute data count; encoded symbols, split symbols:
 *   uint32 before 2.0, varints from 2.0.
 *
 * Draco accepts major versions 1 and 2 up to 2.2 for meshes. */
bool declared_counts(const void* data, size_t size, uint32_t* faces, uint64_t* vertices)
{
	draco::DecoderBuffer b;
	b.Init(static_cast<const char*>(data), size);
	draco::DracoHeader h;
	if (!draco::PointCloudDecoder::DecodeHeader(&b, &h).ok() || h.encoder_type != draco::TRIANGULAR_MESH)
		return false;
	const unsigned version = unsigned(h.version_major) << 8 | h.version_minor;
	if (h.version_major < 1 || version > 0x0202)
		return false;
	b.set_bitstream_version(uint16_t(version));
	if (version >= 0x0103 && (h.flags & METADATA_FLAG_MASK)) {
		draco::GeometryMetadata metadata;
		draco::MetadataDecoder reader;
		if (!reader.DecodeGeometryMetadata(&b, &metadata))
			return false;
	}
	/* A count stored as uint32 before version `varint_from`, a varint from it. */
	auto count = [&](unsigned varint_from, uint32_t* out) {
		return version < varint_from ? b.Decode(out) : draco::DecodeVarint(out, &b);
	};
	if (h.encoder_method == draco::MESH_SEQUENTIAL_ENCODING) {
		uint32_t points;
		if (!count(0x0202, faces) || !count(0x0202, &points))
			return false;
		*vertices = points;
		return true;
	}
	if (h.encoder_method != draco::MESH_EDGEBREAKER_ENCODING)
		return false;
	uint8_t traversal, attribute_data;
	uint32_t new_vertices, encoded_vertices, symbols, split_symbols;
	if (!b.Decode(&traversal) || (version < 0x0202 && !count(0x0200, &new_vertices)) ||
	    !count(0x0200, &encoded_vertices) || !count(0x0200, faces) || !b.Decode(&attribute_data) ||
	    !count(0x0200, &symbols) || !count(0x0200, &split_symbols))
		return false;
	*vertices = uint64_t(encoded_vertices) + split_symbols;
	return true;
}

/* libdraco sizes its connectivity tables from the counts a stream declares,
 * before it reads the data that would contradict them: a 163-byte stream
 * found by fuzzing made it allocate 4.6 GB. A stream is refused when its
 * counts are both implausible for its size (more than max_per_byte faces or
 * vertices per byte of stream: edgebreaker's best ratios on real meshes are
 * a few triangles per byte) and more than Draco could allocate room for
 * under memory_cap (about 40 bytes per face and 16 per vertex of tables):
 * a stream within the cap is always left to Draco, so that no valid stream
 * is called hostile. Returns why a stream is refused, or an empty string
 * (also when the counts cannot be read: the decoder then says why). */
constexpr uint64_t max_per_byte = 4096;
constexpr uint64_t memory_cap = uint64_t(1) << 28;

std::string implausible(const void* data, size_t size)
{
	uint32_t faces;
	uint64_t vertices;
	if (!declared_counts(data, size, &faces, &vertices))
		return "";
	const bool dense = faces > max_per_byte * size || vertices > max_per_byte * size;
	if (!dense || 40 * uint64_t(faces) + 16 * vertices <= memory_cap)
		return "";
	return "the stream declares " + std::to_string(faces) + " faces and " + std::to_string(vertices) +
	       " points in " + std::to_string(size) + " bytes: corrupt or hostile";
}

const char* const semantic_names[] = {"POSITION", "NORMAL", "COLOR", "TEX_COORD", "GENERIC",
                                      "TANGENT", "MATERIAL", "JOINTS", "WEIGHTS"};
static_assert(sizeof semantic_names / sizeof semantic_names[0] == vn_drc_semantic_count &&
                  int(vn_drc_semantic_count) == int(draco::GeometryAttribute::NAMED_ATTRIBUTES_COUNT),
              "a name per Draco attribute type");

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
	const auto found = quantizations(data, size);

	g->point_count = mesh.num_points();
	g->triangle_count = mesh.num_faces();
	g->indices = static_cast<uint32_t*>(std::malloc(3 * g->triangle_count * sizeof(uint32_t) + 1));
	g->attributes =
	    static_cast<vn_drc_attribute*>(std::calloc(size_t(mesh.num_attributes()) + 1, sizeof(vn_drc_attribute)));
	if (!g->indices || !g->attributes)
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	if (mesh.GetMetadata())
		g->metadata = new draco::GeometryMetadata(*mesh.GetMetadata());
	for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f)
		for (int k = 0; k < 3; ++k) {
			const uint32_t v = mesh.face(f)[k].value();
			if (v >= g->point_count)
				return vn_io_fail(error, vn_io_error_parse, "%s: face %u has point %u of %zu", name, f.value(), v,
				                  g->point_count);
			g->indices[3 * f.value() + k] = v;
		}
	/* Streams before version 1.3 carry no unique ids (Draco 1.5.5 leaves
	 * them all 0): such attributes are numbered in their order. */
	bool numbered = true;
	for (int i = 0; i < mesh.num_attributes(); ++i)
		for (int j = 0; j < i; ++j)
			numbered = numbered && mesh.attribute(i)->unique_id() != mesh.attribute(j)->unique_id();
	for (int i = 0; i < mesh.num_attributes(); ++i) {
		const draco::PointAttribute& a = *mesh.attribute(i);
		vn_drc_attribute& out = g->attributes[g->attribute_count];
		out.unique_id = numbered ? a.unique_id() : uint32_t(i);
		out.semantic = a.attribute_type();
		out.component_type = gl_type(a.data_type());
		out.components = a.num_components();
		out.normalized = a.normalized();
		if (out.semantic < vn_drc_position || out.semantic >= vn_drc_semantic_count || !out.component_type ||
		    out.components < 1 || out.components > 4)
			return vn_io_fail(error, vn_io_error_unsupported,
			                  "%s: attribute %u has a type or size vn does not handle", name, out.unique_id);
		if (found.size() == size_t(mesh.num_attributes()) && found[size_t(i)].unique_id == a.unique_id() &&
		    out.component_type == vn_drc_float32) {
			const quantization& q = found[size_t(i)];
			out.quantization_bits = q.bits;
			if (q.grid.bits && out.semantic != vn_drc_normal && q.grid.bits == q.bits)
				out.grid = q.grid;
		}
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

/* Whether float attribute a can be quantized on its own grid: bits as the
 * grid's, not NORMAL, and every value within half a step of the grid's box
 * (Draco's quantizer rounds to the nearest step). */
bool on_grid(const vn_drc_attribute& a, size_t points)
{
	const vn_drc_grid& grid = a.grid;
	if (grid.bits <= 0 || grid.bits != a.quantization_bits || a.semantic == vn_drc_normal ||
	    a.component_type != vn_drc_float32 || !(grid.range > 0) || !std::isfinite(grid.range))
		return false;
	const double steps = double((uint64_t(1) << grid.bits) - 1), scale = steps / grid.range;
	const float* v = static_cast<const float*>(a.data);
	for (size_t i = 0; i < points * size_t(a.components); ++i) {
		const double q = (double(v[i]) - grid.origin[i % size_t(a.components)]) * scale;
		if (!(q >= -0.25 && q <= steps + 0.25))
			return false;
	}
	return true;
}

/* Tells encoder to quantize Draco attribute id on a's grid. Draco 1.5.5's
 * SetAttributeExplicitQuantization keeps the origin and range as options
 * written with std::to_string, six decimals (0.44509998 comes back as
 * 0.4451001): the options are set again with every digit a float needs,
 * which Draco's strtof and atof read back exactly. */
void set_grid(draco::ExpertEncoder* encoder, int id, const vn_drc_attribute& a)
{
	encoder->SetAttributeExplicitQuantization(id, a.grid.bits, a.components, a.grid.origin, a.grid.range);
	const draco::Options* set = encoder->options().FindAttributeOptions(id);
	if (!set)
		return;
	draco::Options options = *set;
	auto exact = [](float v) {
		char text[40];
		std::snprintf(text, sizeof text, "%.17g", double(v));
		return std::string(text);
	};
	std::string origin;
	for (int c = 0; c < a.components; ++c)
		origin += (c ? " " : "") + exact(a.grid.origin[c]);
	options.SetString("quantization_origin", origin);
	options.SetString("quantization_range", exact(a.grid.range));
	encoder->options().SetAttributeOptions(id, options);
}

/* An error naming the first non-finite value of a float attribute that is
 * to be quantized (Draco's quantizer crashes on NaN), or whose values span
 * more than a float holds; empty when there is none. */
std::string unquantizable(const vn_drc_attribute& a, size_t points)
{
	if (a.component_type != vn_drc_float32 || a.quantization_bits <= 0)
		return "";
	const size_t k = size_t(a.components);
	const float* v = static_cast<const float*>(a.data);
	const char* what = a.semantic >= 0 && a.semantic < vn_drc_semantic_count ? semantic_names[a.semantic] : "?";
	std::vector<float> lo(k, INFINITY), hi(k, -INFINITY);
	for (size_t p = 0; p < points; ++p)
		for (size_t c = 0; c < k; ++c) {
			const float x = v[k * p + c];
			if (!std::isfinite(x))
				return "attribute " + std::to_string(a.unique_id) + " (" + what + ") has a non-finite value at point " +
				       std::to_string(p) + ", which Draco cannot quantize";
			lo[c] = std::min(lo[c], x), hi[c] = std::max(hi[c], x);
		}
	for (size_t c = 0; c < k && points && a.semantic != vn_drc_normal; ++c)
		if (!std::isfinite(hi[c] - lo[c]))
			return "attribute " + std::to_string(a.unique_id) + " (" + what +
			       ") spans more than a float can hold, which Draco cannot quantize";
	return "";
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
	std::vector<std::pair<int, const vn_drc_attribute*>> quantize; // Draco attribute id, attribute
	for (size_t i = 0; i < g->attribute_count; ++i) {
		const vn_drc_attribute& a = g->attributes[i];
		const draco::DataType type = draco_type(a.component_type);
		if (type == draco::DT_INVALID || a.semantic < vn_drc_position || a.semantic >= vn_drc_semantic_count ||
		    a.components < 1 || a.components > 4 || a.quantization_bits < 0 || a.quantization_bits > VN_DRC_MAX_BITS)
			return vn_io_fail(error, vn_io_error_unsupported, "%s: attribute %u has a type, size or bits Draco does not take",
			                  name, a.unique_id);
		if (a.semantic == vn_drc_normal && a.quantization_bits == 1)
			return vn_io_fail(error, vn_io_error_unsupported, "%s: normals need 2 to %d quantization bits", name,
			                  VN_DRC_MAX_BITS);
		for (size_t j = 0; j < i; ++j) {
			if (g->attributes[j].unique_id == a.unique_id)
				return vn_io_fail(error, vn_io_error_unsupported, "%s: two attributes have unique id %u", name,
				                  a.unique_id);
			/* Draco 1.5.5's edgebreaker encoder crashes on a second POSITION
			 * (found by fuzzing: a stream whose NORMAL was typed POSITION). */
			if (a.semantic == vn_drc_position && g->attributes[j].semantic == vn_drc_position)
				return vn_io_fail(error, vn_io_error_unsupported,
				                  "%s: attributes %u and %u are both POSITION, which Draco cannot encode", name,
				                  g->attributes[j].unique_id, a.unique_id);
		}
		const std::string bad = unquantizable(a, g->point_count);
		if (!bad.empty())
			return vn_io_fail(error, vn_io_error_unsupported, "%s: %s", name, bad.c_str());
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
			quantize.emplace_back(id, &a);
	}
	/* The metadata, with the attribute metadata of the unique ids kept
	 * (AddAttributeMetadata files it under the attribute's unique id). */
	if (const auto* metadata = static_cast<const draco::GeometryMetadata*>(g->metadata)) {
		mesh.AddMetadata(std::unique_ptr<draco::GeometryMetadata>(
		    new draco::GeometryMetadata(static_cast<const draco::Metadata&>(*metadata))));
		for (int id = 0; id < mesh.num_attributes(); ++id)
			if (const draco::AttributeMetadata* m = metadata->GetAttributeMetadataByUniqueId(
			        int32_t(mesh.attribute(id)->unique_id())))
				mesh.AddAttributeMetadata(id, std::unique_ptr<draco::AttributeMetadata>(new draco::AttributeMetadata(*m)));
	}
	/* A float attribute decoded from a grid is quantized on it again (same
	 * integers, same decoded values) when its bits did not change. */
	std::vector<bool> explicit_grid;
	for (const auto& q : quantize)
		explicit_grid.push_back(on_grid(*q.second, g->point_count));
	/* Levels below 10 pick edgebreaker, which splits non-manifold vertices
	 * and drops degenerate triangles; the sequential method keeps every point
	 * and triangle, so it is the fallback when edgebreaker changed a count. */
	for (const bool sequential : {level == 10 || keep_order, true}) {
		draco::ExpertEncoder encoder(mesh);
		for (size_t i = 0; i < quantize.size(); ++i) {
			const vn_drc_attribute& a = *quantize[i].second;
			if (explicit_grid[i])
				set_grid(&encoder, quantize[i].first, a);
			else
				encoder.SetAttributeQuantization(quantize[i].first, a.quantization_bits);
		}
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

/* The mesh as Draco attributes: positions, normals, texcoords, colours (bytes
 * when the source had bytes: lossless), then every attribute of
 * mesh->attributes (TEXCOORD_n and COLOR_n as TEX_COORD and COLOR, floats
 * quantized with the texcoord and colour bits; the others GENERIC, named in
 * their attribute metadata as "name" without the leading underscore, and
 * lossless, as are integers), polygons fan-triangulated. Draco's decoders
 * refuse more points than 3 per triangle, so a mesh with that many keeps
 * only the vertices faces use (in their order; b->kept lists them). */
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

/* What glTF can hold as TEXCOORD_n (2 floats, or normalized unsigned
 * bytes or shorts) and COLOR_n (3 or 4 of those). */
bool gltf_texcoord(const vn_drc_attribute& a)
{
	return a.components == 2 && (a.component_type == vn_drc_float32 ||
	                             (a.normalized && (a.component_type == vn_drc_uint8 || a.component_type == vn_drc_uint16)));
}

bool gltf_color(const vn_drc_attribute& a)
{
	return (a.components == 3 || a.components == 4) &&
	       (a.component_type == vn_drc_float32 ||
	        (a.normalized && (a.component_type == vn_drc_uint8 || a.component_type == vn_drc_uint16)));
}

/* "_" and the attribute's metadata "name" in upper case, characters other
 * than letters, digits and '_' as '_'; without a name "_GENERIC_<unique id>"
 * (or the Draco type's name). */
std::string application_name(const vn_drc_geometry& g, const vn_drc_attribute& a)
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
vn_io_result to_mesh(const vn_drc_geometry& g, const char* name, vn_io_mesh* mesh, vn_drc_options* found,
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
	if (!position || position->components != 3 || position->component_type != vn_drc_float32)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: no 3-component float POSITION", name);
	if (normal && (normal->components != 3 || normal->component_type != vn_drc_float32))
		normal = nullptr; /* replaced by the new normals; kept as an attribute below */

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

/* Owns a decoded geometry. */
struct decoded_geometry {
	vn_drc_geometry g{};
	decoded_geometry() = default;
	decoded_geometry(const decoded_geometry&) = delete;
	decoded_geometry& operator=(const decoded_geometry&) = delete;
	~decoded_geometry() { vn_drc_geometry_free(&g); }
};

double now()
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/* vn_io_write_file's writer for bytes encoded beforehand (its settings). */
vn_io_result write_bytes(FILE* out, const char* path, const vn_io_mesh*, const void* settings, vn_io_error* error)
{
	const auto& bytes = *static_cast<const std::vector<char>*>(settings);
	if (std::fwrite(bytes.data(), 1, bytes.size(), out) != bytes.size())
		return vn_io_fail(error, vn_io_error_write, "%s: cannot write", path);
	return vn_io_success;
}

vn_io_result convert(const char* in, const char* out, const vn_drc_convert_options& o, vn_drc_convert_stats& st,
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
		r = vn_drc_decode(data, size, in, &d.g, error);
		std::free(data);
		if (r != vn_io_success)
			return r;
	}
	const vn_drc_geometry& g = d.g;
	const vn_drc_attribute* position = first(g, vn_drc_position);
	if (!position || position->components != 3 || position->component_type != vn_drc_float32)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: no 3-component float POSITION", in);
	const float* p = static_cast<const float*>(position->data);
	for (size_t i = 0; i < g.point_count; ++i)
		if (!std::isfinite(p[3 * i]) || !std::isfinite(p[3 * i + 1]) || !std::isfinite(p[3 * i + 2]))
			return vn_io_fail(error, vn_io_error_unsupported,
			                  "%s: point %zu has a non-finite position (%g, %g, %g), which no output can hold", in, i,
			                  double(p[3 * i]), double(p[3 * i + 1]), double(p[3 * i + 2]));
	const double t1 = now();

	std::vector<float> normals(3 * g.point_count + 3);
	const vn_positions positions = {p, g.point_count, 0, vn_scalar_float32};
	const vn_vectors vectors = {normals.data(), 0, vn_scalar_float32};
	vn_options vo;
	std::memset(&vo, 0, sizeof vo);
	vo.threads = o.threads;
	const vn_result vr =
	    vn_triangle_normals(&vectors, &positions, g.indices, 3 * g.triangle_count, o.method, &vo, &st.normals);
	if (vr != vn_result_success)
		return vn_io_fail(error, vr == vn_result_out_of_memory ? vn_io_error_memory : vn_io_error_unsupported,
		                  "%s: %s", in, vn_result_string(vr));
	const double t2 = now();

	/* Every attribute as decoded, NORMAL replaced (or added), bits given
	 * for a semantic replacing the stream's. */
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
	if (!normal) {
		vn_drc_attribute a{};
		for (const vn_drc_attribute& b : attributes)
			a.unique_id = std::max(a.unique_id, b.unique_id + 1);
		a.semantic = vn_drc_normal;
		attributes.push_back(a);
		normal = &attributes.back();
	}
	const int normal_bits = given.normal_bits >= 0 ? given.normal_bits
	                        : normal->component_type == vn_drc_float32 && normal->quantization_bits > 0
	                            ? normal->quantization_bits
	                            : defaults.normal_bits;
	normal->component_type = vn_drc_float32;
	normal->components = 3;
	normal->normalized = 0;
	normal->quantization_bits = normal_bits;
	normal->grid = vn_drc_grid{};
	normal->data = normals.data();
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

	if (o.normal_error) {
		const std::vector<double> xyz(p, p + 3 * g.point_count), nxyz(normals.begin(), normals.begin() + 3 * g.point_count);
		if ((r = vn_drc_triangle_normal_error(xyz.data(), nxyz.data(), g.point_count, g.indices, g.triangle_count,
		                                      &st.used, out, &st.normal_error, error)) != vn_io_success)
			return r;
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
	delete static_cast<draco::GeometryMetadata*>(g->metadata);
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
	std::memset(mesh, 0, sizeof *mesh);
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

int vn_drc_declared_counts(const void* data, size_t size, uint32_t* faces, uint64_t* vertices)
{
	*faces = 0;
	*vertices = 0;
	try {
		return declared_counts(data, size, faces, vertices);
	} catch (const std::bad_alloc&) {
		return 0;
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

int vn_drc_given_bits(const vn_drc_options* given, int semantic, int component_type)
{
	if (component_type != vn_drc_float32)
		return -1; /* integers are lossless */
	switch (semantic) {
	case vn_drc_position: return given->position_bits;
	case vn_drc_normal: return given->normal_bits;
	case vn_drc_texcoord: return given->texcoord_bits;
	case vn_drc_color: return given->color_bits;
	default: return -1;
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
