/* The test ensemble of Jin, Lewis, West 2005 (section 3.1, Tables 2 and 3):
 * ten surfaces with exact normals, each at three resolutions. Everything is
 * deterministic (no random numbers, no mutable global state); the same
 * table, with the reasons for each choice, is in docs/ENSEMBLE.md.
 *
 * TP, section 3.1.1: vertices on a (u, v) grid, seams and poles welded, so
 * the surfaces are closed; exact normal = normalize(P_u x P_v).
 *   sphere_tp  unit sphere, u = polar angle (bands), v = longitude (segments);
 *              the poles are single vertices with the radial normal.
 *   torus_tp   R = 1 (centre of the tube), r = 0.6 (tube), u around z
 *              (segments), v around the tube (bands). r > R / 2 gives the
 *              inner band cos v < -R / (2r) (19% of the tube) negative mean
 *              curvature, where MEWCSA's uncorrected sign shows (section
 *              4.1.1); the sphere's is positive everywhere.
 *   grids (bands x segments): low 12 x 24, medium 24 x 48, high 48 x 96.
 *
 * HF, section 3.1.2: z = a f(x, y) on an n x n grid over [0, 2]^2, n = 16,
 * 32, 64 (450, 1922, 7938 triangles as in Table 3), a = 0.5, every quad cut
 * along its (i, j)-(i+1, j+1) diagonal; exact normal normalize(-a f_x,
 * -a f_y, 1). f is sampled at z = 1/3 of the 3D noise: at an integer z the
 * slice would contain the lattice points, where the noise is 0 by
 * construction (a gradient-only lattice), pinning the terrain to 0 on a
 * regular grid; 1/3 also stays 1/3 away from the lattice planes for every
 * octave's 2^i z (0.5 would land on them from i = 1 on).
 *   perlin_hf      f = noise(x, y, 1/3): the domain spans 2 x 2 noise cells.
 *   fractalH_hf    f = sum_{i<3} noise(2^i p) 2^(-iH), H = 0.9, 0.5, 0.1:
 *                  3 octaves, the finest (8 cycles per side) beyond what
 *                  the 16 x 16 grid can resolve, so the low resolution is
 *                  rough as in section 4.1.3 (H = 0.1: 70% of the interior
 *                  vertices are 20 degrees off or more for MWA).
 *
 * MT, section 3.1.3 (marching.c): the box [-1, 1]^3 cut into cells^3 cubes;
 * exact normal = normalized analytic gradient.
 *   sphere_mt      f = x^2 + y^2 + z^2, iso 0.64 (radius 0.8); closed.
 *   cosine_mt      eq. 10, f = sum cos(2 pi d x_k), d = 0.75 (1.5 periods
 *                  across the box), iso 0; cut by the box (boundary).
 *   perlin_mt      f = noise(p + (0.37, 0.61, 0.23)), iso 0 (2 noise cells
 *                  across; the offset keeps lattice points, where the noise
 *                  is exactly 0, off the samples).
 *   turbulence_mt  f = sum_{i<4} |noise(2^i q)| / 2^i, q = p / 2 +
 *                  (0.37, 0.61, 0.23), iso 0.15 (the surface wraps the zero
 *                  sheets of the noise).
 *   cells: sphere, cosine, perlin 13, 29, 59 (primes: no sample lies
 *   exactly on the sphere or the cosine surface); turbulence 10, 14, 18,
 *   chosen for Table 3's 1501, 3758, 7136 triangles (we get 1572, 3786,
 *   7248: +4.7%, +0.7%, +1.6%).
 *
 * Beyond the paper (appended, so the ten keep their values):
 *   ellipsoid_tp   semi-axes (1, 0.75, 0.5) by the sphere's parameterization
 *                  with every ring vertex jittered in (u, v) by up to 1/4
 *                  of a grid step (a fixed integer hash, not random): rings
 *                  of irregular shape, vertices exactly on the surface;
 *                  exact normal normalize(bc sin u cos v, ac sin u sin v,
 *                  ab cos u) (P_u x P_v / sin u, so the poles need no
 *                  special case). Grids as the TP models.
 *   gyroid_mt      the gyroid sin x cos y + sin y cos z + sin z cos x = 0
 *                  at q = 1.5 pi p + (0.3, 0.5, 0.7) (1.5 periods across
 *                  the box, cut by it), cells 13, 29, 59.
 *
 * vn_model_generate_grid generates any model on another grid (bands, side
 * or cells) for convergence studies; the three resolutions are its
 * vn_model_grid values.
 *
 * Counts (vertices, triangles, boundary vertices):
 *   model          low                  medium                 high
 *   sphere_tp        266    528    0      1106   2208    0       4514   9024    0
 *   torus_tp         288    576    0      1152   2304    0       4608   9216    0
 *   perlin_hf        256    450   60      1024   1922  124       4096   7938  252
 *   fractal09_hf     256    450   60      1024   1922  124       4096   7938  252
 *   fractal05_hf     256    450   60      1024   1922  124       4096   7938  252
 *   fractal01_hf     256    450   60      1024   1922  124       4096   7938  252
 *   sphere_mt       1562   3120    0      7586  15168    0      31514  63024    0
 *   cosine_mt       2642   4704  564     12530  23688 1356      50294  97776 2796
 *   perlin_mt       3182   5916  452     15322  29634 1010      62670 123288 2056
 *   turbulence_mt    908   1572  200      2042   3786  304       3840   7248  460
 *   ellipsoid_tp     266    528    0      1106   2208    0       4514   9024    0
 *   gyroid_mt       3868   7128  644     18566  35706 1462      75522 148100 2980
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "paper.h"

/* ---------------------------------------------------------------- names */

