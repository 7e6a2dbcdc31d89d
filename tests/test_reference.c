/*
 * The library against an independent reference (reference.c), on random and
 * adversarial meshes, plus properties the paper states that do not need a
 * reference at all: Max's sphere exactness of MWSELR and the sign behaviour
 * of MEWCSA. Every mesh is generated from a fixed seed, so a failure
 * reproduces exactly.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reference.h"
#include "vn.h"

/* The reference numbers methods on its own; they must match vn_method. */
_Static_assert(ref_mwe == (int)vn_method_mwe, "method order");
_Static_assert(ref_mwa == (int)vn_method_mwa, "method order");
_Static_assert(ref_mwselr == (int)vn_method_mwselr, "method order");
_Static_assert(ref_mwaat == (int)vn_method_mwaat, "method order");
_Static_assert(ref_mwelr == (int)vn_method_mwelr, "method order");
_Static_assert(ref_mwrelr == (int)vn_method_mwrelr, "method order");
_Static_assert(ref_mewcsa == (int)vn_method_mewcsa, "method order");
_Static_assert(ref_smewcsa == (int)vn_method_smewcsa, "method order");
_Static_assert(ref_quadric == (int)vn_method_quadric, "method order");
_Static_assert(ref_jet == (int)vn_method_jet, "method order");
_Static_assert(ref_adaptive == (int)vn_method_adaptive, "method order");
_Static_assert(ref_method_count == (int)vn_method_count, "every method, in order");

#define PI 3.14159265358979323846
/* Library vs reference: 0.01 degree. Both compute in (at least) double, so
 * anything near this is a real difference, not rounding. */
#define TOLERANCE_RAD (0.01 * PI / 180)
/* A vertex whose sum is below this fraction of its summed contribution
 * lengths has a direction made of rounding noise: not compared. */
#define MIN_CONDITION 1e-9
/* Library (normal equations, Cholesky, double) vs reference (Householder QR,
 * long double) on a fit whose unit-diagonal normal matrix has reciprocal
 * condition rc: the library's coefficients are exact to about k eps / rc
 * (k <= 10 unknowns, eps = 1.1e-16, the normal equations square the design
 * matrix's condition), the refit carries the first fit's error along, and
 * the reference's rc is an estimate within a factor k: 1e-13 / rc, and at
 * least 1e-9 (the largest difference measured where rc > 1e-4 is ~1e-13). */
#define FIT_TOLERANCE(rc) fmax(1e-9, 1e-13 / (rc))
/* How many mismatches to print per mesh before only counting. */
#define MAX_REPORTS 6

static const char* const method_names[ref_method_count] = {
	"mwe", "mwa", "mwselr", "mwaat", "mwelr", "mwrelr", "mewcsa", "smewcsa", "quadric", "jet", "adaptive"};

/* ------------------------------------------------------------------ vectors */

static double dot3(const double* a, const double* b)
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double* a, const double* b, double* out)
{
	out[0] = a[1] * b[2] - a[2] * b[1];
	out[1] = a[2] * b[0] - a[0] * b[2];
	out[2] = a[0] * b[1] - a[1] * b[0];
}

static double length3(const double* a)
{
	return sqrt(dot3(a, a));
}

static void normalize3(double* a)
{
	double l = length3(a);
	a[0] /= l;
	a[1] /= l;
	a[2] /= l;
}

/* Angle between two non-zero vectors, accurate for tiny angles (acos is not). */
static double angle3(const double* a, const double* b)
{
	double c[3];
	cross3(a, b, c);
	return atan2(length3(c), dot3(a, b));
}

/* ------------------------------------------------------------------ random */

/* xorshift64: deterministic everywhere, unlike rand(). */
typedef struct rng {
	uint64_t state;
} rng;

static rng rng_seed(uint64_t seed)
{
	rng r = {seed * 0x9E3779B97F4A7C15ull | 1};
	return r;
}

static uint64_t rng_next(rng* r)
{
	uint64_t x = r->state;
	x ^= x << 13;
	x ^= x >> 7;
	x ^= x << 17;
	r->state = x;
	return x;
}

/* Uniform in [lo, hi). */
static double rng_range(rng* r, double lo, double hi)
{
	double unit = (double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
	return lo + (hi - lo) * unit;
}

static uint32_t rng_below(rng* r, uint32_t n)
{
	return (uint32_t)(rng_next(r) % n);
}

/* A uniformly random unit vector. */
static void rng_direction(rng* r, double* out)
{
	do {
		out[0] = rng_range(r, -1, 1);
		out[1] = rng_range(r, -1, 1);
		out[2] = rng_range(r, -1, 1);
	} while (dot3(out, out) > 1 || dot3(out, out) < 1e-4);
	normalize3(out);
}

/* ------------------------------------------------------------------ meshes */

typedef struct mesh {
	char name[64];
	double* pos; /* 3 per vertex */
	size_t nv, vcap;
	uint32_t* idx;
	size_t ni, icap;
	uint32_t* off; /* nf + 1 entries */
	size_t nf, fcap;
} mesh;

static void* grow(void* p, size_t* cap, size_t need, size_t elem)
{
	if (need <= *cap)
		return p;
	size_t c = *cap ? *cap : 64;
	while (c < need)
		c *= 2;
	p = realloc(p, c * elem);
	assert_non_null(p);
	*cap = c;
	return p;
}

static void mesh_init(mesh* m, const char* name)
{
	memset(m, 0, sizeof *m);
	snprintf(m->name, sizeof m->name, "%s", name);
	m->off = grow(NULL, &m->fcap, 1, sizeof *m->off);
	m->off[0] = 0;
}

static void mesh_free(mesh* m)
{
	free(m->pos);
	free(m->idx);
	free(m->off);
	memset(m, 0, sizeof *m);
}

static uint32_t mesh_vertex(mesh* m, double x, double y, double z)
{
	m->pos = grow(m->pos, &m->vcap, 3 * (m->nv + 1), sizeof *m->pos);
	m->pos[3 * m->nv] = x;
	m->pos[3 * m->nv + 1] = y;
	m->pos[3 * m->nv + 2] = z;
	return (uint32_t)m->nv++;
}

static void mesh_face(mesh* m, const uint32_t* corners, size_t k)
{
	m->idx = grow(m->idx, &m->icap, m->ni + k, sizeof *m->idx);
	memcpy(m->idx + m->ni, corners, k * sizeof *corners);
	m->ni += k;
	m->off = grow(m->off, &m->fcap, m->nf + 2, sizeof *m->off);
	m->off[++m->nf] = (uint32_t)m->ni;
}

/* Adds the face wound so that its Newell normal has dot(normal, dir) >= 0:
 * generators then need not get every winding right by hand. */
static void mesh_face_facing(mesh* m, const uint32_t* corners, size_t k, const double* dir)
{
	double n[3] = {0, 0, 0};
	const double* p0 = m->pos + 3 * (size_t)corners[0];
	for (size_t i = 1; i + 1 < k; i++) {
		double a[3], b[3], c[3];
		for (int d = 0; d < 3; d++) {
			a[d] = m->pos[3 * (size_t)corners[i] + d] - p0[d];
			b[d] = m->pos[3 * (size_t)corners[i + 1] + d] - p0[d];
		}
		cross3(a, b, c);
		for (int d = 0; d < 3; d++)
			n[d] += c[d];
	}
	if (dot3(n, dir) >= 0) {
		mesh_face(m, corners, k);
		return;
	}
	uint32_t reversed[16];
	assert_true(k <= 16);
	for (size_t i = 0; i < k; i++)
		reversed[i] = corners[k - 1 - i];
	mesh_face(m, reversed, k);
}

static void mesh_triangle(mesh* m, uint32_t a, uint32_t b, uint32_t c)
{
	uint32_t t[3] = {a, b, c};
	mesh_face(m, t, 3);
}

/* Faces facing away from a centre point (for closed convex shapes). */
static void mesh_face_outward(mesh* m, const uint32_t* corners, size_t k, const double* centre)
{
	double dir[3] = {0, 0, 0};
	for (size_t i = 0; i < k; i++) {
		for (int d = 0; d < 3; d++)
			dir[d] += m->pos[3 * (size_t)corners[i] + d] - centre[d];
	}
	mesh_face_facing(m, corners, k, dir);
}

static int mesh_is_triangles(const mesh* m)
{
	for (size_t f = 0; f < m->nf; f++) {
		if (m->off[f + 1] - m->off[f] != 3)
			return 0;
	}
	return 1;
}

/* Moves every vertex by a random vector of length up to `amount`. */
static void mesh_jitter(mesh* m, uint64_t seed, double amount)
{
	rng r = rng_seed(seed);
	for (size_t v = 0; v < m->nv; v++) {
		double d[3];
		rng_direction(&r, d);
		double s = rng_range(&r, 0, amount);
		for (int k = 0; k < 3; k++)
			m->pos[3 * v + k] += s * d[k];
	}
}

static void mesh_reverse_faces(mesh* m)
{
	for (size_t f = 0; f < m->nf; f++) {
		uint32_t* c = m->idx + m->off[f];
		size_t k = m->off[f + 1] - m->off[f];
		for (size_t i = 0; i < k / 2; i++) {
			uint32_t t = c[i];
			c[i] = c[k - 1 - i];
			c[k - 1 - i] = t;
		}
	}
}

/* Random points and random triangles, with the awkward cases mixed in: a
 * repeated index now and then, unused vertices (exactly zero normals) and one
 * vertex with a NaN coordinate (its faces contribute nothing). */
static void make_triangle_soup(mesh* m, uint64_t seed, size_t nv, size_t nf)
{
	rng r = rng_seed(seed);
	for (size_t v = 0; v < nv; v++)
		mesh_vertex(m, rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1));
	m->pos[3 * 5 + 1] = NAN;
	uint32_t used = (uint32_t)nv - 8;
	for (size_t f = 0; f < nf; f++) {
		uint32_t a = rng_below(&r, used), b = rng_below(&r, used), c = rng_below(&r, used);
		if (rng_below(&r, 40) == 0)
			b = a;
		mesh_triangle(m, a, b, c);
	}
}

