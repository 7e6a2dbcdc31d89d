/* Marching tetrahedra (Jin et al. 2005 section 3.1.3): the isosurface
 * f = iso of an implicit function sampled on a regular grid.
 *
 * The ensemble's five MT models (ensemble.c, docs/ENSEMBLE.md), all in
 * the box [-1, 1]^3:
 *   model          f, iso                                     cells        triangles
 *   sphere_mt      x^2 + y^2 + z^2, 0.64                       13, 29, 59   3120, 15168, 63024
 *   cosine_mt      sum cos(1.5 pi x_k), 0 (eq. 10, d = 0.75)   13, 29, 59   4704, 23688, 97776
 *   perlin_mt      noise(p + (0.37, 0.61, 0.23)), 0            13, 29, 59   5916, 29634, 123288
 *   turbulence_mt  sum_{i<4} |noise(2^i q)| / 2^i, 0.15,       10, 14, 18   1572, 3786, 7248
 *                  q = p / 2 + (0.37, 0.61, 0.23)
 *   gyroid_mt      sin x cos y + sin y cos z + sin z cos x,    13, 29, 59   7128, 35706, 148100
 *                  0, at q = 1.5 pi p + (0.3, 0.5, 0.7)
 *
 * Subdivision. Each cube of the grid is split into the 6 tetrahedra of the
 * Freudenthal (Kuhn) subdivision: for every order (a, b, c) of the axes the
 * tetrahedron 0, e_a, e_a + e_b, (1,1,1). All six share the cube's main
 * diagonal and the split is the same in every cube, so the two triangles a
 * cube face gets from either side match. Every tetrahedron edge joins two
 * grid points p and p + d with d in {0,1}^3 \ {0}: a cube edge, a face
 * diagonal or the main diagonal. So edge (p, d) has the id 7 p + d - 1, and
 * the surface vertex on an edge is made once and shared by every triangle
 * that uses the edge (vertices are numbered in id order: deterministic).
 *
 * Sides. A sample is inside when f <= iso. An edge with one end inside and
 * one outside carries a vertex at the linear interpolation
 * t = (iso - f_a) / (f_b - f_a), so within one tetrahedron the vertices are
 * the zero set of the linear interpolant of its four samples, a triangle or
 * a planar quad (cut along its shorter diagonal). Triangles are ordered
 * counter-clockwise around the direction from inside to outside, which is
 * the gradient's (the exact normal's) direction.
 *
 * Ties. Putting f == iso on one side keeps the classification consistent but
 * gives t = 0 (or, rounded, t = 1): several edges leaving that sample would
 * put coincident vertices on it, and their triangles would have zero area.
 * So t is clamped to [VN_MT_MIN_T, 1 - VN_MT_MIN_T] (2^-20): the vertices of
 * a tie sit a millionth of their edges away from the sample, distinct, each
 * on its own edge, and the triangles between them are tiny but keep their
 * area and their orientation (which comes from the case table, not from the
 * geometry). A clamped vertex is off the interpolated crossing by at most
 * 2^-20 of its edge. The ensemble's grids keep every sample off its
 * isosurface (ensemble.c) and never trigger the clamp (tested); the clamp
 * is the rule that keeps the output sound for any function.
 *
 * Exact normals are the normalized analytic gradient at each vertex.
 */
#include <math.h>
#include <string.h>

#include "paper.h"

/* The 6 Kuhn tetrahedra as corner masks (bit 0: +x, bit 1: +y, bit 2: +z),
 * each listed with positive orientation: for an odd axis order the middle
 * corners are swapped. */
static const unsigned char tets[6][4] = {
    {0, 1, 3, 7}, /* x, y, z */
    {0, 2, 6, 7}, /* y, z, x */
    {0, 4, 5, 7}, /* z, x, y */
    {0, 5, 1, 7}, /* x, z, y (odd) */
    {0, 6, 4, 7}, /* z, y, x (odd) */
    {0, 3, 2, 7}, /* y, x, z (odd) */
};

