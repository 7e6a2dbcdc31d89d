/*
 * vn_paper: the test ensemble of Jin, Lewis, West 2005 (section 3.1), the
 * research harness behind vneval, as a library of its own (libvnpaper.a,
 * src/paper/). It generates the paper's test surfaces with their exact
 * normals so that any scheme's error can be measured. It is built on libvn's
 * public header only; libvn, the Blender add-on and the MeshLab plugin do not
 * carry it. Conventions as in vn.h (results, allocators, no global state).
 */
#ifndef VN_PAPER_H
#define VN_PAPER_H

#include "vn.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ test ensemble
 *
 * The paper's test models (section 3.1): surfaces whose exact normals are
 * known, so that any scheme's error can be measured (eq. 11). Every model is
 * generated deterministically at three resolutions; docs/ENSEMBLE.md lists
 * every parameter (domains, dilations, octaves, isovalues, grids) and the
 * resulting counts, docs/REPRODUCTION.md what vneval measures on them. Two
 * smooth surfaces not in the paper follow the paper's ten (so the ten keep
 * their values); docs/ACCURACY.md measures every scheme on all twelve. */

typedef enum vn_model {
	vn_model_sphere_tp = 0, /* sphere, trigonometric parameterization */
	vn_model_torus_tp,      /* torus, trigonometric parameterization */
	vn_model_perlin_hf,     /* height field of Perlin's improved noise */
	vn_model_fractal09_hf,  /* fBm height field, H = 0.9 */
	vn_model_fractal05_hf,  /* fBm height field, H = 0.5 */
	vn_model_fractal01_hf,  /* fBm height field, H = 0.1 */
	vn_model_sphere_mt,     /* sphere, marching tetrahedra */
	vn_model_cosine_mt,     /* cos(2 pi d x) + cos(2 pi d y) + cos(2 pi d z), marching tetrahedra (eq. 10) */
	vn_model_perlin_mt,     /* 3D Perlin noise, marching tetrahedra */
	vn_model_turbulence_mt, /* Perlin turbulence sum |noise(2^i p)| / 2^i, marching tetrahedra */
	vn_model_ellipsoid_tp,  /* ellipsoid (1, 0.75, 0.5), jittered trigonometric parameterization */
	vn_model_gyroid_mt,     /* gyroid sin x cos y + sin y cos z + sin z cos x = 0, marching tetrahedra */
	vn_model_count
} vn_model;

/* The paper's ten models come first: values below this one. */
#define VN_MODEL_PAPER_COUNT 10

typedef enum vn_resolution {
	vn_resolution_low = 0,
	vn_resolution_medium,
	vn_resolution_high,
	vn_resolution_count
} vn_resolution;

/* A generated triangle mesh with its exact normals. The arrays are allocated
 * with the allocator given to vn_model_generate; free with vn_model_free. */
typedef struct vn_model_mesh {
	size_t vertex_count;
	size_t triangle_count;
	double* positions;  /* 3 per vertex */
	double* normals;    /* 3 per vertex: the exact unit normal at the vertex (for
	                       marching tetrahedra, the gradient's direction at the
	                       interpolated vertex, which lies near the surface) */
	uint8_t* boundary;  /* 1 per vertex: 1 when the vertex is on a mesh boundary
	                       edge (an edge of exactly one triangle), else 0 */
	uint32_t* indices;  /* 3 per triangle, counter-clockwise around the exact normal */
} vn_model_mesh;

/* The model's short name ("torus_tp"), or NULL for an invalid value. */
const char* vn_model_name(vn_model m);
/* One line describing the model, or NULL for an invalid value. */
const char* vn_model_description(vn_model m);
/* "low", "medium", "high", or NULL for an invalid value. */
const char* vn_resolution_name(vn_resolution r);

/* Generates model m at resolution r into *mesh (overwritten; zeroed on any
 * error). allocator may be NULL or all-NULL (malloc/free). Returns
 * invalid_argument for an invalid m or r, a NULL mesh or an allocator with
 * only one function, out_of_memory when an allocation fails (nothing leaks). */
vn_result vn_model_generate(vn_model m, vn_resolution r, const vn_allocator* allocator,
                                   vn_model_mesh* mesh);

/* The grid of model m at resolution r, the size that vn_model_generate_grid
 * takes: bands between the poles for the TP models (by twice as many
 * segments), samples per side for the height fields, cubes per axis for
 * marching tetrahedra. 0 for an invalid m or r. */
unsigned vn_model_grid(vn_model m, vn_resolution r);

/* The largest grids vn_model_generate_grid accepts: TP and HF meshes grow as
 * grid^2, marching tetrahedra's sampling (36 bytes a sample) as grid^3. */
#define VN_MODEL_GRID_MAX 2048
#define VN_MODEL_CELLS_MAX 256

/* Generates model m on any grid, for convergence studies:
 * vn_model_generate(m, r) is vn_model_generate_grid(m, vn_model_grid(m, r)).
 * grid is from 3 (TP), 2 (HF, MT) to VN_MODEL_GRID_MAX (TP, HF) or
 * VN_MODEL_CELLS_MAX (MT); otherwise, and for the other errors, as
 * vn_model_generate. */
vn_result vn_model_generate_grid(vn_model m, unsigned grid, const vn_allocator* allocator, vn_model_mesh* mesh);

/* Frees what vn_model_generate allocated, with the same allocator, and
 * zeroes *mesh. NULL or a zeroed mesh is fine. */
void vn_model_free(vn_model_mesh* mesh, const vn_allocator* allocator);

/* Ken Perlin's improved noise (2002 reference permutation, fade
 * 6t^5 - 15t^4 + 10t^3) at p, with its exact gradient written to gradient
 * (3 doubles) when not NULL. Values lie in about [-1, 1]. */
double vn_perlin_noise(const double p[3], double* gradient);

#ifdef __cplusplus
}
#endif

#endif /* VN_PAPER_H */
