/*
 * vn: vertex normals with any published weighting scheme.
 *
 * This header is the manual. Conventions used throughout:
 *  - Inputs are plain arrays with byte strides; the caller owns every output
 *    array and sizes it as each function says.
 *  - Every function returns a vn_result; vn_result_string() names it.
 *  - Options structs are all-zero for the defaults; a NULL options pointer
 *    means the same.
 *  - Nothing is global or mutable: distinct meshes may be processed from
 *    distinct threads at the same time.
 *  - Positions are in any length unit; normals are unitless unit vectors.
 *
 * Weighting schemes: Jin, Lewis, West, "A Comparison of Algorithms for Vertex
 * Normal Computation", 2005 (the paper's equation numbers are cited below).
 */
#ifndef VN_H
#define VN_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32) && defined(VN_SHARED)
#  ifdef VN_BUILDING
#    define VN_API __declspec(dllexport)
#  else
#    define VN_API __declspec(dllimport)
#  endif
#elif defined(__GNUC__) || defined(__clang__)
#  define VN_API __attribute__((visibility("default")))
#else
#  define VN_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ version */

#define VN_VERSION_MAJOR 0
#define VN_VERSION_MINOR 3
#define VN_VERSION_PATCH 0
/* (major << 16) | (minor << 8) | patch, comparable as an integer. */
#define VN_VERSION ((VN_VERSION_MAJOR << 16) | (VN_VERSION_MINOR << 8) | VN_VERSION_PATCH)
#define VN_VERSION_STRING "0.3.0"

/* The VN_VERSION the library was built with. A program should check at start
 * that vn_version() >> 8 == VN_VERSION >> 8: before 1.0 a minor version may
 * change the ABI (0.2 appended vn_options.face_strength and 0.3
 * vn_options.keep_existing, so a program built with an older vn.h passes a
 * shorter vn_options). */
VN_API uint32_t vn_version(void);
/* The same as a "MAJOR.MINOR.PATCH" string with static storage. */
VN_API const char* vn_version_string(void);

/* ------------------------------------------------------------------ results */

typedef enum vn_result {
	vn_result_success = 0,
	vn_result_invalid_argument,   /* a required pointer is NULL, a stride too small, a count inconsistent */
	vn_result_index_out_of_range, /* an index >= vertex_count; nothing was written */
	vn_result_unknown_method,     /* not a vn_method value, or a name no method has */
	vn_result_out_of_memory,      /* the allocator returned NULL; nothing was written */
	vn_result_count_
} vn_result;

/* A short English description of r ("index out of range"); never NULL. */
VN_API const char* vn_result_string(vn_result r);

/* ------------------------------------------------------------------ methods */

/* The paper's seven schemes. For a face f around vertex v: N_f is f's unit
 * normal (Newell's method on polygons), E and E' the vectors from v to its
 * previous and next corner in f, alpha = atan2(|E x E'|, E . E'). Every method
 * normalizes the sum at the end. */
