/* Public entry points: version, names, argument checks and dispatch. */
#include <ctype.h>

#include "internal.h"
#include "simd.h"
#include "weights.h"

uint32_t vn_version(void)
{
	return VN_VERSION;
}

const char* vn_version_string(void)
{
	return VN_VERSION_STRING;
}

const char* vn_result_string(vn_result r)
{
	switch (r) {
	case vn_result_success:
		return "success";
	case vn_result_invalid_argument:
		return "invalid argument";
	case vn_result_index_out_of_range:
		return "index out of range";
	case vn_result_unknown_method:
		return "unknown method";
	case vn_result_out_of_memory:
		return "out of memory";
	default:
		return "unknown result";
	}
}

static const struct {
	const char* name;
	const char* description;
	const char* reference;
} methods[vn_method_count] = {
    {"mwe", "mean weighted equally: sum of unit face normals", "Gouraud 1971; Jin et al. 2005 eq. 1"},
    {"mwa", "mean weighted by angle: face normals times the corner angle",
     "Thurmer & Wuthrich 1998; Jin et al. 2005 eq. 2"},
    {"mwselr", "mean weighted by sine and edge length reciprocals: sin(a) / (|E||E'|)",
     "Max 1999; Jin et al. 2005 eq. 4"},
    {"mwaat", "mean weighted by areas of adjacent triangles: |E x E'|", "Max 1999; Jin et al. 2005 eq. 5"},
    {"mwelr", "mean weighted by edge length reciprocals: 1 / (|E||E'|)", "Max 1999; Jin et al. 2005 eq. 6"},
    {"mwrelr", "mean weighted by square root of edge length reciprocals: 1 / sqrt(|E||E'|)",
     "Max 1999; Jin et al. 2005 eq. 7"},
    {"mewcsa", "mean edge weighted by cotangents of subtended angles (area gradient; sign not corrected)",
     "Desbrun et al. 1999; Jin et al. 2005 eq. 9"},
    {"smewcsa", "sign-correct MEWCSA: oriented by MWSELR, which it falls back to where mean curvature is about zero",
     "Desbrun et al. 1999; Meyer et al. 2003"},
    {"quadric", "weighted least-squares quadric z = f(x, y) on the 1-ring, in MWA's tangent frame, refitted once",
     "beyond Jin et al. 2005; O(h^2)"},
    {"jet", "weighted least-squares cubic jet on the 2-ring, in MWA's tangent frame, refitted once",
     "Cazals & Pouget 2003; O(h^3)"},
    {"adaptive",
     "the 2-ring jet, or a Gaussian-weighted 5-ring fit that averages noise out, by GCV score; "
     "MWSELR on spheres and where the jet agrees with it; "
     "where rough, MWAAT on a lattice height field, else MWA: the choice when unsure",
     "beyond Jin et al. 2005; Craven & Wahba 1979 (GCV)"},
};

const char* vn_method_name(vn_method m)
{
	return (unsigned)m < vn_method_count ? methods[m].name : NULL;
}

const char* vn_method_description(vn_method m)
{
	return (unsigned)m < vn_method_count ? methods[m].description : NULL;
}

const char* vn_method_reference(vn_method m)
{
	return (unsigned)m < vn_method_count ? methods[m].reference : NULL;
}

vn_result vn_method_from_name(const char* name, vn_method* out)
{
	if (!name || !out)
		return vn_result_invalid_argument;
	for (unsigned m = 0; m < vn_method_count; ++m) {
		const char* a = name;
		const char* b = methods[m].name;
		while (*a && tolower((unsigned char)*a) == *b)
			++a, ++b;
		if (!*a && !*b) {
			*out = (vn_method)m;
			return vn_result_success;
		}
	}
	return vn_result_unknown_method;
}

/* ---------------------------------------------------------------- checks */

/* Validates everything but the indices and fills the common part of *w. */
static vn_result prepare(vn_work* w, const vn_vectors* normals, const vn_positions* positions, vn_method method,
                         const vn_options* options)
{
	const size_t in_stride = vn_positions_stride(positions);
	if (!in_stride || !vn_vectors_stride(normals) || (positions->count && !normals->data) ||
	    !vn_options_valid(options))
		return vn_result_invalid_argument;
	if ((unsigned)method >= vn_method_count)
		return vn_result_unknown_method;
	*w = vn_position_reader(positions, in_stride);
	w->method = method;
	return vn_result_success;
}

/* The family's runner: the seven are one pass of their kernels; SMEWCSA
 * combines two (cotangent.c); the fits seed with MWA, then fit (fit.c). */
