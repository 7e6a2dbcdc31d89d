/* The test ensemble (vn.h, docs/ENSEMBLE.md): literal counts for all 30
 * instances, mesh sanity, orientation, exact normals against central finite
 * differences of the generating functions, marching-tetrahedra vertices
 * against their grid edges, determinism, allocators, names, and Perlin's
 * noise against an independent port of his Java reference. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vn_paper.h"
#include "paper.h" /* internal: the fBm and turbulence sums, VN_MT_MIN_T */

#define NM vn_model_count
#define NR vn_resolution_count

/* ---------------------------------------------------------------- expected values */

typedef struct expect {
	size_t vertices, triangles, boundary;
	size_t zero_area; /* triangles with a zero cross product */
	size_t reversed;  /* face normal 90 degrees or more from its vertices' mean exact normal */
} expect;

static const expect expected[NM][NR] = {
    {{266, 528, 0, 0, 0}, {1106, 2208, 0, 0, 0}, {4514, 9024, 0, 0, 0}},                 /* sphere_tp */
    {{288, 576, 0, 0, 0}, {1152, 2304, 0, 0, 0}, {4608, 9216, 0, 0, 0}},                 /* torus_tp */
    {{256, 450, 60, 0, 0}, {1024, 1922, 124, 0, 0}, {4096, 7938, 252, 0, 0}},            /* perlin_hf */
    {{256, 450, 60, 0, 0}, {1024, 1922, 124, 0, 0}, {4096, 7938, 252, 0, 0}},            /* fractal09_hf */
    {{256, 450, 60, 0, 0}, {1024, 1922, 124, 0, 0}, {4096, 7938, 252, 0, 0}},            /* fractal05_hf */
    {{256, 450, 60, 0, 0}, {1024, 1922, 124, 0, 0}, {4096, 7938, 252, 0, 0}},            /* fractal01_hf */
    {{1562, 3120, 0, 0, 0}, {7586, 15168, 0, 0, 0}, {31514, 63024, 0, 0, 0}},            /* sphere_mt */
    {{2642, 4704, 564, 0, 0}, {12530, 23688, 1356, 0, 0}, {50294, 97776, 2796, 0, 0}},   /* cosine_mt */
    {{3182, 5916, 452, 0, 13}, {15322, 29634, 1010, 0, 9}, {62670, 123288, 2056, 0, 17}}, /* perlin_mt */
    {{908, 1572, 200, 0, 300}, {2042, 3786, 304, 0, 598}, {3840, 7248, 460, 0, 614}},    /* turbulence_mt */
    {{266, 528, 0, 0, 0}, {1106, 2208, 0, 0, 0}, {4514, 9024, 0, 0, 0}},                 /* ellipsoid_tp */
    {{3868, 7128, 644, 0, 0}, {18566, 35706, 1462, 0, 0}, {75522, 148100, 2980, 0, 0}},  /* gyroid_mt */
};

/* The largest angle (degrees) between a face normal and its vertices' mean
 * exact normal: it halves with each resolution on the smooth models; the
 * aliased ones (perlin_mt near the noise's critical points, turbulence_mt at
 * every crease) have reversed faces, counted above. 180: not bounded. */
static const double face_bound[NM][NR] = {
    {4.0, 2.0, 1.0},  /* sphere_tp */
    {6.5, 3.0, 1.5},  /* torus_tp */
    {9.0, 4.0, 2.0},  /* perlin_hf */
    {45, 31, 16},     /* fractal09_hf */
    {66, 46, 25},     /* fractal05_hf */
    {86, 64, 39},     /* fractal01_hf */
    {9.0, 4.5, 2.25}, /* sphere_mt */
    {21, 12, 6.5},    /* cosine_mt */
    {180, 180, 180},  /* perlin_mt */
    {180, 180, 180},  /* turbulence_mt */
    {14.5, 8.0, 6.0}, /* ellipsoid_tp */
    {45, 21, 10.5},   /* gyroid_mt */
};

/* The documented parameters (ensemble.c), repeated as literals. */
static const unsigned tp_grid[NR][2] = {{12, 24}, {24, 48}, {48, 96}}; /* bands, segments */
static const unsigned hf_grid[NR] = {16, 32, 64};
static const double hf_size = 2.0, hf_z = 1.0 / 3.0, hf_amplitude = 0.5;
static const unsigned hf_octaves = 3;
static const double torus_big = 1.0, torus_small = 0.6;
static const double noise_offset[3] = {0.37, 0.61, 0.23};
static const double ellipsoid_axes[3] = {1.0, 0.75, 0.5}, ellipsoid_jitter = 0.15;
static const double gyroid_dilation = 1.5 * 3.14159265358979323846, gyroid_offset[3] = {0.3, 0.5, 0.7};

/* ---------------------------------------------------------------- helpers */

static vn_model_mesh gen(vn_model m, vn_resolution r)
{
	vn_model_mesh mesh;
	assert_int_equal(vn_model_generate(m, r, NULL, &mesh), vn_result_success);
	return mesh;
}

