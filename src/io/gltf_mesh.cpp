/*
 * glTF as a vn_io format (gltf.h): every triangle and POINTS primitive of a
 * document merged into one vn_io_mesh (vn_io_gltf_read), and a minimal glTF
 * or GLB written from a vn_io_mesh (vn_io_gltf_write, vn_io_glb_write).
 */
#include "gltf.h"
#include "gltf_primitive.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>

namespace vn_gltf {

/* The values of attribute `name` of primitive p (decoded Draco data or its
 * accessor), as doubles, with its type; false when p lacks it. */
static bool attribute_values(const document& d, const primitive& p, const std::string& name, std::vector<double>& values,
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

/* A 4x4 matrix, column-major as glTF stores it. */
typedef std::array<double, 16> matrix;
static const matrix IDENTITY{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

static matrix product(const matrix& a, const matrix& b)
{
	matrix c{};
	for (int col = 0; col < 4; ++col)
		for (int row = 0; row < 4; ++row)
			for (int k = 0; k < 4; ++k)
				c[4 * col + row] += a[4 * k + row] * b[4 * col + k];
	return c;
}

/* The numbers of node[key] (n of them), or false when it has none. */
static bool numbers(const json& node, const char* key, size_t n, double* out, const std::string& what)
{
	auto it = node.find(key);
	if (it == node.end())
		return false;
	if (!it->is_array() || it->size() != n)
		fail(vn_io_error_parse, str("%s.%s is not an array of %zu numbers", what.c_str(), key, n));
	for (size_t i = 0; i < n; ++i) {
		if (!(*it)[i].is_number() || !std::isfinite((*it)[i].get<double>()))
			fail(vn_io_error_parse, str("%s.%s[%zu] is not a finite number", what.c_str(), key, i));
		out[i] = (*it)[i].get<double>();
	}
	return true;
}

/* A node's local transform: its matrix, else T * R * S. */
static matrix local_transform(const json& node, const std::string& what)
{
	matrix m{};
	if (numbers(node, "matrix", 16, m.data(), what))
		return m;
	double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, sc[3] = {1, 1, 1};
	numbers(node, "translation", 3, t, what);
	numbers(node, "rotation", 4, q, what);
	numbers(node, "scale", 3, sc, what);
	const double x = q[0], y = q[1], z = q[2], w = q[3];
	const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
	                     2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
	                     2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)}; /* columns */
	for (int col = 0; col < 3; ++col)
		for (int row = 0; row < 3; ++row)
			m[4 * col + row] = r[3 * col + row] * sc[col];
	m[12] = t[0], m[13] = t[1], m[14] = t[2], m[15] = 1;
	return m;
}

/* A primitive (index into the document's triangle primitives) where it is
 * drawn: with the world transform of a node that instances its mesh, or
 * as it is (placed == false). */
struct placement {
	size_t k;
	bool placed = false;
	matrix world{};
	double normal[9] = {}; /* inverse transpose of world's upper 3x3, columns */
	bool mirrored = false; /* negative determinant: the winding turns over */
	size_t first = 0;      /* its first vertex in the mesh */
	bool owner = true;     /* false: its vertices are an earlier placement's */
};

/* Every node of the default scene (scene, else scenes[0], else every root
 * node) with a mesh, in depth-first order, with its world transform. */
static void scene_meshes(const document& d, std::vector<std::pair<size_t, matrix>>& out)
{
	auto nodes = d.j.find("nodes");
	if (nodes == d.j.end())
		return;
	if (!nodes->is_array())
		fail(vn_io_error_parse, "nodes is not an array");
	std::vector<long long> roots;
	auto scenes = d.j.find("scenes");
	if (scenes != d.j.end() && scenes->is_array() && !scenes->empty()) {
		const long long s = get_int(d.j, "scene", 0, "the document");
		const json& scene = element(d.j, "scenes", s, "scene");
		if (scene.is_object() && scene.contains("nodes")) {
			if (!scene["nodes"].is_array())
				fail(vn_io_error_parse, str("scenes[%lld].nodes is not an array", s));
			for (const json& n : scene["nodes"])
				roots.push_back(n.is_number_integer() ? n.get<long long>() : -1);
		}
	} else {
		std::vector<bool> child(nodes->size(), false);
		for (const json& node : *nodes)
			if (node.is_object() && node.contains("children") && node["children"].is_array())
				for (const json& c : node["children"])
					if (c.is_number_integer() && c.get<long long>() >= 0 && (size_t)c.get<long long>() < child.size())
						child[(size_t)c.get<long long>()] = true;
		for (size_t i = 0; i < child.size(); ++i)
			if (!child[i])
				roots.push_back((long long)i);
	}
	/* glTF's nodes form trees: a node met twice on one path is a cycle.
	 * Depth first with a stack of its own, not recursion: a chain of many
	 * nodes is a valid file, and must not overflow the call stack. */
	struct frame {
		long long node;
		matrix world;
		size_t child; /* the next child to visit */
	};
	std::vector<frame> path;
	std::vector<bool> on_path(nodes->size(), false);
	auto enter = [&](long long i, const matrix& parent) {
		const std::string what = str("nodes[%lld]", i);
		const json& node = element(d.j, "nodes", i, what);
		if (on_path[(size_t)i])
			fail(vn_io_error_parse, what + " is its own ancestor (the node hierarchy has a cycle)");
		on_path[(size_t)i] = true;
		const matrix world = product(parent, local_transform(node, what));
		if (node.contains("mesh"))
			out.emplace_back((size_t)get_int(node, "mesh", 0, what), world);
		if (node.contains("children") && !node["children"].is_array())
			fail(vn_io_error_parse, what + ".children is not an array");
		path.push_back(frame{i, world, 0});
	};
	for (long long r : roots) {
		enter(r, IDENTITY);
		while (!path.empty()) {
			const json& node = (*nodes)[(size_t)path.back().node];
			auto children = node.find("children");
			if (children != node.end() && path.back().child < children->size()) {
				const json& c = (*children)[path.back().child++];
				const matrix world = path.back().world; /* enter grows path */
				enter(c.is_number_integer() ? c.get<long long>() : -1, world);
			} else {
				on_path[(size_t)path.back().node] = false;
				path.pop_back();
			}
		}
	}
}

/* Where each primitive goes: once each, as it is; or (scene) once per node
 * of the default scene that instances its mesh, transformed. */
static std::vector<placement> placements(const document& d, const std::vector<primitive>& prims, bool scene)
{
	std::vector<placement> out;
	if (!scene) {
		for (size_t k = 0; k < prims.size(); ++k)
			out.push_back(placement{k});
		return out;
	}
	std::vector<std::pair<size_t, matrix>> instances;
	scene_meshes(d, instances);
	for (const auto& in : instances)
		for (size_t k = 0; k < prims.size(); ++k) {
			if (prims[k].mesh != in.first)
				continue;
			placement p{k};
			p.placed = true;
			p.world = in.second;
			const matrix& m = p.world;
			/* Cofactors of the upper 3x3 are its inverse transpose times the
			 * determinant, whose sign alone matters once normalized. */
			auto a = [&](int row, int col) { return m[4 * col + row]; };
			for (int col = 0; col < 3; ++col)
				for (int row = 0; row < 3; ++row) {
					const int r1 = (row + 1) % 3, r2 = (row + 2) % 3, c1 = (col + 1) % 3, c2 = (col + 2) % 3;
					p.normal[3 * col + row] = a(r1, c1) * a(r2, c2) - a(r1, c2) * a(r2, c1);
				}
			const double det = a(0, 0) * p.normal[0] + a(0, 1) * p.normal[3] + a(0, 2) * p.normal[6];
			p.mirrored = det < 0;
			if (p.mirrored)
				for (double& x : p.normal)
					x = -x;
			out.push_back(p);
		}
	return out;
}

/* Without --apply-transforms, where the default scene draws its meshes
 * elsewhere than in their own coordinates (a node transform other than the
 * identity, a mesh drawn twice or by no node), the output is not the scene
 * as viewers show it: named, with the option that writes it so. A scene
 * vn cannot follow (a node cycle, a bad index) is not named: the meshes
 * are read as they are, and the option fails naming the fault. */
static void note_unapplied_transforms(document& d, const std::vector<primitive>& prims)
{
	std::vector<std::pair<size_t, matrix>> instances;
	try {
		scene_meshes(d, instances);
	} catch (const failure&) {
		return;
	}
	std::map<size_t, size_t> drawn; /* mesh -> instances */
	size_t moved = 0, instanced = 0;
	for (const primitive& p : prims)
		drawn[p.mesh] = 0;
	for (const auto& in : instances)
		if (drawn.count(in.first)) {
			++drawn[in.first], ++instanced;
			moved += in.second != IDENTITY;
		}
	size_t twice = 0, never = 0;
	for (const auto& m : drawn)
		twice += m.second > 1, never += m.second == 0;
	std::string how;
	if (moved)
		how += str("%zu of %zu mesh instances with a node transform", moved, instanced);
	if (twice)
		how += str("%s%zu mesh%s more than once", how.empty() ? "" : ", ", twice, twice > 1 ? "es" : "");
	if (never)
		how += str("%s%zu mesh%s by no node", how.empty() ? "" : ", ", never, never > 1 ? "es" : "");
	if (!how.empty())
		d.warnings.push_back("node transforms not applied: each mesh is written once, in its own coordinates, "
		                     "where the scene draws " + how + " (--apply-transforms writes the scene as drawn)");
}

/* n for an attribute named TEXCOORD_n (n of 1 to 5 digits), else -1. */
static long long texcoord_set(const std::string& name)
{
	if (name.rfind("TEXCOORD_", 0) != 0 || name.size() < 10 || name.size() > 14 ||
	    name.find_first_not_of("0123456789", 9) != std::string::npos)
		return -1;
	return std::stoll(name.substr(9));
}

/* The KHR_texture_transform that p's material gives texture coordinate set
 * n, as the 2x3 matrix T R S of its offset, rotation and scale (row-major:
 * u' = m[0] u + m[1] v + m[2], v' = m[3] u + m[4] v + m[5]), or false. The
 * first of the material's textures that reads set n decides (base colour
 * first): gltfpack quantizes texture coordinates and puts the
 * dequantization there, so in a format without materials the coordinates
 * are those the transform gives. A transform whose numbers are not finite
 * is none. */
static bool uv_transform(const document& d, const primitive& p, long long n, double m[6])
{
	const json* material = material_of(d, p);
	if (!material)
		return false;
	const json& mat = *material;
	static const char* const pbr[] = {"baseColorTexture", "metallicRoughnessTexture"};
	static const char* const own[] = {"normalTexture", "occlusionTexture", "emissiveTexture"};
	std::vector<const json*> infos;
	auto add = [&](const json& owner, const char* key) {
		auto info = owner.find(key);
		if (info != owner.end() && info->is_object())
			infos.push_back(&*info);
	};
	auto metal = mat.find("pbrMetallicRoughness");
	if (metal != mat.end() && metal->is_object())
		for (const char* key : pbr)
			add(*metal, key);
	for (const char* key : own)
		add(mat, key);
	auto number = [](const json& o, const char* key, size_t i, double fallback) {
		auto x = o.find(key);
		if (x == o.end())
			return fallback;
		const json& e = x->is_array() ? (i < x->size() ? (*x)[i] : json()) : *x;
		return e.is_number() ? e.get<double>() : NAN;
	};
	for (const json* info : infos) {
		const json* t = nullptr;
		auto ext = info->find("extensions");
		if (ext != info->end() && ext->is_object() && ext->contains("KHR_texture_transform") &&
		    (*ext)["KHR_texture_transform"].is_object())
			t = &(*ext)["KHR_texture_transform"];
		const double set = t && t->contains("texCoord") ? number(*t, "texCoord", 0, 0) : number(*info, "texCoord", 0, 0);
		if (set != (double)n)
			continue;
		if (!t)
			return false;
		const double ox = number(*t, "offset", 0, 0), oy = number(*t, "offset", 1, 0), r = number(*t, "rotation", 0, 0);
		const double sx = number(*t, "scale", 0, 1), sy = number(*t, "scale", 1, 1), c = std::cos(r), s = std::sin(r);
		const double out[6] = {c * sx, s * sy, ox, -s * sx, c * sy, oy};
		if (!std::all_of(out, out + 6, [](double x) { return std::isfinite(x); }))
			return false;
		std::copy(out, out + 6, m);
		return true;
	}
	return false;
}

/* glTF's texture coordinates have their origin at the image's top left;
 * OBJ's, PLY's, OFF's and Draco files' at its bottom left, as a mesh holds
 * them: v becomes 1 - v between the two, as Blender's glTF importer and
 * exporter and Draco's glTF decoder (draco/io/gltf_decoder.h) do. A value
 * as its type stores it: a float 1 - v, a normalized unsigned integer
 * max - k (exact, so that it flips back); other types are no [0, 1]
 * coordinate and stay. */
static double flip_v(double v, long long component, bool normalized)
{
	if (component == 5126)
		return 1.0 - v;
	if (normalized && (component == 5121 || component == 5123))
		return (component == 5121 ? 255.0 : 65535.0) - v;
	return v;
}

/* Whether placements a and b give the same vertices: one vertex array (the
 * same accessor for every attribute) drawn by two primitives, as Cesium's
 * batched tiles draw one with a primitive per material, placed alike and
 * under the same texture transforms. */
static bool same_vertices(const document& d, const std::vector<primitive>& prims, const placement& a, const placement& b)
{
	const primitive &p = prims[a.k], &q = prims[b.k];
	if (p.draco || q.draco || p.position != q.position || a.placed != b.placed || (a.placed && a.world != b.world))
		return false;
	const json& attributes = d.j["meshes"][p.mesh]["primitives"][p.index]["attributes"];
	if (attributes != d.j["meshes"][q.mesh]["primitives"][q.index]["attributes"])
		return false;
	for (auto& kv : attributes.items()) {
		const long long set = texcoord_set(kv.key());
		double ma[6] = {}, mb[6] = {};
		if (set >= 0 && (uv_transform(d, p, set, ma) != uv_transform(d, q, set, mb) || !std::equal(ma, ma + 6, mb)))
			return false;
	}
	return true;
}

/* Each placement's first vertex in the mesh: after the vertices before it,
 * or an earlier placement's where both give the same vertices; returns the
 * vertex count. */
static size_t lay_out(const document& d, const std::vector<primitive>& prims, std::vector<placement>& at)
{
	std::map<long long, std::vector<size_t>> owners; /* by POSITION accessor */
	size_t vertices = 0;
	for (size_t i = 0; i < at.size(); ++i) {
		placement& pl = at[i];
		std::vector<size_t>& same_position = owners[prims[pl.k].position];
		for (size_t j : same_position)
			if (same_vertices(d, prims, at[j], pl)) {
				pl.first = at[j].first;
				pl.owner = false;
				break;
			}
		if (!pl.owner)
			continue;
		pl.first = vertices;
		vertices += prims[pl.k].vertices();
		same_position.push_back(i);
	}
	return vertices;
}

/* Every triangle primitive merged into one mesh, and every POINTS one (not
 * Draco-compressed) as vertices without faces: positions, triangles,
 * NORMAL into normals (when any primitive has it), the first colour set
 * (COLOR_0) into colors, TEXCOORD_0 into texcoords, every other vertex
 * attribute (TEXCOORD_n, COLOR_n, JOINTS_n, WEIGHTS_n, TANGENT, _NAME)
 * into attributes in its own type, texture coordinates with v flipped
 * (flip_v); a primitive without an attribute another one has gets zeros
 * there. */
static void mesh_from_document(document& d, vn_io_mesh* mesh, bool scene)
{
	vn_gltf_stats st{};
	std::vector<primitive> prims = triangle_primitives(d, &st, true);
	/* Another format holds the triangles and points alone: what is left out
	 * is named. */
	const size_t skipped[3] = {st.skipped_points, st.skipped_lines, st.skipped_no_position};
	static const char* const kinds[3] = {"POINTS compressed with Draco", "LINES (or LINE_LOOP, LINE_STRIP)",
	                                     "without POSITION"};
	std::string left_out;
	for (int k = 0; k < 3; ++k)
		if (skipped[k])
			left_out += str("%s%zu %s", left_out.empty() ? "" : ", ", skipped[k], kinds[k]);
	if (!left_out.empty())
		d.warnings.push_back("primitives left out (vn reads triangles and points): " + left_out);
	if (!scene)
		note_unapplied_transforms(d, prims);
	std::vector<placement> at = placements(d, prims, scene);
	const size_t vertices = lay_out(d, prims, at);
	size_t triangles = 0;
	for (const placement& pl : at)
		triangles += prims[pl.k].triangles.size() / 3;
	if (vertices > UINT32_MAX || 3 * triangles > UINT32_MAX)
		fail(vn_io_error_unsupported, "the meshes have more than 2^32 vertices or indices");
	mesh->vertex_count = vertices;
	mesh->face_count = triangles;
	mesh->positions = (double*)malloc(3 * sizeof(double) * (vertices ? vertices : 1));
	mesh->indices = (uint32_t*)malloc(3 * sizeof(uint32_t) * (triangles ? triangles : 1));
	mesh->face_offsets = (uint32_t*)malloc(sizeof(uint32_t) * (triangles + 1));
	if (!mesh->positions || !mesh->indices || !mesh->face_offsets)
		fail(vn_io_error_memory, "out of memory");
	size_t t = 0;
	for (const placement& pl : at) {
		const primitive& p = prims[pl.k];
		const size_t v = pl.first;
		for (size_t i = 0; pl.owner && i < p.vertices(); ++i) {
			double* x = mesh->positions + 3 * (v + i);
			p.positions.load(i, x);
			if (pl.placed) {
				const double y[3] = {x[0], x[1], x[2]};
				for (int r = 0; r < 3; ++r)
					x[r] = pl.world[r] * y[0] + pl.world[4 + r] * y[1] + pl.world[8 + r] * y[2] + pl.world[12 + r];
			}
		}
		for (size_t c = 0; c < p.triangles.size(); ++c)
			/* A mirrored triangle is wound the other way round to face out. */
			mesh->indices[t++] = (uint32_t)(v + p.triangles[pl.mirrored && c % 3 ? c + 3 - 2 * (c % 3) : c]);
	}
	for (size_t f = 0; f <= triangles; ++f)
		mesh->face_offsets[f] = (uint32_t)(3 * f);
	/* The input's normals, which a vertex no face gives a normal keeps
	 * (zeros where a primitive has none). */
	if (std::any_of(prims.begin(), prims.end(), [](const primitive& p) { return !p.input_normals.empty(); })) {
		mesh->normals = (double*)calloc(3 * (vertices ? vertices : 1), sizeof(double));
		if (!mesh->normals)
			fail(vn_io_error_memory, "out of memory");
		for (const placement& pl : at) {
			const primitive& p = prims[pl.k];
			for (size_t i = 0; pl.owner && i < p.input_normals.size(); ++i) {
				double* n = mesh->normals + 3 * (pl.first + i);
				p.input_normals.load(i, n);
				if (pl.placed) {
					const double y[3] = {n[0], n[1], n[2]};
					for (int r = 0; r < 3; ++r)
						n[r] = pl.normal[r] * y[0] + pl.normal[3 + r] * y[1] + pl.normal[6 + r] * y[2];
					const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
					for (int r = 0; r < 3 && l > 0; ++r)
						n[r] /= l;
				}
			}
		}
	}

	/* Attribute names in first-seen order. */
	std::vector<std::string> names;
	for (const placement& pl : at)
		for (auto& kv : d.j["meshes"][prims[pl.k].mesh]["primitives"][prims[pl.k].index]["attributes"].items())
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
		const int semantic = name.rfind("TEXCOORD_", 0) == 0 ? vn_io_semantic_texcoord
		                     : name.rfind("COLOR_", 0) == 0  ? vn_io_semantic_color
		                                                     : vn_io_semantic_generic;
		/* A texture coordinate set under its material's transform
		 * (uv_transform): the transformed coordinates, as floats. */
		std::vector<std::array<double, 6>> transform(prims.size());
		std::vector<bool> transformed(prims.size(), false);
		const long long set = texcoord_set(name);
		if (set >= 0 && type.components == 2)
			for (size_t k = 0; k < prims.size(); ++k)
				if (has[k] && types[k].components == 2 && uv_transform(d, prims[k], set, transform[k].data())) {
					transformed[k] = true;
					type.component = 5126;
					type.normalized = false;
				}
		const bool color = name == "COLOR_0" && (type.components == 3 || type.components == 4);
		const bool texcoord = name == "TEXCOORD_0" && type.components == 2;
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
		for (const placement& pl : at) {
			const size_t j = pl.k, v = pl.first;
			const primitive& p = prims[j];
			const accessor& here = types[j];
			if (!pl.owner)
				continue;
			if (has[j])
				for (size_t i = 0; i < p.vertices(); ++i)
					for (size_t c = 0; c < k; ++c) {
						/* Colours and texture coordinates as the floats they
						 * stand for; other attributes in their own type. */
						const bool have = c < here.components;
						double x = have ? values[j][i * here.components + c] : 1.0; /* missing alpha: opaque */
						if ((floats || type.component == 5126) && have && here.normalized)
							x = normalized_value(x, here.component);
						if (transformed[j] && c < 2) {
							const double* u = &values[j][i * here.components];
							const double* m = transform[j].data();
							const double u0 = here.normalized ? normalized_value(u[0], here.component) : u[0];
							const double u1 = here.normalized ? normalized_value(u[1], here.component) : u[1];
							x = m[3 * c] * u0 + m[3 * c + 1] * u1 + m[3 * c + 2];
						}
						if (semantic == vn_io_semantic_texcoord && k == 2 && c == 1 && have)
							x = flip_v(x, floats ? 5126 : type.component, type.normalized);
						if (floats)
							floats[(v + i) * k + c] = (float)x;
						else if (have)
							write_component((unsigned char*)a->data + ((v + i) * k + c) * csize, type.component, x);
					}
			else if (color)
				for (size_t i = 0; i < p.vertices(); ++i)
					std::fill_n(&floats[(v + i) * 4], 4, 1.0f); /* white where a primitive has no colours */
		}
		if (color && !mesh->colors_are_bytes) /* float or unsigned short colours made from bytes */
			mesh->colors_are_bytes = vn_io_colors_are_bytes(mesh->colors, vertices);
	}
}