static const struct {
	const char* name;
	const char* description;
} models[vn_model_count] = {
    {"sphere_tp", "unit sphere, latitude-longitude trigonometric parameterization (section 3.1.1)"},
    {"torus_tp", "torus R = 1, r = 0.6, trigonometric parameterization (section 3.1.1)"},
    {"perlin_hf", "height field of Perlin's improved noise (section 3.1.2)"},
    {"fractal09_hf", "height field of fBm Perlin noise, H = 0.9 (section 3.1.2, Table 3)"},
    {"fractal05_hf", "height field of fBm Perlin noise, H = 0.5 (section 3.1.2, Table 3)"},
    {"fractal01_hf", "height field of fBm Perlin noise, H = 0.1 (section 3.1.2, Table 3)"},
    {"sphere_mt", "sphere of radius 0.8 by marching tetrahedra (section 3.1.3)"},
    {"cosine_mt", "cosine sum sum_k cos(2 pi d x_k) = 0, d = 0.75, by marching tetrahedra (eq. 10)"},
    {"perlin_mt", "zero set of 3D Perlin noise by marching tetrahedra (section 3.1.3)"},
    {"turbulence_mt", "isosurface of Perlin turbulence by marching tetrahedra (section 3.1.3, Table 3)"},
    {"ellipsoid_tp", "ellipsoid (1, 0.75, 0.5), jittered trigonometric parameterization (not in the paper)"},
    {"gyroid_mt", "gyroid sin x cos y + sin y cos z + sin z cos x = 0 by marching tetrahedra (not in the paper)"},
};

static const char* const resolutions[vn_resolution_count] = {"low", "medium", "high"};

const char* vn_model_name(vn_model m)
{
	return (unsigned)m < vn_model_count ? models[m].name : NULL;
}

const char* vn_model_description(vn_model m)
{
	return (unsigned)m < vn_model_count ? models[m].description : NULL;
}

const char* vn_resolution_name(vn_resolution r)
{
	return (unsigned)r < vn_resolution_count ? resolutions[r] : NULL;
}

/* ---------------------------------------------------------------- helpers */

static void normalize_into(double* out, double x, double y, double z)
{
	const double inv = 1.0 / sqrt(x * x + y * y + z * z);
	out[0] = x * inv, out[1] = y * inv, out[2] = z * inv;
}