static void cross(const double a[3], const double b[3], double c[3])
{
	c[0] = a[1] * b[2] - a[2] * b[1];
	c[1] = a[2] * b[0] - a[0] * b[2];
	c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double norm(const double a[3])
{
	return sqrt(dot(a, a));
}

/* Angle between two non-zero vectors, in radians, accurate near 0. */
static double angle(const double a[3], const double b[3])
{
	double c[3];
	cross(a, b, c);
	return atan2(norm(c), dot(a, b));
}

static void face_normal(const vn_model_mesh* mesh, size_t t, double n[3])
{
	const uint32_t* tri = mesh->indices + 3 * t;
	const double* a = mesh->positions + 3 * (size_t)tri[0];
	const double* b = mesh->positions + 3 * (size_t)tri[1];
	const double* c = mesh->positions + 3 * (size_t)tri[2];
	const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
	cross(e1, e2, n);
}

/* A deterministic stream of doubles in [lo, hi). */
static double next_uniform(uint64_t* s, double lo, double hi)
{
	*s = *s * 6364136223846793005u + 1442695040888963407u;
	return lo + (hi - lo) * (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static const char* instance(vn_model m, vn_resolution r)
{
	static char buf[64]; /* test-only: messages are printed before the next call */
	strcpy(buf, vn_model_name(m));
	strcat(buf, " ");
	strcat(buf, vn_resolution_name(r));
	return buf;
}

/* ---------------------------------------------------------------- allocators */

typedef struct counting {
	size_t allocations, frees;
	size_t fail_at; /* 1-based call number to fail; 0: never */
} counting;

static void* counting_allocate(void* user, size_t size)
{
	counting* c = (counting*)user;
	if (c->fail_at && c->allocations + 1 == c->fail_at) {
		c->fail_at = 0; /* one failure: later calls would succeed */
		return NULL;
	}
	++c->allocations;
	return malloc(size);
}

static void counting_deallocate(void* user, void* ptr)
{
	assert_non_null(ptr);
	++((counting*)user)->frees;
	free(ptr);
}

/* ---------------------------------------------------------------- generating functions
 *
 * Written here from the documented formulas (ensemble.c, docs/ENSEMBLE.md). */

static void tp_point(vn_model m, double u, double v, double p[3])
{
	if (m == vn_model_sphere_tp) {
		p[0] = sin(u) * cos(v), p[1] = sin(u) * sin(v), p[2] = cos(u);
	} else {
		const double ring = torus_big + torus_small * cos(v);
		p[0] = ring * cos(u), p[1] = ring * sin(u), p[2] = torus_small * sin(v);
	}
}

/* The HF height function f (z = a f): noise or fBm at (x, y, 1/3). */
static double hf_f(vn_model m, double x, double y)
{
	static const double h[4] = {-1, 0.9, 0.5, 0.1};
	const double p[3] = {x, y, hf_z};
	const double hh = h[m - vn_model_perlin_hf];
	return hh < 0 ? vn_perlin_noise(p, NULL) : vn_fbm_noise(p, hf_octaves, hh, NULL);
}

/* The MT models' implicit functions f(p) and isovalues, indexed by mt_index. */
#define NMT 5
static const vn_model mt_models[NMT] = {vn_model_sphere_mt, vn_model_cosine_mt, vn_model_perlin_mt,
                                        vn_model_turbulence_mt, vn_model_gyroid_mt};
static const double mt_iso[NMT] = {0.64, 0.0, 0.0, 0.15, 0.0};
static const unsigned mt_cells[NMT][NR] = {{13, 29, 59}, {13, 29, 59}, {13, 29, 59}, {10, 14, 18}, {13, 29, 59}};

static int mt_index(vn_model m)
{
	for (int i = 0; i < NMT; ++i)
		if (mt_models[i] == m)
			return i;
	fail_msg("%s is not a marching-tetrahedra model", vn_model_name(m));
	return -1;
}

static void turbulence_point(const double p[3], double q[3])
{
	for (int k = 0; k < 3; ++k)
		q[k] = 0.5 * p[k] + noise_offset[k];
}

static double mt_f(vn_model m, const double p[3])
{
	double q[3];
	switch (m) {
	case vn_model_sphere_mt:
		return p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
	case vn_model_cosine_mt: {
		const double w = 2 * 3.14159265358979323846 * 0.75;
		return cos(w * p[0]) + cos(w * p[1]) + cos(w * p[2]);
	}
	case vn_model_perlin_mt:
		for (int k = 0; k < 3; ++k)
			q[k] = p[k] + noise_offset[k];
		return vn_perlin_noise(q, NULL);
	case vn_model_gyroid_mt:
		for (int k = 0; k < 3; ++k)
			q[k] = gyroid_dilation * p[k] + gyroid_offset[k];
		return sin(q[0]) * cos(q[1]) + sin(q[1]) * cos(q[2]) + sin(q[2]) * cos(q[0]);
	default:
		turbulence_point(p, q);
		return vn_turbulence_noise(q, 4, NULL);
	}
}

/* Whether the turbulence at p is at least 1e-3 away from a crease (some
 * octave's noise at 0), where finite differences straddle a kink. */
static int off_crease(const double q[3])
{
	double s = 1;
	for (int i = 0; i < 4; ++i, s *= 2) {
		const double qi[3] = {s * q[0], s * q[1], s * q[2]};
		if (fabs(vn_perlin_noise(qi, NULL)) < 1e-3)
			return 0;
	}
	return 1;
}

/* Central differences of a scalar function of 3 variables. */
typedef double (*scalar3)(const void* ctx, const double p[3]);

static void central_gradient(scalar3 f, const void* ctx, const double p[3], double h, double g[3])
{
	for (int k = 0; k < 3; ++k) {
		double a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]};
		a[k] += h, b[k] -= h;
		g[k] = (f(ctx, a) - f(ctx, b)) / (2 * h);
	}
}

static double mt_scalar(const void* ctx, const double p[3])
{
	return mt_f(*(const vn_model*)ctx, p);
}

static double noise_scalar(const void* ctx, const double p[3])
{
	(void)ctx;
	return vn_perlin_noise(p, NULL);
}

static double fbm_scalar(const void* ctx, const double p[3])
{
	return vn_fbm_noise(p, 3, *(const double*)ctx, NULL);
}

static double turbulence_scalar(const void* ctx, const double p[3])
{
	(void)ctx;
	return vn_turbulence_noise(p, 4, NULL);
}

/* Asserts the analytic gradient g and the central differences of f at p
 * agree in direction to 1e-6 rad and in length to 1e-6 relative. */
static void check_gradient(scalar3 f, const void* ctx, const double p[3], const double g[3])
{
	double fd[3];
	central_gradient(f, ctx, p, 1e-6, fd);
	const double a = angle(g, fd), rel = fabs(norm(fd) - norm(g)) / norm(g);
	if (a > 1e-6 || rel > 1e-6)
		fail_msg("at (%.17g, %.17g, %.17g): gradient (%g, %g, %g), differences (%g, %g, %g), angle %g", p[0], p[1],
		         p[2], g[0], g[1], g[2], fd[0], fd[1], fd[2], a);
}

/* ---------------------------------------------------------------- names and arguments */

static void names(void** state)
{
	(void)state;
	static const char* const model_names[NM] = {"sphere_tp",    "torus_tp",  "perlin_hf", "fractal09_hf",
	                                            "fractal05_hf", "fractal01_hf", "sphere_mt", "cosine_mt",
	                                            "perlin_mt",    "turbulence_mt", "ellipsoid_tp", "gyroid_mt"};
	assert_int_equal(VN_MODEL_PAPER_COUNT, 10);
	assert_int_equal(vn_model_ellipsoid_tp, VN_MODEL_PAPER_COUNT); /* the paper's ten keep their values */
	for (int m = 0; m < NM; ++m) {
		assert_string_equal(vn_model_name((vn_model)m), model_names[m]);
		assert_non_null(vn_model_description((vn_model)m));
	}
	assert_null(vn_model_name(vn_model_count));
	assert_null(vn_model_name((vn_model)-1));
	assert_null(vn_model_description(vn_model_count));
	assert_null(vn_model_description((vn_model)-1));
	assert_string_equal(vn_resolution_name(vn_resolution_low), "low");
	assert_string_equal(vn_resolution_name(vn_resolution_medium), "medium");
	assert_string_equal(vn_resolution_name(vn_resolution_high), "high");
	assert_null(vn_resolution_name(vn_resolution_count));
	assert_null(vn_resolution_name((vn_resolution)-1));
}

static void invalid_arguments(void** state)
{
	(void)state;
	vn_model_mesh mesh;
	counting c = {0, 0, 0};
	assert_int_equal(vn_model_generate(vn_model_sphere_tp, vn_resolution_low, NULL, NULL),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_model_generate(vn_model_count, vn_resolution_low, NULL, &mesh), vn_result_invalid_argument);
	assert_null(mesh.positions);
	assert_int_equal(vn_model_generate((vn_model)-1, vn_resolution_low, NULL, &mesh), vn_result_invalid_argument);
	assert_int_equal(vn_model_generate(vn_model_sphere_tp, vn_resolution_count, NULL, &mesh),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_model_generate(vn_model_sphere_tp, (vn_resolution)-1, NULL, &mesh),
	                 vn_result_invalid_argument);
	/* Half an allocator is an error, as in vn_options; an empty one is malloc. */
	const vn_allocator only_allocate = {counting_allocate, NULL, &c}, only_free = {NULL, counting_deallocate, &c};
	assert_int_equal(vn_model_generate(vn_model_sphere_tp, vn_resolution_low, &only_allocate, &mesh),
	                 vn_result_invalid_argument);
	assert_int_equal(vn_model_generate(vn_model_sphere_tp, vn_resolution_low, &only_free, &mesh),
	                 vn_result_invalid_argument);
	assert_int_equal(c.allocations, 0);
	const vn_allocator empty = {NULL, NULL, NULL};
	assert_int_equal(vn_model_generate(vn_model_sphere_tp, vn_resolution_low, &empty, &mesh), vn_result_success);
	vn_model_free(&mesh, &empty);
	assert_null(mesh.positions);
	assert_int_equal(mesh.vertex_count, 0);
	vn_model_free(NULL, NULL);
	vn_model_free(&mesh, NULL); /* zeroed: nothing to do */
}

/* ---------------------------------------------------------------- every instance */

/* Counts, finiteness, unit normals, index range, zero-area triangles,
 * boundary flags: all against the literal table. */
static void check_counts(vn_model m, vn_resolution r)
{
	const expect* e = &expected[m][r];
	vn_model_mesh mesh = gen(m, r);
	if (mesh.vertex_count != e->vertices || mesh.triangle_count != e->triangles)
		fail_msg("%s: %zu vertices, %zu triangles", instance(m, r), mesh.vertex_count, mesh.triangle_count);
	size_t boundary = 0, zero = 0;
	for (size_t i = 0; i < mesh.vertex_count; ++i) {
		const double* p = mesh.positions + 3 * i;
		const double* n = mesh.normals + 3 * i;
		assert_true(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]));
		assert_true(isfinite(n[0]) && isfinite(n[1]) && isfinite(n[2]));
		if (fabs(norm(n) - 1) > 1e-12)
			fail_msg("%s: normal %zu has length %.17g", instance(m, r), i, norm(n));
		assert_true(mesh.boundary[i] <= 1);
		boundary += mesh.boundary[i];
	}
	for (size_t t = 0; t < 3 * mesh.triangle_count; ++t)
		assert_true(mesh.indices[t] < mesh.vertex_count);
	for (size_t t = 0; t < mesh.triangle_count; ++t) {
		double n[3];
		face_normal(&mesh, t, n);
		zero += dot(n, n) == 0;
	}
	if (boundary != e->boundary || zero != e->zero_area)
		fail_msg("%s: %zu boundary vertices, %zu zero-area triangles", instance(m, r), boundary, zero);
	vn_model_free(&mesh, NULL);
}

