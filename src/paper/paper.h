/* Internal interfaces of the paper library (vn_paper.h): the memory helpers
 * of model_mesh.c, the noise sums of noise.c and the marching tetrahedra of
 * marching.c, which ensemble.c builds the models from. Not installed. */
#ifndef VN_PAPER_INTERNAL_H
#define VN_PAPER_INTERNAL_H

#include "vn_paper.h"

#define VN_PI 3.14159265358979323846

/* ---------------------------------------------------------------- noise.c */

/* Fractional Brownian motion, sum_{i<octaves} noise(2^i p) 2^(-iH), with its
 * exact gradient sum_i 2^(i(1-H)) grad noise(2^i p) written to gradient
 * (3 doubles) when not NULL. */
double vn_fbm_noise(const double p[3], unsigned octaves, double h, double* gradient);

/* Perlin turbulence, sum_{i<octaves} |noise(2^i p)| / 2^i, with its gradient
 * sum_i sign(noise_i) grad noise(2^i p) (the chain rule's 2^i cancels the
 * weight) written to gradient when not NULL. The gradient jumps across the
 * creases where some noise_i is 0; there it is one of the one-sided values. */
double vn_turbulence_noise(const double p[3], unsigned octaves, double* gradient);

/* ---------------------------------------------------------------- model_mesh.c */

/* Memory from a vn_allocator with both functions set, or neither (then
 * malloc/free); vn_model_generate refuses one with a single function. */
void* vn_paper_allocate(const vn_allocator* heap, size_t size);
/* NULL is ignored (a user deallocator need not accept it). */
void vn_paper_free(const vn_allocator* heap, void* ptr);

/* Allocates the four arrays of *mesh for its vertex_count and triangle_count
 * (boundary zeroed); on failure frees what it got, zeroes *mesh and returns
 * out_of_memory. */
vn_result vn_mesh_allocate(const vn_allocator* heap, vn_model_mesh* mesh);
/* Frees the four arrays of *mesh and zeroes it. */
void vn_mesh_release(const vn_allocator* heap, vn_model_mesh* mesh);

/* ---------------------------------------------------------------- marching.c */

/* An implicit function f(p) with its exact gradient, written to gradient
 * (3 doubles) when not NULL. */
typedef double (*vn_implicit_fn)(const void* params, const double p[3], double* gradient);

typedef struct vn_implicit {
	vn_implicit_fn f;
	const void* params;
	double iso;      /* the surface is f = iso; inside is f <= iso */
	double lo, hi;   /* the sampled box [lo, hi]^3 */
	unsigned cells;  /* cubes per axis: (cells + 1)^3 samples */
} vn_implicit;

/* The isosurface of s by marching tetrahedra: positions, exact normals (the
 * normalized gradient) and indices of *mesh, which it allocates; the
 * boundary flags are left zero. On failure nothing is left allocated. */
vn_result vn_marching_tetrahedra(const vn_implicit* s, const vn_allocator* heap, vn_model_mesh* mesh);

/* The fraction of a tetrahedron edge kept between a crossing and either end
 * of the edge, so that no two vertices coincide (see marching.c). */
#define VN_MT_MIN_T (1.0 / 1048576.0)

#endif /* VN_PAPER_INTERNAL_H */