/* normalize(pu x pv): the exact normal of a parameterization (section 3.1.1). */
static void cross_normal(double* out, const double pu[3], const double pv[3])
{
	normalize_into(out, pu[1] * pv[2] - pu[2] * pv[1], pu[2] * pv[0] - pu[0] * pv[2], pu[0] * pv[1] - pu[1] * pv[0]);
}

static void put3(double* out, double x, double y, double z)
{
	out[0] = x, out[1] = y, out[2] = z;
}

static uint32_t* put_triangle(uint32_t* out, uint32_t a, uint32_t b, uint32_t c)
{
	out[0] = a, out[1] = b, out[2] = c;
	return out + 3;
}

/* ---------------------------------------------------------------- TP (section 3.1.1) */

/* The grids are `bands` between the poles (sphere: latitude, torus: around
 * the tube) by twice as many segments around the z axis (table `grids`). */

#define TORUS_R 1.0
#define TORUS_r 0.6

/* The sphere P(u, v) = (sin u cos v, sin u sin v, cos u), u in [0, pi] from
 * the north pole, v in [0, 2 pi); P_u x P_v = sin u P points outward. */
static void sphere_vertex(unsigned j, unsigned i, unsigned bands, unsigned segs, double* p, double* n)
{
	const double u = VN_PI * j / bands, v = 2 * VN_PI * i / segs;
	const double su = sin(u), cu = cos(u), sv = sin(v), cv = cos(v);
	put3(p, su * cv, su * sv, cu);
	/* P_u = (cu cv, cu sv, -su), P_v = (-su sv, su cv, 0). */
	const double pu[3] = {cu * cv, cu * sv, -su}, pv[3] = {-su * sv, su * cv, 0};
	cross_normal(n, pu, pv);
}

#define ELLIPSOID_A 1.0
#define ELLIPSOID_B 0.75
#define ELLIPSOID_C 0.5
#define ELLIPSOID_JITTER 0.15

/* A fixed value in [-ELLIPSOID_JITTER, ELLIPSOID_JITTER) for grid point (i, j)
 * and coordinate k: an integer hash (Wang/Murmur-style mixing), so the mesh
 * is irregular yet deterministic. 0.15 of a step keeps every parameter-space
 * triangle counter-clockwise (its cross product stays >= 0.7^2 - 0.3 * 1.3). */
static double jitter(unsigned i, unsigned j, unsigned k)
{
	uint32_t h = (uint32_t)i * 0x9E3779B1u ^ (uint32_t)j * 0x85EBCA77u ^ (uint32_t)k * 0xC2B2AE3Du;
	h ^= h >> 15, h *= 0x2C1B3C6Du, h ^= h >> 12, h *= 0x297A2D39u, h ^= h >> 15;
	return ELLIPSOID_JITTER * (2.0 * (double)h / 4294967296.0 - 1.0);
}

/* The ellipsoid P(u, v) = (a sin u cos v, b sin u sin v, c cos u) at the
 * jittered grid point; P_u x P_v = sin u (bc sin u cos v, ac sin u sin v,
 * ab cos u). */
static void ellipsoid_vertex(unsigned j, unsigned i, unsigned bands, unsigned segs, double* p, double* n)
{
	const double u = VN_PI * (j + jitter(i, j, 0)) / bands, v = 2 * VN_PI * (i + jitter(i, j, 1)) / segs;
	const double su = sin(u), cu = cos(u), sv = sin(v), cv = cos(v);
	put3(p, ELLIPSOID_A * su * cv, ELLIPSOID_B * su * sv, ELLIPSOID_C * cu);
	normalize_into(n, ELLIPSOID_B * ELLIPSOID_C * su * cv, ELLIPSOID_A * ELLIPSOID_C * su * sv,
	               ELLIPSOID_A * ELLIPSOID_B * cu);
}

