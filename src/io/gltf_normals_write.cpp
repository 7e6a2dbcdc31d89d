/*
 * Writing the computed normals into the document (gltf_primitive.h): over
 * the NORMAL accessors where they allow it, else into new accessors; split
 * primitives' vertex data copied; Draco primitives encoded again (or
 * compressed with --draco on) through gltf_draco.cpp.
 */
#include "gltf_primitive.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace vn_gltf {

double write_unit(unsigned char* p, long long type, double v)
{
	if (type == 5126) {
		const float f = (float)v;
		memcpy(p, &f, 4);
		return f;
	}
	const double stored = (double)std::lround(std::max(-1.0, std::min(1.0, v)) * (type == 5120 ? 127 : 32767));
	write_component(p, type, stored);
	return stored;
}

/* Writes values (3 per element) over accessor a (float32, or normalized
 * byte/short), and its min/max when it has them. */
static void overwrite_vec3(document& d, long long index, const accessor& a, const std::vector<float>& values)
{
	std::vector<double> lo(3, INFINITY), hi(3, -INFINITY);
	const size_t size = component_size(a.component);
	for (size_t i = 0; i < values.size() / 3; ++i) {
		unsigned char* e = element_at(d, a.data, i);
		for (size_t c = 0; c < 3; ++c) {
			const double stored = write_unit(e + size * c, a.component, values[3 * i + c]);
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
static long long put_vec3(document& d, long long index, const std::vector<float>& values,
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
	return append_accessor(d, json{{"bufferView", append_view(d, std::move(data), 0, 34962)},
	                               {"componentType", 5126},
	                               {"count", values.size() / 3},
	                               {"type", "VEC3"}});
}

/* A copy of accessor `index` with p's split vertices appended (copies of
 * their input vertices), in a new bufferView; returns the new accessor. */
static long long split_accessor(document& d, long long index, const primitive& p)
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
	j["bufferView"] = append_view(d, std::move(data), stride == a.element ? 0 : stride, 34962);
	j["count"] = p.output_vertices();
	return append_accessor(d, j);
}

/* Points a split primitive's every attribute (and its morph targets') at
 * copies with the split vertices, and its indices at the new triangles.
 * A Draco-compressed primitive's attributes in the Draco data and its
 * indices are the Draco encoder's (write_draco): only the others are
 * copied here. */
static void write_split(document& d, const primitive& p)
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
	prim["indices"] = append_accessor(d, with_indices_label(d, prim,
	                                                        json{{"bufferView", append_view(d, std::move(data), 0, 34963)},
	                                                             {"componentType", 5125},
	                                                             {"count", p.split_triangles.size()},
	                                                             {"type", "SCALAR"}}));
	if (prim.contains("mode"))
		prim["mode"] = 4; /* strips and fans become triangle lists */
}

/* Writes p's normals and morph targets' NORMAL displacements (and, when
 * split, copies of all its vertex data). */
void normals_writer::write(primitive& p)
{
	const bool split = !p.split_source.empty(), compressed = p.draco != nullptr; /* write_draco releases p */
	if (split)
		write_split(d, p);
	if (compressed) {
		write_draco(d, p, o, st, draco);
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
	if (!compressed && o.draco == vn_gltf_draco_on)
		compress_draco(d, p, o, st, draco);
	if (split) /* its normals went into an accessor of its own: nothing compares them */
		std::vector<float>().swap(p.normals);
	p.release();
}

void normals_writer::finish()
{
	if (o.draco_normal_error)
		normal_errors(draco.quantized, o, st);
}

} // namespace vn_gltf
