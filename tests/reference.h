/*
 * An independent, deliberately plain reference for the seven vertex-normal
 * weighting schemes, used only by the tests. It is written from the paper's
 * definitions (Jin, Lewis, West 2005) and vn.h's degenerate-input rules, not
 * from the library's source, and computes per vertex ("gather") in long
 * double so that a shared mistake with the library's per-face ("scatter")
 * code is unlikely.
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
	ref_method_count
};

/* Unit normals of every vertex. positions has 3 doubles per vertex; face f has
 * the corners indices[face_offsets[f]] .. indices[face_offsets[f+1] - 1] (so a
 * triangle mesh has face_offsets 0, 3, 6, ...). Every index must be below
 * vertex_count. out_normals receives 3 doubles per vertex; a vertex that no
 * corner contributes to, or whose contributions cancel exactly, gets 0, 0, 0. */
void ref_normals(int method, const double* positions, size_t vertex_count, const uint32_t* indices,
                 const uint32_t* face_offsets, size_t face_count, double* out_normals);

/* As ref_normals, and also how well defined each direction is: out_condition[v]
 * (may be NULL) is |sum of contributions| / sum of |contributions|, in [0, 1];
 * near 0 means cancellation left only rounding noise. It is -1 where no
 * corner contributed at all (the only case where the output must be exactly
 * zero whatever the arithmetic). */
void ref_normals_ex(int method, const double* positions, size_t vertex_count, const uint32_t* indices,
                    const uint32_t* face_offsets, size_t face_count, double* out_normals,
                    double* out_condition);

#endif /* VN_TEST_REFERENCE_H */