typedef enum vn_method {
	vn_method_mwe = 0, /* sum N_f                              (Gouraud 1971, eq. 1) */
	vn_method_mwa,     /* sum alpha N_f                        (Thurmer & Wuthrich 1998, eq. 2) */
	vn_method_mwselr,  /* sum N_f sin(alpha) / (|E||E'|)       (Max 1999, eq. 4) */
	vn_method_mwaat,   /* sum N_f |E x E'|                     (Max 1999, eq. 5) */
	vn_method_mwelr,   /* sum N_f / (|E||E'|)                  (Max 1999, eq. 6) */
	vn_method_mwrelr,  /* sum N_f / sqrt(|E||E'|)              (Max 1999, eq. 7) */
	vn_method_mewcsa,  /* sum (p_next - p_prev) x N_f; on triangles the cotangent
	                      formula (Desbrun et al. 1999, eq. 9). The sign is NOT
	                      corrected: it points inward where mean curvature < 0. */

	/* Beyond the paper (they keep the seven's indices). */
	vn_method_smewcsa, /* MEWCSA with its sign corrected (Meyer et al. 2003): K =
	                      the MEWCSA sum, H = K / |K|, S = the MWSELR normal;
	                      H flipped when H . S < 0, and S where the mean
	                      curvature is about zero: where |K| <= 2^-12 times
	                      the sum of its contributions' lengths (a flat
	                      region: K is rounding noise, float32 positions'
	                      included while |p| is under about 1000 edge
	                      lengths), or H is more than 30 degrees from S (K's
	                      normal part no larger than its tangential part,
	                      its discretization error). Zero where S is zero.
	                      Two passes: about twice MEWCSA's cost. */
	vn_method_quadric, /* weighted least squares of z = f(x, y) = c + a x + b y
	                      + d x^2 + e xy + g y^2 over the vertex and its 1-ring,
	                      in the tangent frame of the vertex's MWA normal S, the
	                      vertex at the origin, coordinates over h (the mean
	                      distance from the vertex to its 1-ring members),
	                      weights 1 / (1 + |p|^2 / h^2); normal (-a, -b, 1) in
	                      that frame; then one refit in the frame of that
	                      normal (the first fit kept if the refit is
	                      ill-conditioned). A fit in the frame of a quadric
	                      height field's axis is exact; the method's frames
	                      are S's and the fit's, so it is exact only where
	                      those are that axis, and O(h^2) on irregular meshes,
	                      where the seven are O(h). Falls back to S with fewer
	                      points (the vertex included) than unknowns, an
	                      ill-conditioned system or a final normal over 60
	                      degrees from S. */
	vn_method_jet,     /* the same with the cubic terms x^3, x^2 y, x y^2, y^3,
	                      over the vertex and its 2-ring (Cazals & Pouget 2003,
	                      osculating jets), h still the 1-ring's; O(h^3);
	                      falls back to QUADRIC. */
	vn_method_adaptive, /* per vertex, one of three fits: JET's 2-ring jet
	                      (without its QUADRIC fallback), and on the vertex
	                      and its 5-ring a quadric and a cubic with weights
	                      exp(-|p|^2 / (2 r^2)), r 0.6 times the 5-ring
	                      members' RMS distance (wide enough to average out
	                      the position noise of e.g. marching-tetrahedra
	                      vertices), both fitted once, in the jet's
	                      frame. The jet is taken
	                      outright where its e <= 1e-4 (exact to its
	                      model; e a fit's weighted RMS residual over h).
	                      Where the jet's e exceeds 0.05 (no cubic
	                      describes the surface at the scale of its edges:
	                      fractal or turbulent), or the jet strays over 60
	                      degrees from S, a face-weighted normal, without
	                      wide fits: MWAAT's where the 1-ring is a height
	                      field sampled on a lattice (the vertex's faces
	                      close one fan of 2m >= 4 members p_i, at most 16,
	                      in order around p, and the m second differences
	                      p_i + p_(i+m) - 2 p are parallel, or zero, to
	                      0.01 h, which float32 grids meet up to about
	                      40,000 cells from the origin: seen along them
	                      the ring is centrally symmetric, as a grid's
	                      rows, diagonals and quads are), where MWAAT's
	                      sum, the ring's vector area, is a central
	                      difference (the best of the seven on the paper's
	                      fractal height fields); elsewhere S (there face
	                      areas say how the surface was cut, not how far a
	                      face reaches: on the paper's rough isosurface
	                      MWAAT is 6 to 11% above the best of the seven,
	                      MWA 2 to 5%).
	                      Else the quadric or the cubic, by T = |d|^2 /
	                      var(d), d the quadric's slopes minus the
	                      cubic's, var(d) = s^2 (V_c - V_q), V the sum of
	                      the slopes' diagonal entries of the inverse
	                      normal matrix, s^2 the cubic's weighted squared
	                      residuals over (its points - 10): the cubic where
	                      the mean of log T over the vertex and its 1-ring
	                      (those whose two wide fits succeeded) exceeds
	                      log 2, the break-even of the quadric's estimated
	                      squared bias |d|^2 - var(d) against the variance
	                      the cubic adds; T's noise averages out over the
	                      ring, the cubic terms do not. The one taken (the
	                      other where it failed) is then compared with the
	                      jet by generalized cross-validation (Craven &
	                      Wahba 1979) e^2 / (1 - k / n)^2, k its unknowns (6
	                      or 10), n its effective number of points (sum
	                      w)^2 / sum w^2: the wide fit unless the jet's
	                      score is below half of its (the jet's rests on
	                      about 14 effective points for 10 unknowns, and
	                      scatters). Where the jet is taken and MWSELR's
	                      normal is within 0.5 e radians of it (the jet
	                      cannot tell them apart), MWSELR's: exact where
	                      the jet is not, e.g. on a sphere's or a torus's
	                      latitude-longitude grid. Before all of these,
	                      MWSELR's normal outright where the vertex's
	                      2-ring (5 points or more) lies on a sphere
	                      through it tangent to MWSELR's plane (z = k |p|^2
	                      / 2, z the height over that plane, k by least
	                      squares), every point within 1024 units of
	                      rounding of the largest coordinate among them
	                      (float32's where every coordinate of the mesh is
	                      a float32 value, whatever type it is passed in,
	                      as from glTF; where every one is a decimal of at
	                      most 12 places or 15 significant digits, as read
	                      from text, the larger of half a unit in the last
	                      place and in the last digit that write them all,
	                      e.g. 5e-7 for Blender's OBJ; else float64's) and
	                      at most 1e-4 h, and the sphere not a plane to
	                      that tolerance: MWSELR is that sphere's normal
	                      (Max 1999), so ADAPTIVE is exact on any mesh
	                      whose vertices lie on a sphere (UV spheres,
	                      icospheres), to the precision of its
	                      coordinates. Where the jet cannot be fitted
	                      (fewer points than unknowns, or
	                      ill-conditioned), or has only as many (it
	                      interpolates them, and its e of 0 says nothing),
	                      JET's fallback:
	                      the 1-ring quadric, else S (on an open
	                      cylinder's strip S is exact, MWAAT 5 degrees
	                      off); the wide fits are not tried there: at e.g.
	                      a boundary vertex of a cone's fan, whose 5-ring
	                      is the rim (on a conic) and the apex, a quadric
	                      through them all tilts as the apex asks (40
	                      degrees). The 5-ring stops at the ring
	                      capacity of JET's 2-rings (the largest vertex's
	                      candidate count c: c (c + 1) members, nearest
	                      rings first). The thresholds 1e-4 and 0.05, the
	                      factors 2 and 0.5, the 5-ring and the width 0.6 were
	                      chosen with vneval (docs/ACCURACY.md): the scheme
	                      to use when unsure. */
	/* The fits (QUADRIC, JET, ADAPTIVE): rings are the vertices sharing a
	 * face (a polygon's corners when it has at most 8, else its two edge
	 * neighbours) whose corners are all finite (a polygon: 3 or more), so
	 * NaN never enters; a face of zero area joins its corners, samples of
	 * the surface like any other. Wider rings do not expand through a member with more than
	 * 256 ring members (a fan's hub), so that a fan of any size costs
	 * linear time (its rim vertices' 2-rings would be the whole fan).
	 * The tangent frame of a unit axis a = (x, y, z) is Duff et al. 2017's: with s the sign of z (-0 negative), A = -1 / (s + z) and
	 * B = x y A, t1 = (1 + s x^2 A, s B, -s x), t2 = (B, s + y^2 A, -y).
	 * The normal does not depend on it,
	 * but the conditioning test does: the system (columns 1, x, y, x^2, xy,
	 * y^2, x^3, x^2 y, x y^2, y^3 in that order) is ill-conditioned when a
	 * Cholesky pivot of its normal matrix scaled to unit diagonal (the
	 * squared diagonal of R) is below 1e-8, or the reciprocal condition
	 * 1 / (k trace(M~^-1)) of that matrix M~ is below 1e-10 (rounding
	 * would move the normal by more than about 1e-3 radians). Boundary
	 * vertices fit their one-sided rings, non-manifold
	 * ones the union of their sheets. A vertex whose S is zero gets zero
	 * (ADAPTIVE too); every
	 * other fitted normal is unit with a positive dot product with S.
	 * Memory: about 9 bytes a corner + 1 a polygon + 33 a vertex (ADAPTIVE 137)
	 * + 4 a 1-ring member (JET, ADAPTIVE) + 4 a vertex per thread from the
	 * allocator (the workspace serves the seed pass only), + 144 bytes a
	 * 2-ring member per thread. Cost on one thread, on a smooth torus:
	 * QUADRIC about 10x MWSELR's, JET about 25x, ADAPTIVE about 30x (the
	 * jet is exact to 1e-4 h there, and neither the 5-ring is gathered nor
	 * its fits made; also where rough); where every vertex fits its 5-ring
	 * (a marching-tetrahedra isosurface), about 120x (docs/PERFORMANCE.md).
	 * Per corner
	 * (vn_corner_normals, vn_polygon_corner_normals): a
	 * corner whose fan is its vertex's whole star (one fan, no degenerate
	 * face, with face strengths all equally strong) gets the vertex's
	 * fitted normal, any other corner its fan's MWA normal. SMEWCSA per
	 * corner likewise: the vertex's normal, or the fan's MWSELR normal (a
	 * partial fan's MEWCSA sum is no mean-curvature normal). */
	vn_method_count
} vn_method;

