/*
 * Draco (.drc) for vn_io, the bitstream: see draco.h. Everything goes
 * through the plain vn_drc_geometry structs, so the vn_io format
 * (draco_mesh.cpp) and the API that glTF's KHR_draco_mesh_compression
 * (gltf_draco.cpp) uses are the same code. Here: decoding and encoding
 * them (each attribute's quantization grid, the metadata), the counts a
 * stream declares, and the vn_drc_* codec entry points.
 */
#include "draco.h"
#include "draco_internal.h"

extern "C" {
#include "text.h"
}

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
#include <memory>
#include <new>
#include <string>
#include <vector>

/* A geometry copied into Draco's mesh, with how to quantize each float
 * attribute: what vn_drc_encoder_new makes and vn_drc_encoder_encode encodes. */
struct vn_drc_encoder {
	draco::Mesh mesh; /* no faces for a point cloud, encoded as one where cloud */
	bool cloud;
	/* Draco attribute id, the attribute (its data not kept), whether it is
	 * quantized on its own grid. */
	struct quantized {
		int id;
		vn_drc_attribute a;
		bool on_grid;
	};
	std::vector<quantized> quantize;
	/* Integer NORMAL attributes: Draco 1.5.5 predicts a NORMAL from the
	 * positions below speed 4 in a way only its octahedral float normals
	 * survive (an int8 normal (0, 0, 127) decodes as (4, 4, 5)); they get
	 * difference prediction, lossless. */
	std::vector<int> integer_normals;
	/* A point cloud's float NORMALs decoded from a kd-tree stream (their
	 * grid, bits 0), quantized on it where kd-tree writes the cloud again:
	 * with every other attribute quantized or integer (Draco's condition
	 * for kd-tree), not kd_blocked. */
	std::vector<quantized> kd_normals;
	bool kd_blocked = false;
	/* A point cloud with a quantized float NORMAL: written by the sequential
	 * method, which codes it octahedrally as meshes are. kd-tree would
	 * quantize it per component: an input's octahedral (0, 0, -1) came back
	 * as (0.001, 0.001, -1), and 100k points with normals took 517 kB
	 * there against 373 kB. */
	bool octahedral_normals = false;
	/* Attribute values stored without entropy coding: see symbol_bound. */
	bool plain_values = false;
};

