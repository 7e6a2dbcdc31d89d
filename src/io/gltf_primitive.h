/*
 * The triangle primitives of a glTF document as the normals stages see
 * them (C++ only, internal to vn_io): their positions, triangles and input
 * normals (views into the buffers or the decoded Draco data), and the
 * stages that work on them: the KHR_draco_mesh_compression bridge
 * (gltf_draco.cpp), the normals plan (gltf_normals.cpp) and writing the
 * normals into the document (gltf_normals_write.cpp). Built on
 * gltf_document.h.
 */
#ifndef VN_IO_GLTF_PRIMITIVE_H
#define VN_IO_GLTF_PRIMITIVE_H

#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "gltf_document.h"
#include "split_normals.h"

namespace vn_gltf {

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
	void load(size_t i, double out[3]) const { vn_split::load(view, i, out); }
	void append_to(std::vector<double>& to) const
	{
		const size_t first = to.size();
		to.resize(first + 3 * size());
		for (size_t i = 0; i < size(); ++i)
			load(i, &to[first + 3 * i]);
	}
};

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
	/* Frees what only computing and writing the normals need (the
	 * geometry, the Draco data unless another primitive shares them,
	 * input normals, split and morphed positions) once p is written: the
	 * normals stay, for primitives sharing a NORMAL accessor to compare. */
	void release()
	{
		positions = vec3s();
		triangles = corners();
		input_normals = vec3s();
		std::vector<std::vector<double>>().swap(target_positions);
		std::vector<uint32_t>().swap(split_source);
		std::vector<uint32_t>().swap(split_triangles);
		draco.reset();
	}
	size_t output_vertices() const { return vertices() + split_source.size(); }
	/* The triangles on the output vertices. */
	corners output_triangles() const
	{
		return split_source.empty() ? corners(triangles.data(), triangles.size())
		                            : corners(split_triangles.data(), split_triangles.size());
	}
};

inline json& mesh_primitive(document& d, const primitive& p)
{
	return d.j["meshes"][p.mesh]["primitives"][p.index];
}

/* p's material object, or null where it has none (or its index is none). */
inline const json* material_of(const document& d, const primitive& p)
{
	const json& prim = d.j["meshes"][p.mesh]["primitives"][p.index];
	auto material = prim.find("material");
	auto materials = d.j.find("materials");
	if (material == prim.end() || !material->is_number_integer() || materials == d.j.end() || !materials->is_array() ||
	    material->get<long long>() < 0 || (size_t)material->get<long long>() >= materials->size())
		return nullptr;
	const json& m = (*materials)[(size_t)material->get<long long>()];
	return m.is_object() ? &m : nullptr;
}

/* Draco primitives written, per normal quantization bits: their positions,
 * new normals and triangles, for the --stats quantization error. */
struct quantized_normals {
	std::vector<double> positions, normals;
	std::vector<uint32_t> indices;
};

/* What writing Draco primitives gathers: the --stats data per normal bits
 * (with --stats only), and the POSITION accessors given the bounds of
 * positions decoded anew (primitives may share one, each with its own data). */
struct draco_written {
	std::map<int, quantized_normals> quantized;
	std::set<long long> bounded;
};

/* Decoded Draco data by extension object (its JSON text). */
using draco_cache = std::map<std::string, std::shared_ptr<const draco_mesh>>;

/* ------------------------------------------------------------------ Draco (gltf_draco.cpp) */

/* Primitive prim's Draco data decoded (through cache, when not null) and
 * checked; see gltf_draco.cpp. */
std::shared_ptr<const draco_mesh> decode_draco(const document& d, const json& prim, const json& ext, const std::string& what,
                                               draco_cache* cache);

/* --draco off: every Draco-compressed primitive written uncompressed. */
void decompress_draco(document& d);

/* Draco primitive p encoded again with its new normals; p is released,
 * its normals too. */
void write_draco(document& d, primitive& p, const vn_gltf_options& o, vn_gltf_stats& st, draco_written& w);

/* --draco on: p Draco-compressed. */
void compress_draco(document& d, const primitive& p, const vn_gltf_options& o, vn_gltf_stats& st, draco_written& w);

/* --stats: the angle normal quantization adds, per normal bits. */
void normal_errors(const std::map<int, quantized_normals>& quantized, const vn_gltf_options& o, vn_gltf_stats& st);

/* ------------------------------------------------------------------ normals (gltf_normals.cpp) */

/* Reads the triangle primitives, and where points is set the POINTS ones
 * (not Draco-compressed) as primitives of vertices without triangles;
 * counts the others (st may be null). */
std::vector<primitive> triangle_primitives(const document& d, vn_gltf_stats* st, bool points);

/* Whether a and b draw one vertex array with one normal a vertex: neither
 * Draco-compressed, the same POSITION and NORMAL accessors, and the same
 * morph targets. */
inline bool same_vertex_array(const primitive& a, const primitive& b)
{
	return !a.draco && !b.draco && a.normal >= 0 && a.position == b.position && a.normal == b.normal &&
	       a.target_normal == b.target_normal && a.target_positions == b.target_positions;
}

/* The normals of a group of primitives (one, primitives on one vertex
 * array, or a whole mesh): their vertex arrays joined, each once, so that a
 * vertex primitives on one array share has one normal. */
void compute_group(std::vector<primitive*>& prims, const vn_gltf_options& o, vn_gltf_stats& st);

/* ------------------------------------------------------------------ into the document (gltf_normals_write.cpp) */

/* v (a unit vector's component) stored at p as a float32, or as a
 * normalized int8 or int16 (type); returns the stored value. */
double write_unit(unsigned char* p, long long type, double v);

/* Writes primitives' normals and morph targets' NORMAL displacements, in
 * the primitives' order, each released once written; finish() after the
 * last. */
struct normals_writer {
	document& d;
	const vn_gltf_options& o;
	vn_gltf_stats& st;
	std::map<long long, const std::vector<float>*> written; /* NORMAL accessors written over, with what */
	draco_written draco;
	normals_writer(document& doc, const vn_gltf_options& options, vn_gltf_stats& stats) : d(doc), o(options), st(stats) {}
	void write(primitive& p);
	void finish();
};

} // namespace vn_gltf

#endif /* VN_IO_GLTF_PRIMITIVE_H */
