/*
 * Reference vertex normals: see reference.h. Plain and slow on purpose:
 * long double throughout, one vertex at a time, each of its corners visited
 * through a vertex -> corners table.
 */
#include "reference.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct vec {
	long double x, y, z;
} vec;

static vec vec_make(long double x, long double y, long double z)
{
	vec v = {x, y, z};
	return v;
}

static vec vec_sub(vec a, vec b)
{
	return vec_make(a.x - b.x, a.y - b.y, a.z - b.z);
}

static vec vec_add(vec a, vec b)
{
	return vec_make(a.x + b.x, a.y + b.y, a.z + b.z);
}

static vec vec_scale(vec a, long double s)
{
	return vec_make(a.x * s, a.y * s, a.z * s);
}

static long double vec_dot(vec a, vec b)
{
	return a.x * b.x + a.y * b.y + a.z * b.z;
}

static vec vec_cross(vec a, vec b)
{
	return vec_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

static long double vec_length(vec a)
{
	return sqrtl(vec_dot(a, a));
}

static vec position(const double* positions, uint32_t i)
{
	return vec_make(positions[3 * (size_t)i], positions[3 * (size_t)i + 1], positions[3 * (size_t)i + 2]);
}

static int vec_finite(vec a)
{
	return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}

static void* checked_calloc(size_t count, size_t size)
{
	/* A test helper: running out of memory here is not worth recovering from. */
	void* p = calloc(count ? count : 1, size);
	if (!p) {
		fprintf(stderr, "reference: out of memory\n");
		abort();
	}
	return p;
}

/* Newell's normal of face f, as a unit vector; returns 0 when the face is
 * degenerate (fewer than 3 corners, a non-finite coordinate, a zero or
 * non-finite normal). Newell's vector sum p_i x p_(i+1) is translation
 * invariant, so it is summed here as the fan (p_i - p_0) x (p_(i+1) - p_0):
 * the same vector with less cancellation, and exactly (p1-p0) x (p2-p0) on a
 * triangle. */
static int face_normal(const double* positions, const uint32_t* corners, size_t count, vec* out)
{
	if (count < 3)
		return 0;
	for (size_t i = 0; i < count; i++) {
		if (!vec_finite(position(positions, corners[i])))
			return 0;
	}
	vec p0 = position(positions, corners[0]);
	vec n = vec_make(0, 0, 0);
	for (size_t i = 1; i + 1 < count; i++) {
		vec a = vec_sub(position(positions, corners[i]), p0);
		vec b = vec_sub(position(positions, corners[i + 1]), p0);
		n = vec_add(n, vec_cross(a, b));
	}
	long double len = vec_length(n);
	if (!(len > 0) || !isfinite(len))
		return 0;
	*out = vec_scale(n, 1 / len);
	return 1;
}

/* What one corner adds to its vertex's sum, straight from the paper's
 * equations. e0 = E (to the previous corner), e1 = E' (to the next one). */
static vec corner_contribution(int method, vec n, vec e0, vec e1)
{
	long double l0 = vec_length(e0);
	long double l1 = vec_length(e1);
	long double cross = vec_length(vec_cross(e0, e1));
	long double alpha = atan2l(cross, vec_dot(e0, e1));
	switch (method) {
	case ref_mwe:
		return n;
	case ref_mwa:
		return vec_scale(n, alpha);
	case ref_mwselr:
		return vec_scale(n, sinl(alpha) / (l0 * l1));
	case ref_mwaat:
		return vec_scale(n, cross);
	case ref_mwelr:
		return vec_scale(n, 1 / (l0 * l1));
	case ref_mwrelr:
		return vec_scale(n, 1 / sqrtl(l0 * l1));
	case ref_mewcsa:
		/* p_next - p_prev = E' - E: twice the gradient of the face's area
		 * with respect to the vertex. */
		return vec_cross(vec_sub(e1, e0), n);
	default:
		return vec_make(0, 0, 0);
	}
}

/* The mesh's faces and a vertex -> corners table (counting sort). */
typedef struct tables {
	const double* positions;
	size_t vertex_count;
	const uint32_t* indices;
	const uint32_t* face_offsets;
	vec* normals;        /* per face: Newell's unit normal */
	char* valid;         /* per face: not degenerate */
	size_t* first;       /* vertex_count + 1: where each vertex's corners start */
	size_t* corners;     /* corners by vertex */
	size_t* corner_face; /* per corner */
} tables;

static tables tables_make(const double* positions, size_t vertex_count, const uint32_t* indices,
                          const uint32_t* face_offsets, size_t face_count)
{
	tables t = {positions, vertex_count, indices, face_offsets, NULL, NULL, NULL, NULL, NULL};
	size_t corner_count = face_offsets[face_count];
	t.normals = checked_calloc(face_count, sizeof *t.normals);
	t.valid = checked_calloc(face_count, 1);
	for (size_t f = 0; f < face_count; f++) {
		size_t k = face_offsets[f + 1] - face_offsets[f];
		t.valid[f] = (char)face_normal(positions, indices + face_offsets[f], k, &t.normals[f]);
	}
	t.first = checked_calloc(vertex_count + 1, sizeof *t.first);
	t.corners = checked_calloc(corner_count, sizeof *t.corners);
	t.corner_face = checked_calloc(corner_count, sizeof *t.corner_face);
	size_t* fill = checked_calloc(vertex_count, sizeof *fill);
	for (size_t f = 0; f < face_count; f++) {
		for (size_t c = face_offsets[f]; c < face_offsets[f + 1]; c++) {
			t.corner_face[c] = f;
			t.first[indices[c] + 1]++;
		}
	}
	for (size_t v = 0; v < vertex_count; v++)
		t.first[v + 1] += t.first[v];
	for (size_t c = 0; c < corner_count; c++) {
		uint32_t v = indices[c];
		t.corners[t.first[v] + fill[v]++] = c;
	}
	free(fill);
	return t;
}

static void tables_free(tables* t)
{
	free(t->corner_face);
	free(t->corners);
	free(t->first);
	free(t->valid);
	free(t->normals);
}

/* One of the seven: each vertex sums over its own corners. */
static void weighted_normals(int method, const tables* t, double* out_normals, double* out_condition)
{
	for (size_t v = 0; v < t->vertex_count; v++) {
		vec sum = vec_make(0, 0, 0);
		long double magnitude = 0; /* sum of |contribution| */
		int contributed = 0;
		vec p = position(t->positions, (uint32_t)v);
		for (size_t j = t->first[v]; j < t->first[v + 1]; j++) {
			size_t c = t->corners[j];
			size_t f = t->corner_face[c];
			if (!t->valid[f])
				continue;
			size_t begin = t->face_offsets[f];
			size_t k = t->face_offsets[f + 1] - begin;
			size_t i = c - begin;
			/* Corners in a row with index v are one corner: the last of
			 * them counts, with the nearest other indices around the row. */
			if (t->indices[begin + (i + 1) % k] == v)
				continue;
			size_t before = 1;
			while (before < k && t->indices[begin + (i + k - before) % k] == v)
				before++;
			uint32_t prev = t->indices[begin + (i + k - before) % k];
			uint32_t next = t->indices[begin + (i + 1) % k];
			vec e0 = vec_sub(position(t->positions, prev), p);
			vec e1 = vec_sub(position(t->positions, next), p);
			/* A corner with a zero-length edge (another vertex at the same
			 * point) has no angle: skip it. */
			if (vec_length(e0) == 0 || vec_length(e1) == 0)
				continue;
			vec w = corner_contribution(method, t->normals[f], e0, e1);
			sum = vec_add(sum, w);
			magnitude += vec_length(w);
			contributed = 1;
		}
		long double len = vec_length(sum);
		double* out = out_normals + 3 * v;
		if (len > 0) {
			out[0] = (double)(sum.x / len);
			out[1] = (double)(sum.y / len);
			out[2] = (double)(sum.z / len);
		} else {
			out[0] = out[1] = out[2] = 0;
		}
		out_condition[v] = !contributed ? -1.0 : magnitude > 0 ? (double)(len / magnitude) : 0.0;
	}
}

/* ------------------------------------------------------------------ beyond the paper (vn.h) */

/* vn.h's constants. */
#define RING_ALL_MAX 8        /* a polygon gives all its corners to a ring up to this size */
#define RING_HUB_MAX 256      /* a vertex of a larger 1-ring is not expanded into wider rings */
#define PIVOT_MIN 1e-8L       /* smallest squared diagonal of R (the Cholesky pivot) */
#define RCOND_MIN 1e-10L      /* smallest 1 / (|R|_F |R^-1|_F)^2 */
#define SEED_COS_MIN 0.5L     /* 60 degrees from the seed */
/* ADAPTIVE: the jet alone at or below this weighted RMS residual over h;
 * the rough fallback (S, or MWAAT on a lattice) above this residual of
 * the jet; a wide fit where its GCV score is below the margin times the
 * jet's; the wide fits on this ring, with a Gaussian this wide relative to
 * the members' RMS distance. */
#define ADAPTIVE_JET_EXACT 1e-4L
#define ADAPTIVE_ROUGH_MAX 0.05L
/* ADAPTIVE: MWSELR's normal for the jet's within this many times the
 * jet's residual (radians). */
#define ADAPTIVE_MWSELR_AGREE 0.5L
/* ADAPTIVE: MWSELR's normal outright where the 2-ring lies on a sphere
 * through the vertex tangent to MWSELR's plane, to this many units of
 * rounding of the coordinates' precision (at most ADAPTIVE_JET_EXACT h),
 * with at least ADAPTIVE_SPHERE_POINTS points. */
#define ADAPTIVE_SPHERE_ROUNDING 1024.0L
#define ADAPTIVE_SPHERE_POINTS 5
/* ADAPTIVE: a lattice ring has at most this many members, its second
 * differences parallel to this fraction of h. */
#define LATTICE_MEMBERS_MAX 16
#define LATTICE_SLACK 1e-2L
#define ADAPTIVE_JET_MARGIN 2.0L
#define ADAPTIVE_RINGS 5
#define ADAPTIVE_WIDTH 0.6L
/* ADAPTIVE: the cubic's outcome where the mean log T over the vertex and its
 * 1-ring is above log ADAPTIVE_T (vn.h); log T is kept within +-T_LOG_MAX. */
#define ADAPTIVE_T 2.0L
#define T_LOG_MAX 50.0L
#define SMEWCSA_FLAT 0x1p-12L /* SMEWCSA: MEWCSA's condition at or below it is flat */
/* How close to a threshold a decision is borderline: far above the two
 * implementations' measured differences, far below any real margin. */
#define BORDER 1e-9L

static int is_zero(const double* n)
{
	return n[0] == 0 && n[1] == 0 && n[2] == 0;
}

static vec load(const double* n)
{
	return vec_make(n[0], n[1], n[2]);
}

static void o_set(double* o, vec n)
{
	o[0] = (double)n.x;
	o[1] = (double)n.y;
	o[2] = (double)n.z;
}

static long double dot_d(const double* a, const double* b)
{
	return (long double)a[0] * b[0] + (long double)a[1] * b[1] + (long double)a[2] * b[2];
}

/* SMEWCSA from the MEWCSA sum K, H = K / |K|, and the MWSELR normal S: H,
 * its sign flipped when H . S < 0, unless |K| <= SMEWCSA_FLAT times the sum
 * of K's contributions' lengths (MEWCSA's condition) or H is more than 30
 * degrees from S; then S (zero where S is). */
static void smewcsa_normals(const tables* t, double* out, double* cond, unsigned char* path)
{
	size_t n = t->vertex_count;
	double* h = checked_calloc(3 * n, sizeof *h);
	double* hc = checked_calloc(n, sizeof *hc);
	weighted_normals(ref_mewcsa, t, h, hc);
	weighted_normals(ref_mwselr, t, out, cond); /* S, kept where chosen */
	const long double cos30 = sqrtl(3) / 2;
	for (size_t v = 0; v < n; v++) {
		const double* hv = h + 3 * v;
		double* o = out + 3 * v;
		long double d = dot_d(hv, o);
		if (is_zero(o)) {
			path[v] = ref_path_zero;
			continue;
		}
		if (hc[v] > SMEWCSA_FLAT && fabsl(d) >= cos30) {
			long double sign = d < 0 ? -1 : 1;
			for (int i = 0; i < 3; i++)
				o[i] = (double)(sign * hv[i]);
			cond[v] = hc[v];
			path[v] = ref_path_cotangent;
		} else {
			path[v] = ref_path_seed;
		}
		if (fabsl(hc[v] / SMEWCSA_FLAT - 1) < BORDER || (hc[v] > SMEWCSA_FLAT && fabsl(fabsl(d) - cos30) < BORDER))
			path[v] |= ref_path_borderline;
	}
	free(hc);
	free(h);
}

/* Whether face f joins its corners to the fits' rings: 3 corners or more,
 * every coordinate finite (its area may be zero: vn.h). */
static int joins_rings(const tables* t, size_t f)
{
	size_t begin = t->face_offsets[f], k = t->face_offsets[f + 1] - begin;
	if (k < 3)
		return 0;
	for (size_t i = begin; i < begin + k; i++)
		for (int d = 0; d < 3; d++)
			if (!isfinite(t->positions[3 * (size_t)t->indices[i] + d]))
				return 0;
	return 1;
}

/* Appends to ring (n members so far) the vertices sharing a face with u
 * that joins rings (joins_rings) and are not marked yet, and marks them: a
 * triangle's other corners, a polygon's other corners up to RING_ALL_MAX
 * corners, else its corners next to u. */
static size_t add_ring(const tables* t, uint32_t u, char* mark, uint32_t* ring, size_t n)
{
	for (size_t j = t->first[u]; j < t->first[u + 1]; j++) {
		size_t c = t->corners[j], f = t->corner_face[c];
		if (!joins_rings(t, f))
			continue;
		size_t begin = t->face_offsets[f], k = t->face_offsets[f + 1] - begin, i = c - begin;
		for (size_t o = 0; o < k; o++) {
			if (k > RING_ALL_MAX && o != (i + 1) % k && o != (i + k - 1) % k)
				continue;
			uint32_t x = t->indices[begin + o];
			if (!mark[x]) {
				mark[x] = 1;
				ring[n++] = x;
			}
		}
	}
	return n;
}

typedef struct fit_result {
	vec normal;
	long double residual;  /* weighted RMS of z - f, over h */
	long double rcond;     /* of the unit-diagonal normal matrix R^T R */
	int borderline;        /* a pivot within rounding of PIVOT_MIN */
	long double slope[2];  /* f_x, f_y at the origin */
	long double vs;        /* (M^-1)_11 + (M^-1)_22, M the weighted normal matrix */
	long double swe;       /* sum of w (z - f)^2 */
	size_t rows;           /* the points fitted, the origin included */
} fit_result;

/* The monomials 1, x, y, x^2, xy, y^2 (degree 2) and x^3, x^2 y, x y^2, y^3. */
static void monomials(long double x, long double y, int k, long double* m)
{
	long double all[10] = {1, x, y, x * x, x * y, y * y, x * x * x, x * x * y, x * y * y, y * y * y};
	for (int j = 0; j < k; j++)
		m[j] = all[j];
}

/* 1 / (|R|_F |R^-1|_F)^2 for the leading n x n block of the upper
 * triangular r: the reciprocal condition number of R^T R, estimated within a
 * factor n of it, from below. */
static long double upper_rcond(long double r[10][10], int n)
{
	long double inv[10][10] = {{0}}, nr = 0, ni = 0;
	for (int col = 0; col < n; col++) {
		for (int j = col; j >= 0; j--) {
			long double s = j == col ? 1 : 0;
			for (int l = j + 1; l <= col; l++)
				s -= r[j][l] * inv[l][col];
			inv[j][col] = s / r[j][j];
		}
	}
	for (int j = 0; j < n; j++) {
		for (int l = j; l < n; l++) {
			nr += r[j][l] * r[j][l];
			ni += inv[j][l] * inv[j][l];
		}
	}
	return 1 / (nr * ni);
}

/* (M^-1)_11 + (M^-1)_22 for M = D R^T R D, D = diag(scale): row j of R^-1
 * by back substitution, over scale_j^2. */
static long double slope_variance(long double r[10][10], const long double* scale, int k)
{
	long double sum = 0;
	for (int j = 1; j <= 2; j++) {
		long double row[10] = {0}, s = 0; /* e_j^T R^-1 */
		for (int l = j; l < k; l++) {
			long double x = l == j ? 1 : 0;
			for (int i = j; i < l; i++)
				x -= row[i] * r[i][l];
			row[l] = x / r[l][l];
			s += row[l] * row[l];
		}
		sum += s / (scale[j] * scale[j]);
	}
	return sum;
}

/* How far the library's double-precision result may be from the exact one:
 * its normal equations square the design matrix's condition, and solving
 * them loses a factor 1 / rcond over the rounding error (k eps, k <= 10
 * unknowns): a bound on the normal's angle and on the pivots' errors. */
static long double fit_slack(long double rcond)
{
	return 1e-13L / rcond;
}

/* Weighted least squares of z = f(x, y) over the origin (the vertex) and the
 * m points q (relative to the vertex) in a frame with height axis `axis`,
 * coordinates over h, weights 1 / (1 + |p|^2 / h^2), or with gauss > 0
 * exp(-|p|^2 / (2 gauss h^2)) (the origin's weight is 1 either way). The columns of the
 * weighted design matrix are scaled to unit length (so R^T R is the normal
 * matrix scaled to unit diagonal) and factored by Householder QR. Returns 0
 * when the fit is not trusted: fewer points than unknowns, a zero column, a
 * squared diagonal of R below PIVOT_MIN, or 1 / (|R|_F |R^-1|_F)^2 (R^T R
 * having unit diagonal: 1 / (k trace((R^T R)^-1)), the library's estimate)
 * below RCOND_MIN. A pivot is borderline when another
 * correct computation in double, in a frame up to `slack` radians away, may
 * put it on the other side of PIVOT_MIN. */
static int fit_in_frame(const vec* q, size_t m, vec axis, int degree, long double h, long double gauss,
                        long double slack, fit_result* out)
{
	enum { K_MAX = 10 };
	const int k = degree == 3 ? 10 : 6;
	const size_t rows = m + 1;
	out->borderline = 0;
	if (rows < (size_t)k || !(h > 0) || !isfinite(h))
		return 0;
	/* vn.h's tangent frame (Duff et al. 2017's basis): with s the sign of
	 * axis.z (-0 counts as negative), A = -1 / (s + z), B = x y A:
	 * t1 = (1 + s x^2 A, s B, -s x), t2 = (B, s + y^2 A, -y). The fitted
	 * normal does not depend on it (the polynomial space is invariant under
	 * rotations of (x, y)), but the pivots do. */
	const long double sgn = signbit(axis.z) ? -1.0L : 1.0L;
	const long double fa = -1 / (sgn + axis.z), fb = axis.x * axis.y * fa;
	vec t1 = vec_make(1 + sgn * axis.x * axis.x * fa, sgn * fb, -sgn * axis.x);
	vec t2 = vec_make(fb, sgn + axis.y * axis.y * fa, -axis.y);

	long double* a = checked_calloc(rows * (K_MAX + 5), sizeof *a); /* row-major, rows x k */
	long double *b = a + rows * K_MAX, *z = b + rows, *w = z + rows, *x = w + rows, *y = x + rows;
	w[0] = 1; /* the vertex itself: the origin */
	for (size_t i = 0; i < m; i++) {
		vec p = q[i];
		x[i + 1] = vec_dot(p, t1) / h;
		y[i + 1] = vec_dot(p, t2) / h;
		z[i + 1] = vec_dot(p, axis) / h;
		w[i + 1] = gauss > 0 ? expl(-vec_dot(p, p) / (2 * gauss * h * h)) : 1 / (1 + vec_dot(p, p) / (h * h));
	}
	for (size_t i = 0; i < rows; i++) {
		long double mono[K_MAX];
		monomials(x[i], y[i], k, mono);
		for (int j = 0; j < k; j++)
			a[i * K_MAX + j] = sqrtl(w[i]) * mono[j];
		b[i] = sqrtl(w[i]) * z[i];
	}
	long double scale[K_MAX], r[K_MAX][K_MAX] = {{0}}, c[K_MAX];
	int ok = 1, borderline = 0;
	for (int j = 0; j < k && ok; j++) {
		long double s = 0;
		for (size_t i = 0; i < rows; i++)
			s += a[i * K_MAX + j] * a[i * K_MAX + j];
		scale[j] = sqrtl(s);
		if (!(scale[j] > 0))
			ok = 0;
		for (size_t i = 0; i < rows && ok; i++)
			a[i * K_MAX + j] /= scale[j];
	}
	/* Householder: column j's reflection zeroes it below the diagonal. */
	for (int j = 0; j < k && ok; j++) {
		long double norm = 0;
		for (size_t i = (size_t)j; i < rows; i++)
			norm += a[i * K_MAX + j] * a[i * K_MAX + j];
		norm = sqrtl(norm);
		/* A pivot is exact to about k eps / rcond of the block before it. */
		if (fabsl(norm * norm - PIVOT_MIN) < 1e-12L + (j ? fit_slack(upper_rcond(r, j)) : 0) + slack)
			borderline = 1;
		if (!(norm * norm >= PIVOT_MIN)) {
			ok = 0;
			break;
		}
		long double alpha = a[(size_t)j * K_MAX + j] > 0 ? -norm : norm;
		long double v0 = a[(size_t)j * K_MAX + j] - alpha, vv = v0 * v0;
		for (size_t i = (size_t)j + 1; i < rows; i++)
			vv += a[i * K_MAX + j] * a[i * K_MAX + j];
		/* v = (v0, a[j+1..][j]); apply I - 2 v v^T / v^T v to the columns right of j and to b. */
		for (int l = j + 1; l <= k; l++) {
			long double s = v0 * (l < k ? a[(size_t)j * K_MAX + l] : b[j]);
			for (size_t i = (size_t)j + 1; i < rows; i++)
				s += a[i * K_MAX + j] * (l < k ? a[i * K_MAX + l] : b[i]);
			s *= 2 / vv;
			if (l < k) {
				a[(size_t)j * K_MAX + l] -= s * v0;
				for (size_t i = (size_t)j + 1; i < rows; i++)
					a[i * K_MAX + l] -= s * a[i * K_MAX + j];
			} else {
				b[j] -= s * v0;
				for (size_t i = (size_t)j + 1; i < rows; i++)
					b[i] -= s * a[i * K_MAX + j];
			}
		}
		r[j][j] = alpha;
		for (int l = j + 1; l < k; l++)
			r[j][l] = a[(size_t)j * K_MAX + l];
	}
	if (ok) {
		/* R c = (Q^T b)[0..k), back to the unscaled coefficients. */
		for (int j = k - 1; j >= 0; j--) {
			long double s = b[j];
			for (int l = j + 1; l < k; l++)
				s -= r[j][l] * c[l];
			c[j] = s / r[j][j];
		}
		for (int j = 0; j < k; j++)
			c[j] /= scale[j];
		long double sw = 0, swe = 0;
		for (size_t i = 0; i < rows; i++) {
			long double mono[K_MAX], f = 0;
			monomials(x[i], y[i], k, mono);
			for (int j = 0; j < k; j++)
				f += c[j] * mono[j];
			sw += w[i];
			swe += w[i] * (z[i] - f) * (z[i] - f);
		}
		/* The graph's normal at the origin: (-f_x, -f_y, 1) in the frame. */
		vec n = vec_sub(axis, vec_add(vec_scale(t1, c[1]), vec_scale(t2, c[2])));
		long double len = vec_length(n);
		ok = len > 0 && isfinite(len);
		if (ok) {
			out->normal = vec_scale(n, 1 / len);
			out->residual = sqrtl(swe / sw);
			out->slope[0] = c[1], out->slope[1] = c[2];
			out->vs = slope_variance(r, scale, k);
			out->swe = swe, out->rows = rows;
			out->rcond = upper_rcond(r, k);
			/* The library's estimate, from its normal equations, is exact to
			 * about eps / rcond relative; its frame may be `slack` away. */
			borderline |= fabsl(out->rcond / RCOND_MIN - 1) < 1e-3L + 1e3L * slack;
			ok = out->rcond >= RCOND_MIN;
		}
	}
	out->borderline = borderline;
	free(a);
	return ok;
}

/* The fit in the seed's frame, then once more in the frame of its normal
 * (the first fit kept when the second is not trusted); 0 when the first is
 * not trusted or the result is more than 60 degrees from the seed.
 * *fitted (when not NULL): whether the first was trusted. */
static int fit_twice(const vec* q, size_t m, vec seed, int degree, long double h, long double gauss, fit_result* out,
                     int* borderline, int* fitted)
{
	fit_result first, second = {.rows = 0};
	int ok = fit_in_frame(q, m, seed, degree, h, gauss, 0, &first);
	*borderline |= first.borderline;
	if (fitted)
		*fitted = ok;
	if (!ok)
		return 0;
	/* The second frame is the first fit's normal: as uncertain as it. */
	if (fit_in_frame(q, m, first.normal, degree, h, gauss, fit_slack(first.rcond), &second)) {
		second.rcond = fminl(second.rcond, first.rcond);
		first = second;
	}
	*borderline |= second.borderline;
	long double d = vec_dot(first.normal, seed);
	*borderline |= fabsl(d - SEED_COS_MIN) < BORDER + fit_slack(first.rcond);
	if (!(d >= SEED_COS_MIN))
		return 0;
	*out = first;
	return 1;
}

/* Whether a and b are within rounding of each other (relative), the
 * library's fits being up to `slack` off. */
static int near(long double a, long double b, long double slack)
{
	return isfinite(a) && isfinite(b) && fabsl(a - b) <= (BORDER + slack) * fmaxl(fabsl(a), fabsl(b));
}

/* (sum w)^2 / sum w^2 over the origin (weight 1) and the m points q, with
 * fit_in_frame's weights. */
static long double effective_points(const vec* q, size_t m, long double h, long double gauss)
{
	long double sw = 1, sww = 1;
	for (size_t i = 0; i < m; i++) {
		long double d = vec_dot(q[i], q[i]) / (h * h);
		long double w = gauss > 0 ? expl(-d / (2 * gauss)) : 1 / (1 + d);
		sw += w, sww += w * w;
	}
	return sw * sw / sww;
}

/* Generalized cross-validation (Craven & Wahba 1979): the fit's residual
 * inflated for its k unknowns among n effective points. */
static long double gcv(long double residual, long double n, int k)
{
	long double d = 1 - k / n;
	return d > 0 ? residual * residual / (d * d) : INFINITY;
}

/* One fit in the frame of `axis` (itself up to `slack` radians uncertain),
 * trusted like fit_twice's: 0 when not, or more than 60 degrees from S. */
static int fit_once(const vec* q, size_t m, vec axis, vec s, int degree, long double h, long double gauss,
                    long double slack, fit_result* out, int* borderline)
{
	int ok = fit_in_frame(q, m, axis, degree, h, gauss, slack, out);
	*borderline |= out->borderline;
	if (!ok)
		return 0;
	long double d = vec_dot(out->normal, s);
	*borderline |= fabsl(d - SEED_COS_MIN) < BORDER + slack + fit_slack(out->rcond);
	return d >= SEED_COS_MIN;
}

/* ADAPTIVE's outcomes at a vertex (adaptive_vertex), before the choice
 * between them over the 1-ring. */
typedef struct adaptive_result {
	vec normal[2];      /* the quadric's outcome, the cubic's */
	int path[2];        /* their ref_path_* */
	long double rcond[2];
	long double log_t;  /* NAN unless both wide fits were taken */
	int borderline;     /* some decision within rounding of its threshold */
	int t_borderline;   /* whether log_t's presence or value is within rounding */
} adaptive_result;

/* The last step of an outcome: the fit f on path `path`. */
static void outcome(const fit_result* f, int path, adaptive_result* a, int k)
{
	a->path[k] = path;
	a->normal[k] = f->normal;
	a->rcond[k] = f->rcond;
}

typedef struct rounding {
	long double unit, quantum; /* relative to a coordinate, absolute */
} rounding;

/* Whether x, written by printf with k places ("%.*f", k <= 12, with N =
 * |x| 10^k below 2^51, the library's bound) or, without `places`, with
 * k + 1 significant digits ("%.*e", k < 15), reads back as x, for the
 * fewest such k; raises *count to that k (places) or to the text's
 * significant digits. The library finds the same by arithmetic. */
static int decimal_text(double x, int places, int* count)
{
	char text[400];
	x = fabs(x);
	for (int k = 0; places ? k <= 12 && x * powl(10, k) < 0x1p51L : k < 15; k++) {
		snprintf(text, sizeof text, places ? "%.*f" : "%.*e", k, x);
		if (strtod(text, NULL) != x)
			continue;
		int n = 0, last = 0;
		for (char* c = text; *c && *c != 'e'; c++)
			if (*c >= '0' && *c <= '9')
				n += n || *c != '0', last = *c != '0' ? n : last;
		last = places ? k : last;
		*count = last > *count ? last : *count;
		return 1;
	}
	return 0;
}

/* The coordinates' rounding: float32's unit where every finite one is a
 * float32 value; else float64's unit, raised to half a unit in the last of
 * the fewest significant digits that write every coordinate (at most 15,
 * decimal_text), and quantum half a unit in the last of the fewest places
 * that do (at most 12; else 0). */
static rounding coordinate_rounding(const double* x, size_t n)
{
	int floats = 1, fixed = 1, digits_ok = 1, places = 0, digits = 0;
	for (size_t i = 0; i < n; i++)
		if (isfinite(x[i])) {
			floats &= fabs(x[i]) <= FLT_MAX && (double)(float)x[i] == x[i];
			fixed = fixed && decimal_text(x[i], 1, &places);
			digits_ok = digits_ok && decimal_text(x[i], 0, &digits);
		}
	rounding r = {FLT_EPSILON / 2, 0};
	if (!floats) {
		r.unit = DBL_EPSILON / 2;
		if (digits_ok && digits > 0)
			r.unit = fmaxl(r.unit, 0.5L * powl(10, 1 - digits));
		if (fixed)
			r.quantum = 0.5L * powl(10, -places);
	}
	return r;
}

/* Whether the m points q (relative to the vertex at p) lie on a sphere
 * through the vertex tangent to the plane of unit normal n: z = k |q|^2 / 2,
 * z = q . n, k by least squares, every point within the tolerance:
 * ADAPTIVE_SPHERE_ROUNDING times the rounding r of the largest coordinate
 * among them (bounded by the rounding of p's largest, at least r.quantum,
 * plus r.unit times the farthest point's distance), at most
 * ADAPTIVE_JET_EXACT h; and the sphere not a plane to it (|k| max |q|^2 / 2
 * above it). Sets *borderline where a
 * test is within a factor 2 of its tolerance: near rounding, the two
 * implementations' sums differ by about as much as the tolerance allows. */
static int on_sphere(const vec* q, size_t m, vec p, vec n, long double h, rounding r, int* borderline)
{
	if (m < ADAPTIVE_SPHERE_POINTS || (n.x == 0 && n.y == 0 && n.z == 0))
		return 0;
	long double zb = 0, bb = 0, bmax = 0;
	for (size_t i = 0; i < m; i++) {
		long double b = vec_dot(q[i], q[i]) / 2;
		zb += vec_dot(q[i], n) * b, bb += b * b, bmax = fmaxl(bmax, b);
	}
	long double k = bb > 0 ? zb / bb : 0;
	long double big = fmaxl(r.unit * fmaxl(fabsl(p.x), fmaxl(fabsl(p.y), fabsl(p.z))), r.quantum) +
	                  r.unit * sqrtl(2 * bmax);
	long double tol = fminl(ADAPTIVE_SPHERE_ROUNDING * big, ADAPTIVE_JET_EXACT * h);
	long double worst = 0;
	for (size_t i = 0; i < m; i++)
		worst = fmaxl(worst, fabsl(vec_dot(q[i], n) - k * vec_dot(q[i], q[i]) / 2));
	long double bend = fabsl(k) * bmax;
	*borderline |= (bend > tol / 2 && bend < 2 * tol) || (worst > tol / 2 && worst < 2 * tol);
	return bend > tol && worst <= tol;
}

/* Whether vertex v's 1-ring is a height field sampled on a lattice (vn.h,
 * ADAPTIVE): its faces, each joining rings, close one fan around v whose
 * members in order, 2m >= 4 of them (at most LATTICE_MEMBERS_MAX, each
 * once, not v), have parallel second differences p_i + p_(i + m) - 2 p
 * (or all zero), to LATTICE_SLACK h. Sets *borderline where the longest
 * difference, or the largest part of one across it, is within rounding of
 * the tolerance (near). */
static int lattice_ring(const tables* t, uint32_t v, long double h, int* borderline)
{
	size_t faces = t->first[v + 1] - t->first[v];
	if (faces < 2 || faces > LATTICE_MEMBERS_MAX)
		return 0;
	/* Each face's corners after v, in the face's order. */
	uint32_t path[LATTICE_MEMBERS_MAX][LATTICE_MEMBERS_MAX + 1];
	size_t len[LATTICE_MEMBERS_MAX];
	for (size_t i = 0; i < faces; i++) {
		size_t c = t->corners[t->first[v] + i], f = t->corner_face[c];
		size_t begin = t->face_offsets[f], k = t->face_offsets[f + 1] - begin;
		if (!joins_rings(t, f) || k - 1 > LATTICE_MEMBERS_MAX)
			return 0;
		len[i] = k - 1;
		for (size_t o = 1; o < k; o++)
			path[i][o - 1] = t->indices[begin + (c - begin + o) % k];
	}
	/* Walk the fan: a face ends where exactly one other begins. */
	uint32_t ring[LATTICE_MEMBERS_MAX];
	size_t n = 0, at = 0;
	char used[LATTICE_MEMBERS_MAX] = {0};
	for (size_t step = 0; step < faces; step++) {
		used[at] = 1;
		if (n + len[at] - 1 > LATTICE_MEMBERS_MAX)
			return 0;
		for (size_t i = 0; i + 1 < len[at]; i++)
			ring[n++] = path[at][i];
		uint32_t end = path[at][len[at] - 1];
		size_t found = 0, next = 0;
		for (size_t i = 0; i < faces; i++)
			if (!used[i] && path[i][0] == end)
				found++, next = i;
		if (step + 1 < faces ? found != 1 : end != path[0][0])
			return 0;
		at = next;
	}
	if (n < 4 || n % 2)
		return 0;
	for (size_t i = 0; i < n; i++)
		for (size_t k = 0; k < n; k++)
			if (ring[i] == v || (k != i && ring[k] == ring[i]))
				return 0;
	vec p = position(t->positions, v), u[LATTICE_MEMBERS_MAX / 2];
	long double longest = 0;
	size_t m = n / 2, top = 0;
	for (size_t i = 0; i < m; i++) {
		u[i] = vec_sub(vec_add(position(t->positions, ring[i]), position(t->positions, ring[i + m])),
		               vec_add(p, p));
		if (vec_length(u[i]) > longest)
			longest = vec_length(u[i]), top = i;
	}
	long double tol = LATTICE_SLACK * h;
	*borderline |= near(longest, tol, 0);
	if (!(longest > tol))
		return 1;
	vec d = vec_scale(u[top], 1 / longest);
	long double worst = 0;
	for (size_t i = 0; i < m; i++)
		worst = fmaxl(worst, vec_length(vec_cross(u[i], d)));
	*borderline |= near(worst, tol, 0);
	return worst <= tol;
}

/* ADAPTIVE at a vertex p with the 1-, 2- and 5-ring ends m1 <= m2 <= m5 of
 * q: MWSELR's normal `sel` where the 2-ring lies on a sphere (on_sphere,
 * the coordinates' rounding r); else the jet on the 2-ring; the rough fallback where its residual is above
 * ADAPTIVE_ROUGH_MAX; where it is between ADAPTIVE_JET_EXACT and that, the
 * quadric and the cubic on the 5-ring with Gaussian weights
 * (gauss = ADAPTIVE_WIDTH^2 times the mean |q|^2 / h^2), each fitted once
 * in the jet's frame. Two outcomes: the jet or the quadric (the cubic if
 * the quadric failed), the wide fit where its GCV score is below
 * ADAPTIVE_JET_MARGIN times the jet's, and the jet or the cubic (the
 * quadric if the cubic failed) likewise; the jet's outcome is MWSELR's
 * normal `sel` where that is within ADAPTIVE_MWSELR_AGREE times the jet's
 * residual of the jet's. Where the jet could not be fitted
 * (not trusted in its first frame, or no more points than its unknowns,
 * which it would interpolate), JET's fallback: the quadric on the
 * 1-ring, else S; where it was fitted but strays from S, the rough
 * fallback. log T, T = |d|^2 /
 * var(d): d the quadric's slopes minus the cubic's, var(d) = sigma^2
 * (vs_cubic - vs_quadric), sigma^2 = the cubic's sum w e^2 over (points -
 * 10). */
static void adaptive_vertex(const vec* q, size_t m1, size_t m2, size_t m5, vec s, const double* sel, long double h,
                            vec p, rounding r, adaptive_result* a)
{
	fit_result jet, wq = {.rows = 0}, wc;
	int jet_ok = 0, fitted = 0, q_ok = 0, c_ok = 0;
	long double best = 0, slack = 0;
	a->log_t = NAN;
	a->borderline = a->t_borderline = 0;
	if (on_sphere(q, m2, p, load(sel), h, r, &a->borderline)) {
		for (int k = 0; k < 2; k++)
			a->path[k] = ref_path_mwselr, a->normal[k] = load(sel);
		return;
	}
	/* With no more points than its 10 unknowns the jet interpolates: its
	 * residual says nothing, and it counts as not fitted. */
	if (m2 + 1 > 10 && fit_twice(q, m2, s, 3, h, 0, &jet, &a->borderline, &fitted)) {
		slack = fit_slack(jet.rcond);
		a->borderline |= near(jet.residual, ADAPTIVE_ROUGH_MAX, slack);
		jet_ok = jet.residual <= ADAPTIVE_ROUGH_MAX;
		a->borderline |= fabsl(jet.residual - ADAPTIVE_JET_EXACT) < BORDER + slack;
		if (jet_ok && jet.residual > ADAPTIVE_JET_EXACT)
			best = ADAPTIVE_JET_MARGIN * gcv(jet.residual, effective_points(q, m2, h, 0), 10);
	}
	int fallback = fitted                                                  ? ref_path_rough
	               : fit_twice(q, m1, s, 2, h, 0, &wq, &a->borderline, NULL) ? ref_path_quadric
	                                                                         : ref_path_seed;
	int agree = 0;
	if (jet_ok && !is_zero(sel)) {
		vec e = load(sel);
		long double angle = atan2l(vec_length(vec_cross(e, jet.normal)), vec_dot(e, jet.normal));
		long double limit = ADAPTIVE_MWSELR_AGREE * jet.residual;
		a->borderline |= fabsl(angle - limit) < BORDER + slack;
		agree = angle < limit;
	}
	for (int k = 0; k < 2; k++) {
		if (agree) {
			a->path[k] = ref_path_mwselr;
			a->normal[k] = load(sel);
		} else if (jet_ok) {
			outcome(&jet, ref_path_jet, a, k);
		} else {
			a->path[k] = fallback;
			a->normal[k] = wq.normal;
			a->rcond[k] = wq.rcond;
		}
	}
	if (!(best > 0 && m5 > m1))
		return;
	vec axis = jet.normal;
	long double gauss = 0;
	for (size_t i = 0; i < m5; i++)
		gauss += vec_dot(q[i], q[i]) / (h * h);
	gauss *= ADAPTIVE_WIDTH * ADAPTIVE_WIDTH / (long double)m5;
	long double n = effective_points(q, m5, h, gauss);
	int fit_border = 0;
	q_ok = fit_once(q, m5, axis, s, 2, h, gauss, slack, &wq, &fit_border);
	c_ok = fit_once(q, m5, axis, s, 3, h, gauss, slack, &wc, &fit_border);
	a->borderline |= fit_border;
	a->t_borderline |= fit_border;
	for (int k = 0; k < 2 && (q_ok || c_ok); k++) {
		int cubic = k ? c_ok : !q_ok;
		const fit_result* w = cubic ? &wc : &wq;
		long double g = gcv(w->residual, n, cubic ? 10 : 6);
		a->borderline |= near(g, best, slack + fit_slack(w->rcond) + (jet_ok ? fit_slack(jet.rcond) : 0));
		if (g < best)
			outcome(w, ref_path_wide, a, k);
	}
	if (q_ok && c_ok) {
		long double d0 = wq.slope[0] - wc.slope[0], d1 = wq.slope[1] - wc.slope[1];
		long double var = wc.swe / (long double)(wc.rows - 10) * (wc.vs - wq.vs);
		long double t = (d0 * d0 + d1 * d1) / var;
		a->log_t = !(var > 0) ? T_LOG_MAX : t > 0 ? fminl(fmaxl(logl(t), -T_LOG_MAX), T_LOG_MAX) : -T_LOG_MAX;
		/* d and var are differences of the library's fits, each exact to
		 * about fit_slack relative: T's error grows as d shrinks. */
		a->t_borderline |= !(var > 0) || t == 0;
	}
}

/* The slack in ADAPTIVE's mean log T: the fits' own relative error, over
 * |d|^2 / (|d|^2 + var) as d shrinks, far above the measured differences. */
#define T_SLACK 1e-6L

/* QUADRIC, JET and ADAPTIVE: the MWA normal S as seed and fallback;
 * ADAPTIVE's rough fallback is MWAAT's normal where the 1-ring is a
 * lattice (lattice_ring), else S. */
static void fit_normals(int method, const tables* t, double* out, double* cond, unsigned char* path)
{
	size_t n = t->vertex_count;
	weighted_normals(ref_mwa, t, out, cond); /* S, kept where chosen */
	/* ADAPTIVE: MWA's (S, as out is overwritten), MWAAT's and MWSELR's
	 * normals, then conditions */
	double *rough = NULL, *lattice = NULL, *sel = NULL;
	long double* hs = NULL; /* ADAPTIVE: each vertex's h */
	if (method == ref_adaptive) {
		rough = checked_calloc(4 * n, sizeof *rough);
		weighted_normals(ref_mwa, t, rough, rough + 3 * n);
		lattice = checked_calloc(4 * n, sizeof *lattice);
		weighted_normals(ref_mwaat, t, lattice, lattice + 3 * n);
		hs = checked_calloc(n, sizeof *hs);
		sel = checked_calloc(4 * n, sizeof *sel);
		weighted_normals(ref_mwselr, t, sel, sel + 3 * n);
	}
	const rounding coords = coordinate_rounding(t->positions, 3 * n);
	char* mark = checked_calloc(n, 1);
	uint32_t* ring = checked_calloc(n, sizeof *ring);
	vec* q = checked_calloc(n, sizeof *q);
	adaptive_result* ad = method == ref_adaptive ? checked_calloc(n, sizeof *ad) : NULL;
	char* hub = checked_calloc(n, 1); /* more than RING_HUB_MAX 1-ring members */
	for (size_t u = 0; u < n; u++) {
		mark[u] = 1;
		size_t m = add_ring(t, (uint32_t)u, mark, ring, 0);
		hub[u] = m > RING_HUB_MAX;
		for (size_t i = 0; i < m; i++)
			mark[ring[i]] = 0;
		mark[u] = 0;
	}
	for (size_t v = 0; v < n; v++) {
		double* o = out + 3 * v;
		vec s = load(o);
		if (ad)
			ad[v].log_t = NAN;
		if (is_zero(o) || vec_dot(s, s) == 0) {
			path[v] = is_zero(o) ? ref_path_zero : ref_path_rough;
			continue;
		}
		path[v] = ref_path_seed;
		vec p = position(t->positions, (uint32_t)v);
		mark[v] = 1;
		size_t m1 = add_ring(t, (uint32_t)v, mark, ring, 0), m2 = m1, m5 = m1;
		long double h = 0;
		for (size_t i = 0; i < m1; i++) {
			q[i] = vec_sub(position(t->positions, ring[i]), p);
			h += vec_length(q[i]);
		}
		h /= m1 ? (long double)m1 : 1;
		if (hs)
			hs[v] = h;
		if (method != ref_quadric) {
			for (size_t i = 0; i < m1; i++)
				if (!hub[ring[i]])
					m2 = add_ring(t, ring[i], mark, ring, m2);
			m5 = m2;
		}
		for (size_t from = m1, r = 3; method == ref_adaptive && r <= ADAPTIVE_RINGS; r++) { /* the 3- to 5-rings */
			size_t to = m5;
			for (size_t i = from; i < to; i++)
				if (!hub[ring[i]])
					m5 = add_ring(t, ring[i], mark, ring, m5);
			from = to;
		}
		for (size_t i = m1; i < m5; i++)
			q[i] = vec_sub(position(t->positions, ring[i]), p);
		fit_result f = {.rows = 0};
		int borderline = 0;
		if (m1 && method == ref_adaptive)
			adaptive_vertex(q, m1, m2, m5, s, sel + 3 * v, h, p, coords, ad + v); /* chosen below */
		else if (m1 && method == ref_jet && fit_twice(q, m2, s, 3, h, 0, &f, &borderline, NULL)) {
			path[v] = ref_path_jet;
		} else if (m1 && method != ref_adaptive && fit_twice(q, m1, s, 2, h, 0, &f, &borderline, NULL)) {
			path[v] = ref_path_quadric;
		}
		if (path[v] != ref_path_seed) {
			o_set(o, f.normal);
			cond[v] = (double)f.rcond;
		}
		if (borderline)
			path[v] |= ref_path_borderline;
		for (size_t i = 0; i < m5; i++)
			mark[ring[i]] = 0;
		mark[v] = 0;
	}
	/* ADAPTIVE: the cubic's outcome where the mean log T over the vertex and
	 * its 1-ring (those that have one) is above log ADAPTIVE_T. */
	for (size_t v = 0; ad && v < n; v++) {
		if (path[v] == ref_path_zero || !ad[v].path[0])
			continue; /* no fit was tried: the fallback, set above */
		mark[v] = 1;
		size_t m1 = add_ring(t, (uint32_t)v, mark, ring, 0), count = 0;
		long double sum = 0;
		int border = ad[v].t_borderline;
		for (size_t i = 0; i <= m1; i++) {
			const adaptive_result* a = ad + (i < m1 ? ring[i] : v);
			border |= a->t_borderline;
			if (!isnan(a->log_t))
				sum += a->log_t, count++;
			if (i < m1)
				mark[ring[i]] = 0;
		}
		mark[v] = 0;
		const adaptive_result* a = ad + v;
		int k = count && sum > logl(ADAPTIVE_T) * (long double)count;
		int differ = a->path[0] != a->path[1] || vec_dot(a->normal[0], a->normal[1]) != vec_dot(a->normal[0], a->normal[0]);
		border |= count && fabsl(sum / (long double)count - logl(ADAPTIVE_T)) < T_SLACK;
		path[v] = (unsigned char)a->path[k];
		int lattice_border = 0;
		if (path[v] == ref_path_rough && hs[v] > 0 && lattice_ring(t, (uint32_t)v, hs[v], &lattice_border))
			path[v] = ref_path_lattice;
		if (path[v] == ref_path_rough || path[v] == ref_path_lattice || path[v] == ref_path_mwselr) {
			const double* from = path[v] == ref_path_rough ? rough : path[v] == ref_path_lattice ? lattice : sel;
			memcpy(out + 3 * v, from + 3 * v, 3 * sizeof *out);
			cond[v] = from[3 * n + v];
		} else if (path[v] != ref_path_seed) {
			o_set(out + 3 * v, a->normal[k]);
			cond[v] = (double)a->rcond[k];
		}
		if (a->borderline || (differ && border) || lattice_border)
			path[v] |= ref_path_borderline;
	}
	free(ad);
	free(rough);
	free(lattice);
	free(hs);
	free(sel);
	free(q);
	free(ring);
	free(mark);
	free(hub);
}

void ref_normals_ex(int method, const double* positions, size_t vertex_count, const uint32_t* indices,
                    const uint32_t* face_offsets, size_t face_count, double* out_normals,
                    double* out_condition, unsigned char* out_path)
{
	tables t = tables_make(positions, vertex_count, indices, face_offsets, face_count);
	double* cond = out_condition ? out_condition : checked_calloc(vertex_count, sizeof *cond);
	unsigned char* path = out_path ? out_path : checked_calloc(vertex_count, 1);
	if (method == ref_smewcsa) {
		smewcsa_normals(&t, out_normals, cond, path);
	} else if (method >= ref_quadric) {
		fit_normals(method, &t, out_normals, cond, path);
	} else {
		weighted_normals(method, &t, out_normals, cond);
		for (size_t v = 0; v < vertex_count; v++)
			path[v] = is_zero(out_normals + 3 * v) ? ref_path_zero : ref_path_weighted;
	}
	if (!out_condition)
		free(cond);
	if (!out_path)
		free(path);
	tables_free(&t);
}

void ref_normals(int method, const double* positions, size_t vertex_count, const uint32_t* indices,
                 const uint32_t* face_offsets, size_t face_count, double* out_normals)
{
	ref_normals_ex(method, positions, vertex_count, indices, face_offsets, face_count, out_normals, NULL, NULL);
}