static vn_result run_method(const vn_work* w, const vn_options* o, vn_range_stats* st)
{
	const int poly = w->offsets != NULL;
	const vn_accumulate_fn cot = poly ? vn_accumulate_cotangent_polygons : vn_accumulate_cotangent_triangles;
	const vn_accumulate_fn weighted = poly ? vn_accumulate_weighted_polygons : vn_accumulate_weighted_triangles;
	switch (w->method) {
	case vn_method_mewcsa:
		return vn_run(w, cot, o, st);
	case vn_method_smewcsa:
		return vn_smewcsa_run(w, cot, weighted, o, st);
	case vn_method_quadric:
	case vn_method_jet:
	case vn_method_adaptive:
		return vn_fit_run(w, o, st);
	default:
		return vn_run(w, weighted, o, st);
	}
}

static vn_result compute(vn_work* w, const vn_vectors* normals, const vn_options* options, vn_stats* stats)
{
	static const vn_options defaults;
	const vn_options* o = options ? options : &defaults;
	vn_vectors out = *normals;
	out.stride = vn_vectors_stride(normals);
	w->out = &out;
	w->want_stats = stats != NULL;
	w->simd = o->simd == vn_simd_auto && vn_cpu_has_avx2();
	w->keep_existing = o->keep_existing != 0;

	vn_range_stats st = {0, 0, 0, 0};
	vn_result r = w->vertex_count ? run_method(w, o, &st) : vn_result_success;
	if (r == vn_result_success && stats) {
		stats->faces = w->face_count;
		stats->degenerate_faces = st.degenerate_faces;
		stats->zero_normals = st.zero_normals;
		stats->nonfinite_vertices = st.nonfinite_vertices;
	}
	return r;
}

/* ---------------------------------------------------------------- entry points */

size_t vn_workspace_size(size_t vertex_count, const vn_options* options)
{
	if (vertex_count > UINT32_MAX)
		return 0;
	return vn_work_bytes((uint32_t)vertex_count, options ? options->threads : 0);
}

/* vn_triangle_normals on the kernels of `kernel`: method, or VN_MWA_POLY. */
static vn_result triangle_normals(const vn_vectors* normals, const vn_positions* positions, const uint32_t* indices,
                                  size_t index_count, vn_method method, vn_method kernel, const vn_options* options,
                                  vn_stats* stats)
{
	vn_work w;
	vn_result r = prepare(&w, normals, positions, method, options);
	if (r != vn_result_success)
		return r;
	if (index_count % 3 || (index_count && !indices))
		return vn_result_invalid_argument;
	if (index_count && !w.vertex_count)
		return vn_result_index_out_of_range;
	/* The triangle kernels check the indices as they scan them. */
	w.indices = indices;
	w.face_count = index_count / 3;
	w.method = kernel;
	return compute(&w, normals, options, stats);
}

vn_result vn_triangle_normals(const vn_vectors* normals, const vn_positions* positions, const uint32_t* indices,
                              size_t index_count, vn_method method, const vn_options* options, vn_stats* stats)
{
	return triangle_normals(normals, positions, indices, index_count, method, method, options, stats);
}

vn_result vn_triangle_normals_mwa_poly(const vn_vectors* normals, const vn_positions* positions,
                                       const uint32_t* indices, size_t index_count, const vn_options* options,
                                       vn_stats* stats)
{
	return triangle_normals(normals, positions, indices, index_count, vn_method_mwa, VN_MWA_POLY, options, stats);
}

vn_result vn_polygon_normals(const vn_vectors* normals, const vn_positions* positions, const uint32_t* indices,
                             const uint32_t* face_offsets, size_t face_count, vn_method method,
                             const vn_options* options, vn_stats* stats)
{
	vn_work w;
	vn_result r = prepare(&w, normals, positions, method, options);
	if (r != vn_result_success)
		return r;
	if (!face_offsets)
		return vn_result_invalid_argument;
	for (size_t f = 0; f < face_count; ++f)
		if (face_offsets[f + 1] < face_offsets[f])
			return vn_result_invalid_argument;
	const size_t index_count = face_offsets[face_count];
	if (index_count && !indices)
		return vn_result_invalid_argument;
	if ((r = vn_check_indices(indices, index_count, w.vertex_count)) != vn_result_success)
		return r;
	w.indices = indices;
	w.offsets = face_offsets;
	w.face_count = face_count;
	return compute(&w, normals, options, stats);
}
