/*
 * An independent, deliberately plain reference for the vertex-normal schemes,
 * used only by the tests. The seven are written from the paper's definitions
 * (Jin, Lewis, West 2005), the four beyond it from vn.h's documentation, and
 * all from vn.h's degenerate-input rules, not from the library's source. It
 * computes per vertex ("gather") in long double, and solves the fits'
 * least-squares systems by Householder QR of the weighted design matrix (the
 * library forms the normal equations and uses Cholesky), so that a shared
 * mistake with the library is unlikely.
 */
#ifndef VN_TEST_REFERENCE_H
#define VN_TEST_REFERENCE_H

#include <stddef.h>
#include <stdint.h>

/* Method numbers, in vn_method's order (kept separate from vn.h on purpose). */
enum {
	ref_mwe = 0,
	ref_mwa,
	ref_mwselr,
	ref_mwaat,
	ref_mwelr,
	ref_mwrelr,
	ref_mewcsa,
	ref_smewcsa,
	ref_quadric,
	ref_jet,
	ref_adaptive,
	ref_method_count
};

/* How a vertex's normal was obtained (ref_normals_ex's out_path). */
enum {
	ref_path_zero = 0, /* the zero vector */
	ref_path_weighted, /* the method's own sum: one of the seven */
	ref_path_seed,     /* the fallback: MWA for the fits, MWSELR for SMEWCSA */
	ref_path_cotangent, /* SMEWCSA: the MEWCSA normal, its sign corrected */
	ref_path_quadric,  /* the 1-ring quadric fit */
	ref_path_jet,      /* the 2-ring cubic jet fit */
	ref_path_wide,     /* ADAPTIVE: a 5-ring fit with Gaussian weights */
	ref_path_rough,    /* ADAPTIVE's rough fallback: MWA (S) */
	ref_path_mwselr,   /* ADAPTIVE: MWSELR, for a jet that agrees with it */
	ref_path_lattice,  /* ADAPTIVE's rough fallback on a lattice height field: MWAAT */
	ref_path_count,
	/* Added to the path: a decision on the way (a pivot, the 60 degree or
	 * 30 degree rule, ADAPTIVE's residual, SMEWCSA's flatness) was within
	 * rounding of its threshold; another correct implementation may decide
	 * otherwise. */
	ref_path_borderline = 16
};

/* Unit normals of every vertex. positions has 3 doubles per vertex; face f has
 * the corners indices[face_offsets[f]] .. indices[face_offsets[f+1] - 1] (so a
 * triangle mesh has face_offsets 0, 3, 6, ...). Every index must be below
 * vertex_count. out_normals receives 3 doubles per vertex; a vertex that no
 * corner contributes to, or whose contributions cancel exactly, gets 0, 0, 0. */
void ref_normals(int method, const double* positions, size_t vertex_count, const uint32_t* indices,
                 const uint32_t* face_offsets, size_t face_count, double* out_normals);

/* As ref_normals, and also how well defined each direction is: out_condition[v]
 * (may be NULL) is, for a sum of contributions (the seven; SMEWCSA's chosen
 * MEWCSA or MWSELR sum; a fit's fallback to MWA), |sum of contributions| /
 * sum of |contributions|, in [0, 1]; near 0 means cancellation left only
 * rounding noise. It is -1 where no corner contributed at all (the only case
 * where the output must be exactly zero whatever the arithmetic). For a fitted
 * normal it is the reciprocal condition number (2-norm, estimated from above
 * within a factor k) of the unit-diagonal normal matrix of the worst
 * conditioned of the two fits that made it, in (0, 1]. out_path (may be NULL)
 * receives a ref_path_* value per vertex. */
void ref_normals_ex(int method, const double* positions, size_t vertex_count, const uint32_t* indices,
                    const uint32_t* face_offsets, size_t face_count, double* out_normals,
                    double* out_condition, unsigned char* out_path);

#endif /* VN_TEST_REFERENCE_H */