/* The method's lower-case name ("mwselr"), or NULL for an invalid value. */
VN_API const char* vn_method_name(vn_method m);
/* One line saying what the method weights by, or NULL for an invalid value. */
VN_API const char* vn_method_description(vn_method m);
/* The method's origin as a short citation, or NULL for an invalid value. */
VN_API const char* vn_method_reference(vn_method m);
/* Finds a method by name, case-insensitively. Writes *out only on success;
 * returns vn_result_unknown_method for an unknown name, invalid_argument for NULL. */
VN_API vn_result vn_method_from_name(const char* name, vn_method* out);

/* ------------------------------------------------------------------ data */

typedef enum vn_scalar {
	vn_scalar_float32 = 0,
	vn_scalar_float64 = 1
} vn_scalar;

/* Input positions: count vertices, each x, y, z of type `type`, the first at
 * `data`, vertex i at (const char*)data + i * stride. stride 0 means packed
 * (3 * scalar size). Computation is in double whatever the input type. */
typedef struct vn_positions {
	const void* data;
	size_t count;
	size_t stride;
	vn_scalar type;
} vn_positions;

/* Output vectors: one x, y, z triple of type `type` per element, element i at
 * (char*)data + i * stride; stride 0 means packed. The caller allocates. */
typedef struct vn_vectors {
	void* data;
	size_t stride;
	vn_scalar type;
} vn_vectors;