static void counts_and_sanity(void** state)
{
	(void)state;
	for (int m = 0; m < NM; ++m)
		for (int r = 0; r < NR; ++r)
			check_counts((vn_model)m, (vn_resolution)r);
}

/* Table 3: 450, 1922 and 7938 triangles; an n x n grid has 4 (n - 1)
 * boundary vertices. */
static void height_field_grids(void** state)
{
	(void)state;
	static const size_t triangles[NR] = {450, 1922, 7938};
	for (int m = vn_model_perlin_hf; m <= vn_model_fractal01_hf; ++m) {
		for (int r = 0; r < NR; ++r) {
			vn_model_mesh mesh = gen((vn_model)m, (vn_resolution)r);
			assert_int_equal(mesh.triangle_count, triangles[r]);
			size_t boundary = 0;
			for (size_t i = 0; i < mesh.vertex_count; ++i)
				boundary += mesh.boundary[i];
			assert_int_equal(boundary, 4 * (hf_grid[r] - 1));
			vn_model_free(&mesh, NULL);
		}
	}
}

/* The closed models have no boundary; the cosine sum is cut by its box. */
static void closed_and_cut_models(void** state)
{
	(void)state;
	static const vn_model closed[] = {vn_model_sphere_tp, vn_model_torus_tp, vn_model_sphere_mt, vn_model_ellipsoid_tp};
	for (int r = 0; r < NR; ++r) {
		for (size_t k = 0; k < 4; ++k) {
			vn_model_mesh mesh = gen(closed[k], (vn_resolution)r);
			for (size_t i = 0; i < mesh.vertex_count; ++i)
				assert_int_equal(mesh.boundary[i], 0);
			vn_model_free(&mesh, NULL);
		}
		vn_model_mesh mesh = gen(vn_model_cosine_mt, (vn_resolution)r);
		size_t boundary = 0;
		for (size_t i = 0; i < mesh.vertex_count; ++i)
			boundary += mesh.boundary[i];
		assert_true(boundary > 0);
		assert_int_equal(boundary, expected[vn_model_cosine_mt][r].boundary);
		vn_model_free(&mesh, NULL);
		mesh = gen(vn_model_gyroid_mt, (vn_resolution)r);
		boundary = 0;
		for (size_t i = 0; i < mesh.vertex_count; ++i)
			boundary += mesh.boundary[i];
		assert_int_equal(boundary, expected[vn_model_gyroid_mt][r].boundary);
		vn_model_free(&mesh, NULL);
	}
}

static int compare_u64(const void* a, const void* b)
{
	const uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
	return (x > y) - (x < y);
}

/* Every undirected edge is used by one or two triangles, and by two in
 * opposite directions: a consistently oriented manifold. An edge of one
 * triangle is a boundary edge and its ends are exactly the flagged vertices. */