/* Random polygons of 3..8 corners over random points: non-planar, non-convex,
 * self-intersecting; also zero-length edges, a 2-corner and an empty face. */
static void make_polygon_soup(mesh* m, uint64_t seed, size_t nv, size_t nf)
{
	rng r = rng_seed(seed);
	for (size_t v = 0; v < nv; v++)
		mesh_vertex(m, rng_range(&r, -1, 1), rng_range(&r, -1, 1), rng_range(&r, -1, 1));
	uint32_t used = (uint32_t)nv - 5;
	for (size_t f = 0; f < nf; f++) {
		uint32_t c[8];
		size_t k = 3 + rng_below(&r, 6);
		for (size_t i = 0; i < k; i++)
			c[i] = rng_below(&r, used);
		if (rng_below(&r, 20) == 0)
			c[1] = c[0];
		mesh_face(m, c, k);
		if (f == nf / 3)
			mesh_face(m, c, 2);
		if (f == nf / 2)
			mesh_face(m, c, 0);
	}
}

/* Icosphere: subdivided icosahedron on a sphere, outward wound. */
typedef struct edge_map {
	uint64_t* keys;
	uint32_t* values;
	size_t mask;
} edge_map;

static uint32_t midpoint(mesh* m, edge_map* map, uint32_t a, uint32_t b)
{
	uint64_t lo = a < b ? a : b, hi = a < b ? b : a;
	uint64_t key = (lo << 32 | hi) + 1;
	size_t h = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & map->mask;
	while (map->keys[h] && map->keys[h] != key)
		h = (h + 1) & map->mask;
	if (map->keys[h] == key)
		return map->values[h];
	double p[3];
	for (int d = 0; d < 3; d++)
		p[d] = m->pos[3 * (size_t)a + d] + m->pos[3 * (size_t)b + d];
	normalize3(p);
	map->keys[h] = key;
	map->values[h] = mesh_vertex(m, p[0], p[1], p[2]);
	return map->values[h];
}