/* Memory for temporary work arrays. Both functions NULL means malloc/free. */
typedef struct vn_allocator {
	void* (*allocate)(void* user, size_t size);
	void (*deallocate)(void* user, void* ptr);
	void* user;
} vn_allocator;

/* Whether the triangle kernels may use the CPU's vector instructions (AVX2 on
 * x86-64, detected at run time). Results are bit-identical either way. */
typedef enum vn_simd {
	vn_simd_auto = 0, /* use them when the CPU has them */
	vn_simd_off = 1   /* portable scalar code only: to verify or to measure */
} vn_simd;

typedef struct vn_options {
	/* Worker threads; 0 or 1 computes on the calling thread. Results are
	 * bit-identical whatever the thread count. Meshes with fewer than 16384
	 * vertices per thread use fewer threads; a thread that cannot be started
	 * has its share computed on the calling thread. */
	unsigned threads;
	vn_simd simd;
	/* Work memory (about 32 bytes per vertex) comes from `workspace` when it
	 * is not NULL and workspace_size >= vn_workspace_size(); the call then
	 * allocates nothing. Otherwise it comes from `allocator`. A workspace
	 * serves one call at a time. threads, simd and the workspace apply to
	 * vn_triangle_normals and vn_polygon_normals; threads and a workspace
	 * (of the size their comments give) to vn_corner_normals and
	 * vn_polygon_corner_normals; the other functions run on the calling
	 * thread and use only the allocator. */
	void* workspace;
	size_t workspace_size;
	vn_allocator allocator;
	/* Face Influence, as Blender's Weighted Normal modifier has it: NULL, or
	 * one strength per face (index_count / 3 triangles for vn_corner_normals,
	 * face_count faces for vn_polygon_corner_normals). In each fan of corners
	 * that share a normal, only the faces of the fan's highest strength
	 * contribute, and the result goes to every corner of the fan. Values are
	 * only compared (Blender's: -16384 weak, 0 medium, 16384 strong; any
	 * int32 here); equal strengths change nothing. The corners of a
	 * degenerate face get the strongest usable faces of their whole vertex.
	 * Read by the two corner-normal functions; the vertex-normal functions
	 * ignore it. */
	const int32_t* face_strength;
	/* Nonzero: vn_triangle_normals and vn_polygon_normals do not write the
	 * output of a vertex whose normal is the zero vector (no face
	 * contributes, or the contributions cancel), so it keeps what the
	 * caller put there, e.g. the normals the mesh came with; stats still
	 * count it in zero_normals. Zero: such a vertex gets (0, 0, 0). The
	 * corner-normal functions ignore it. */
	int keep_existing;
} vn_options;