static void check_manifold(vn_model m, vn_resolution r)
{
	vn_model_mesh mesh = gen(m, r);
	const size_t ne = 3 * mesh.triangle_count;
	uint64_t* directed = (uint64_t*)malloc(ne * sizeof(uint64_t));
	uint8_t* flagged = (uint8_t*)calloc(mesh.vertex_count, 1);
	assert_non_null(directed);
	assert_non_null(flagged);
	for (size_t t = 0; t < mesh.triangle_count; ++t)
		for (int c = 0; c < 3; ++c)
			directed[3 * t + c] = (uint64_t)mesh.indices[3 * t + c] << 32 | mesh.indices[3 * t + (c + 1) % 3];
	qsort(directed, ne, sizeof(uint64_t), compare_u64);
	for (size_t i = 0; i < ne; ++i) {
		const uint64_t e = directed[i], rev = e >> 32 | e << 32;
		if (i + 1 < ne && directed[i + 1] == e)
			fail_msg("%s: directed edge %u-%u used twice", instance(m, r), (unsigned)(e >> 32), (unsigned)e);
		if (!bsearch(&rev, directed, ne, sizeof(uint64_t), compare_u64))
			flagged[e >> 32] = flagged[e & UINT32_MAX] = 1;
	}
	assert_memory_equal(flagged, mesh.boundary, mesh.vertex_count);
	free(flagged);
	free(directed);
	vn_model_free(&mesh, NULL);
}

static void oriented_manifolds(void** state)
{
	(void)state;
	for (int m = 0; m < NM; ++m)
		for (int r = 0; r < NR; ++r)
			check_manifold((vn_model)m, (vn_resolution)r);
}

/* Each face normal against the mean of its vertices' exact normals: the
 * literal count of reversed faces (90 degrees or more) and the largest
 * angle where it is bounded. */
static void check_face_orientation(vn_model m, vn_resolution r)
{
	vn_model_mesh mesh = gen(m, r);
	size_t reversed = 0;
	double worst = 0;
	for (size_t t = 0; t < mesh.triangle_count; ++t) {
		double n[3], mean[3] = {0, 0, 0};
		face_normal(&mesh, t, n);
		for (int c = 0; c < 3; ++c)
			for (int k = 0; k < 3; ++k)
				mean[k] += mesh.normals[3 * (size_t)mesh.indices[3 * t + c] + k];
		const double a = angle(n, mean) * 180 / 3.14159265358979323846;
		reversed += a >= 90;
		worst = a > worst ? a : worst;
	}
	if (reversed != expected[m][r].reversed || worst > face_bound[m][r])
		fail_msg("%s: %zu reversed faces, largest angle %.3f degrees", instance(m, r), reversed, worst);
	vn_model_free(&mesh, NULL);
}

static void faces_follow_exact_normals(void** state)
{
	(void)state;
	for (int m = 0; m < NM; ++m)
		for (int r = 0; r < NR; ++r)
			check_face_orientation((vn_model)m, (vn_resolution)r);
}

/* However rough, a height field is seen counter-clockwise from above. */
static void height_fields_face_up(void** state)
{
	(void)state;
	for (int m = vn_model_perlin_hf; m <= vn_model_fractal01_hf; ++m) {
		for (int r = 0; r < NR; ++r) {
			vn_model_mesh mesh = gen((vn_model)m, (vn_resolution)r);
			for (size_t t = 0; t < mesh.triangle_count; ++t) {
				double n[3];
				face_normal(&mesh, t, n);
				assert_true(n[2] > 0);
			}
			vn_model_free(&mesh, NULL);
		}
	}
}

/* ---------------------------------------------------------------- exact normals */

/* TP: vertex positions are P(u, v) on the documented grid and normals are
 * P_u x P_v by central differences of P; the sphere's vertices lie on it. */
static void check_tp(vn_model m, vn_resolution r)
{
	const unsigned bands = tp_grid[r][0], segs = tp_grid[r][1];
	vn_model_mesh mesh = gen(m, r);
	const double pi = 3.14159265358979323846, h = 1e-6;
	for (size_t k = 0; k < mesh.vertex_count; ++k) {
		const double* p = mesh.positions + 3 * k;
		const double* n = mesh.normals + 3 * k;
		double u, v;
		if (m == vn_model_sphere_tp) {
			assert_true(fabs(norm(p) - 1) <= 1e-15);
			if (k == 0 || k + 1 == mesh.vertex_count) { /* poles: the radial normal */
				assert_true(p[0] == 0 && p[1] == 0 && fabs(p[2]) == 1);
				assert_true(n[0] == 0 && n[1] == 0 && n[2] == p[2]);
				continue;
			}
			u = pi * (double)(1 + (k - 1) / segs) / bands, v = 2 * pi * (double)((k - 1) % segs) / segs;
		} else {
			u = 2 * pi * (double)(k / bands) / segs, v = 2 * pi * (double)(k % bands) / bands;
		}
		double q[3], a[3], b[3], pu[3], pv[3], c[3];
		tp_point(m, u, v, q);
		for (int i = 0; i < 3; ++i)
			assert_true(fabs(q[i] - p[i]) <= 1e-15);
		tp_point(m, u + h, v, a), tp_point(m, u - h, v, b);
		for (int i = 0; i < 3; ++i)
			pu[i] = (a[i] - b[i]) / (2 * h);
		tp_point(m, u, v + h, a), tp_point(m, u, v - h, b);
		for (int i = 0; i < 3; ++i)
			pv[i] = (a[i] - b[i]) / (2 * h);
		cross(pu, pv, c);
		if (angle(c, n) > 1e-6)
			fail_msg("%s: vertex %zu normal off P_u x P_v by %g rad", instance(m, r), k, angle(c, n));
	}
	vn_model_free(&mesh, NULL);
}

/* The ellipsoid: every vertex on x^2/a^2 + y^2/b^2 + z^2/c^2 = 1 with the
 * normal of its gradient (x/a^2, y/b^2, z/c^2), the poles first and last,
 * and every ring vertex's parameters (u = acos(z / c), v = atan2(y / b,
 * x / a)) within the jitter of its grid point, with an irregular spread. */