namespace vn_drc {

static_assert(int(vn_drc_position) == int(draco::GeometryAttribute::POSITION) &&
                  int(vn_drc_normal) == int(draco::GeometryAttribute::NORMAL) &&
                  int(vn_drc_color) == int(draco::GeometryAttribute::COLOR) &&
                  int(vn_drc_texcoord) == int(draco::GeometryAttribute::TEX_COORD) &&
                  int(vn_drc_generic) == int(draco::GeometryAttribute::GENERIC),
              "vn_drc_semantic mirrors draco::GeometryAttribute::Type");

namespace {

struct type_pair {
	int gl;
	draco::DataType draco;
};
const type_pair types[] = {
    {vn_drc_int8, draco::DT_INT8},   {vn_drc_uint8, draco::DT_UINT8},   {vn_drc_int16, draco::DT_INT16},
    {vn_drc_uint16, draco::DT_UINT16}, {vn_drc_int32, draco::DT_INT32}, {vn_drc_uint32, draco::DT_UINT32},
    {vn_drc_float32, draco::DT_FLOAT32}, {vn_drc_float64, draco::DT_FLOAT64},
};

} // namespace

static int gl_type(draco::DataType t)
{
	for (const type_pair& p : types)
		if (p.draco == t)
			return p.gl;
	return 0;
}

static draco::DataType draco_type(int gl)
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

double component(const vn_drc_attribute& a, size_t i)
{
	switch (a.component_type) {
	case vn_drc_int8: return static_cast<const int8_t*>(a.data)[i];
	case vn_drc_uint8: return static_cast<const uint8_t*>(a.data)[i];
	case vn_drc_int16: return static_cast<const int16_t*>(a.data)[i];
	case vn_drc_uint16: return static_cast<const uint16_t*>(a.data)[i];
	case vn_drc_int32: return static_cast<const int32_t*>(a.data)[i];
	case vn_drc_uint32: return static_cast<const uint32_t*>(a.data)[i];
	case vn_drc_float64: return static_cast<const double*>(a.data)[i];
	default: return static_cast<const float*>(a.data)[i];
	}
}

namespace {

/* What each attribute (in the decoder's order) was quantized with: bits
 * (0: not quantized) and, for
 * Draco's AttributeQuantizationTransform, the grid. Draco keeps the
 * transform parameters only on its portable (still quantized) attributes,
 * which a decode hands out when told to skip the inverse transform: so a
 * second decode with every transform skipped reads them back. A stream
 * that one cannot decode fails the full decode too: its error is returned
 * in *failure then, which saves decoding a hostile stream twice (seconds of
 * libdraco time for some 300-byte streams the fuzzer made). The two
 * decodes list the attributes in the same order; each is matched by its
 * type, not its unique id, which the kd-tree point cloud decoder leaves 0
 * on the portable attributes (so a kd-tree stream's bits were lost). */
struct quantization {
	int semantic;
	int bits;
	vn_drc_grid grid; /* bits 0: octahedral (normals) */
};

} // namespace

static std::vector<quantization> quantizations(const void* data, size_t size, std::string* failure)
{
	std::vector<quantization> found;
	draco::DecoderBuffer buffer;
	buffer.Init(static_cast<const char*>(data), size);
	draco::Decoder decoder;
	for (int t = draco::GeometryAttribute::POSITION; t < draco::GeometryAttribute::NAMED_ATTRIBUTES_COUNT; ++t)
		decoder.SetSkipAttributeTransform(static_cast<draco::GeometryAttribute::Type>(t));
	auto decoded = decoder.DecodePointCloudFromBuffer(&buffer); /* a mesh too */
	if (!decoded.ok()) {
		const std::string& why = decoded.status().error_msg_string();
		*failure = why.empty() ? "cannot decode" : why;
		return found;
	}
	const draco::PointCloud& geometry = *decoded.value();
	for (int i = 0; i < geometry.num_attributes(); ++i) {
		const draco::PointAttribute& a = *geometry.attribute(i);
		draco::AttributeQuantizationTransform q;
		draco::AttributeOctahedronTransform o;
		quantization f{a.attribute_type(), 0, vn_drc_grid{}};
		if (q.InitFromAttribute(a)) {
			f.bits = q.quantization_bits();
			if (q.min_values().size() >= 1 && q.min_values().size() <= 4) {
				f.grid.bits = f.bits;
				for (size_t c = 0; c < q.min_values().size(); ++c)
					f.grid.origin[c] = q.min_value(int(c));
				f.grid.range = q.range();
			}
			/* A NORMAL's bits are its octahedral coding's: kd-tree point
			 * clouds quantize normals per component instead, which only
			 * kd-tree writes back, so such a normal keeps its grid with bits
			 * 0 (unquantized wherever kd-tree does not write it). */
			if (a.attribute_type() == draco::GeometryAttribute::NORMAL)
				f.bits = 0;
		} else if (o.InitFromAttribute(a)) {
			f.bits = o.quantization_bits();
		}
		found.push_back(f);
	}
	return found;
}

/* The counts a stream declares, read as Draco 1.5.5 reads them
 * (point_cloud_decoder.cc, point_cloud_sequential_decoder.cc,
 * point_cloud_kd_tree_decoder.cc, mesh_sequential_decoder.cc,
 * mesh_edgebreaker_decoder.cc and mesh_edgebreaker_decoder_impl.cc):
 *
 *   header: "DRACO", major, minor, geometry type, method, uint16 flags;
 *   metadata from 1.3 when flagged;
 *   point cloud (either method): int32 points;
 *   sequential: faces, points: uint32 before 2.2, varints from 2.2;
 *   edgebreaker: uint8 traversal decoder type; before 2.2 the new vertex
 *   count (uint32 before 2.0, varint in 2.0 and 2.1); encoded vertices,
 *   faces; uint8 attribute data count; encoded symbols, split symbols:
 *   uint32 before 2.0, varints from 2.0.
 *
 * Draco accepts major versions 1 and 2 up to 2.2 for meshes, 2.3 for point
 * clouds. */
static bool declared_counts(const void* data, size_t size, uint32_t* faces, uint64_t* vertices, bool* is_cloud)
{
	draco::DecoderBuffer b;
	b.Init(static_cast<const char*>(data), size);
	draco::DracoHeader h;
	if (!draco::PointCloudDecoder::DecodeHeader(&b, &h).ok() ||
	    (h.encoder_type != draco::TRIANGULAR_MESH && h.encoder_type != draco::POINT_CLOUD))
		return false;
	const bool cloud = h.encoder_type == draco::POINT_CLOUD;
	*is_cloud = cloud;
	const unsigned version = unsigned(h.version_major) << 8 | h.version_minor;
	if (h.version_major < 1 || version > (cloud ? 0x0203u : 0x0202u))
		return false;
	b.set_bitstream_version(uint16_t(version));
	if (version >= 0x0103 && (h.flags & METADATA_FLAG_MASK)) {
		draco::GeometryMetadata metadata;
		draco::MetadataDecoder reader;
		if (!reader.DecodeGeometryMetadata(&b, &metadata))
			return false;
	}
	if (cloud) { /* sequential and kd-tree: an int32 point count (a negative one reads as uint32) */
		int32_t points;
		if ((h.encoder_method != draco::POINT_CLOUD_SEQUENTIAL_ENCODING &&
		     h.encoder_method != draco::POINT_CLOUD_KD_TREE_ENCODING) ||
		    !b.Decode(&points))
			return false;
		*faces = 0;
		*vertices = uint32_t(points);
		return true;
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
 * a mesh stream within the cap is always left to Draco. A point cloud's
 * memory is its attributes (up to 255 components of 8 bytes a point, read
 * after the counts), so no cap bounds it: a point cloud is refused when it
 * is dense at all. A valid stream can be that dense: 17M identical points
 * fit in 58 bytes, but no real mesh or scan compresses to 4096 points a
 * byte (fuzzing found libdraco decoding a cloud of 16M points from 60 bytes
 * into gigabytes). Returns why a stream is refused, or an empty string
 * (also when the counts cannot be read: the decoder then says why). */
constexpr uint64_t max_per_byte = 4096;
constexpr uint64_t memory_cap = uint64_t(1) << 28;

static std::string implausible(const void* data, size_t size)
{
	uint32_t faces;
	uint64_t vertices;
	bool cloud;
	if (!declared_counts(data, size, &faces, &vertices, &cloud))
		return "";
	const bool dense = faces > max_per_byte * size || vertices > max_per_byte * size;
	if (!dense || (!cloud && 40 * uint64_t(faces) + 16 * vertices <= memory_cap))
		return "";
	return "the stream declares " + (faces ? std::to_string(faces) + " faces and " : std::string()) +
	       std::to_string(vertices) + " points in " + std::to_string(size) + " bytes: corrupt or hostile";
}

const char* const semantic_names[] = {"POSITION", "NORMAL", "COLOR", "TEX_COORD", "GENERIC",
                                      "TANGENT", "MATERIAL", "JOINTS", "WEIGHTS"};
static_assert(sizeof semantic_names / sizeof semantic_names[0] == vn_drc_semantic_count &&
                  int(vn_drc_semantic_count) == int(draco::GeometryAttribute::NAMED_ATTRIBUTES_COUNT),
              "a name per Draco attribute type");

static vn_io_result decode(const void* data, size_t size, const char* name, bool clouds, vn_drc_geometry* g,
                           vn_io_error* error)
{
	const vn_io_result lfs = vn_io_refuse_lfs_pointer(data, size, name, error);
	if (lfs != vn_io_success)
		return lfs;
	const std::string refused = implausible(data, size);
	if (!refused.empty())
		return vn_io_fail(error, vn_io_error_parse, "%s: %s", name, refused.c_str());
	draco::DecoderBuffer buffer;
	buffer.Init(static_cast<const char*>(data), size);
	auto kind = draco::Decoder::GetEncodedGeometryType(&buffer);
	if (!kind.ok())
		return vn_io_fail(error, vn_io_error_parse, "%s: not a Draco stream (%s)", name,
		                  kind.status().error_msg());
	if (kind.value() == draco::POINT_CLOUD && !clouds)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: a Draco point cloud, not a mesh", name);
	if (kind.value() != draco::TRIANGULAR_MESH && kind.value() != draco::POINT_CLOUD)
		return vn_io_fail(error, vn_io_error_parse, "%s: not a Draco mesh or point cloud", name);
	/* A kd-tree point cloud before bitstream 2.3 (Draco before 1.4) carries
	 * a second point count inside its attribute data, which libdraco sizes
	 * the attributes from unchecked (fuzzing found 50 GB asked for by 49
	 * bytes), and which vn cannot read before it does. */
	const unsigned char* head = static_cast<const unsigned char*>(data);
	if (kind.value() == draco::POINT_CLOUD && size >= 9 && head[8] == draco::POINT_CLOUD_KD_TREE_ENCODING &&
	    (unsigned(head[5]) << 8 | head[6]) < 0x0203)
		return vn_io_fail(error, vn_io_error_unsupported,
		                  "%s: a kd-tree point cloud of bitstream %u.%u, which vn does not read (libdraco would size "
		                  "it from counts vn cannot check): encode it again with Draco 1.4 or later",
		                  name, unsigned(head[5]), unsigned(head[6]));
	/* Read first: Draco's decoder needs several times the decoded mesh,
	 * which is then not in memory yet. */
	std::string failure;
	const auto found = quantizations(data, size, &failure);
	if (!failure.empty())
		return vn_io_fail(error, vn_io_error_parse, "%s: corrupt Draco stream (%s)", name, failure.c_str());
	draco::Decoder decoder;
	auto decoded = decoder.DecodePointCloudFromBuffer(&buffer); /* a Mesh where the stream is one */
	if (!decoded.ok())
		return vn_io_fail(error, vn_io_error_parse, "%s: corrupt Draco stream (%s)", name,
		                  decoded.status().error_msg());
	const draco::PointCloud& points = *decoded.value();
	const draco::Mesh* faces = kind.value() == draco::TRIANGULAR_MESH ? static_cast<const draco::Mesh*>(&points) : nullptr;

	g->point_count = points.num_points();
	g->triangle_count = faces ? faces->num_faces() : 0;
	g->point_cloud = !faces;
	g->indices = static_cast<uint32_t*>(std::malloc(3 * g->triangle_count * sizeof(uint32_t) + 1));
	g->attributes =
	    static_cast<vn_drc_attribute*>(std::calloc(size_t(points.num_attributes()) + 1, sizeof(vn_drc_attribute)));
	if (!g->indices || !g->attributes)
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	if (points.GetMetadata())
		g->metadata = new draco::GeometryMetadata(*points.GetMetadata());
	for (draco::FaceIndex f(0); faces && f < faces->num_faces(); ++f)
		for (int k = 0; k < 3; ++k) {
			const uint32_t v = faces->face(f)[k].value();
			if (v >= g->point_count)
				return vn_io_fail(error, vn_io_error_parse, "%s: face %u has point %u of %zu", name, f.value(), v,
				                  g->point_count);
			g->indices[3 * f.value() + k] = v;
		}
	/* Streams before version 1.3 carry no unique ids (Draco 1.5.5 leaves
	 * them all 0): such attributes are numbered in their order. */
	bool numbered = true;
	for (int i = 0; i < points.num_attributes(); ++i)
		for (int j = 0; j < i; ++j)
			numbered = numbered && points.attribute(i)->unique_id() != points.attribute(j)->unique_id();
	for (int i = 0; i < points.num_attributes(); ++i) {
		const draco::PointAttribute& a = *points.attribute(i);
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
		if (found.size() == size_t(points.num_attributes()) && found[size_t(i)].semantic == a.attribute_type() &&
		    out.component_type == vn_drc_float32) {
			const quantization& q = found[size_t(i)];
			out.quantization_bits = q.bits;
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
		for (draco::PointIndex p(0); p < points.num_points(); ++p)
			std::memcpy(static_cast<char*>(out.data) + n * p.value(), a.GetAddress(a.mapped_index(p)), n);
	}
	return vn_io_success;
}

/* Whether float attribute a has a grid (bits > 0) and every value within a
 * quarter step of its box (Draco's quantizer rounds to the nearest step). */
static bool values_on_grid(const vn_drc_attribute& a, size_t points)
{
	const vn_drc_grid& grid = a.grid;
	if (grid.bits <= 0 || a.component_type != vn_drc_float32 || !(grid.range > 0) || !std::isfinite(grid.range))
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

/* Whether float attribute a can be quantized on its own grid: bits as the
 * grid's, not NORMAL (coded octahedrally but by kd-tree), its values on it. */
static bool on_grid(const vn_drc_attribute& a, size_t points)
{
	return a.grid.bits == a.quantization_bits && a.semantic != vn_drc_normal && values_on_grid(a, points);
}

/* Tells encoder to quantize Draco attribute id on a's grid. Draco 1.5.5's
 * SetAttributeExplicitQuantization keeps the origin and range as options
 * written with std::to_string, six decimals (0.44509998 comes back as
 * 0.4451001): the options are set again with every digit a float needs,
 * which Draco's strtof and atof read back exactly. */
static void set_grid(draco::ExpertEncoder* encoder, int id, const vn_drc_attribute& a)
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
static std::string unquantizable(const vn_drc_attribute& a, size_t points)
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

/* Draco entropy codes an attribute's values (its prediction's
 * corrections, zigzag coded) with a table of 4 bytes for every symbol up
 * to the largest, so memory follows the values' span, not their count:
 * 1,065 points of one float attribute quantized to 30 bits took 4 GB.
 * This bounds that symbol, plus one: a correction is at most the span of
 * the values and 0 (lo to hi, from integer_span; that of a quantized
 * value, bits bits), twice that zigzag coded; other floats are stored as
 * they are. */
static uint64_t symbol_bound(const vn_drc_attribute& a, double lo, double hi)
{
	if (a.component_type == vn_drc_float32 || a.component_type == vn_drc_float64)
		return a.component_type == vn_drc_float32 && a.quantization_bits > 0 ? uint64_t(2) << a.quantization_bits : 0;
	return 2 * uint64_t(hi - lo) + 2;
}

/* The smallest and largest of 0 and integer attribute a's values: one pass
 * for symbol_bound and the 32-bit check. */
static void integer_span(const vn_drc_attribute& a, size_t points, double* lo, double* hi)
{
	*lo = 0, *hi = 0;
	if (a.component_type == vn_drc_float32 || a.component_type == vn_drc_float64)
		return;
	for (size_t i = 0; i < points * size_t(a.components); ++i) {
		const double x = component(a, i);
		*lo = std::min(*lo, x), *hi = std::max(*hi, x);
	}
}

/* Above this bound (a table of 512 MB: more than 26 quantization bits, or
 * integers spanning more than 2^26), values are stored without entropy
 * coding. The bound is about what Draco allocates: the first value of a
 * mesh, and of each component, is coded from nothing, so its largest
 * symbol is near the quantized range (a torus of 200k triangles took
 * 154 MB at 25 bits, 3.6 GB and 17 s at 30). Beyond float's 24 bits of
 * precision a finer grid gains little, and plain values cost about 3
 * times the size there. */
static const uint64_t max_symbols = uint64_t(1) << 27;

/* Checks g and copies it into e->mesh. */
static vn_io_result prepare(const vn_drc_geometry* g, const char* name, vn_drc_encoder* e, vn_io_error* error)
{
	if (g->point_count > UINT32_MAX / 2)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: too many points for Draco", name);
	if (g->point_cloud && g->triangle_count)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: a point cloud with %zu triangles", name,
		                  g->triangle_count);
	e->cloud = g->point_cloud != 0;
	/* Draco 1.5.5's decoders refuse such a stream (sequential connectivity):
	 * writing one would make a file nobody can read. */
	if (!e->cloud && g->point_count > 3 * g->triangle_count)
		return vn_io_fail(error, vn_io_error_unsupported,
		                  "%s: %zu points and %zu triangles: Draco cannot store more points than 3 per triangle "
		                  "(remove the unused vertices)", name, g->point_count, g->triangle_count);
	draco::Mesh& mesh = e->mesh;
	mesh.set_num_points(static_cast<uint32_t>(g->point_count));
	mesh.SetNumFaces(g->triangle_count);
	for (size_t t = 0; t < g->triangle_count; ++t) {
		draco::Mesh::Face face;
		for (int k = 0; k < 3; ++k) {
			const uint32_t v = g->indices[3 * t + k];
			if (v >= g->point_count)
				return vn_io_fail(error, vn_io_error_unsupported, "%s: triangle %zu has point %u of %zu", name, t,
				                  v, g->point_count);
			face[k] = draco::PointIndex(v);
		}
		mesh.SetFace(draco::FaceIndex(uint32_t(t)), face);
	}
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
		/* Draco 1.5.5 predicts 32-bit integers in int32 arithmetic, which
		 * overflows from 2^30 on: such values came back different, or were
		 * refused (the sequential method decoded 2147483646 as another). */
		double lo, hi;
		integer_span(a, g->point_count, &lo, &hi);
		if (-lo >= 1073741824.0 || hi >= 1073741824.0)
			for (size_t p = 0;; ++p) /* the first such value, to name it */
				if (std::fabs(component(a, p)) >= 1073741824.0)
					return vn_io_fail(error, vn_io_error_unsupported,
					                  "%s: attribute %u (%s) has %.0f at point %zu, and Draco codes 32-bit integers "
					                  "only of magnitude below 2^30 (1073741824)",
					                  name, a.unique_id, semantic_names[a.semantic], component(a, p),
					                  p / size_t(a.components));
		e->plain_values = e->plain_values || symbol_bound(a, lo, hi) > max_symbols;
		const size_t n = value_bytes(a);
		draco::GeometryAttribute ga;
		ga.Init(static_cast<draco::GeometryAttribute::Type>(a.semantic), nullptr, uint8_t(a.components), type,
		        a.normalized != 0, int64_t(n), 0);
		const int id = mesh.AddAttribute(ga, true, static_cast<uint32_t>(g->point_count));
		draco::PointAttribute* pa = mesh.attribute(id);
		pa->set_unique_id(a.unique_id); // AddAttribute numbers them 0, 1, ...
		if (g->point_count)
			pa->buffer()->Write(0, a.data, n * g->point_count);
		if (a.semantic == vn_drc_normal && type != draco::DT_FLOAT32)
			e->integer_normals.push_back(id);
		/* A float attribute decoded from a grid is quantized on it again
		 * (same integers, same decoded values) when its bits did not change. */
		if (type == draco::DT_FLOAT32 && a.quantization_bits > 0) {
			vn_drc_encoder::quantized q{id, a, on_grid(a, g->point_count)};
			/* New float colours in [0, 1] (glTF's range for them) go on the
			 * unit grid: Draco's own spans the values with one range for
			 * all components, so a component whose minimum is above 0
			 * decoded 1.0 as up to half a step more (1.00196 at 8 bits:
			 * the validator's ACCESSOR_NON_CLAMPED once decoded into glTF). */
			if (!q.on_grid && a.semantic == vn_drc_color) {
				q.a.grid = vn_drc_grid{a.quantization_bits, {0, 0, 0, 0}, 1.0f};
				q.on_grid = on_grid(q.a, g->point_count);
			}
			q.a.data = nullptr;
			e->quantize.push_back(q);
			e->octahedral_normals = e->octahedral_normals || (e->cloud && a.semantic == vn_drc_normal);
		} else if (e->cloud && a.semantic == vn_drc_normal && values_on_grid(a, g->point_count)) {
			vn_drc_encoder::quantized q{id, a, true};
			q.a.data = nullptr;
			e->kd_normals.push_back(q);
		} else if (type == draco::DT_FLOAT32 || type == draco::DT_FLOAT64) {
			e->kd_blocked = true;
		}
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
	/* Points that share a value (bit for bit) share it in the stream, as
	 * Draco's own loaders and its JavaScript encoder make them: edgebreaker
	 * connects triangles through shared POSITION values only, so with one
	 * value a point every seam was a cut. That lost the polygons of a
	 * --preserve_polygons file (its "added_edges" marks are read across
	 * edges) and compressed worse. The points and their values are unchanged.
	 * A point cloud has no connectivity to gain (kd-tree codes positions, not
	 * value indices), and libdraco's hashing of 2M values took 20 s. */
	if (!e->cloud && !mesh.DeduplicateAttributeValues())
		return vn_io_fail(error, vn_io_error_unsupported, "%s: Draco cannot index this mesh's attribute values", name);
	return vn_io_success;
}

/* Encodes e->mesh into *bytes. */
static vn_io_result run(const vn_drc_encoder& e, int level, bool keep_order, const char* name, std::vector<char>* bytes,
                        vn_io_error* error)
{
	if (level < 0 || level > 10)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: compression level %d is not 0 to 10", name, level);
	/* Levels below 10 pick edgebreaker (kd-tree for a point cloud, where its
	 * attributes allow and it has no quantized NORMAL), which splits
	 * non-manifold vertices and drops degenerate triangles (and refuses a
	 * mesh of nothing else); the sequential method keeps every point and
	 * triangle, so it is the fallback when the other changed a count or
	 * failed. */
	for (const bool sequential : {level == 10 || keep_order || e.octahedral_normals, true}) {
		/* As a point cloud where one: Draco's encoder picks its methods by
		 * the constructor's type (a point cloud keeps its order only with the
		 * sequential method; kd-tree sorts the points). */
		draco::ExpertEncoder encoder = e.cloud ? draco::ExpertEncoder(static_cast<const draco::PointCloud&>(e.mesh))
		                                       : draco::ExpertEncoder(e.mesh);
		for (const vn_drc_encoder::quantized& q : e.quantize)
			if (q.on_grid)
				set_grid(&encoder, q.id, q.a);
			else
				encoder.SetAttributeQuantization(q.id, q.a.quantization_bits);
		for (const int id : e.integer_normals)
			encoder.SetAttributePredictionScheme(id, draco::PREDICTION_DIFFERENCE);
		if (e.cloud && !sequential && !e.kd_blocked)
			for (const vn_drc_encoder::quantized& q : e.kd_normals)
				set_grid(&encoder, q.id, q.a);
		if (e.plain_values)
			encoder.SetUseBuiltInAttributeCompression(false);
		encoder.SetSpeedOptions(10 - level, 10 - level);
		if (sequential)
			encoder.SetEncodingMethod(e.cloud ? int(draco::POINT_CLOUD_SEQUENTIAL_ENCODING)
			                                  : int(draco::MESH_SEQUENTIAL_ENCODING));
		draco::EncoderBuffer out;
		const draco::Status status = encoder.EncodeToBuffer(&out);
		if (!status.ok() && !sequential)
			continue; /* edgebreaker refuses a mesh whose every triangle is degenerate: so to the sequential method */
		if (!status.ok())
			return vn_io_fail(error, vn_io_error_unsupported, "%s: Draco cannot encode this mesh (%s)", name,
			                  status.error_msg());
		bytes->assign(out.data(), out.data() + out.size());
		if (sequential)
			break;
		draco::DecoderBuffer check;
		check.Init(bytes->data(), bytes->size());
		if (e.cloud) {
			auto decoded = draco::Decoder().DecodePointCloudFromBuffer(&check);
			if (decoded.ok() && decoded.value()->num_points() == e.mesh.num_points())
				break;
			continue;
		}
		auto decoded = draco::Decoder().DecodeMeshFromBuffer(&check);
		if (decoded.ok() && decoded.value()->num_points() == e.mesh.num_points() &&
		    decoded.value()->num_faces() == e.mesh.num_faces())
			break;
	}
	return vn_io_success;
}

vn_io_result encode(const vn_drc_geometry* g, int level, bool keep_order, const char* name, std::vector<char>* bytes,
                    vn_io_error* error)
{
	vn_drc_encoder e;
	const vn_io_result r = prepare(g, name, &e, error);
	return r != vn_io_success ? r : run(e, level, keep_order, name, bytes, error);
}

} // namespace vn_drc

using namespace vn_drc;

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

static vn_io_result decode_or_free(const void* data, size_t size, const char* name, bool clouds, vn_drc_geometry* g,
                                   vn_io_error* error)
{
	*g = vn_drc_geometry{};
	vn_io_result r;
	try {
		r = decode(data, size, name, clouds, g, error);
	} catch (const std::bad_alloc&) {
		r = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	}
	if (r != vn_io_success)
		vn_drc_geometry_free(g);
	return r;
}

vn_io_result vn_drc_decode(const void* data, size_t size, const char* name, vn_drc_geometry* g, vn_io_error* error)
{
	return decode_or_free(data, size, name, false, g, error);
}

vn_io_result vn_drc_decode_any(const void* data, size_t size, const char* name, vn_drc_geometry* g, vn_io_error* error)
{
	return decode_or_free(data, size, name, true, g, error);
}

vn_io_result vn_drc_encode(const vn_drc_geometry* g, int compression_level, int keep_order, const char* name,
                           void** data, size_t* size, vn_io_error* error)
{
	*data = nullptr;
	*size = 0;
	vn_drc_encoder* e;
	vn_io_result r = vn_drc_encoder_new(g, name, &e, error);
	if (r == vn_io_success)
		r = vn_drc_encoder_encode(e, compression_level, keep_order, name, data, size, error);
	vn_drc_encoder_free(e);
	return r;
}

vn_io_result vn_drc_encoder_new(const vn_drc_geometry* g, const char* name, vn_drc_encoder** out, vn_io_error* error)
{
	*out = nullptr;
	try {
		std::unique_ptr<vn_drc_encoder> e(new vn_drc_encoder);
		const vn_io_result r = prepare(g, name, e.get(), error);
		if (r == vn_io_success)
			*out = e.release();
		return r;
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	}
}

vn_io_result vn_drc_encoder_encode(const vn_drc_encoder* e, int compression_level, int keep_order, const char* name,
                                   void** data, size_t* size, vn_io_error* error)
{
	*data = nullptr;
	*size = 0;
	try {
		std::vector<char> bytes;
		const vn_io_result r =
		    run(*e, compression_level, keep_order != 0, name, &bytes, error);
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

void vn_drc_encoder_free(vn_drc_encoder* e)
{
	delete e;
}

void vn_drc_default_options(vn_drc_options* o)
{
	o->position_bits = 14;
	o->normal_bits = 10;
	o->texcoord_bits = 12;
	o->color_bits = 8;
	o->compression_level = 7;
}

int vn_drc_declared_counts(const void* data, size_t size, uint32_t* faces, uint64_t* vertices)
{
	*faces = 0;
	*vertices = 0;
	try {
		bool cloud;
		return declared_counts(data, size, faces, vertices, &cloud);
	} catch (const std::bad_alloc&) {
		return 0;
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

} // extern "C"