/* What the computation met. Every field is a count. */
typedef struct vn_stats {
	size_t faces;            /* faces given */
	size_t degenerate_faces; /* faces that contributed nothing: fewer than 3
	                            corners, zero or non-finite area, or a vertex
	                            with a non-finite coordinate */
	size_t zero_normals;     /* outputs (vertices; corners for vn_corner_normals)
	                            that are the zero vector: no face contributed
	                            (isolated, or every face degenerate), or the
	                            contributions cancelled */
	size_t nonfinite_vertices; /* vertices with a NaN or infinite coordinate */
} vn_stats;

/* ------------------------------------------------------------------ vertex normals */

/* Bytes of work memory a call for vertex_count vertices with these options
 * (NULL: defaults) needs; 0 when vertex_count is too large (> UINT32_MAX). */
VN_API size_t vn_workspace_size(size_t vertex_count, const vn_options* options);

/* Per-vertex normals of a triangle mesh.
 *
 * Triangle t has corners indices[3t], indices[3t+1], indices[3t+2], counter-
 * clockwise seen from the side its normal points to; index_count must be a
 * multiple of 3. normals receives positions->count unit vectors.
 *
 * Degenerate input never yields NaN: a triangle with zero or non-finite area
 * (including a repeated index or a NaN/Inf coordinate) contributes nothing; a
 * vertex no face contributes to gets (0, 0, 0). Non-manifold edges need no
 * special care: each face simply contributes to its corners.
 *
 * indices are all checked against positions->count before any work starts;
 * on any error nothing is written. stats may be NULL; options may be NULL.
 */
VN_API vn_result vn_triangle_normals(const vn_vectors* normals, const vn_positions* positions,
                                     const uint32_t* indices, size_t index_count, vn_method method,
                                     const vn_options* options, vn_stats* stats);