static void check_ellipsoid(vn_resolution r)
{
	const unsigned bands = tp_grid[r][0], segs = tp_grid[r][1];
	const double pi = 3.14159265358979323846, *ax = ellipsoid_axes;
	vn_model_mesh mesh = gen(vn_model_ellipsoid_tp, r);
	double lo = 1, hi = -1;
	for (size_t k = 0; k < mesh.vertex_count; ++k) {
		const double* p = mesh.positions + 3 * k;
		const double g[3] = {p[0] / (ax[0] * ax[0]), p[1] / (ax[1] * ax[1]), p[2] / (ax[2] * ax[2])};
		const double level = p[0] * g[0] + p[1] * g[1] + p[2] * g[2];
		if (fabs(level - 1) > 1e-14 || angle(g, mesh.normals + 3 * k) > 1e-12)
			fail_msg("%s: vertex %zu off the surface (%g) or its normal", instance(vn_model_ellipsoid_tp, r), k,
			         level - 1);
		if (k == 0 || k + 1 == mesh.vertex_count) {
			assert_true(p[0] == 0 && p[1] == 0 && p[2] == (k ? -ax[2] : ax[2]));
			continue;
		}
		const double u = acos(p[2] / ax[2]) * bands / pi - (double)(1 + (k - 1) / segs);
		double v = atan2(p[1] / ax[1], p[0] / ax[0]) * segs / (2 * pi) - (double)((k - 1) % segs);
		v -= segs * round(v / segs); /* the seam */
		if (fabs(u) > ellipsoid_jitter + 1e-9 || fabs(v) > ellipsoid_jitter + 1e-9)
			fail_msg("%s: vertex %zu jittered by (%g, %g) steps", instance(vn_model_ellipsoid_tp, r), k, u, v);
		lo = u < lo ? u : lo, hi = u > hi ? u : hi;
	}
	assert_true(lo < -0.8 * ellipsoid_jitter && hi > 0.8 * ellipsoid_jitter);
	vn_model_free(&mesh, NULL);
}

static void tp_normals_are_pu_cross_pv(void** state)
{
	(void)state;
	for (int r = 0; r < NR; ++r) {
		check_tp(vn_model_sphere_tp, (vn_resolution)r);
		check_tp(vn_model_torus_tp, (vn_resolution)r);
		check_ellipsoid((vn_resolution)r);
	}
}

/* vn_model_generate is vn_model_generate_grid on vn_model_grid's grid;
 * other grids give other meshes, out-of-range ones an error. */
static void any_grid(void** state)
{
	(void)state;
	static const unsigned smallest[NM] = {3, 3, 2, 2, 2, 2, 2, 2, 2, 2, 3, 2};
	for (int m = 0; m < NM; ++m) {
		for (int r = 0; r < NR; ++r) {
			vn_model_mesh a = gen((vn_model)m, (vn_resolution)r), b;
			assert_int_equal(vn_model_generate_grid((vn_model)m, vn_model_grid((vn_model)m, (vn_resolution)r), NULL, &b),
			                 vn_result_success);
			assert_int_equal(a.vertex_count, b.vertex_count);
			assert_int_equal(a.triangle_count, b.triangle_count);
			assert_memory_equal(a.positions, b.positions, 3 * a.vertex_count * sizeof(double));
			assert_memory_equal(a.indices, b.indices, 3 * a.triangle_count * sizeof(uint32_t));
			vn_model_free(&a, NULL);
			vn_model_free(&b, NULL);
		}
		vn_model_mesh mesh;
		const unsigned most = m >= vn_model_sphere_mt && m != vn_model_ellipsoid_tp ? VN_MODEL_CELLS_MAX : VN_MODEL_GRID_MAX;
		assert_int_equal(vn_model_generate_grid((vn_model)m, smallest[m] - 1, NULL, &mesh), vn_result_invalid_argument);
		assert_null(mesh.positions);
		assert_int_equal(vn_model_generate_grid((vn_model)m, most + 1, NULL, &mesh), vn_result_invalid_argument);
		assert_int_equal(vn_model_generate_grid((vn_model)m, smallest[m], NULL, &mesh), vn_result_success);
		vn_model_free(&mesh, NULL);
	}
	/* The documented grids; a TP grid of n bands has 2 n segments. */
	static const unsigned tp[NR] = {12, 24, 48}, hf[NR] = {16, 32, 64};
	for (int r = 0; r < NR; ++r) {
		assert_int_equal(vn_model_grid(vn_model_torus_tp, (vn_resolution)r), tp[r]);
		assert_int_equal(vn_model_grid(vn_model_ellipsoid_tp, (vn_resolution)r), tp[r]);
		assert_int_equal(vn_model_grid(vn_model_perlin_hf, (vn_resolution)r), hf[r]);
		assert_int_equal(vn_model_grid(vn_model_gyroid_mt, (vn_resolution)r), mt_cells[NMT - 1][r]);
		assert_int_equal(vn_model_grid(vn_model_turbulence_mt, (vn_resolution)r), mt_cells[3][r]);
	}
	vn_model_mesh mesh = {0, 0, NULL, NULL, NULL, NULL};
	assert_int_equal(vn_model_generate_grid(vn_model_torus_tp, 20, NULL, &mesh), vn_result_success);
	assert_int_equal(mesh.vertex_count, 20 * 40);
	assert_int_equal(mesh.triangle_count, 2 * 20 * 40);
	vn_model_free(&mesh, NULL);
	assert_int_equal(vn_model_generate_grid(vn_model_sphere_mt, 37, NULL, &mesh), vn_result_success);
	assert_true(mesh.vertex_count > expected[vn_model_sphere_mt][vn_resolution_medium].vertices);
	assert_true(mesh.vertex_count < expected[vn_model_sphere_mt][vn_resolution_high].vertices);
	vn_model_free(&mesh, NULL);
	assert_int_equal(vn_model_grid(vn_model_count, vn_resolution_low), 0);
	assert_int_equal(vn_model_grid(vn_model_sphere_tp, vn_resolution_count), 0);
	assert_int_equal(vn_model_generate_grid(vn_model_count, 20, NULL, &mesh), vn_result_invalid_argument);
	assert_int_equal(vn_model_generate_grid(vn_model_sphere_tp, 20, NULL, NULL), vn_result_invalid_argument);
}

typedef struct hf_ctx {
	vn_model m;
	double x, y;
} hf_ctx;

/* HF: z = a f(x, y) on the documented grid; the normal is
 * normalize(-a f_x, -a f_y, 1) by central differences of f. */
static void check_hf(vn_model m, vn_resolution r)
{
	const unsigned n = hf_grid[r];
	const double h = 1e-6;
	vn_model_mesh mesh = gen(m, r);
	for (unsigned j = 0; j < n; ++j) {
		for (unsigned i = 0; i < n; ++i) {
			const size_t k = (size_t)j * n + i;
			const double* p = mesh.positions + 3 * k;
			const double x = hf_size * i / (n - 1), y = hf_size * j / (n - 1);
			assert_true(p[0] == x && p[1] == y);
			assert_true(fabs(p[2] - hf_amplitude * hf_f(m, x, y)) <= 1e-15);
			const double fx = (hf_f(m, x + h, y) - hf_f(m, x - h, y)) / (2 * h);
			const double fy = (hf_f(m, x, y + h) - hf_f(m, x, y - h)) / (2 * h);
			const double fd[3] = {-hf_amplitude * fx, -hf_amplitude * fy, 1};
			if (angle(fd, mesh.normals + 3 * k) > 1e-6)
				fail_msg("%s: vertex %zu normal off by %g rad", instance(m, r), k, angle(fd, mesh.normals + 3 * k));
		}
	}
	vn_model_free(&mesh, NULL);
}