typedef void (*ring_vertex_fn)(unsigned j, unsigned i, unsigned bands, unsigned segs, double* p, double* n);

/* A closed surface of revolution's topology, parameterized from the north
 * pole (u = 0) to the south pole (u = pi): rings 1 .. bands - 1 of `segs`
 * vertices each placed by `ring`, between the two poles (first and last
 * vertex, at z = +-pole_z, normal (0, 0, +-1): P_u x P_v vanishes there).
 * Quads (a, b, c, d) = ((j, i), (j+1, i), (j+1, i+1), (j, i+1)) are
 * counter-clockwise in (u, v), hence around P_u x P_v; the pole rows keep
 * the one triangle that does not collapse. */
static vn_result pole_grid(const vn_allocator* heap, unsigned bands, double pole_z, ring_vertex_fn ring,
                           vn_model_mesh* mesh)
{
	const unsigned segs = 2 * bands;
	mesh->vertex_count = 2 + (size_t)(bands - 1) * segs;
	mesh->triangle_count = 2 * (size_t)(bands - 1) * segs;
	const vn_result res = vn_mesh_allocate(heap, mesh);
	if (res != vn_result_success)
		return res;

	const uint32_t south = (uint32_t)mesh->vertex_count - 1;
	put3(mesh->positions, 0, 0, pole_z), put3(mesh->normals, 0, 0, 1);
	put3(mesh->positions + 3 * (size_t)south, 0, 0, -pole_z), put3(mesh->normals + 3 * (size_t)south, 0, 0, -1);
	for (unsigned j = 1; j < bands; ++j)
		for (unsigned i = 0; i < segs; ++i) {
			const size_t k = 1 + (size_t)(j - 1) * segs + i;
			ring(j, i, bands, segs, mesh->positions + 3 * k, mesh->normals + 3 * k);
		}
	uint32_t* out = mesh->indices;
	for (unsigned j = 0; j < bands; ++j) {
		for (unsigned i = 0; i < segs; ++i) {
			const unsigned i1 = (i + 1) % segs;
			const uint32_t a = j == 0 ? 0 : 1 + (j - 1) * segs + i, d = j == 0 ? 0 : 1 + (j - 1) * segs + i1;
			const uint32_t b = j + 1 == bands ? south : 1 + j * segs + i;
			const uint32_t c = j + 1 == bands ? south : 1 + j * segs + i1;
			if (j + 1 < bands)
				out = put_triangle(out, a, b, c);
			if (j > 0)
				out = put_triangle(out, a, c, d);
		}
	}
	return vn_result_success;
}

/* The torus P(u, v) = ((R + r cos v) cos u, (R + r cos v) sin u, r sin v),
 * u around the z axis, v around the tube; P_u x P_v =
 * r (R + r cos v) (cos v cos u, cos v sin u, sin v) points outward. Vertex
 * (u_i, v_j) is i * bands + j; both seams are welded. */
static vn_result torus_tp(const vn_allocator* heap, unsigned bands, vn_model_mesh* mesh)
{
	const unsigned segs = 2 * bands;
	mesh->vertex_count = (size_t)bands * segs;
	mesh->triangle_count = 2 * (size_t)bands * segs;
	const vn_result res = vn_mesh_allocate(heap, mesh);
	if (res != vn_result_success)
		return res;

	for (unsigned i = 0; i < segs; ++i) {
		const double u = 2 * VN_PI * i / segs, su = sin(u), cu = cos(u);
		for (unsigned j = 0; j < bands; ++j) {
			const double v = 2 * VN_PI * j / bands, sv = sin(v), cv = cos(v);
			const double ring = TORUS_R + TORUS_r * cv;
			const size_t k = (size_t)i * bands + j;
			put3(mesh->positions + 3 * k, ring * cu, ring * su, TORUS_r * sv);
			/* P_u = (-ring su, ring cu, 0), P_v = (-r sv cu, -r sv su, r cv). */
			const double pu[3] = {-ring * su, ring * cu, 0};
			const double pv[3] = {-TORUS_r * sv * cu, -TORUS_r * sv * su, TORUS_r * cv};
			cross_normal(mesh->normals + 3 * k, pu, pv);
		}
	}
	uint32_t* out = mesh->indices;
	for (unsigned i = 0; i < segs; ++i) {
		const unsigned i1 = (i + 1) % segs;
		for (unsigned j = 0; j < bands; ++j) {
			const unsigned j1 = (j + 1) % bands;
			const uint32_t a = i * bands + j, b = i1 * bands + j, c = i1 * bands + j1, d = i * bands + j1;
			out = put_triangle(out, a, b, c);
			out = put_triangle(out, a, c, d);
		}
	}
	return vn_result_success;
}