/* glTF's name for mesh attribute a, given the TEXCOORD_n and COLOR_n sets
 * already written (numbered on from them: glTF wants them consecutive), or
 * "" when glTF cannot hold it as such: TEXCOORD is VEC2, COLOR VEC3/VEC4,
 * of float or normalized unsigned byte/short; an application-specific name
 * starts with '_'. */
static std::string gltf_name(const vn_io_attribute& a, int* texcoords, int* colors)
{
	const bool allowed = a.component_type == 5126 || (a.normalized && (a.component_type == 5121 || a.component_type == 5123));
	if (a.semantic == vn_io_semantic_texcoord && a.components == 2 && allowed)
		return str("TEXCOORD_%d", (*texcoords)++);
	if (a.semantic == vn_io_semantic_color && (a.components == 3 || a.components == 4) && allowed)
		return str("COLOR_%d", (*colors)++);
	return a.name[0] == '_' ? std::string(a.name) : "_" + std::string(a.name);
}

/* s as the UTF-8 glTF's JSON must be: as it is where it is UTF-8, else
 * read as Latin-1 (names from older Windows tools: "caf\xe9"). */
static std::string utf8_text(const char* s)
{
	try {
		(void)json(s).dump();
		return s;
	} catch (const json::type_error&) {
		std::string out;
		for (const unsigned char* p = (const unsigned char*)s; *p; ++p)
			if (*p < 0x80)
				out += (char)*p;
			else
				out += (char)(0xC0 | (*p >> 6)), out += (char)(0x80 | (*p & 0x3F));
		return out;
	}
}