static void hf_normals_match_differences(void** state)
{
	(void)state;
	for (int m = vn_model_perlin_hf; m <= vn_model_fractal01_hf; ++m)
		for (int r = 0; r < NR; ++r)
			check_hf((vn_model)m, (vn_resolution)r);
}

/* MT: at every vertex (every one off a crease, for the turbulence), the
 * normal is the normalized central-difference gradient of f. */
static void check_mt_normals(vn_model m, vn_resolution r)
{
	vn_model_mesh mesh = gen(m, r);
	size_t checked = 0;
	for (size_t k = 0; k < mesh.vertex_count; ++k) {
		const double* p = mesh.positions + 3 * k;
		double q[3], fd[3];
		turbulence_point(p, q);
		if (m == vn_model_turbulence_mt && !off_crease(q))
			continue;
		central_gradient(mt_scalar, &m, p, 1e-6, fd);
		if (angle(fd, mesh.normals + 3 * k) > 1e-6)
			fail_msg("%s: vertex %zu normal off by %g rad", instance(m, r), k, angle(fd, mesh.normals + 3 * k));
		++checked;
	}
	/* The creases are thin: almost every vertex was checked. */
	assert_true(checked > mesh.vertex_count * 9 / 10);
	vn_model_free(&mesh, NULL);
}

static void mt_normals_match_differences(void** state)
{
	(void)state;
	for (int i = 0; i < NMT; ++i)
		for (int r = 0; r < NR; ++r)
			check_mt_normals(mt_models[i], (vn_resolution)r);
}

/* MT vertex k lies on a grid edge: coordinates exactly on a grid plane stay
 * put, the others move by one common fraction t of a cell. The edge's ends
 * straddle the isovalue, t is their linear interpolation, the clamp of
 * marching.c never acts on this ensemble, and |f - iso| is within the
 * interpolation error bound documented in docs/ENSEMBLE.md:
 *   smooth f:   t (1 - t) l^2 M2 / 2, M2 bounding |f''| along the edge
 *               (sphere 2, cosine (1.5 pi)^2, perlin 16: sampled max 12.4,
 *               gyroid 4 (1.5 pi)^2: each sin a cos b term's is at most
 *               (|d_a| + |d_b|)^2 <= 2 (d_a^2 + d_b^2) along unit d);
 *   turbulence: 2 t (1 - t) l L, L = 8 bounding |grad f| (4 octaves times
 *               max |grad noise| <= 4, sampled max 2.97, times 1/2). */
static void check_mt_vertex(vn_model m, vn_resolution r, const double* p)
{
	const double pi2 = 3.14159265358979323846 * 3.14159265358979323846;
	static const double m2[NMT] = {2.0, 1.5 * 1.5 * pi2, 16.0, 0.0, 4 * 1.5 * 1.5 * pi2};
	const int i_m = mt_index(m);
	const unsigned n = mt_cells[i_m][r];
	const double iso = mt_iso[i_m];
	double a[3], b[3], t = -1;
	for (int k = 0; k < 3; ++k) {
		const double s = (p[k] + 1) * n / 2;
		const double on = -1.0 + 2.0 * (double)(long)round(s) / (double)n;
		if (p[k] == on) {
			a[k] = b[k] = on;
			continue;
		}
		const long i = (long)floor(s);
		a[k] = -1.0 + 2.0 * (double)i / (double)n, b[k] = -1.0 + 2.0 * (double)(i + 1) / (double)n;
		const double tk = (p[k] - a[k]) / (b[k] - a[k]);
		if (t >= 0 && fabs(tk - t) > 1e-9)
			fail_msg("%s: vertex (%g, %g, %g) is off its grid edge", instance(m, r), p[0], p[1], p[2]);
		t = tk;
	}
	assert_true(t > 0 && t < 1);
	const double fa = mt_f(m, a), fb = mt_f(m, b), fp = mt_f(m, p);
	assert_true((fa <= iso) != (fb <= iso));
	const double lerp_t = (iso - fa) / (fb - fa);
	assert_true(lerp_t > VN_MT_MIN_T && lerp_t < 1 - VN_MT_MIN_T);
	assert_true(fabs(t - lerp_t) <= 1e-9);
	const double l = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
	const double bound = m == vn_model_turbulence_mt ? 2 * t * (1 - t) * l * 8.0
	                                                 : t * (1 - t) * l * l * m2[i_m] / 2;
	if (fabs(fp - iso) > bound + 1e-12)
		fail_msg("%s: |f - iso| = %g exceeds %g", instance(m, r), fabs(fp - iso), bound);
}

static void mt_vertices_on_grid_edges(void** state)
{
	(void)state;
	for (int i = 0; i < NMT; ++i) {
		for (int r = 0; r < NR; ++r) {
			vn_model_mesh mesh = gen(mt_models[i], (vn_resolution)r);
			for (size_t k = 0; k < mesh.vertex_count; ++k)
				check_mt_vertex(mt_models[i], (vn_resolution)r, mesh.positions + 3 * k);
			vn_model_free(&mesh, NULL);
		}
	}
}

/* ---------------------------------------------------------------- noise gradients */

static void noise_gradient_matches_differences(void** state)
{
	(void)state;
	uint64_t s = 1;
	for (int i = 0; i < 1000; ++i) {
		const double p[3] = {next_uniform(&s, -8, 8), next_uniform(&s, -8, 8), next_uniform(&s, -8, 8)};
		double g[3];
		vn_perlin_noise(p, g);
		if (norm(g) > 1e-2) /* the direction of a vanishing gradient is noise */
			check_gradient(noise_scalar, NULL, p, g);
	}
}

static void fbm_gradient_matches_differences(void** state)
{
	(void)state;
	static const double hs[3] = {0.9, 0.5, 0.1};
	uint64_t s = 2;
	for (int k = 0; k < 3; ++k) {
		for (int i = 0; i < 1000; ++i) {
			const double p[3] = {next_uniform(&s, 0, 2), next_uniform(&s, 0, 2), next_uniform(&s, -1, 1)};
			double g[3];
			vn_fbm_noise(p, 3, hs[k], g);
			if (norm(g) > 1e-2)
				check_gradient(fbm_scalar, &hs[k], p, g);
		}
	}
}