/* ---------------------------------------------------------------- HF (section 3.1.2) */

#define HF_SIZE 2.0
#define HF_Z (1.0 / 3.0)
#define HF_AMPLITUDE 0.5
#define HF_OCTAVES 3

/* z = a f(x, y) over [0, HF_SIZE]^2, f the noise (H < 0: one octave) or the
 * fBm at (x, y, HF_Z). */
static double hf_height(double h, double x, double y, double g[3])
{
	const double p[3] = {x, y, HF_Z};
	return h < 0 ? vn_perlin_noise(p, g) : vn_fbm_noise(p, HF_OCTAVES, h, g);
}

static vn_result height_field(const vn_allocator* heap, unsigned n, double h, vn_model_mesh* mesh)
{
	mesh->vertex_count = (size_t)n * n;
	mesh->triangle_count = 2 * (size_t)(n - 1) * (n - 1);
	const vn_result res = vn_mesh_allocate(heap, mesh);
	if (res != vn_result_success)
		return res;

	for (unsigned j = 0; j < n; ++j) {
		const double y = HF_SIZE * j / (n - 1);
		for (unsigned i = 0; i < n; ++i) {
			const double x = HF_SIZE * i / (n - 1);
			double g[3];
			const double z = HF_AMPLITUDE * hf_height(h, x, y, g);
			const size_t k = (size_t)j * n + i;
			put3(mesh->positions + 3 * k, x, y, z);
			normalize_into(mesh->normals + 3 * k, -HF_AMPLITUDE * g[0], -HF_AMPLITUDE * g[1], 1);
		}
	}
	/* Every quad cut along the same diagonal, counter-clockwise seen from +z. */
	uint32_t* out = mesh->indices;
	for (unsigned j = 0; j + 1 < n; ++j) {
		for (unsigned i = 0; i + 1 < n; ++i) {
			const uint32_t a = j * n + i, b = a + 1, c = a + 1 + n, d = a + n;
			out = put_triangle(out, a, b, c);
			out = put_triangle(out, a, c, d);
		}
	}
	return vn_result_success;
}

/* ---------------------------------------------------------------- MT (section 3.1.3) */

/* f(p) = g(d p + offset) for the noise models. */
typedef struct field {
	double dilation;
	double offset[3];
	unsigned octaves;
} field;

static double sphere_f(const void* params, const double p[3], double* g)
{
	(void)params;
	if (g)
		put3(g, 2 * p[0], 2 * p[1], 2 * p[2]);
	return p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
}

/* eq. 10 */
static double cosine_f(const void* params, const double p[3], double* g)
{
	const double w = 2 * VN_PI * ((const field*)params)->dilation;
	if (g)
		put3(g, -w * sin(w * p[0]), -w * sin(w * p[1]), -w * sin(w * p[2]));
	return cos(w * p[0]) + cos(w * p[1]) + cos(w * p[2]);
}

static void field_point(const field* s, const double p[3], double q[3])
{
	for (int k = 0; k < 3; ++k)
		q[k] = s->dilation * p[k] + s->offset[k];
}

static void field_gradient(const field* s, double* g)
{
	if (g)
		g[0] *= s->dilation, g[1] *= s->dilation, g[2] *= s->dilation;
}