/* glTF's material for mesh material k: its name (utf8_text); where the
 * library defines it (vn_io_mtl_read), map_Kd as baseColorTexture, Kd where
 * there is none and d as baseColorFactor (opacity below 1: alpha mode
 * BLEND), the roughness, map_Bump as normalTexture (its -bm as scale),
 * map_Ke as emissiveTexture (factor 1), else Ke as emissiveFactor;
 * metallicFactor Pm, else 0: an OBJ describes no metal, and glTF's
 * default, 1, would make it one. The MTL specification multiplies map_Kd
 * by Kd, but exporters write Kd 0.8 beside a texture (Blender 2.8), and
 * Blender and obj2gltf read the texture alone (Ke likewise). texture_index
 * gives the index of a texture of image (path, jpeg). */
static json gltf_material(const vn_io_mesh* mesh, uint32_t k,
                          const std::function<size_t(const char*, int)>& texture_index)
{
	const vn_io_material* m = mesh->material_defs && mesh->material_defs[k].defined ? &mesh->material_defs[k] : nullptr;
	const auto texture = [&](int kind) { return m ? m->textures[kind] : nullptr; };
	json pbr = {{"metallicFactor", m ? m->metallic : 0.0}};
	double colour[4] = {1.0, 1.0, 1.0, 1.0};
	for (int c = 0; m && c < 4; ++c)
		colour[c] = c < 3 && texture(vn_io_texture_base) ? 1.0 : m->color[c];
	if (std::any_of(colour, colour + 4, [](double c) { return c != 1.0; }))
		pbr["baseColorFactor"] = {colour[0], colour[1], colour[2], colour[3]};
	if (m && m->roughness >= 0.0)
		pbr["roughnessFactor"] = m->roughness;
	if (texture(vn_io_texture_base))
		pbr["baseColorTexture"] = {{"index", texture_index(m->textures[0], m->jpeg[0])}};
	json out = {{"name", utf8_text(mesh->materials.names[k])}, {"pbrMetallicRoughness", pbr}};
	if (m && m->color[3] < 1.0)
		out["alphaMode"] = "BLEND";
	if (texture(vn_io_texture_normal)) {
		out["normalTexture"] = {{"index", texture_index(m->textures[1], m->jpeg[1])}};
		if (m->normal_scale != 1.0)
			out["normalTexture"]["scale"] = m->normal_scale;
	}
	if (texture(vn_io_texture_emissive)) {
		out["emissiveTexture"] = {{"index", texture_index(m->textures[2], m->jpeg[2])}};
		out["emissiveFactor"] = {1.0, 1.0, 1.0};
	} else if (m && std::any_of(m->emissive, m->emissive + 3, [](double c) { return c != 0.0; })) {
		out["emissiveFactor"] = {m->emissive[0], m->emissive[1], m->emissive[2]};
	}
	return out;
}