static void turbulence_gradient_matches_differences(void** state)
{
	(void)state;
	uint64_t s = 3;
	int checked = 0;
	for (int i = 0; i < 1000; ++i) {
		const double p[3] = {next_uniform(&s, -2, 2), next_uniform(&s, -2, 2), next_uniform(&s, -2, 2)};
		double g[3];
		vn_turbulence_noise(p, 4, g);
		if (!off_crease(p) || norm(g) <= 1e-2)
			continue;
		check_gradient(turbulence_scalar, NULL, p, g);
		++checked;
	}
	assert_true(checked > 900);
}

/* ---------------------------------------------------------------- Perlin's reference */

/* Ken Perlin's Java reference ImprovedNoise (2002), ported line by line as an
 * independent implementation (no gradient, the original structure). */
static const int permutation[256] = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103, 30,  69,  142,
    8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,  197, 62,  94,  252, 219, 203,
    117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174, 20,  125, 136, 171, 168, 68,  175, 74,  165,
    71,  134, 139, 48,  27,  166, 77,  146, 158, 231, 83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,
    55,  46,  245, 40,  244, 102, 143, 54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,
    18,  169, 200, 196, 135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250,
    124, 123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,  182, 189,
    28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,
    129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,  228, 251, 34,
    242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,  51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,
    181, 199, 106, 157, 184, 84,  204, 176, 115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114,
    67,  29,  24,  72,  243, 141, 128, 195, 78,  66,  215, 61,  156, 180};

typedef struct java_noise {
	int p[512];
} java_noise;

static void java_init(java_noise* j)
{
	for (int i = 0; i < 256; i++)
		j->p[256 + i] = j->p[i] = permutation[i];
}

static double fade(double t)
{
	return t * t * t * (t * (t * 6 - 15) + 10);
}

static double lerp(double t, double a, double b)
{
	return a + t * (b - a);
}

static double grad(int hash, double x, double y, double z)
{
	int h = hash & 15;
	double u = h < 8 ? x : y, v = h < 4 ? y : h == 12 || h == 14 ? x : z;
	return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}

static double noise(const java_noise* j, double x, double y, double z)
{
	const int* p = j->p;
	int X = (int)floor(x) & 255, Y = (int)floor(y) & 255, Z = (int)floor(z) & 255;
	x -= floor(x);
	y -= floor(y);
	z -= floor(z);
	double u = fade(x), v = fade(y), w = fade(z);
	int A = p[X] + Y, AA = p[A] + Z, AB = p[A + 1] + Z, B = p[X + 1] + Y, BA = p[B] + Z, BB = p[B + 1] + Z;
	return lerp(w,
	            lerp(v, lerp(u, grad(p[AA], x, y, z), grad(p[BA], x - 1, y, z)),
	                 lerp(u, grad(p[AB], x, y - 1, z), grad(p[BB], x - 1, y - 1, z))),
	            lerp(v, lerp(u, grad(p[AA + 1], x, y, z - 1), grad(p[BA + 1], x - 1, y, z - 1)),
	                 lerp(u, grad(p[AB + 1], x, y - 1, z - 1), grad(p[BB + 1], x - 1, y - 1, z - 1))));
}

static double vn_noise3(double x, double y, double z)
{
	const double p[3] = {x, y, z};
	return vn_perlin_noise(p, NULL);
}

static void noise_matches_java_reference(void** state)
{
	(void)state;
	java_noise j;
	java_init(&j);
	/* The table is a permutation of 0..255. */
	int seen[256] = {0};
	for (int i = 0; i < 256; ++i)
		++seen[permutation[i]];
	for (int i = 0; i < 256; ++i)
		assert_int_equal(seen[i], 1);
	/* Values the Java reference prints (published with it, and Rosetta Code's). */
	assert_true(vn_noise3(3.14, 42, 7) == 0.13691995878400012);
	assert_true(vn_noise3(-4.20, 10, 6) == 0.14208000000000043);
	assert_true(vn_noise3(0.5, 0.5, 0.5) == -0.25);
	assert_true(noise(&j, 3.14, 42, 7) == 0.13691995878400012);
	uint64_t s = 4;
	for (int i = 0; i < 1000; ++i) {
		const double x = next_uniform(&s, -300, 300), y = next_uniform(&s, -300, 300), z = next_uniform(&s, -300, 300);
		const double want = noise(&j, x, y, z), got = vn_noise3(x, y, z);
		if (fabs(got - want) > 1e-15)
			fail_msg("noise(%.17g, %.17g, %.17g) = %.17g, reference %.17g", x, y, z, got, want);
	}
}

/* The noise is 0 on the integer lattice, where its gradient is one of the
 * 12 directions (two coordinates +-1, one 0); non-finite input gives NaN. */
static void noise_lattice_and_nonfinite(void** state)
{
	(void)state;
	for (int x = -3; x <= 3; ++x) {
		for (int y = -3; y <= 3; ++y) {
			for (int z = -3; z <= 3; ++z) {
				const double p[3] = {x * 37.0, y * 11.0, z * 5.0};
				double g[3];
				assert_true(vn_perlin_noise(p, g) == 0);
				assert_true(fabs(g[0]) + fabs(g[1]) + fabs(g[2]) == 2);
				assert_true(g[0] * g[1] * g[2] == 0);
			}
		}
	}
	const double bad[3] = {NAN, 0, 0}, inf[3] = {0, 0, INFINITY};
	double g[3];
	assert_true(isnan(vn_perlin_noise(bad, g)) && isnan(g[0]));
	assert_true(isnan(vn_perlin_noise(inf, NULL)));
}

/* ---------------------------------------------------------------- determinism and memory */

static void deterministic(void** state)
{
	(void)state;
	for (int m = 0; m < NM; ++m) {
		for (int r = 0; r < NR; ++r) {
			vn_model_mesh a = gen((vn_model)m, (vn_resolution)r), b = gen((vn_model)m, (vn_resolution)r);
			assert_int_equal(a.vertex_count, b.vertex_count);
			assert_int_equal(a.triangle_count, b.triangle_count);
			assert_memory_equal(a.positions, b.positions, 3 * a.vertex_count * sizeof(double));
			assert_memory_equal(a.normals, b.normals, 3 * a.vertex_count * sizeof(double));
			assert_memory_equal(a.boundary, b.boundary, a.vertex_count);
			assert_memory_equal(a.indices, b.indices, 3 * a.triangle_count * sizeof(uint32_t));
			vn_model_free(&a, NULL);
			vn_model_free(&b, NULL);
		}
	}
}

/* Every allocation goes through the allocator and is freed by the end. */
static void counting_allocator(void** state)
{
	(void)state;
	for (int m = 0; m < NM; ++m) {
		for (int r = 0; r < NR; ++r) {
			counting c = {0, 0, 0};
			const vn_allocator a = {counting_allocate, counting_deallocate, &c};
			vn_model_mesh mesh;
			assert_int_equal(vn_model_generate((vn_model)m, (vn_resolution)r, &a, &mesh), vn_result_success);
			assert_true(c.allocations >= 4);
			assert_int_equal(c.frees, c.allocations - 4); /* the four arrays remain */
			vn_model_free(&mesh, &a);
			assert_int_equal(c.frees, c.allocations);
			assert_null(mesh.positions);
		}
	}
}