/* Per-vertex normals of a polygon mesh.
 *
 * Face f has the corners indices[face_offsets[f]] .. indices[face_offsets[f+1] - 1]
 * in order; face_offsets has face_count + 1 non-decreasing entries, the last
 * the number of indices. Faces of any size; a face with fewer than 3 corners
 * is degenerate. N_f is Newell's normal. Corners in a row with one index
 * (a triangle written as the quad a b b c) are one corner of the face: its
 * E and E' go to the nearest corners with other indices, and it contributes
 * once. A corner whose E or E' has zero length (another vertex at the same
 * point) contributes nothing; otherwise as vn_triangle_normals, with which
 * it agrees on triangles.
 */
VN_API vn_result vn_polygon_normals(const vn_vectors* normals, const vn_positions* positions,
                                    const uint32_t* indices, const uint32_t* face_offsets, size_t face_count,
                                    vn_method method, const vn_options* options, vn_stats* stats);

/* ------------------------------------------------------------------ welding and split normals
 *
 * Files split vertices along UV seams and hard edges. Computing normals on
 * the split mesh shows the seams; computing them on vertices welded by
 * position and writing the result back to every copy does not. Hard edges
 * are kept with per-corner normals: a corner's normal sums only the faces
 * around its vertex that can be reached from it without crossing a sharp
 * edge. */

/* Welds vertices by position: remap[i] receives the representative of
 * vertex i, the lowest-numbered vertex of its group, so remap[remap[i]] ==
 * remap[i]. Two vertices are in one group when their positions differ by at
 * most epsilon in every coordinate (same unit as the positions), or through
 * a chain of such pairs. epsilon 0 welds exactly equal positions only (-0
 * equals +0); a vertex with a NaN coordinate is never welded; equal infinite
 * coordinates count as 0 apart. remap has positions->count entries. A
 * negative, NaN or infinite epsilon is invalid_argument.
 * Runs in O(n) expected time for epsilon 0 (a hash table, about 16 bytes of
 * work memory a vertex), O(n log n) otherwise (64 bytes a vertex), with no
 * global state; options may be NULL (its allocator is used for work memory). */
VN_API vn_result vn_weld_positions(uint32_t* remap, const vn_positions* positions, double epsilon,
                                   const vn_options* options);

/* Per-corner normals of a triangle mesh: corner i (index i of `indices`)
 * gets normalize(sum of method's contributions, as in vn_triangle_normals,
 * of the triangles around vertex indices[i] that are connected to corner
 * i's triangle through smooth edges). An edge is sharp, and separates the
 * faces on its two sides, when it is
 *   - a boundary or non-manifold edge (used by other than two triangles, or
 *     by two triangles that disagree on its direction),
 *   - flagged: sharp_edges != NULL and sharp_edges[i] != 0 for either
 *     corner i whose edge indices[i] -> next corner of its triangle it is,
 *   - creased: the angle between its two triangles' unit normals exceeds
 *     crease_angle (radians; pass a value >= pi to disable, 0 makes every
 *     non-coplanar edge sharp).
 * Edges are identified by vertex index: weld first (vn_weld_positions)
 * when a file splits vertices along seams. normals receives index_count
 * vectors. A corner of a degenerate triangle gets its vertex's smooth
 * normal over all its non-degenerate triangles, or zero; degenerate
 * triangles take part in no edge (so a zero-area sliver next to a face is a
 * boundary of it). options->face_strength (one per triangle) gives
 * Blender's Face Influence (vn_options). A negative or NaN crease_angle, or
 * index_count above UINT32_MAX, is invalid_argument. */
VN_API vn_result vn_corner_normals(const vn_vectors* normals, const vn_positions* positions, const uint32_t* indices,
                                   size_t index_count, vn_method method, double crease_angle,
                                   const uint8_t* sharp_edges, const vn_options* options, vn_stats* stats);