/* A minimal document for mesh: one node, one mesh, its vertices' POSITION,
 * NORMAL, COLOR_0 (vertex colours), TEXCOORD_0 (v flipped, as every
 * TEXCOORD_n: flip_v) and every other attribute (in its type; 32-bit
 * integers, which glTF allows only for indices, as floats), and on them
 * one TRIANGLES primitive per material (OBJ's: gltf_material; one without
 * material for faces that have none), or for a mesh without faces (a
 * point cloud) POINTS, every vertex a point, with NORMAL only where the
 * mesh has a normal other than zero (vn computes none without faces).
 * Texture images are embedded in the buffer. `indices` receives each
 * TRIANGLES primitive's, in order. */
static bytes document_from_mesh(const vn_io_mesh* mesh, json& j, std::vector<std::vector<uint32_t>>& indices)
{
	/* An empty mesh: a scene without nodes, as a glTF of no mesh is read. */
	if (mesh->vertex_count == 0) {
		j = json{{"asset", {{"version", "2.0"}, {"generator", "vn"}}},
		         {"scene", 0},
		         {"scenes", json::array({json::object()})}};
		return bytes();
	}
	const bool cloud = mesh->face_count == 0;
	/* The triangles of each material (VN_IO_NO_NAME: none), in the order
	 * of their first faces: a primitive each. */
	std::vector<uint32_t> keys;
	std::map<uint32_t, size_t> group;
	for (size_t f = 0; f < mesh->face_count; ++f) {
		const uint32_t key = mesh->materials.of_face ? mesh->materials.of_face[f] : VN_IO_NO_NAME;
		if (mesh->face_offsets[f + 1] - mesh->face_offsets[f] < 3)
			continue;
		auto at = group.emplace(key, keys.size()).first;
		if (at->second == keys.size())
			keys.push_back(key), indices.emplace_back();
		std::vector<uint32_t>& out = indices[at->second];
		for (uint32_t c = mesh->face_offsets[f] + 1; c + 1 < mesh->face_offsets[f + 1]; ++c)
			out.insert(out.end(), {mesh->indices[mesh->face_offsets[f]], mesh->indices[c], mesh->indices[c + 1]});
	}
	if (indices.empty() && !cloud)
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
	/* glTF's normals are unit vectors: one that is not (an input's normal a
	 * vertex without faces kept, from a format that allows any length) is
	 * normalized, and none (or zero, or not finite) is written as +Z. A
	 * unit vector is written as it is, bit for bit. A point cloud without
	 * normals gets none. */
	const bool normals =
	    !cloud || (mesh->normals && std::any_of(mesh->normals, mesh->normals + 3 * n, [](double x) { return x != 0.0; }));
	if (normals)
		add("NORMAL", 5126, 3, false, n, [&](size_t i, size_t c) {
			const double* v = mesh->normals ? &mesh->normals[3 * i] : nullptr;
			const double l = v ? std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) : 0;
			if (!(l > 0) || !std::isfinite(l))
				return c == 2 ? 1.0 : 0.0;
			return std::fabs(l - 1) <= 1e-6 ? v[c] : v[c] / l; }, false, 34962);
	int texcoords = 0, colors = 0;
	if (mesh->texcoords)
		add(str("TEXCOORD_%d", texcoords++), 5126, 2, false, n, [&](size_t i, size_t c) {
			    const double v = mesh->texcoords[2 * i + c];
			    return c == 1 ? flip_v(v, 5126, false) : v; }, false, 34962);
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
		/* glTF has 32-bit integers for indices only, and no double. */
		const bool wide = a.component_type == 5124 || a.component_type == 5125 || a.component_type == 5130;
		const std::string name = gltf_name(a, &texcoords, &colors);
		const bool texcoord = name.rfind("TEXCOORD_", 0) == 0;
		add(name, wide ? 5126 : a.component_type, (size_t)a.components, a.normalized && !wide, n, [&](size_t i, size_t c) {
			    const double v = read_component((const unsigned char*)a.data + (i * a.components + c) * csize, a.component_type, false);
			    return texcoord && c == 1 ? flip_v(v, a.component_type, a.normalized != 0) : v; },
		    false, 34962);
	}
	json primitives = json::array(), materials = json::array(), textures = json::array(), images = json::array();
	std::map<std::string, size_t> texture_of; /* an image file's texture */
	for (size_t k = 0; k < indices.size(); ++k) {
		const std::vector<uint32_t>& list = indices[k];
		add("", 5125, 1, false, list.size(), [&](size_t i, size_t) { return (double)list[i]; }, false, 34963);
		json primitive = {{"attributes", attributes}, {"indices", accessors.size() - 1}, {"mode", 4}};
		if (keys[k] != VN_IO_NO_NAME) {
			primitive["material"] = materials.size();
			materials.push_back(gltf_material(mesh, keys[k], [&](const char* path, int jpeg) {
				auto known = texture_of.find(path);
				if (known != texture_of.end())
					return known->second;
				char* data;
				size_t size;
				vn_io_error e;
				if (vn_io_read_all(path, &data, &size, &e) != vn_io_success)
					fail(vn_io_error_open, e.message);
				bin.resize((bin.size() + 3) / 4 * 4, 0);
				const size_t offset = bin.size();
				bin.insert(bin.end(), data, data + size);
				free(data);
				views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}});
				images.push_back({{"bufferView", views.size() - 1}, {"mimeType", jpeg ? "image/jpeg" : "image/png"}});
				textures.push_back({{"source", images.size() - 1}});
				return texture_of[path] = textures.size() - 1;
			}));
		}
		primitives.push_back(primitive);
	}
	if (cloud)
		primitives.push_back({{"attributes", attributes}, {"mode", 0}});
	j = json{{"asset", {{"version", "2.0"}, {"generator", "vn"}}},
	         {"scene", 0},
	         {"scenes", json::array({json{{"nodes", {0}}}})},
	         {"nodes", json::array({json{{"mesh", 0}}})},
	         {"meshes", json::array({json{{"primitives", primitives}}})}};
	if (!materials.empty())
		j["materials"] = materials;
	if (!textures.empty())
		j["textures"] = textures, j["images"] = images;
	j["accessors"] = accessors;
	j["bufferViews"] = views;
	j["buffers"] = json::array({json{{"byteLength", bin.size()}}});
	return bin;
}