/* Failing the k-th allocation, for every k, reports out_of_memory, leaves
 * nothing allocated and a zeroed mesh. */
static void failing_allocator(void** state)
{
	(void)state;
	for (int m = 0; m < NM; ++m) {
		for (int r = 0; r < NR; ++r) {
			for (size_t k = 1;; ++k) {
				counting c = {0, 0, k};
				const vn_allocator a = {counting_allocate, counting_deallocate, &c};
				vn_model_mesh mesh;
				const vn_result res = vn_model_generate((vn_model)m, (vn_resolution)r, &a, &mesh);
				if (c.fail_at) { /* k is past the last allocation */
					assert_int_equal(res, vn_result_success);
					vn_model_free(&mesh, &a);
					assert_true(k > 4);
					break;
				}
				assert_int_equal(res, vn_result_out_of_memory);
				assert_int_equal(c.frees, c.allocations);
				assert_int_equal(mesh.vertex_count, 0);
				assert_null(mesh.positions);
				assert_null(mesh.indices);
			}
		}
	}
}

/* ---------------------------------------------------------------- the paper's observations */

static int compare_double(const void* a, const void* b)
{
	const double x = *(const double*)a, y = *(const double*)b;
	return (x > y) - (x < y);
}

/* A method's discrepancies (eq. 11, degrees) over the interior vertices, sorted. */
static double* discrepancies(const vn_model_mesh* mesh, vn_method method, size_t* count)
{
	double* out = (double*)malloc(3 * mesh->vertex_count * sizeof(double));
	double* err = (double*)malloc(mesh->vertex_count * sizeof(double));
	assert_non_null(out);
	assert_non_null(err);
	const vn_positions p = {mesh->positions, mesh->vertex_count, 0, vn_scalar_float64};
	const vn_vectors o = {out, 0, vn_scalar_float64};
	assert_int_equal(vn_triangle_normals(&o, &p, mesh->indices, 3 * mesh->triangle_count, method, NULL, NULL),
	                 vn_result_success);
	*count = 0;
	for (size_t i = 0; i < mesh->vertex_count; ++i)
		if (!mesh->boundary[i])
			err[(*count)++] = angle(out + 3 * i, mesh->normals + 3 * i) * 180 / 3.14159265358979323846;
	qsort(err, *count, sizeof(double), compare_double);
	free(out);
	return err;
}

static double median(vn_model m, vn_resolution r, vn_method method)
{
	vn_model_mesh mesh = gen(m, r);
	size_t n;
	double* err = discrepancies(&mesh, method, &n);
	const double med = err[n / 2];
	free(err);
	vn_model_free(&mesh, NULL);
	return med;
}

/* Section 4.1.3: at low resolution, for H = 0.1, "over 50% of the vertices
 * had discrepancies of 20 degrees or more". */
static void rough_fractal_at_low_resolution(void** state)
{
	(void)state;
	vn_model_mesh mesh = gen(vn_model_fractal01_hf, vn_resolution_low);
	size_t n, over = 0;
	double* err = discrepancies(&mesh, vn_method_mwa, &n);
	for (size_t i = 0; i < n; ++i)
		over += err[i] >= 20;
	assert_true(over * 2 > n);
	free(err);
	vn_model_free(&mesh, NULL);
}

/* The high resolution resolves the smooth MT models: sub-degree medians
 * for the schemes the paper ranks first (section 4.1.4): MWA and MWRELR on
 * the sphere, MWA and MWE on the cosine sum, MWA on the Perlin noise. */
static void smooth_mt_models_resolved_at_high_resolution(void** state)
{
	(void)state;
	static const struct {
		vn_model m;
		vn_method method;
	} best[] = {{vn_model_sphere_mt, vn_method_mwa}, {vn_model_sphere_mt, vn_method_mwrelr},
	            {vn_model_cosine_mt, vn_method_mwa}, {vn_model_cosine_mt, vn_method_mwe},
	            {vn_model_perlin_mt, vn_method_mwa}};
	for (size_t i = 0; i < sizeof(best) / sizeof(best[0]); ++i) {
		const double med = median(best[i].m, vn_resolution_high, best[i].method);
		if (med >= 1)
			fail_msg("%s high: median %s %.3f degrees", vn_model_name(best[i].m), vn_method_name(best[i].method), med);
	}
}

/* Sections 4.1.4 and 5: the turbulence is aliased, about 40 degrees or more
 * at low resolution, medians of 20 to 40 degrees even at the highest. */
static void turbulence_aliased(void** state)
{
	(void)state;
	for (int method = vn_method_mwe; method <= vn_method_mwrelr; ++method) {
		const double low = median(vn_model_turbulence_mt, vn_resolution_low, (vn_method)method);
		const double high = median(vn_model_turbulence_mt, vn_resolution_high, (vn_method)method);
		if (low < 40 || high < 20 || high > 40)
			fail_msg("%s: median %.2f (low), %.2f (high) degrees", vn_method_name((vn_method)method), low, high);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(names),
	    cmocka_unit_test(invalid_arguments),
	    cmocka_unit_test(counts_and_sanity),
	    cmocka_unit_test(height_field_grids),
	    cmocka_unit_test(closed_and_cut_models),
	    cmocka_unit_test(oriented_manifolds),
	    cmocka_unit_test(faces_follow_exact_normals),
	    cmocka_unit_test(height_fields_face_up),
	    cmocka_unit_test(tp_normals_are_pu_cross_pv),
	    cmocka_unit_test(any_grid),
	    cmocka_unit_test(hf_normals_match_differences),
	    cmocka_unit_test(mt_normals_match_differences),
	    cmocka_unit_test(mt_vertices_on_grid_edges),
	    cmocka_unit_test(noise_gradient_matches_differences),
	    cmocka_unit_test(fbm_gradient_matches_differences),
	    cmocka_unit_test(turbulence_gradient_matches_differences),
	    cmocka_unit_test(noise_matches_java_reference),
	    cmocka_unit_test(noise_lattice_and_nonfinite),
	    cmocka_unit_test(deterministic),
	    cmocka_unit_test(counting_allocator),
	    cmocka_unit_test(failing_allocator),
	    cmocka_unit_test(rough_fractal_at_low_resolution),
	    cmocka_unit_test(smooth_mt_models_resolved_at_high_resolution),
	    cmocka_unit_test(turbulence_aliased),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