static double perlin_f(const void* params, const double p[3], double* g)
{
	const field* s = (const field*)params;
	double q[3];
	field_point(s, p, q);
	const double v = vn_perlin_noise(q, g);
	field_gradient(s, g);
	return v;
}

static double turbulence_f(const void* params, const double p[3], double* g)
{
	const field* s = (const field*)params;
	double q[3];
	field_point(s, p, q);
	const double v = vn_turbulence_noise(q, s->octaves, g);
	field_gradient(s, g);
	return v;
}

/* The gyroid sin x cos y + sin y cos z + sin z cos x at q = d p + offset. */
static double gyroid_f(const void* params, const double p[3], double* g)
{
	const field* s = (const field*)params;
	double q[3];
	field_point(s, p, q);
	const double sx = sin(q[0]), cx = cos(q[0]), sy = sin(q[1]), cy = cos(q[1]), sz = sin(q[2]), cz = cos(q[2]);
	if (g) {
		put3(g, cx * cy - sz * sx, cy * cz - sx * sy, cz * cx - sy * sz);
		field_gradient(s, g);
	}
	return sx * cy + sy * cz + sz * cx;
}

static const field cosine_field = {0.75, {0, 0, 0}, 0};
static const field perlin_field = {1.0, {0.37, 0.61, 0.23}, 0};
static const field turbulence_field = {0.5, {0.37, 0.61, 0.23}, 4};
static const field gyroid_field = {1.5 * VN_PI, {0.3, 0.5, 0.7}, 0};

typedef struct mt_model {
	vn_implicit_fn f;
	const field* params;
	double iso;
} mt_model;

static const mt_model mt_sphere = {sphere_f, NULL, 0.64}, mt_cosine = {cosine_f, &cosine_field, 0.0},
                      mt_perlin = {perlin_f, &perlin_field, 0.0}, mt_turbulence = {turbulence_f, &turbulence_field, 0.15},
                      mt_gyroid = {gyroid_f, &gyroid_field, 0.0};

static vn_result marching_model(const vn_allocator* heap, const mt_model* k, unsigned cells, vn_model_mesh* mesh)
{
	const vn_implicit s = {k->f, k->params, k->iso, -1.0, 1.0, cells};
	return vn_marching_tetrahedra(&s, heap, mesh);
}

/* ---------------------------------------------------------------- boundary */

static int compare_keys(const void* a, const void* b)
{
	const uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
	return (x > y) - (x < y);
}

/* A vertex is on the boundary when it ends an edge used by exactly one
 * triangle: sort the undirected edge keys, flag the ends of lone keys. */
static vn_result mark_boundary(const vn_allocator* heap, vn_model_mesh* mesh)
{
	const size_t ne = 3 * mesh->triangle_count;
	uint64_t* keys = (uint64_t*)vn_paper_allocate(heap, ne * sizeof(uint64_t));
	if (!keys)
		return vn_result_out_of_memory;
	for (size_t t = 0; t < mesh->triangle_count; ++t) {
		const uint32_t* tri = mesh->indices + 3 * t;
		for (int c = 0; c < 3; ++c) {
			const uint64_t a = tri[c], b = tri[(c + 1) % 3];
			keys[3 * t + c] = a < b ? a << 32 | b : b << 32 | a;
		}
	}
	qsort(keys, ne, sizeof(uint64_t), compare_keys);
	for (size_t i = 0; i < ne;) {
		size_t j = i + 1;
		while (j < ne && keys[j] == keys[i])
			++j;
		if (j - i == 1)
			mesh->boundary[keys[i] >> 32] = mesh->boundary[keys[i] & UINT32_MAX] = 1;
		i = j;
	}
	vn_paper_free(heap, keys);
	return vn_result_success;
}

/* ---------------------------------------------------------------- entry points */

enum family { tp, hf, mt };