static void make_icosphere(mesh* m, int level, double radius, const double* centre)
{
	static const double base[12][3] = {
		{-1, 1.618033988749895, 0}, {1, 1.618033988749895, 0}, {-1, -1.618033988749895, 0},
		{1, -1.618033988749895, 0}, {0, -1, 1.618033988749895}, {0, 1, 1.618033988749895},
		{0, -1, -1.618033988749895}, {0, 1, -1.618033988749895}, {1.618033988749895, 0, -1},
		{1.618033988749895, 0, 1}, {-1.618033988749895, 0, -1}, {-1.618033988749895, 0, 1}};
	static const uint32_t faces[20][3] = {
		{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
		{11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
		{3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
	for (int v = 0; v < 12; v++) {
		double p[3] = {base[v][0], base[v][1], base[v][2]};
		normalize3(p);
		mesh_vertex(m, p[0], p[1], p[2]);
	}
	/* Triangles as a flat list, subdivided 1 -> 4 per level (winding kept). */
	size_t count = 20;
	uint32_t* tris = malloc(count * 3 * sizeof *tris);
	assert_non_null(tris);
	const double origin[3] = {0, 0, 0};
	for (size_t t = 0; t < 20; t++) {
		/* Orient the base faces outward once; subdivision preserves it. */
		mesh_face_outward(m, faces[t], 3, origin);
		memcpy(tris + 3 * t, m->idx + m->off[m->nf - 1], 3 * sizeof *tris);
	}
	m->ni = 0;
	m->nf = 0;
	for (int l = 0; l < level; l++) {
		edge_map map;
		size_t size = 1;
		while (size < count * 4)
			size *= 2;
		map.keys = calloc(size, sizeof *map.keys);
		map.values = calloc(size, sizeof *map.values);
		map.mask = size - 1;
		uint32_t* next = malloc(count * 4 * 3 * sizeof *next);
		assert_non_null(map.keys);
		assert_non_null(map.values);
		assert_non_null(next);
		for (size_t t = 0; t < count; t++) {
			uint32_t a = tris[3 * t], b = tris[3 * t + 1], c = tris[3 * t + 2];
			uint32_t ab = midpoint(m, &map, a, b), bc = midpoint(m, &map, b, c), ca = midpoint(m, &map, c, a);
			uint32_t out[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
			memcpy(next + 12 * t, out, sizeof out);
		}
		free(map.keys);
		free(map.values);
		free(tris);
		tris = next;
		count *= 4;
	}
	for (size_t t = 0; t < count; t++)
		mesh_face(m, tris + 3 * t, 3);
	free(tris);
	for (size_t v = 0; v < m->nv; v++) {
		for (int d = 0; d < 3; d++)
			m->pos[3 * v + d] = centre[d] + radius * m->pos[3 * v + d];
	}
}

/* UV sphere of radius 1 at the origin: triangle fans at the poles, and bands
 * of triangles (kind 0, random diagonals), quads (kind 1) or a mix of quads,
 * pentagons and hexagons (kind 2). */
static void make_uv_sphere(mesh* m, uint64_t seed, uint32_t stacks, uint32_t slices, int kind)
{
	rng r = rng_seed(seed);
	const double origin[3] = {0, 0, 0};
	uint32_t north = mesh_vertex(m, 0, 0, 1);
	uint32_t first = (uint32_t)m->nv;
	for (uint32_t i = 1; i < stacks; i++) {
		double phi = PI * i / stacks;
		for (uint32_t s = 0; s < slices; s++) {
			double theta = 2 * PI * (s + 0.5 * (i % 2)) / slices;
			mesh_vertex(m, sin(phi) * cos(theta), sin(phi) * sin(theta), cos(phi));
		}
	}
	uint32_t south = mesh_vertex(m, 0, 0, -1);
#define RING(i, s) (first + ((i) - 1) * slices + (s) % slices)
	for (uint32_t s = 0; s < slices; s++) {
		uint32_t top[3] = {north, RING(1, s), RING(1, s + 1)};
		uint32_t bottom[3] = {south, RING(stacks - 1, s), RING(stacks - 1, s + 1)};
		mesh_face_outward(m, top, 3, origin);
		mesh_face_outward(m, bottom, 3, origin);
	}
	for (uint32_t i = 1; i + 1 < stacks; i++) {
		for (uint32_t s = 0; s < slices;) {
			uint32_t w = kind == 2 ? 1 + rng_below(&r, 2) : 1;
			if (s + w > slices)
				w = slices - s;
			if (kind == 0) {
				uint32_t a = RING(i, s), b = RING(i, s + 1), c = RING(i + 1, s + 1), d = RING(i + 1, s);
				uint32_t t0[3] = {a, b, c}, t1[3] = {a, c, d}, t2[3] = {a, b, d}, t3[3] = {b, c, d};
				int diagonal = (int)rng_below(&r, 2);
				mesh_face_outward(m, diagonal ? t0 : t2, 3, origin);
				mesh_face_outward(m, diagonal ? t1 : t3, 3, origin);
			} else {
				uint32_t c[8];
				size_t k = 0;
				for (uint32_t j = 0; j <= w; j++)
					c[k++] = RING(i, s + j);
				for (uint32_t j = 0; j <= w; j++) {
					/* Now and then skip a middle corner: a pentagon. */
					if (j > 0 && j < w && rng_below(&r, 3) == 0)
						continue;
					c[k++] = RING(i + 1, s + w - j);
				}
				mesh_face_outward(m, c, k, origin);
			}
			s += w;
		}
	}
#undef RING
}

/* A smooth height field, in the order of 1 in slope and curvature. */
static double height(double x, double y)
{
	return 0.3 * sin(1.7 * x + 0.4) * cos(1.3 * y) + 0.2 * x * y;
}

/* Rows of polygons over a (nx+1) x (ny+1) grid: each face spans 1..3 cells
 * of a row (quad, hexagon, octagon) and may skip middle corners (pentagon,
 * heptagon...; the skipped vertex is a T-junction, or unused altogether).
 * planar: every vertex in one tilted plane (jittered within it); otherwise
 * on a jittered height field. */
static void make_polygon_grid(mesh* m, uint64_t seed, uint32_t nx, uint32_t ny, int planar)
{
	rng r = rng_seed(seed);
	const double h = 0.1;
	const double u[3] = {0.8, 0.0, 0.6}, v[3] = {-0.36, 0.8, 0.48}; /* orthonormal */
	double up[3];
	cross3(u, v, up);
	for (uint32_t j = 0; j <= ny; j++) {
		for (uint32_t i = 0; i <= nx; i++) {
			double x = 0.3 + h * (i + rng_range(&r, -0.25, 0.25));
			double y = -0.2 + h * (j + rng_range(&r, -0.25, 0.25));
			if (planar)
				mesh_vertex(m, 0.5 + x * u[0] + y * v[0], x * u[1] + y * v[1], 2 + x * u[2] + y * v[2]);
			else
				mesh_vertex(m, x, y, height(x, y) + h * rng_range(&r, -0.2, 0.2));
		}
	}
	const double z[3] = {0, 0, 1};
	for (uint32_t j = 0; j < ny; j++) {
		for (uint32_t i = 0; i < nx;) {
			uint32_t w = 1 + rng_below(&r, 3);
			if (i + w > nx)
				w = nx - i;
			uint32_t c[8];
			size_t k = 0;
			for (uint32_t t = 0; t <= w; t++) {
				if (t > 0 && t < w && rng_below(&r, 3) == 0)
					continue;
				c[k++] = j * (nx + 1) + i + t;
			}
			for (uint32_t t = 0; t <= w; t++) {
				if (t > 0 && t < w && rng_below(&r, 3) == 0)
					continue;
				c[k++] = (j + 1) * (nx + 1) + i + w - t;
			}
			mesh_face_facing(m, c, k, planar ? up : z);
			i += w;
		}
	}
}

/* A triangulated height field on an (nx+1) x (ny+1) grid, random diagonals. */
static void make_height_field(mesh* m, uint64_t seed, uint32_t nx, uint32_t ny, double h, double jitter)
{
	rng r = rng_seed(seed);
	for (uint32_t j = 0; j <= ny; j++) {
		for (uint32_t i = 0; i <= nx; i++) {
			double x = -1 + h * (i + rng_range(&r, -jitter, jitter));
			double y = -1 + h * (j + rng_range(&r, -jitter, jitter));
			mesh_vertex(m, x, y, height(x, y));
		}
	}
	for (uint32_t j = 0; j < ny; j++) {
		for (uint32_t i = 0; i < nx; i++) {
			uint32_t a = j * (nx + 1) + i, b = a + 1, c = b + nx + 1, d = a + nx + 1;
			if (rng_below(&r, 2)) {
				mesh_triangle(m, a, b, c);
				mesh_triangle(m, a, c, d);
			} else {
				mesh_triangle(m, a, b, d);
				mesh_triangle(m, b, c, d);
			}
		}
	}
}

/* A torus (R = 1, r = 0.4: its inner half is a saddle) on an nu x nv
 * parameter grid jittered by up to `jitter` of a cell, outward faces: quads
 * (quads 1) or triangles with random diagonals. */
static void make_torus(mesh* m, uint64_t seed, uint32_t nu, uint32_t nv, double jitter, int quads)
{
	rng r = rng_seed(seed);
	for (uint32_t j = 0; j < nv; j++) {
		for (uint32_t i = 0; i < nu; i++) {
			double u = 2 * PI * (i + rng_range(&r, -jitter, jitter)) / nu;
			double v = 2 * PI * (j + rng_range(&r, -jitter, jitter)) / nv;
			mesh_vertex(m, (1 + 0.4 * cos(v)) * cos(u), (1 + 0.4 * cos(v)) * sin(u), 0.4 * sin(v));
		}
	}
	for (uint32_t j = 0; j < nv; j++) {
		for (uint32_t i = 0; i < nu; i++) {
			/* (u, v) is right-handed for the outward normal. */
			uint32_t a = j * nu + i, b = j * nu + (i + 1) % nu, c = (j + 1) % nv * nu + (i + 1) % nu,
			         d = (j + 1) % nv * nu + i;
			if (quads) {
				uint32_t q[4] = {a, b, c, d};
				mesh_face(m, q, 4);
			} else if (rng_below(&r, 2)) {
				mesh_triangle(m, a, b, c);
				mesh_triangle(m, a, c, d);
			} else {
				mesh_triangle(m, a, b, d);
				mesh_triangle(m, b, c, d);
			}
		}
	}
}

/* Marching-tetrahedra-like slivers on the smooth height field: grid lines
 * come in pairs 1e-5..1e-7 cell apart (needles with one tiny edge, and tiny
 * cells), and some edges get a cap: a vertex 1e-5..1e-7 (relative) off the
 * edge's midpoint, splitting one side of the edge and leaving a triangle with
 * corners at ~1e-6 rad and ~pi. x0, y0 place the patch (coordinates near 1
 * leave fewer float bits for the slivers than near 0). */
static void make_sliver_field(mesh* m, uint64_t seed, double x0, double y0)
{
	rng r = rng_seed(seed);
	const double h = 0.08;
	const uint32_t cells = 14;
	double xs[32], ys[32];
	uint32_t nx = 0, ny = 0;
	for (uint32_t i = 0; i <= cells; i++) {
		xs[nx++] = x0 + h * i;
		ys[ny++] = y0 + h * i;
		double gap = h * pow(10, -5.0 - (double)(i / 2 % 3));
		if (i % 2 == 1 && i < cells)
			xs[nx++] = x0 + h * i + gap;
		if (i % 3 == 1 && i < cells)
			ys[ny++] = y0 + h * i + gap;
	}
	for (uint32_t j = 0; j < ny; j++) {
		for (uint32_t i = 0; i < nx; i++)
			mesh_vertex(m, xs[i], ys[j], height(xs[i], ys[j]));
	}
	const double z[3] = {0, 0, 1};
	for (uint32_t j = 0; j + 1 < ny; j++) {
		for (uint32_t i = 0; i + 1 < nx; i++) {
			uint32_t a = j * nx + i, b = a + 1, c = b + nx, d = a + nx;
			if (rng_below(&r, 4) == 0) {
				/* Cap on edge a-b: m off the midpoint by a tiny perpendicular. */
				const double* pa = m->pos + 3 * (size_t)a;
				const double* pb = m->pos + 3 * (size_t)b;
				double ab[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]}, dir[3], perp[3];
				rng_direction(&r, dir);
				cross3(ab, dir, perp);
				normalize3(perp);
				double off = length3(ab) * pow(10, -5.0 - rng_below(&r, 3)) * rng_range(&r, 1, 3);
				uint32_t mid = mesh_vertex(m, (pa[0] + pb[0]) / 2 + off * perp[0],
				                           (pa[1] + pb[1]) / 2 + off * perp[1],
				                           (pa[2] + pb[2]) / 2 + off * perp[2]);
				uint32_t t0[3] = {a, mid, d}, t1[3] = {mid, c, d}, t2[3] = {mid, b, c}, cap[3] = {a, b, mid};
				mesh_face_facing(m, t0, 3, z);
				mesh_face_facing(m, t1, 3, z);
				mesh_face_facing(m, t2, 3, z);
				mesh_face_facing(m, cap, 3, z);
			} else if (rng_below(&r, 2)) {
				uint32_t t0[3] = {a, b, c}, t1[3] = {a, c, d};
				mesh_face_facing(m, t0, 3, z);
				mesh_face_facing(m, t1, 3, z);
			} else {
				uint32_t t0[3] = {a, b, d}, t1[3] = {b, c, d};
				mesh_face_facing(m, t0, 3, z);
				mesh_face_facing(m, t1, 3, z);
			}
		}
	}
}

/* ------------------------------------------------------------------ library calls */

static vn_result run_library(const mesh* m, int method, int polygon, const void* positions, vn_scalar in,
                             void* out, vn_scalar out_type, unsigned threads, vn_stats* stats)
{
	vn_positions p = {positions, m->nv, 0, in};
	vn_vectors n = {out, 0, out_type};
	vn_options o;
	memset(&o, 0, sizeof o);
	o.threads = threads;
	if (polygon)
		return vn_polygon_normals(&n, &p, m->idx, m->off, m->nf, (vn_method)method, &o, stats);
	return vn_triangle_normals(&n, &p, m->idx, m->ni, (vn_method)method, &o, stats);
}

/* Library normals in double, whatever type they were written in. */
static void read_normal(const void* out, vn_scalar type, size_t v, double* n)
{
	for (int d = 0; d < 3; d++)
		n[d] = type == vn_scalar_float32 ? (double)((const float*)out)[3 * v + d] : ((const double*)out)[3 * v + d];
}

/* The angle allowed between library and reference at a vertex whose
 * reference path and condition (ref_normals_ex) are given; negative: the
 * direction is not compared. A sum (the seven, SMEWCSA, a fallback) is
 * compared where it is not cancellation noise. A fit is compared to
 * FIT_TOLERANCE; a borderline decision may go either way, so not at all. */
static double tolerance(unsigned char path, double cond)
{
	if (path & ref_path_borderline)
		return -1;
	if (path == ref_path_quadric || path == ref_path_jet || path == ref_path_wide)
		return FIT_TOLERANCE(cond);
	return cond >= MIN_CONDITION ? TOLERANCE_RAD : -1;
}

/* Compares one library output with the reference; returns the number of
 * mismatched vertices and raises *worst to the largest angle seen (and
 * *worst_scaled to the largest angle times the condition, for fits). */
static size_t compare_normals(const mesh* m, const char* what, const double* ref, const double* cond,
                              const unsigned char* path, const void* out, vn_scalar type, double* worst,
                              double* worst_scaled, size_t* reports)
{
	size_t bad = 0;
	double unit_tolerance = type == vn_scalar_float32 ? 1e-6 : 1e-12;
	/* float32 output rounds each coordinate by up to 6e-8 relative. */
	double rounding = type == vn_scalar_float32 ? 2e-7 : 0;
	for (size_t v = 0; v < m->nv; v++) {
		double n[3];
		read_normal(out, type, v, n);
		const double* r = ref + 3 * v;
		double len = length3(n);
		double allowed = tolerance(path[v], cond[v]);
		const char* problem = NULL;
		double angle = 0;
		if (cond[v] < 0) {
			/* Nothing contributed: exactly zero, nothing else. */
			if (n[0] != 0 || n[1] != 0 || n[2] != 0)
				problem = "expected exactly (0,0,0)";
		} else if (!isfinite(len)) {
			problem = "non-finite output";
		} else if (len != 0 && fabs(len - 1) > unit_tolerance) {
			problem = "not unit length";
		} else if (allowed >= 0 && (r[0] != 0 || r[1] != 0 || r[2] != 0)) {
			if (len == 0) {
				problem = "zero output, reference non-zero";
			} else {
				angle = angle3(n, r);
				if (angle > *worst)
					*worst = angle;
				if ((path[v] == ref_path_quadric || path[v] == ref_path_jet || path[v] == ref_path_wide) &&
				    angle * cond[v] > *worst_scaled)
					*worst_scaled = angle * cond[v];
				if (!(angle <= allowed + rounding))
					problem = "angle above tolerance";
			}
		}
		if (problem) {
			if ((*reports)++ < MAX_REPORTS)
				print_message("MISMATCH %s %s vertex %zu: %s; lib (%.17g %.17g %.17g) ref (%.17g %.17g %.17g) "
				              "angle %.3g deg, condition %.3g, path %d\n",
				              m->name, what, v, problem, n[0], n[1], n[2], r[0], r[1], r[2],
				              angle * 180 / PI, cond[v], path[v]);
			bad++;
		}
	}
	return bad;
}

static int same3(const double* a, const double* b, double sign)
{
	return a[0] == sign * b[0] && a[1] == sign * b[1] && a[2] == sign * b[2];
}

/* The library's path at vertex v under `method`, read from its outputs
 * (float64 in and out, lib[method]) without looking inside it: a fallback
 * returns its seed method's normal bit for bit (MWA's for the fits, and
 * MWAAT's for ADAPTIVE's rough one on a lattice; MWSELR's for SMEWCSA and for
 * ADAPTIVE's jet where the two agree), JET's and
 * ADAPTIVE's fallback to the 1-ring quadric is QUADRIC's very computation
 * and ADAPTIVE's 2-ring fit is JET's (any other ADAPTIVE normal is a 5-ring
 * fit); SMEWCSA's other path is MEWCSA's normal or its negation. -1: none
 * of these. A fit that equals its fallback to the last bit (possible on a
 * plane) reads as the fallback. */
static int lib_path(int method, size_t v, double* const* lib)
{
	const double* n = lib[method] + 3 * v;
	const double zero[3] = {0, 0, 0};
	if (same3(n, zero, 1))
		return ref_path_zero;
	if (method == ref_smewcsa) {
		if (same3(n, lib[ref_mwselr] + 3 * v, 1))
			return ref_path_seed;
		if (same3(n, lib[ref_mewcsa] + 3 * v, 1) || same3(n, lib[ref_mewcsa] + 3 * v, -1))
			return ref_path_cotangent;
		return -1;
	}
	if (method == ref_adaptive && same3(n, lib[ref_mwaat] + 3 * v, 1))
		return ref_path_lattice;
	if (method == ref_adaptive && same3(n, lib[ref_mwselr] + 3 * v, 1))
		return ref_path_mwselr;
	if (same3(n, lib[ref_mwa] + 3 * v, 1))
		return ref_path_seed;
	if (method == ref_quadric)
		return ref_path_quadric;
	if (same3(n, lib[ref_quadric] + 3 * v, 1))
		return ref_path_quadric;
	return method == ref_jet || same3(n, lib[ref_jet] + 3 * v, 1) ? ref_path_jet : ref_path_wide;
}

/* Path counts of a method beyond the paper on one mesh. */
typedef struct path_counts {
	size_t ref[ref_path_count], lib[ref_path_count];
	size_t differ;     /* the library took another path than the reference */
	size_t borderline; /* not compared: a decision within rounding of its threshold */
	size_t coincident; /* the library's fit equals its fallback to the last bit, the reference's to 1e-12 */
} path_counts;

/* Whether the library took the reference's path at every vertex of m (float64
 * in and out, one entry point); ref holds the reference's normals of every
 * method. */
static void compare_paths(const mesh* m, const char* entry, int method, const unsigned char* path,
                          double* const* ref, double* const* lib, path_counts* pc, size_t* reports)
{
	for (size_t v = 0; v < m->nv; v++) {
		int taken = lib_path(method, v, lib);
		int want = path[v] & ~ref_path_borderline;
		/* Where ADAPTIVE's weighted normals agree to the bit (MWA's, MWAAT's
		 * and MWSELR's normal of a single face), its output reads as any
		 * (weighted: the method of each such path; 0, MWE's, for none); its
		 * rough fallback off a lattice is S, read as the seed. */
		const int weighted[ref_path_count] = {[ref_path_seed] = ref_mwa, [ref_path_rough] = ref_mwa,
		                                      [ref_path_mwselr] = ref_mwselr, [ref_path_lattice] = ref_mwaat};
		if (method == ref_adaptive && taken >= 0 && weighted[taken] && weighted[want] &&
		    same3(lib[method] + 3 * v, lib[weighted[want]] + 3 * v, 1))
			taken = want;
		pc->ref[want]++;
		if (taken >= 0)
			pc->lib[taken]++;
		if (path[v] & ref_path_borderline) {
			pc->borderline++;
			continue;
		}
		/* The fallback the library's output equals, and the reference's fit. */
		int fallback = taken == ref_path_quadric   ? ref_quadric
		               : taken == ref_path_lattice ? ref_mwaat
		               : method == ref_smewcsa    ? ref_mwselr
		                                          : ref_mwa;
		if (taken != want &&
		    (taken == ref_path_seed || taken == ref_path_rough || taken == ref_path_lattice || taken == ref_path_quadric) &&
		    (want == ref_path_quadric || want == ref_path_jet || want == ref_path_wide) &&
		    angle3(ref[method] + 3 * v, ref[fallback] + 3 * v) <= 1e-12) {
			pc->coincident++;
			continue;
		}
		if (taken != want) {
			if ((*reports)++ < MAX_REPORTS)
				print_message("MISMATCH %s %s %s vertex %zu: the reference took path %d, the library %d\n",
				              m->name, method_names[method], entry, v, want, taken);
			pc->differ++;
		}
	}
}

/* The library on mesh m, every method, float32 and float64 in and out, both
 * entry points where the faces are triangles, against the reference on the
 * same coordinates (for float32 input, the exact float values); for the
 * methods beyond the paper, also each vertex's path. Prints the worst angle
 * per method with float64 output (float32 output adds ~2e-6 deg of rounding
 * on top); raises worst_deg[output is float64][method]. With exact_paths, no
 * vertex may be borderline or coincident either: the path counts of library
 * and reference must be equal, path by path. */
static void check_mesh_paths(const mesh* m, double (*worst_deg)[ref_method_count], int exact_paths)
{
	size_t nv = m->nv;
	float* p32 = malloc(3 * nv * sizeof *p32);
	double* p32d = malloc(3 * nv * sizeof *p32d);
	double* out = malloc(3 * nv * sizeof *out); /* large enough for either type */
	double *ref[2][ref_method_count], *cond[2][ref_method_count], *lib[2][ref_method_count];
	unsigned char* path[2][ref_method_count];
	assert_true(p32 && p32d && out);
	for (size_t i = 0; i < 3 * nv; i++) {
		p32[i] = (float)m->pos[i];
		p32d[i] = p32[i];
	}
	for (int in = 0; in < 2; in++) {
		for (int method = 0; method < ref_method_count; method++) {
			ref[in][method] = malloc(3 * nv * sizeof(double));
			cond[in][method] = malloc(nv * sizeof(double));
			path[in][method] = malloc(nv ? nv : 1);
			lib[in][method] = malloc(3 * nv * sizeof(double)); /* [polygon entry] */
			assert_true(ref[in][method] && cond[in][method] && path[in][method] && lib[in][method]);
			ref_normals_ex(method, in ? m->pos : p32d, nv, m->idx, m->off, m->nf, ref[in][method],
			               cond[in][method], path[in][method]);
		}
	}
	int triangles = mesh_is_triangles(m);
	size_t bad = 0, reports = 0, compared = 0, skipped = 0, zero = 0;
	char line[512];
	int at = snprintf(line, sizeof line, "%-24s", m->name);
	for (int method = 0; method < ref_method_count; method++) {
		for (size_t v = 0; v < nv; v++) {
			double allowed = tolerance(path[1][method][v], cond[1][method][v]);
			zero += cond[1][method][v] < 0;
			skipped += cond[1][method][v] >= 0 && allowed < 0;
			compared += cond[1][method][v] >= 0 && allowed >= 0;
		}
		double worst[2] = {0, 0}, scaled = 0;
		for (int in = 0; in < 2; in++) {
			vn_scalar in_type = in ? vn_scalar_float64 : vn_scalar_float32;
			const void* positions = in ? (const void*)m->pos : (const void*)p32;
			for (int o = 0; o < 2; o++) {
				vn_scalar out_type = o ? vn_scalar_float64 : vn_scalar_float32;
				for (int polygon = triangles ? 0 : 1; polygon < 2; polygon++) {
					char what[64];
					snprintf(what, sizeof what, "%s %s %s->%s", method_names[method],
					         polygon ? "polygon" : "triangle", in ? "f64" : "f32", o ? "f64" : "f32");
					vn_stats stats;
					/* f64 -> f64 results are kept, per entry point, for the paths. */
					void* dest = o && in ? (void*)lib[polygon][method] : (void*)out;
					memset(dest, 0xA5, 3 * nv * sizeof *out); /* no stale zeros */
					vn_result res = run_library(m, method, polygon, positions, in_type, dest, out_type, 0, &stats);
					if (res != vn_result_success || stats.faces != m->nf) {
						print_message("MISMATCH %s %s: result %d, stats.faces %zu of %zu\n", m->name, what,
						              (int)res, stats.faces, m->nf);
						bad++;
						continue;
					}
					bad += compare_normals(m, what, ref[in][method], cond[in][method], path[in][method], dest,
					                       out_type, &worst[o], &scaled, &reports);
				}
			}
		}
		for (int o = 0; o < 2; o++)
			worst_deg[o][method] = fmax(worst_deg[o][method], worst[o] * 180 / PI);
		if (at > 0 && (size_t)at < sizeof line)
			at += snprintf(line + at, sizeof line - (size_t)at, " %s %.1e", method_names[method],
			               worst[1] * 180 / PI);
		if (scaled > 0 && at > 0 && (size_t)at < sizeof line)
			at += snprintf(line + at, sizeof line - (size_t)at, " (x cond %.1e)", scaled);
	}
	print_message("%s deg (f64 out) | v %zu f %zu; compared %zu, not compared %zu, zero %zu\n", line, nv, m->nf,
	              compared, skipped, zero);
	for (int method = ref_smewcsa; method < ref_method_count; method++) {
		path_counts pc;
		memset(&pc, 0, sizeof pc);
		for (int polygon = triangles ? 0 : 1; polygon < 2; polygon++)
			compare_paths(m, polygon ? "polygon" : "triangle", method, path[1][method], ref[1], lib[polygon], &pc,
			              &reports);
		int entries = triangles ? 2 : 1;
		print_message("  %-8s paths (ref/lib, %d entr%s): zero %zu/%zu seed %zu/%zu cotangent %zu/%zu quadric %zu/%zu "
		              "jet %zu/%zu wide %zu/%zu rough %zu/%zu lattice %zu/%zu mwselr %zu/%zu; borderline %zu, "
		              "coincident %zu, differ %zu\n",
		              method_names[method], entries, entries > 1 ? "ies" : "y", pc.ref[ref_path_zero],
		              pc.lib[ref_path_zero], pc.ref[ref_path_seed], pc.lib[ref_path_seed], pc.ref[ref_path_cotangent],
		              pc.lib[ref_path_cotangent], pc.ref[ref_path_quadric], pc.lib[ref_path_quadric],
		              pc.ref[ref_path_jet], pc.lib[ref_path_jet], pc.ref[ref_path_wide], pc.lib[ref_path_wide],
		              pc.ref[ref_path_rough], pc.lib[ref_path_rough], pc.ref[ref_path_lattice], pc.lib[ref_path_lattice],
		              pc.ref[ref_path_mwselr], pc.lib[ref_path_mwselr],
		              pc.borderline, pc.coincident, pc.differ);
		bad += pc.differ;
		if (exact_paths) {
			bad += pc.borderline + pc.coincident;
			for (int i = 0; i < ref_path_count; i++)
				bad += pc.ref[i] != pc.lib[i];
		}
	}
	for (int in = 0; in < 2; in++) {
		for (int method = 0; method < ref_method_count; method++) {
			free(ref[in][method]);
			free(cond[in][method]);
			free(path[in][method]);
			free(lib[in][method]);
		}
	}
	free(p32);
	free(p32d);
	free(out);
	if (bad)
		fail_msg("%s: %zu mismatched vertex normals or paths (first %d printed above)", m->name, bad, MAX_REPORTS);
}

static void check_mesh(const mesh* m, double (*worst_deg)[ref_method_count])
{
	check_mesh_paths(m, worst_deg, 0);
}

static void print_worst(const char* test, double (*worst_deg)[ref_method_count])
{
	for (int o = 0; o < 2; o++) {
		char line[512];
		int at = snprintf(line, sizeof line, "%s: worst deg, %s output:", test, o ? "f64" : "f32");
		for (int method = 0; method < ref_method_count && at > 0 && (size_t)at < sizeof line; method++)
			at += snprintf(line + at, sizeof line - (size_t)at, " %s %.2e", method_names[method],
			               worst_deg[o][method]);
		print_message("%s\n", line);
	}
}

/* ------------------------------------------------------------------ tests */

/* 0. A hand-computed vertex, to pin down the reference itself (and the
 * library with it). Vertex 0 at the origin has two faces: (0, 1, 2) with
 * p1 = (1,0,0), p2 = (1,1,0): normal +z, a 45 degree corner, |E| = sqrt 2,
 * |E'| = 1, |E x E'| = 1; and (0, 3, 1) with p3 = (0,0,1): normal +y, a right
 * angle, unit edges. MEWCSA: (p1 - p2) x z + (p3 - p1) x y = (-2, 0, -1). */
static void test_hand_computed(void** state)
{
	(void)state;
	const double s2 = sqrt(2), q = pow(2, -0.25);
	const double expected[ref_method_count][3] = {
		{0, 1, 1},           /* mwe: 1 each */
		{0, PI / 2, PI / 4}, /* mwa: the angles */
		{0, 1, 0.5},         /* mwselr: sin 45 / sqrt 2 = 1/2 */
		{0, 1, 1},           /* mwaat: |E x E'| = 1 each */
		{0, 1, 1 / s2},      /* mwelr */
		{0, 1, q},           /* mwrelr: 1 / sqrt(sqrt 2) */
		{-2, 0, -1},         /* mewcsa */
		/* H = mewcsa is 101.5 degrees from S = mwselr: S */
		{0, 1, 0.5},         /* smewcsa */
		/* 3 ring members, fewer than the fits' unknowns: S = mwa */
		{0, PI / 2, PI / 4}, /* quadric */
		{0, PI / 2, PI / 4}, /* jet */
		{0, PI / 2, PI / 4}, /* adaptive: JET's fallback */
	};
	mesh m;
	mesh_init(&m, "hand computed");
	mesh_vertex(&m, 0, 0, 0);
	mesh_vertex(&m, 1, 0, 0);
	mesh_vertex(&m, 1, 1, 0);
	mesh_vertex(&m, 0, 0, 1);
	mesh_triangle(&m, 0, 1, 2);
	mesh_triangle(&m, 0, 3, 1);
	for (int method = 0; method < ref_method_count; method++) {
		double want[3] = {expected[method][0], expected[method][1], expected[method][2]};
		double ref[3 * 4], lib[3 * 4];
		normalize3(want);
		ref_normals(method, m.pos, m.nv, m.idx, m.off, m.nf, ref);
		assert_int_equal(run_library(&m, method, 0, m.pos, vn_scalar_float64, lib, vn_scalar_float64, 0, NULL),
		                 vn_result_success);
		print_message("hand %-6s want (%.6f %.6f %.6f) ref (%.6f %.6f %.6f) lib (%.6f %.6f %.6f)\n",
		              method_names[method], want[0], want[1], want[2], ref[0], ref[1], ref[2], lib[0], lib[1], lib[2]);
		for (int d = 0; d < 3; d++)
			assert_true(fabs(ref[d] - want[d]) <= 1e-15);
		assert_true(angle3(lib, want) <= 1e-12);
	}
	mesh_free(&m);
}

/* 1. Random triangle meshes, closed and not, every method and type. */
static void test_random_triangles(void** state)
{
	(void)state;
	double worst[2][ref_method_count] = {{0}};
	mesh m;

	mesh_init(&m, "triangle soup");
	make_triangle_soup(&m, 1, 300, 600);
	check_mesh(&m, worst);
	mesh_free(&m);

	for (int level = 0; level <= 3; level++) {
		char name[64];
		const double centre[3] = {0.25, -0.5, 1.0};
		snprintf(name, sizeof name, "jittered icosphere %d", level);
		mesh_init(&m, name);
		make_icosphere(&m, level, 1.3, centre);
		mesh_jitter(&m, 10 + (uint64_t)level, 0.3 * 1.3 / (1 << level));
		check_mesh(&m, worst);
		mesh_free(&m);
	}

	mesh_init(&m, "jittered uv sphere tris");
	make_uv_sphere(&m, 2, 12, 20, 0);
	mesh_jitter(&m, 3, 0.04);
	check_mesh(&m, worst);
	mesh_free(&m);

	mesh_init(&m, "height field tris");
	make_height_field(&m, 4, 24, 20, 0.09, 0.3);
	check_mesh(&m, worst);
	mesh_free(&m);

	print_worst("random triangles", worst);
}

/* 2. Polygon meshes: planar and non-planar quads to octagons, a polygonal
 * sphere, and random non-planar self-intersecting polygons. */
static void test_random_polygons(void** state)
{
	(void)state;
	double worst[2][ref_method_count] = {{0}};
	mesh m;

	mesh_init(&m, "planar polygon grid");
	make_polygon_grid(&m, 5, 18, 14, 1);
	check_mesh(&m, worst);
	mesh_free(&m);

	mesh_init(&m, "height polygon grid");
	make_polygon_grid(&m, 6, 18, 14, 0);
	check_mesh(&m, worst);
	mesh_free(&m);

	mesh_init(&m, "jittered uv sphere quads");
	make_uv_sphere(&m, 7, 10, 16, 1);
	mesh_jitter(&m, 8, 0.05);
	check_mesh(&m, worst);
	mesh_free(&m);

	mesh_init(&m, "jittered uv sphere mixed");
	make_uv_sphere(&m, 9, 14, 24, 2);
	mesh_jitter(&m, 10, 0.03);
	check_mesh(&m, worst);
	mesh_free(&m);

	mesh_init(&m, "polygon soup");
	make_polygon_soup(&m, 11, 200, 300);
	check_mesh(&m, worst);
	mesh_free(&m);

	print_worst("random polygons", worst);
}

/* 3. Marching-tetrahedra-like slivers given as float32 (check_mesh also runs
 * float64): the library must agree with the reference on the exact floats. */
static void test_slivers(void** state)
{
	(void)state;
	double worst[2][ref_method_count] = {{0}};
	mesh m;

	mesh_init(&m, "slivers near origin");
	make_sliver_field(&m, 12, -0.55, -0.5);
	check_mesh(&m, worst);
	mesh_free(&m);

	mesh_init(&m, "slivers near 1");
	make_sliver_field(&m, 13, 0.9, 1.1);
	check_mesh(&m, worst);
	mesh_free(&m);

	print_worst("slivers", worst);
}

/* 4. Max 1999: MWSELR is exact when a closed fan's neighbours lie on a sphere
 * through the vertex. Irregular angles and distances, several radii and
 * valences; the plain MWE on the same fans must be visibly off, so the test
 * can tell an exact method from a merely good one. */
static void test_mwselr_sphere_exact(void** state)
{
	(void)state;
	rng r = rng_seed(14);
	double worst_selr = 0, worst_ref = 0, worst_mwe = 0;
	const double radii[] = {1e-3, 0.05, 1, 30, 1e3};
	for (size_t ri = 0; ri < sizeof radii / sizeof radii[0]; ri++) {
		for (uint32_t valence = 3; valence <= 9; valence++) {
			for (int trial = 0; trial < 3; trial++) {
				double radius = radii[ri];
				double centre[3], n[3], t1[3], t2[3], helper[3];
				for (int d = 0; d < 3; d++)
					centre[d] = rng_range(&r, -2, 2);
				rng_direction(&r, n);
				rng_direction(&r, helper);
				cross3(n, helper, t1);
				normalize3(t1);
				cross3(n, t1, t2);
				/* Angular gaps in [1, 1.8] relative: irregular yet each < pi. */
				double gaps[9], total = 0;
				for (uint32_t k = 0; k < valence; k++)
					total += gaps[k] = rng_range(&r, 1, 1.8);
				mesh m;
				mesh_init(&m, "mwselr fan");
				mesh_vertex(&m, centre[0] + radius * n[0], centre[1] + radius * n[1], centre[2] + radius * n[2]);
				double theta = rng_range(&r, 0, 2 * PI);
				for (uint32_t k = 0; k < valence; k++) {
					double phi = rng_range(&r, 0.08, 0.7); /* polar angle: distance ~ phi R */
					double p[3];
					for (int d = 0; d < 3; d++)
						p[d] = centre[d] + radius * (sin(phi) * (cos(theta) * t1[d] + sin(theta) * t2[d]) +
						                             cos(phi) * n[d]);
					mesh_vertex(&m, p[0], p[1], p[2]);
					theta += 2 * PI * gaps[k] / total;
				}
				for (uint32_t k = 0; k < valence; k++) {
					uint32_t t[3] = {0, 1 + k, 1 + (k + 1) % valence};
					mesh_face_facing(&m, t, 3, n);
				}
				double out[3 * 10], ref[3 * 10];
				assert_int_equal(run_library(&m, vn_method_mwselr, 0, m.pos, vn_scalar_float64, out,
				                             vn_scalar_float64, 0, NULL),
				                 vn_result_success);
				double e = angle3(out, n);
				if (!(e <= 1e-9))
					print_message("mwselr fan R %g valence %u: (%.17g %.17g %.17g) vs (%.17g %.17g %.17g), %.3g rad\n",
					              radius, valence, out[0], out[1], out[2], n[0], n[1], n[2], e);
				worst_selr = fmax(worst_selr, e);
				ref_normals(ref_mwselr, m.pos, m.nv, m.idx, m.off, m.nf, ref);
				worst_ref = fmax(worst_ref, angle3(ref, n));
				assert_int_equal(run_library(&m, vn_method_mwe, 0, m.pos, vn_scalar_float64, out,
				                             vn_scalar_float64, 0, NULL),
				                 vn_result_success);
				worst_mwe = fmax(worst_mwe, angle3(out, n));
				mesh_free(&m);
			}
		}
	}
	print_message("sphere fans: worst mwselr %.3g rad (reference %.3g rad), worst mwe %.3g rad\n", worst_selr,
	              worst_ref, worst_mwe);
	assert_true(worst_ref <= 1e-9); /* the reference itself must show Max's identity */
	assert_true(worst_selr <= 1e-9);
	assert_true(worst_mwe > 1e-3); /* the fans are irregular enough to matter */
}

/* 5. MEWCSA is the mean curvature normal without its sign corrected: on a
 * convex, outward-oriented sphere it points outward like the face normals;
 * where the surface is concave with respect to its orientation (the same
 * sphere wound inward; a dimple in a plane whose faces point up) it points
 * against the face normals. */

/* The sphere of the MEWCSA tests. */
static const double sphere_centre[3] = {0.4, -0.3, 0.2};
static const double sphere_radius = 1.5;

static void make_mewcsa_sphere(mesh* m, const char* name)
{
	mesh_init(m, name);
	make_icosphere(m, 3, sphere_radius, sphere_centre);
	/* Jitter along the sphere only (~15% of an edge): every vertex stays on
	 * it and the triangles stay close to equilateral. */
	mesh_jitter(m, 15, 0.15 * sphere_radius / 8);
	for (size_t v = 0; v < m->nv; v++) {
		double* p = m->pos + 3 * v;
		double d[3] = {p[0] - sphere_centre[0], p[1] - sphere_centre[1], p[2] - sphere_centre[2]};
		normalize3(d);
		for (int k = 0; k < 3; k++)
			p[k] = sphere_centre[k] + sphere_radius * d[k];
	}
}

/* MEWCSA and MWE of every vertex of m (float64 in and out), plus each
 * vertex's unit direction from the sphere's centre (meaningful on the sphere
 * meshes only); the caller frees the three arrays. */
static void mewcsa_and_mwe(const mesh* m, double** mewcsa, double** mwe, double** radial)
{
	*mewcsa = malloc(3 * m->nv * sizeof **mewcsa);
	*mwe = malloc(3 * m->nv * sizeof **mwe);
	*radial = malloc(3 * m->nv * sizeof **radial);
	assert_true(*mewcsa && *mwe && *radial);
	assert_int_equal(run_library(m, vn_method_mewcsa, 0, m->pos, vn_scalar_float64, *mewcsa, vn_scalar_float64, 0,
	                             NULL),
	                 vn_result_success);
	assert_int_equal(run_library(m, vn_method_mwe, 0, m->pos, vn_scalar_float64, *mwe, vn_scalar_float64, 0, NULL),
	                 vn_result_success);
	for (size_t i = 0; i < 3 * m->nv; i++)
		(*radial)[i] = (m->pos[i] - sphere_centre[i % 3]) / sphere_radius;
}

static void test_mewcsa_outward_on_sphere(void** state)
{
	(void)state;
	double worst[2][ref_method_count] = {{0}};
	mesh m;
	make_mewcsa_sphere(&m, "icosphere 3 outward");
	check_mesh(&m, worst);
	double *mewcsa, *mwe, *radial;
	mewcsa_and_mwe(&m, &mewcsa, &mwe, &radial);
	double worst_angle = 0, min_agree = 1;
	size_t wrong = 0;
	for (size_t v = 0; v < m.nv; v++) {
		double a = angle3(mewcsa + 3 * v, radial + 3 * v);
		double agree = dot3(mewcsa + 3 * v, mwe + 3 * v);
		worst_angle = fmax(worst_angle, a);
		min_agree = fmin(min_agree, agree);
		/* Outward, and on the same side as the face normals (themselves outward). */
		wrong += !(dot3(mewcsa + 3 * v, radial + 3 * v) > 0) || !(agree > 0) || !(dot3(mwe + 3 * v, radial + 3 * v) > 0);
	}
	print_message("outward sphere: mewcsa worst angle to the radial direction %.3g deg, min dot(mewcsa, mwe) %.4f\n",
	              worst_angle * 180 / PI, min_agree);
	free(mewcsa);
	free(mwe);
	free(radial);
	mesh_free(&m);
	assert_int_equal(wrong, 0);
	assert_true(worst_angle < 5 * PI / 180);
}

static void test_mewcsa_inward_on_reversed_sphere(void** state)
{
	(void)state;
	double worst[2][ref_method_count] = {{0}};
	mesh m;
	/* Wound inward, the face normals point to the centre and the sphere is
	 * concave with respect to them; MEWCSA (an area gradient) is unchanged. */
	make_mewcsa_sphere(&m, "icosphere 3 inward");
	mesh_reverse_faces(&m);
	check_mesh(&m, worst);
	double *mewcsa, *mwe, *radial;
	mewcsa_and_mwe(&m, &mewcsa, &mwe, &radial);
	double min_outward = 1, max_agree = -1;
	size_t wrong = 0;
	for (size_t v = 0; v < m.nv; v++) {
		double outward = dot3(mewcsa + 3 * v, radial + 3 * v);
		double agree = dot3(mewcsa + 3 * v, mwe + 3 * v);
		min_outward = fmin(min_outward, outward);
		max_agree = fmax(max_agree, agree);
		wrong += !(dot3(mwe + 3 * v, radial + 3 * v) < 0) || !(outward > 0) || !(agree < 0);
	}
	print_message("inward sphere: min dot(mewcsa, radial) %.4f, max dot(mewcsa, mwe) %.4f\n", min_outward,
	              max_agree);
	free(mewcsa);
	free(mwe);
	free(radial);
	mesh_free(&m);
	assert_int_equal(wrong, 0);
	assert_true(min_outward > 0.99);
	assert_true(max_agree < -0.99);
}

/* A Gaussian dimple (bump 0) or bump (bump 1) in a triangulated plane whose
 * faces point up (+z); centre vertex at the origin. */
static void make_dent(mesh* m, int bump, double width)
{
	const uint32_t n = 20;
	const double h = 0.1, depth = 0.15;
	const double up[3] = {0, 0, 1};
	rng r = rng_seed(16);
	mesh_init(m, bump ? "bump" : "dimple");
	for (uint32_t j = 0; j <= n; j++) {
		for (uint32_t i = 0; i <= n; i++) {
			double x = h * ((double)i - n / 2.0), y = h * ((double)j - n / 2.0);
			double z = depth * exp(-(x * x + y * y) / (width * width));
			mesh_vertex(m, x, y, bump ? z : -z);
		}
	}
	for (uint32_t j = 0; j < n; j++) {
		for (uint32_t i = 0; i < n; i++) {
			uint32_t a = j * (n + 1) + i, b = a + 1, c = b + n + 1, d = a + n + 1;
			uint32_t t0[3] = {a, b, c}, t1[3] = {a, c, d}, t2[3] = {a, b, d}, t3[3] = {b, c, d};
			int diagonal = (int)rng_below(&r, 2);
			mesh_face_facing(m, diagonal ? t0 : t2, 3, up);
			mesh_face_facing(m, diagonal ? t1 : t3, 3, up);
		}
	}
}

static void test_mewcsa_dimple_and_bump(void** state)
{
	(void)state;
	double worst[2][ref_method_count] = {{0}};
	const double width = 0.4;
	for (int bump = 0; bump < 2; bump++) {
		mesh m;
		make_dent(&m, bump, width);
		check_mesh(&m, worst);
		double *mewcsa, *mwe, *radial;
		mewcsa_and_mwe(&m, &mewcsa, &mwe, &radial);
		/* Within width/2 of the centre the Gaussian is concave (dimple) or
		 * convex (bump) in every direction: MEWCSA must oppose (dimple) or
		 * follow (bump) the upward face normals at every such vertex. */
		double extreme = bump ? 1 : -1, lowest_mwe = 1;
		size_t checked = 0, wrong = 0, centre = 0;
		for (size_t v = 0; v < m.nv; v++) {
			const double* p = m.pos + 3 * v;
			if (p[0] == 0 && p[1] == 0)
				centre = v;
			if (p[0] * p[0] + p[1] * p[1] > width * width / 4)
				continue;
			double agree = dot3(mewcsa + 3 * v, mwe + 3 * v);
			extreme = bump ? fmin(extreme, agree) : fmax(extreme, agree);
			lowest_mwe = fmin(lowest_mwe, mwe[3 * v + 2]);
			wrong += bump ? !(agree > 0) : !(agree < 0);
			checked++;
		}
		double centre_z = mewcsa[3 * centre + 2];
		print_message("%s: %zu vertices, %s dot(mewcsa, mwe) %.4f, lowest mwe z %.3f; centre mewcsa z %.6f\n",
		              m.name, checked, bump ? "min" : "max", extreme, lowest_mwe, centre_z);
		free(mewcsa);
		free(mwe);
		free(radial);
		mesh_free(&m);
		assert_true(checked >= 9);
		assert_true(lowest_mwe > 0.9); /* the face normals do point up there */
		assert_int_equal(wrong, 0);
		/* The centre is symmetric up to the diagonals: nearly straight down/up. */
		assert_true(bump ? centre_z > 0.99 : centre_z < -0.99);
	}
	print_worst("dimple and bump", worst);
}

/* 6. The schemes beyond the paper on surfaces where they do their work: a
 * torus (saddles on its inner half), height fields with noise (ADAPTIVE
 * chooses between its fits and MWAAT) and every vertex's path
 * taken exactly as the reference takes it, counted path by path. */
static void test_beyond_the_paper(void** state)
{
	(void)state;
	double worst[2][ref_method_count] = {{0}};
	mesh m;

	mesh_init(&m, "jittered torus tris");
	make_torus(&m, 19, 40, 16, 0.3, 0);
	check_mesh_paths(&m, worst, 1);
	mesh_free(&m);

	/* A UV sphere read from text with 6 places (Blender's OBJ) and 7
	 * significant digits (ASCII STL; cos(pi / 2) as 6.123234e-17):
	 * ADAPTIVE's sphere test at the text's rounding, which both find (the
	 * reference by printf and strtod). */
	const char* formats[2] = {"%.6f", "%.6e"};
	for (int k = 0; k < 2; k++) {
		char name[64], text[64];
		snprintf(name, sizeof name, "uv sphere as %s text", formats[k]);
		mesh_init(&m, name);
		make_uv_sphere(&m, 2, 12, 20, 0);
		if (k == 0) /* no face: 11 digits, the places' rounding is the larger */
			mesh_vertex(&m, 12345.678901, 0, 0);
		for (size_t i = 0; i < 3 * m.nv; i++) {
			snprintf(text, sizeof text, formats[k], m.pos[i]);
			m.pos[i] = strtod(text, NULL);
		}
		check_mesh_paths(&m, worst, 1);
		mesh_free(&m);
	}

	mesh_init(&m, "jittered torus quads");
	make_torus(&m, 20, 36, 14, 0.25, 1);
	check_mesh_paths(&m, worst, 1);
	mesh_free(&m);

	/* Noise of up to 12% of an edge in every direction: ADAPTIVE takes the
	 * 5-ring fits at most vertices, the jet at some; at 60%, its fallback
	 * (S) at a part. */
	mesh_init(&m, "noisy height field");
	make_height_field(&m, 21, 30, 26, 0.07, 0.3);
	mesh_jitter(&m, 25, 0.12 * 0.07);
	check_mesh_paths(&m, worst, 1);
	mesh_free(&m);

	mesh_init(&m, "rough height field");
	make_height_field(&m, 27, 30, 26, 0.07, 0.3);
	mesh_jitter(&m, 29, 0.6 * 0.07);
	check_mesh_paths(&m, worst, 1);
	mesh_free(&m);

	/* Noise along z alone on an unjittered grid: ADAPTIVE's rough fallback
	 * is MWAAT where the diagonals of a vertex's four cells are symmetric
	 * about it (its ring is a lattice's), S elsewhere. */
	mesh_init(&m, "rough lattice height field");
	make_height_field(&m, 27, 30, 26, 0.07, 0);
	{
		rng r = rng_seed(35);
		for (size_t v = 0; v < m.nv; v++)
			m.pos[3 * v + 2] += rng_range(&r, -0.6 * 0.07, 0.6 * 0.07);
	}
	check_mesh_paths(&m, worst, 1);
	mesh_free(&m);

	/* Fans: a hub of 300 spokes raised over an interior vertex of a smooth
	 * height field (its neighbours' wider rings do not expand it), and an
	 * open cone of 20 (its rim's jets cannot be fitted: ADAPTIVE takes
	 * JET's fallback there). */
	mesh_init(&m, "height field with a hub");
	make_height_field(&m, 31, 20, 18, 0.1, 0.3);
	const uint32_t hub = 9 * 21 + 10, first = (uint32_t)m.nv;
	for (uint32_t k = 0; k < 300; k++) {
		const double a = 2 * PI * k / 300, *c = m.pos + 3 * (size_t)hub;
		mesh_vertex(&m, c[0] + 0.05 * cos(a), c[1] + 0.05 * sin(a), c[2] + 0.1);
		mesh_triangle(&m, hub, first + k, first + (k + 1) % 300);
	}
	check_mesh_paths(&m, worst, 1);
	mesh_free(&m);

	mesh_init(&m, "open cone");
	mesh_vertex(&m, 0, 0, 0.5);
	for (uint32_t k = 0; k < 20; k++) {
		mesh_vertex(&m, cos(2 * PI * k / 20), sin(2 * PI * k / 20), 0);
		mesh_triangle(&m, 0, 1 + k, 1 + (k + 1) % 20);
	}
	check_mesh_paths(&m, worst, 1);
	mesh_free(&m);

	/* Closed by a 40-gon (more than RING_ALL_MAX corners: only its edge
	 * neighbours join a ring), the rim jittered. */
	mesh_init(&m, "cone with a 40-gon cap");
	mesh_vertex(&m, 0, 0, 0.5);
	uint32_t cap[40];
	for (uint32_t k = 0; k < 40; k++) {
		mesh_vertex(&m, cos(2 * PI * k / 40), sin(2 * PI * k / 40), 0);
		mesh_triangle(&m, 0, 1 + k, 1 + (k + 1) % 40);
		cap[k] = 40 - k;
	}
	mesh_jitter(&m, 33, 0.02);
	mesh_face(&m, cap, 40);
	check_mesh_paths(&m, worst, 1);
	mesh_free(&m);

	print_worst("beyond the paper", worst);
}

/* 7. Hand-computed fits: on a plane every fit is exact in any frame, so the
 * fits give the plane's normal, (-0.5, 0.25, 1) / |.| for z = 0.5 x - 0.25 y
 * + 0.1, with their own path (the residual is zero: ADAPTIVE takes the jet,
 * or MWSELR's normal, also exact, where the two differ by rounding only).
 * The points are an irregular grid, so the seed and the rings are not
 * symmetric. */
static void test_fits_on_a_plane(void** state)
{
	(void)state;
	mesh m;
	mesh_init(&m, "plane");
	make_height_field(&m, 23, 8, 8, 0.25, 0.3);
	for (size_t v = 0; v < m.nv; v++)
		m.pos[3 * v + 2] = 0.5 * m.pos[3 * v] - 0.25 * m.pos[3 * v + 1] + 0.1;
	double want[3] = {-0.5, 0.25, 1};
	normalize3(want);
	double* ref = malloc(3 * m.nv * sizeof *ref);
	double* lib = malloc(3 * m.nv * sizeof *lib);
	unsigned char* path = malloc(m.nv);
	assert_true(ref && lib && path);
	const int centre = 4 * 9 + 4; /* its 2-ring is inside the grid */
	for (int method = ref_quadric; method < ref_method_count; method++) {
		ref_normals_ex(method, m.pos, m.nv, m.idx, m.off, m.nf, ref, NULL, path);
		assert_int_equal(run_library(&m, method, 0, m.pos, vn_scalar_float64, lib, vn_scalar_float64, 0, NULL),
		                 vn_result_success);
		double worst_ref = 0, worst_lib = 0;
		for (size_t v = 0; v < m.nv; v++) {
			worst_ref = fmax(worst_ref, angle3(ref + 3 * v, want));
			worst_lib = fmax(worst_lib, angle3(lib + 3 * v, want));
		}
		print_message("plane %-8s: worst angle to the plane's normal: ref %.2g, lib %.2g rad; centre path %d\n",
		              method_names[method], worst_ref, worst_lib, path[centre]);
		if (method == ref_adaptive) /* the jet, or MWSELR (as exact) within the jet's rounding residual of it */
			assert_true((path[centre] & ~ref_path_borderline) == ref_path_jet ||
			            (path[centre] & ~ref_path_borderline) == ref_path_mwselr);
		else
			assert_int_equal(path[centre], method == ref_quadric ? ref_path_quadric : ref_path_jet);
		/* Rounding only: a few hundred ulps of the 10 x 10 solve (the
		 * library's unrolled LDLT lands at 1.0e-14 for the jet). */
		assert_true(worst_ref <= 5e-14);
		assert_true(worst_lib <= 5e-14);
	}
	free(ref);
	free(lib);
	free(path);
	mesh_free(&m);
}

/* Threads: any thread count gives bit-identical output and statistics, for
 * the methods below method_end. */
static void check_threads(const mesh* m, int polygon, int method_end)
{
	size_t bytes = 3 * m->nv * sizeof(double);
	double* one = malloc(bytes);
	double* many = malloc(bytes);
	assert_true(one && many);
	size_t differ = 0;
	for (int method = 0; method < method_end; method++) {
		vn_stats s1, sn;
		assert_int_equal(run_library(m, method, polygon, m->pos, vn_scalar_float64, one, vn_scalar_float64, 1, &s1),
		                 vn_result_success);
		for (unsigned threads = 2; threads <= 3; threads++) {
			memset(many, 0xA5, bytes);
			assert_int_equal(run_library(m, method, polygon, m->pos, vn_scalar_float64, many, vn_scalar_float64,
			                             threads, &sn),
			                 vn_result_success);
			if (memcmp(one, many, bytes) != 0 || s1.faces != sn.faces || s1.degenerate_faces != sn.degenerate_faces ||
			    s1.zero_normals != sn.zero_normals || s1.nonfinite_vertices != sn.nonfinite_vertices) {
				print_message("%s %s: %u threads differ from 1\n", m->name, method_names[method], threads);
				differ++;
			}
		}
	}
	free(one);
	free(many);
	print_message("%s, %s entry, %zu faces: threads 2 and 3 %s threads 1\n", m->name,
	              polygon ? "polygon" : "triangle", m->nf, differ ? "DIFFER from" : "bit-identical to");
	assert_int_equal(differ, 0);
}

static void test_threads_bit_identical(void** state)
{
	(void)state;
	mesh m;
	mesh_init(&m, "height field 200k");
	make_height_field(&m, 17, 316, 316, 2.0 / 316, 0.3);
	/* Some awkward faces too: degenerate ones must be skipped identically. */
	mesh_triangle(&m, 0, 0, 1);
	mesh_triangle(&m, 5, 6, 5);
	/* The fits split their work above 4096 vertices a thread: the 50k grid
	 * below is large enough for them, and an order of magnitude cheaper. */
	check_threads(&m, 0, ref_quadric);
	check_threads(&m, 1, ref_quadric);
	mesh_free(&m);

	mesh_init(&m, "polygon grid 50k");
	make_polygon_grid(&m, 18, 400, 250, 0);
	check_threads(&m, 1, ref_method_count);
	mesh_free(&m);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_hand_computed),
		cmocka_unit_test(test_random_triangles),
		cmocka_unit_test(test_random_polygons),
		cmocka_unit_test(test_slivers),
		cmocka_unit_test(test_mwselr_sphere_exact),
		cmocka_unit_test(test_mewcsa_outward_on_sphere),
		cmocka_unit_test(test_mewcsa_inward_on_reversed_sphere),
		cmocka_unit_test(test_mewcsa_dimple_and_bump),
		cmocka_unit_test(test_beyond_the_paper),
		cmocka_unit_test(test_fits_on_a_plane),
		cmocka_unit_test(test_threads_bit_identical),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
