/*
 * glTF 2.0 reading and writing: the C++ glue behind gltf.h.
 *
 * The original JSON is kept as an nlohmann::ordered_json so that key order,
 * extras and unknown extensions survive; only NORMAL data change (in place
 * where the accessor allows, else appended; Draco data are decoded and
 * encoded again with draco.h, meshopt-compressed bufferViews with
 * meshoptimizer). Buffers are read once and written once, in
 * place: a GLB's BIN chunk stays in the memory the file was read into, and
 * the output is written from it piece by piece. tinygltf 2.7's loader is not
 * used for this because it copies every buffer into its model (twice the
 * file in memory, half the time of a conversion: docs/PERFORMANCE.md);
 * vn checks everything it reads itself, data URIs included (RFC 2397).
 * One file per stage, each calling only those above it here:
 *
 *  - gltf_document.cpp: loading, accessors, appending (gltf_document.h);
 *  - gltf_meshopt.cpp: EXT_/KHR_meshopt_compression, on meshoptimizer;
 *  - gltf_draco.cpp: the KHR_draco_mesh_compression bridge, on draco.h;
 *  - gltf_save.cpp: writing .gltf and .glb;
 *  - gltf_prune.cpp: removing what the edits leave unused;
 *  - gltf_normals.cpp: the triangle primitives and their normals
 *    (gltf_primitive.h);
 *  - gltf_normals_write.cpp: the normals written into the document;
 *  - gltf_mesh.cpp: glTF to and from vn_io_mesh (the vn_io format);
 *  - here: vn_gltf_convert, which runs the stages in order.
 */
#include "gltf.h"
#include "gltf_primitive.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

using namespace vn_gltf;

/* Whether p's material needs a tangent space that renderers cannot generate
 * without TANGENT: an anisotropy texture or a clearcoat normal map, and no
 * normal map to derive one from (the Khronos validator's
 * MESH_PRIMITIVE_NO_TANGENT_SPACE, an error). */
static bool needs_tangents(const document& d, const primitive& p)
{
	const json* m = material_of(d, p);
	if (!m || m->contains("normalTexture"))
		return false;
	auto ext = m->find("extensions");
	if (ext == m->end() || !ext->is_object())
		return false;
	auto has = [&](const char* extension, const char* texture) {
		auto e = ext->find(extension);
		return e != ext->end() && e->is_object() && e->contains(texture);
	};
	return has("KHR_materials_anisotropy", "anisotropyTexture") || has("KHR_materials_clearcoat", "clearcoatNormalTexture");
}

extern "C" vn_io_result vn_gltf_convert(const char* in, const char* out, int out_glb, const vn_gltf_options* options,
                                        vn_gltf_stats* stats, vn_io_error* error)
{
	vn_gltf_stats st;
	memset(&st, 0, sizeof st);
	vn_io_result r = guarded(in, error, [&] {
		document d = load(in);
		snprintf(st.warnings, sizeof st.warnings, "%s", warning_lines(d).c_str());
		const usage before = used(d.j);
		const std::set<std::string> meshopt = decode_meshopt(d, &st);
		if (options->draco == vn_gltf_draco_off)
			decompress_draco(d);
		std::vector<primitive> prims = triangle_primitives(d, &st, false);
		for (const primitive& p : prims) {
			if (!options->drop_tangents || !p.tangent)
				continue;
			if (needs_tangents(d, p)) {
				++st.tangents_needed;
			} else {
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
		}
		/* Each group written as soon as computed: what it held is then freed.
		 * Primitives that draw one vertex array with one NORMAL accessor
		 * (Cesium's batched tiles, one primitive per material) are computed
		 * together over it, in the first one's turn: a vertex two of them
		 * use is one vertex, with the one normal the accessor holds. */
		const bool weld_mesh = options->weld_mesh && !options->no_weld;
		std::map<long long, std::vector<size_t>> by_normal;
		if (!weld_mesh)
			for (size_t i = 0; i < prims.size(); ++i)
				if (prims[i].normal >= 0)
					by_normal[prims[i].normal].push_back(i);
		std::vector<bool> done(prims.size(), false);
		normals_writer writer(d, *options, st);
		for (size_t i = 0; i < prims.size(); ++i) {
			if (done[i])
				continue;
			std::vector<primitive*> group;
			if (weld_mesh) {
				for (size_t k = i; k < prims.size() && prims[k].mesh == prims[i].mesh; ++k)
					group.push_back(&prims[k]), done[k] = true;
			} else {
				group.push_back(&prims[i]);
				if (prims[i].normal >= 0)
					for (size_t k : by_normal[prims[i].normal])
						if (k > i && !done[k] && same_vertex_array(prims[i], prims[k]))
							group.push_back(&prims[k]), done[k] = true;
			}
			compute_group(group, *options, st);
			for (primitive* p : group)
				writer.write(*p);
		}
		writer.finish();
		/* What reading and computing held is not needed to write the file. */
		std::vector<primitive>().swap(prims);
		write_meshopt(d, options->meshopt, st);
		std::string unknown;
		prune(d, before, st, &unknown);
		tidy_meshopt(d, meshopt);
		snprintf(st.unpruned_extension, sizeof st.unpruned_extension, "%s", unknown.c_str());
		/* OUT may be a link: the buffers and images go beside what it
		 * points at, where the .gltf itself lands. */
		char* target = nullptr;
		vn_io_error e;
		if (vn_io_output_check(out, &target, &e) != vn_io_success)
			fail_named(vn_io_error_write, e.message);
		const std::string resolved = target;
		free(target);
save(d, resolved, out_glb != 0, vn_io_same_file(in, out), options->image_names_from_output != 0);
	});
	if (stats)
		*stats = st;
	return r;
}