/* --draco on for a document made from a mesh: each TRIANGLES primitive
 * (on the mesh's n vertices, its triangles `indices[k]`) Draco-compressed
 * with `bits` (compress_draco: only the vertices it uses), and the plain
 * data it replaces removed (prune). */
static void compress_primitives(document& d, size_t n, std::vector<std::vector<uint32_t>>& indices,
                                const vn_drc_options& bits)
{
	const usage before = used(d.j);
	vn_gltf_options o{};
	o.draco = vn_gltf_draco_on;
	o.draco_options = bits;
	vn_gltf_stats st{};
	draco_written w;
	/* Looked up anew each time: compressing one adds keys to the document. */
	const size_t count = d.j["meshes"][0]["primitives"].size();
	for (size_t k = 0, t = 0; k < count; ++k) {
		if (d.j["meshes"][0]["primitives"][k]["mode"] != 4)
			continue;
		primitive p;
		p.mesh = 0;
		p.index = k;
		/* Only the count matters to the encoder, which reads the accessors. */
		p.positions = vec3s(nullptr, n, 0, vn_scalar_float64);
		p.triangles = corners(std::move(indices[t++]));
		compress_draco(d, p, o, st, w);
	}
	std::string unknown;
	prune(d, before, st, &unknown);
}

/* The mesh as a glTF or GLB; Draco-compressed with `draco` (NULL: plain). */
static vn_io_result write_stream(FILE* out, const char* path, const vn_io_mesh* mesh, bool glb,
                                 const vn_drc_options* draco, vn_io_error* error)
{
	return guarded(path, error, [&] {
		document d;
		d.glb = glb;
		std::vector<std::vector<uint32_t>> indices;
		auto bin = std::make_shared<bytes>(document_from_mesh(mesh, d.j, indices));
		const bool data = d.j.contains("buffers"); /* else no BIN chunk, no buffer */
		if (data) {
			buffer b;
			b.owner = std::shared_ptr<unsigned char>(bin, bin->data());
			b.base = bin->data();
			b.size = bin->size();
			d.buffers.push_back(std::move(b));
			d.input_views = d.j["bufferViews"].size();
			if (draco)
				compress_primitives(d, mesh->vertex_count, indices, *draco);
		}
		pieces file;
		if (glb) {
			file = glb_file(d.j, data ? &d.buffers[0] : nullptr);
		} else {
			if (data) {
				pieces contents;
				contents.add(d.buffers[0], false);
				d.j["buffers"][0]["uri"] = data_uri(json::object(), contents.joined());
			}
			file.add(d.j.dump(2) + "\n");
		}
		for (const auto& piece : file.list)
			if (fwrite(piece.first, 1, piece.second, out) != piece.second)
				fail_named(vn_io_error_write, str("%s: cannot write: %s", path, strerror(errno)));
	});
}