/* What a tetrahedron with inside-corner mask m (bit i: its corner i is
 * inside) produces: an even permutation of its corners, so still positively
 * oriented, that brings it to one of three cases, corner numbers below being
 * positions in the permutation:
 *   one_in:  corner 0 inside:  triangle (e01, e02, e03), which turns away from 0
 *   one_out: corner 0 outside: the same reversed, (e01, e03, e02)
 *   two_in:  corners 0, 1 inside: the quad (e02, e03, e13, e12). */
enum { none, one_in, one_out, two_in };
static const struct {
	unsigned char kind, perm[4];
} cases[16] = {
    {none, {0, 1, 2, 3}},    {one_in, {0, 1, 2, 3}},  {one_in, {1, 0, 3, 2}},  {two_in, {0, 1, 2, 3}},
    {one_in, {2, 0, 1, 3}},  {two_in, {0, 2, 3, 1}},  {two_in, {1, 2, 0, 3}},  {one_out, {3, 0, 2, 1}},
    {one_in, {3, 0, 2, 1}},  {two_in, {0, 3, 1, 2}},  {two_in, {1, 3, 2, 0}},  {one_out, {2, 0, 1, 3}},
    {two_in, {2, 3, 0, 1}},  {one_out, {1, 0, 3, 2}}, {one_out, {0, 1, 2, 3}}, {none, {0, 1, 2, 3}},
};

static unsigned triangles_of(unsigned kind)
{
	return kind == two_in ? 2 : kind != none;
}

typedef struct grid {
	const vn_implicit* s;
	size_t np;        /* samples per axis */
	const double* f;  /* samples, x fastest */
	uint32_t* vertex; /* per edge id: its vertex, or UINT32_MAX */
} grid;

static double coord(const vn_implicit* s, size_t i)
{
	return s->lo + (s->hi - s->lo) * (double)i / (double)s->cells;
}

/* Sample index of corner mask m of the cube at sample c. */
static size_t corner(const grid* g, size_t c, unsigned m)
{
	return c + (m & 1) + ((m >> 1) & 1) * g->np + ((m >> 2) & 1) * g->np * g->np;
}

static int inside(const grid* g, size_t sample)
{
	return g->f[sample] <= g->s->iso;
}

/* The vertex on the edge between corner masks a and b of the cube at c (one
 * contains the other: the edges of a Kuhn tetrahedron form a chain). */
static uint32_t edge_vertex(const grid* g, size_t c, unsigned a, unsigned b)
{
	const unsigned lo = a & b, d = a ^ b;
	return g->vertex[7 * corner(g, c, lo) + d - 1];
}

static void sample_point(const grid* g, size_t sample, double p[3])
{
	const size_t np = g->np;
	p[0] = coord(g->s, sample % np);
	p[1] = coord(g->s, sample / np % np);
	p[2] = coord(g->s, sample / (np * np));
}

/* Numbers the crossed edges in id order; returns the vertex count. */
static uint32_t number_edges(grid* g)
{
	const size_t np = g->np, n = np * np * np;
	uint32_t count = 0;
	for (size_t c = 0; c < n; ++c) {
		const size_t ijk[3] = {c % np, c / np % np, c / (np * np)};
		for (unsigned d = 1; d < 8; ++d) {
			uint32_t v = UINT32_MAX;
			if (!((d & 1 && ijk[0] + 1 == np) || (d & 2 && ijk[1] + 1 == np) || (d & 4 && ijk[2] + 1 == np)) &&
			    inside(g, c) != inside(g, corner(g, c, d)))
				v = count++;
			g->vertex[7 * c + d - 1] = v;
		}
	}
	return count;
}

/* The clamped crossing on every crossed edge, and its exact normal. */
static void place_vertices(const grid* g, vn_model_mesh* mesh)
{
	const size_t n = g->np * g->np * g->np;
	const double iso = g->s->iso;
	for (size_t c = 0; c < n; ++c) {
		for (unsigned d = 1; d < 8; ++d) {
			const uint32_t v = g->vertex[7 * c + d - 1];
			if (v == UINT32_MAX)
				continue;
			const size_t e = corner(g, c, d);
			double t = (iso - g->f[c]) / (g->f[e] - g->f[c]);
			t = t < VN_MT_MIN_T ? VN_MT_MIN_T : t > 1 - VN_MT_MIN_T ? 1 - VN_MT_MIN_T : t;
			double a[3], b[3], grad[3];
			sample_point(g, c, a);
			sample_point(g, e, b);
			double* p = mesh->positions + 3 * (size_t)v;
			for (int k = 0; k < 3; ++k)
				p[k] = a[k] + t * (b[k] - a[k]);
			g->s->f(g->s->params, p, grad);
			const double inv = 1.0 / sqrt(grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2]);
			double* nrm = mesh->normals + 3 * (size_t)v;
			for (int k = 0; k < 3; ++k)
				nrm[k] = grad[k] * inv;
		}
	}
}

