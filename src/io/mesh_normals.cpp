/*
 * vn_io_mesh_normals (vn_io.h): the normals plan of split_normals.h on a
 * vn_io_mesh, its split vertices appended to every per-vertex array.
 */
#include "split_normals.h"
#include "vn_io.h"

#include <cstdlib>
#include <new>

namespace {

vn_io_result compute(vn_io_mesh* mesh, const char* path, const vn_io_normals_options& o, vn_io_normals_stats& st,
                     vn_io_error* error)
{
	auto failed = [&](vn_result r) {
		return vn_io_fail(error, r == vn_result_out_of_memory ? vn_io_error_memory : vn_io_error_parse, "%s: %s", path,
		                  vn_result_string(r));
	};
	const size_t n = mesh->vertex_count;
	/* A point cloud: no face gives a normal, and none is made up; zero
	 * vectors would be read as normals (CloudCompare shades such points
	 * black). */
	if (!mesh->face_count) {
		st.vertices = st.zero_normals = n;
		return vn_io_success;
	}
	static const uint32_t no_faces[1] = {0};
	vn_split::faces f;
	f.corners = mesh->indices;
	f.corner_count = mesh->face_count ? mesh->face_offsets[mesh->face_count] : 0;
	if (!vn_io_mesh_is_triangles(mesh)) {
		f.offsets = mesh->face_count ? mesh->face_offsets : no_faces;
		f.face_count = mesh->face_count;
	}
	const vn_positions pos = {mesh->positions, n, 0, vn_scalar_float64};
	const vn_positions input = {mesh->normals, mesh->normals ? n : 0, 0, vn_scalar_float64};
	vn_split::settings s;
	s.method = o.method;
	s.threads = o.threads;
	s.weld = !o.no_weld;
	s.weld_epsilon = o.weld_epsilon;
	s.crease = o.crease != 0;
	s.crease_angle = o.crease_angle;
	vn_split::plan g;
	std::vector<double> c, normals;
	vn_stats vs{};
	vn_result r = vn_split::make_plan(g, pos, f, input, s, c, &vs);
	if (r == vn_result_success)
		r = vn_split::normals(g, pos, normals, s.crease ? &c : nullptr, &vs);
	if (r != vn_result_success)
		return failed(r);
	std::vector<double>().swap(c);
	const size_t outputs = g.outputs();
	if (outputs > UINT32_MAX)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: splitting at the crease angle makes more than 2^32 vertices",
		                  path);
	for (size_t k = 0; k < outputs; ++k) {
		double* v = &normals[3 * k];
		if (v[0] != 0 || v[1] != 0 || v[2] != 0)
			continue;
		++st.zero_normals;
		if (mesh->normals)
			memcpy(v, &mesh->normals[3 * g.source(k)], 3 * sizeof(double));
	}
	double* out = static_cast<double*>(std::malloc(3 * sizeof(double) * (outputs ? outputs : 1)));
	if (!out)
		return failed(vn_result_out_of_memory);
	if (outputs) /* an empty mesh's vector has no data */
		memcpy(out, normals.data(), 3 * sizeof(double) * outputs);
	if (!g.extra_source.empty()) {
		/* Not the input's normals, which `out` replaces. */
		double* given = mesh->normals;
		mesh->normals = nullptr;
		const int grown = vn_io_mesh_append_vertices(mesh, g.extra_source.data(), g.extra_source.size());
		mesh->normals = given;
		if (!grown) {
			std::free(out);
			return failed(vn_result_out_of_memory);
		}
		memcpy(mesh->indices, g.corner_output.data(), sizeof(uint32_t) * f.corner_count);
	}
	std::free(mesh->normals);
	mesh->normals = out;
	st.vertices = n;
	st.faces = mesh->face_count;
	st.welded_vertices = g.welded_vertices;
	st.hard_edges = g.hard_edges;
	st.split_vertices = g.extra_source.size();
	st.degenerate_faces = vs.degenerate_faces;
	return vn_io_success;
}

} // namespace

extern "C" vn_io_result vn_io_mesh_normals(vn_io_mesh* mesh, const char* path, const vn_io_normals_options* options,
                                           vn_io_normals_stats* stats, vn_io_error* error)
{
	vn_io_normals_stats local;
	vn_io_normals_stats& st = stats ? *stats : local;
	memset(&st, 0, sizeof st);
	vn_io_normals_options defaults;
	memset(&defaults, 0, sizeof defaults);
	defaults.method = vn_method_mwa;
	try {
		return compute(mesh, path, options ? *options : defaults, st, error);
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	}
}