static vn_io_result read_mesh(const char* path, vn_io_mesh* mesh, bool scene, vn_io_error* error)
{
	memset(mesh, 0, sizeof *mesh);
	vn_io_result r = guarded(path, error, [&] {
		document d = load(path);
		decode_meshopt(d, nullptr);
		mesh_from_document(d, mesh, scene);
		const std::string warnings = warning_lines(d);
		if (!warnings.empty() && !(mesh->warnings = strdup(warnings.c_str())))
			throw std::bad_alloc();
	});
	if (r != vn_io_success)
		vn_io_mesh_free(mesh);
	return r;
}

} // namespace vn_gltf

using namespace vn_gltf;

extern "C" vn_io_result vn_io_gltf_read(const char* path, vn_io_mesh* mesh, vn_io_error* error)
{
	return read_mesh(path, mesh, false, error);
}

extern "C" vn_io_result vn_io_gltf_read_scene(const char* path, vn_io_mesh* mesh, vn_io_error* error)
{
	return read_mesh(path, mesh, true, error);
}

extern "C" vn_io_result vn_io_gltf_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error)
{
	return write_stream(out, path, mesh, false, (const vn_drc_options*)settings, error);
}

extern "C" vn_io_result vn_io_glb_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error)
{
	return write_stream(out, path, mesh, true, (const vn_drc_options*)settings, error);
}