/* Per-corner normals of a polygon mesh (faces as vn_polygon_normals:
 * indices, face_offsets, face_count; Newell face normals; the method's
 * corner weights as there): corner i (index i of `indices`) gets
 * normalize(sum of the contributions of the faces around vertex indices[i]
 * that are connected to corner i's face through smooth edges). An edge is
 * sharp as for vn_corner_normals: a boundary or non-manifold edge, flagged
 * (sharp_edges != NULL and sharp_edges[i] != 0 for a corner i whose edge
 * indices[i] -> next corner of its face it is), or creased (the angle
 * between its two faces' unit normals exceeds crease_angle, radians; >= pi
 * disables it). A flat-shaded face is one whose every edge is flagged: its
 * corners get its own normal. normals receives face_offsets[face_count]
 * vectors; a corner no face contributes to gets (0, 0, 0).
 * A degenerate face (fewer than 3 corners, zero or non-finite Newell normal)
 * takes part in no edge, and its corners get their vertex's normal over all
 * its other faces (vn_polygon_normals' normal), or zero. An edge i -> i of
 * a repeated index has zero length and joins its two corners (one corner of
 * the face, which contributes once, as in vn_polygon_normals). Every index
 * is checked before anything is written; a negative or NaN crease_angle,
 * NULL face_offsets or decreasing offsets are invalid_argument.
 * options->face_strength (one per face) gives Blender's Face Influence
 * (vn_options).
 * Computed on options->threads threads (fewer below 4096 vertices a thread),
 * bit-identical whatever their number. With nothing sharp each corner gets
 * its vertex's vn_polygon_normals normal bit for bit; on triangles it
 * agrees with vn_corner_normals to rounding (that one uses the triangle
 * kernels' arithmetic, and runs on this code: same threads, same memory).
 * Work memory comes from options->workspace when workspace_size is at least
 * 36 bytes a corner + 24 a face + 4 a vertex + 64 a thread + 64, else from
 * the allocator; a vertex with more than 24 corners also takes about 64
 * bytes per corner of the largest such star, per thread, from the allocator. */
VN_API vn_result vn_polygon_corner_normals(const vn_vectors* normals, const vn_positions* positions,
                                           const uint32_t* indices, const uint32_t* face_offsets, size_t face_count,
                                           vn_method method, double crease_angle, const uint8_t* sharp_edges,
                                           const vn_options* options, vn_stats* stats);

/* ------------------------------------------------------------------ per-frame plans
 *
 * Animation, simulation and editing recompute normals every frame on a mesh
 * whose faces do not change. A plan does the topology work once: it checks
 * the indices, copies them, lists the corners around every vertex and holds
 * all the work memory; each frame then only reads positions and writes
 * normals. A plan serves one call at a time (distinct plans may run on
 * distinct threads); it keeps no pointer to the caller's arrays except
 * options->face_strength, which vn_plan_corner_normals reads. */
typedef struct vn_plan vn_plan;

/* Builds a plan for faces as vn_triangle_normals takes them (face_offsets
 * NULL: face_count triangles, 3 indices each) or as vn_polygon_normals does
 * (face_offsets: face_count + 1 non-decreasing entries), over vertex_count
 * vertices. options (NULL: defaults) give the threads, simd, allocator,
 * keep_existing and face_strength of every later call; its workspace is not
 * used (the plan holds its own). Every index is checked here, once:
 * index_out_of_range for one >= vertex_count; invalid_argument for NULL
 * out, NULL indices with corners, decreasing offsets, more than UINT32_MAX
 * indices or vertices, or a half-set allocator; out_of_memory when the
 * allocator fails. *out is written on success only. Memory, in one block
 * from the allocator (and 24 bytes a vertex of scratch while it builds):
 * the indices (4 bytes a corner); for triangles the positions' offsets
 * for the fast path (4 bytes a corner), a corner table of 36 bytes a vertex
 * (+ 4 a corner beyond 8 at a vertex, + 24 a corner of a vertex with more
 * than 8 corners, or faces more than 16384 faces apart or in two threads'
 * ranges); and a work area of the largest of vn_workspace_size(),
 * vn_polygon_corner_normals' workspace bound (about 108 bytes a triangle)
 * and the fast path's 48 bytes a face of up to 16384 faces per thread.
 * Triangles in an order without locality (more than a quarter of the
 * corners would be far: a shuffled file) are taken by the fast path in a
 * breadth-first order over shared vertices, which costs 4 more bytes a
 * corner in the block and, while it builds, 8 a corner + 5 a face + 4 a
 * vertex of scratch; each vertex still sums its corners in input order,
 * so the results are the same bits. Takes about as long as 5 or 6
 * vn_triangle_normals calls (7 to 10 on a shuffled mesh, which it sorts;
 * docs/PERFORMANCE.md). */