static double distance2(const double* positions, uint32_t a, uint32_t b)
{
	const double* p = positions + 3 * (size_t)a;
	const double* q = positions + 3 * (size_t)b;
	const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
	return dx * dx + dy * dy + dz * dz;
}

/* The triangles of tetrahedron tet (corner masks) of the cube at sample c,
 * written to out (NULL: counted only); returns how many. */
static unsigned march_tet(const grid* g, size_t c, const unsigned char tet[4], const double* positions, uint32_t* out)
{
	unsigned m = 0;
	for (unsigned i = 0; i < 4; ++i)
		m |= (unsigned)inside(g, corner(g, c, tet[i])) << i;
	const unsigned kind = cases[m].kind;
	if (!out || kind == none)
		return triangles_of(kind);
	unsigned q[4];
	for (unsigned i = 0; i < 4; ++i)
		q[i] = tet[cases[m].perm[i]];
#define E(i, j) edge_vertex(g, c, q[i], q[j])
	if (kind == one_in) {
		out[0] = E(0, 1), out[1] = E(0, 2), out[2] = E(0, 3);
		return 1;
	}
	if (kind == one_out) {
		out[0] = E(0, 1), out[1] = E(0, 3), out[2] = E(0, 2);
		return 1;
	}
	/* The quad a, b, c, d = e02, e03, e13, e12, cut along its shorter diagonal. */
	const uint32_t a = E(0, 2), b = E(0, 3), cc = E(1, 3), d = E(1, 2);
#undef E
	if (distance2(positions, a, cc) <= distance2(positions, b, d)) {
		out[0] = a, out[1] = b, out[2] = cc;
		out[3] = a, out[4] = cc, out[5] = d;
	} else {
		out[0] = b, out[1] = cc, out[2] = d;
		out[3] = b, out[4] = d, out[5] = a;
	}
	return 2;
}

/* Visits every tetrahedron in a fixed order; counts its triangles, or writes
 * them when indices is not NULL. */
static size_t march(const grid* g, const double* positions, uint32_t* indices)
{
	const size_t cells = g->s->cells;
	size_t count = 0;
	for (size_t k = 0; k < cells; ++k)
		for (size_t j = 0; j < cells; ++j)
			for (size_t i = 0; i < cells; ++i) {
				const size_t c = i + g->np * (j + g->np * k);
				for (unsigned t = 0; t < 6; ++t)
					count += march_tet(g, c, tets[t], positions, indices ? indices + 3 * count : NULL);
			}
	return count;
}

vn_result vn_marching_tetrahedra(const vn_implicit* s, const vn_allocator* heap, vn_model_mesh* mesh)
{
	memset(mesh, 0, sizeof(*mesh));
	grid g = {s, (size_t)s->cells + 1, NULL, NULL};
	const size_t n = g.np * g.np * g.np;
	double* f = (double*)vn_paper_allocate(heap, n * sizeof(double));
	g.vertex = (uint32_t*)vn_paper_allocate(heap, 7 * n * sizeof(uint32_t));
	vn_result r = vn_result_out_of_memory;
	if (f && g.vertex) {
		for (size_t c = 0; c < n; ++c) {
			double p[3];
			sample_point(&g, c, p);
			f[c] = s->f(s->params, p, NULL);
		}
		g.f = f;
		mesh->vertex_count = number_edges(&g);
		mesh->triangle_count = march(&g, NULL, NULL);
		r = vn_mesh_allocate(heap, mesh);
	}
	if (r == vn_result_success) {
		place_vertices(&g, mesh);
		march(&g, mesh->positions, mesh->indices);
	}
	vn_paper_free(heap, g.vertex);
	vn_paper_free(heap, f);
	return r;
}