/* Each model's family and grid (bands, side, cells) at the three resolutions. */
static const struct {
	enum family family;
	unsigned grid[vn_resolution_count];
} grids[vn_model_count] = {
    {tp, {12, 24, 48}}, {tp, {12, 24, 48}}, {hf, {16, 32, 64}}, {hf, {16, 32, 64}},
    {hf, {16, 32, 64}}, {hf, {16, 32, 64}}, {mt, {13, 29, 59}}, {mt, {13, 29, 59}},
    {mt, {13, 29, 59}}, {mt, {10, 14, 18}}, {tp, {12, 24, 48}}, {mt, {13, 29, 59}},
};

/* The smallest and largest grid of each family (vn_paper.h). */
static const unsigned grid_min[3] = {3, 2, 2}, grid_max[3] = {VN_MODEL_GRID_MAX, VN_MODEL_GRID_MAX, VN_MODEL_CELLS_MAX};

unsigned vn_model_grid(vn_model m, vn_resolution r)
{
	return (unsigned)m < vn_model_count && (unsigned)r < vn_resolution_count ? grids[m].grid[r] : 0;
}

static vn_result generate(const vn_allocator* heap, vn_model m, unsigned grid, vn_model_mesh* mesh)
{
	switch (m) {
	case vn_model_sphere_tp:
		return pole_grid(heap, grid, 1.0, sphere_vertex, mesh);
	case vn_model_torus_tp:
		return torus_tp(heap, grid, mesh);
	case vn_model_perlin_hf:
		return height_field(heap, grid, -1.0, mesh);
	case vn_model_fractal09_hf:
		return height_field(heap, grid, 0.9, mesh);
	case vn_model_fractal05_hf:
		return height_field(heap, grid, 0.5, mesh);
	case vn_model_fractal01_hf:
		return height_field(heap, grid, 0.1, mesh);
	case vn_model_sphere_mt:
		return marching_model(heap, &mt_sphere, grid, mesh);
	case vn_model_cosine_mt:
		return marching_model(heap, &mt_cosine, grid, mesh);
	case vn_model_perlin_mt:
		return marching_model(heap, &mt_perlin, grid, mesh);
	case vn_model_turbulence_mt:
		return marching_model(heap, &mt_turbulence, grid, mesh);
	case vn_model_ellipsoid_tp:
		return pole_grid(heap, grid, ELLIPSOID_C, ellipsoid_vertex, mesh);
	default:
		return marching_model(heap, &mt_gyroid, grid, mesh);
	}
}

vn_result vn_model_generate_grid(vn_model m, unsigned grid, const vn_allocator* allocator, vn_model_mesh* mesh)
{
	if (!mesh)
		return vn_result_invalid_argument;
	memset(mesh, 0, sizeof(*mesh));
	if (allocator && !allocator->allocate != !allocator->deallocate)
		return vn_result_invalid_argument;
	const vn_allocator heap = allocator ? *allocator : (vn_allocator){NULL, NULL, NULL};
	if ((unsigned)m >= vn_model_count || grid < grid_min[grids[m].family] || grid > grid_max[grids[m].family])
		return vn_result_invalid_argument;

	vn_result res = generate(&heap, m, grid, mesh);
	if (res == vn_result_success)
		res = mark_boundary(&heap, mesh);
	if (res != vn_result_success)
		vn_mesh_release(&heap, mesh);
	return res;
}

vn_result vn_model_generate(vn_model m, vn_resolution r, const vn_allocator* allocator, vn_model_mesh* mesh)
{
	if (mesh && (unsigned)r >= vn_resolution_count)
		memset(mesh, 0, sizeof(*mesh));
	if ((unsigned)r >= vn_resolution_count)
		return vn_result_invalid_argument;
	return vn_model_generate_grid(m, vn_model_grid(m, r), allocator, mesh);
}

void vn_model_free(vn_model_mesh* mesh, const vn_allocator* allocator)
{
	if (!mesh)
		return;
	const vn_allocator heap = allocator ? *allocator : (vn_allocator){NULL, NULL, NULL};
	vn_mesh_release(&heap, mesh);
}