VN_API vn_result vn_plan_create(const uint32_t* indices, const uint32_t* face_offsets, size_t face_count,
                                size_t vertex_count, const vn_options* options, vn_plan** out);

/* Frees the plan; NULL is ignored. */
VN_API void vn_plan_destroy(vn_plan* plan);

/* Per-vertex normals of the plan's mesh at `positions` (count must equal the
 * plan's vertex_count, else invalid_argument), as vn_triangle_normals or
 * vn_polygon_normals compute them: normals receives vertex_count vectors;
 * degenerate faces, NaN positions, isolated vertices, keep_existing and
 * stats (may be NULL) behave as there.
 *
 * The fast path: MWE, MWA, MWSELR, MWAAT, MWELR and MWRELR on triangles
 * with float32 positions, in float arithmetic: each face's corner
 * contributions go to a buffer that stays in cache, then each vertex sums
 * its corners in face order; indices are not checked again. Both passes
 * run on the plan's threads, the results are bit-identical whatever their
 * number (and with or without AVX2: the vector kernels need AVX2 and FMA,
 * the scalar ones round fused multiply-adds as those do, with fmaf), and
 * the call allocates nothing. They are within 1e-4 degrees of
 * vn_triangle_normals on the same positions (cross products correct to 2
 * ulps even on thin triangles; MWA's corner angles from a polynomial
 * atan2 within 3e-7 rad). A triangle whose float arithmetic leaves the
 * float range (zero or non-finite area, or weights beyond about 1e38,
 * e.g. MWSELR's on edges below about 1e-9 units) is computed in double,
 * its contributions rounded to float and clamped to its range. The
 * offsets of positions are made for packed float32 (12-byte stride) at
 * create; a call with another stride than the last makes them again
 * (about 1 ns a corner, once).
 * float64 positions run vn_triangle_normals' kernels (double arithmetic,
 * its results bit for bit, its threads; they check indices as they scan
 * them) with the plan's memory as workspace, allocating nothing; but MWA
 * takes its corner angles from a polynomial atan2 (within 1e-13 rad, one
 * division instead of Cephes' two), so its normals are within 1e-9 degrees
 * of vn_triangle_normals', the same bits whatever the threads and with or
 * without AVX2.
 * Everything else (polygons, MEWCSA, SMEWCSA, QUADRIC, JET, ADAPTIVE)
 * likewise runs vn_polygon_normals or vn_triangle_normals on the plan's
 * indices and memory: the same results, speed and threads as those calls;
 * MEWCSA and the polygon walk allocate nothing, the fits allocate as vn.h
 * says for them. */
VN_API vn_result vn_plan_normals(vn_plan* plan, const vn_positions* positions, vn_method method,
                                 const vn_vectors* normals, vn_stats* stats);

/* Per-corner normals of the plan's mesh: vn_corner_normals (triangles) or
 * vn_polygon_corner_normals (polygons) on the plan's indices, with the
 * plan's memory as workspace and its options (threads, face_strength), so
 * the results equal theirs; nothing is allocated but the scratch those
 * functions take for a vertex of more than 24 corners and the fits' memory.
 * normals receives one vector per corner; positions->count must equal the
 * plan's vertex_count. */
VN_API vn_result vn_plan_corner_normals(vn_plan* plan, const vn_positions* positions, vn_method method,
                                        double crease_angle, const uint8_t* sharp_edges, const vn_vectors* normals,
                                        vn_stats* stats);

#ifdef __cplusplus
}
#endif

#endif /* VN_H */
