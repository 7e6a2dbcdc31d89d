/*
 * Reference vertex normals: see reference.h. Plain and slow on purpose:
 * long double throughout, one vertex at a time, each of its corners visited
 * through a vertex -> corners table.
 */
#include "reference.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

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

void ref_normals_ex(int method, const double* positions, size_t vertex_count, const uint32_t* indices,
                    const uint32_t* face_offsets, size_t face_count, double* out_normals,
                    double* out_condition)
{
	size_t corner_count = face_offsets[face_count];

	/* Face normals and validity, once per face. */
	vec* normals = checked_calloc(face_count, sizeof *normals);
	char* valid = checked_calloc(face_count, 1);
	for (size_t f = 0; f < face_count; f++) {
		size_t k = face_offsets[f + 1] - face_offsets[f];
		valid[f] = (char)face_normal(positions, indices + face_offsets[f], k, &normals[f]);
	}

	/* Vertex -> corners table (counting sort), and each corner's face. */
	size_t* first = checked_calloc(vertex_count + 1, sizeof *first);
	size_t* corners = checked_calloc(corner_count, sizeof *corners);
	size_t* corner_face = checked_calloc(corner_count, sizeof *corner_face);
	size_t* fill = checked_calloc(vertex_count, sizeof *fill);
	for (size_t f = 0; f < face_count; f++) {
		for (size_t c = face_offsets[f]; c < face_offsets[f + 1]; c++) {
			corner_face[c] = f;
			first[indices[c] + 1]++;
		}
	}
	for (size_t v = 0; v < vertex_count; v++)
		first[v + 1] += first[v];
	for (size_t c = 0; c < corner_count; c++) {
		uint32_t v = indices[c];
		corners[first[v] + fill[v]++] = c;
	}

	/* Gather: each vertex sums over its own corners. */
	for (size_t v = 0; v < vertex_count; v++) {
		vec sum = vec_make(0, 0, 0);
		long double magnitude = 0; /* sum of |contribution| */
		int contributed = 0;
		vec p = position(positions, (uint32_t)v);
		for (size_t j = first[v]; j < first[v + 1]; j++) {
			size_t c = corners[j];
			size_t f = corner_face[c];
			if (!valid[f])
				continue;
			size_t begin = face_offsets[f];
			size_t k = face_offsets[f + 1] - begin;
			size_t i = c - begin;
			uint32_t prev = indices[begin + (i + k - 1) % k];
			uint32_t next = indices[begin + (i + 1) % k];
			vec e0 = vec_sub(position(positions, prev), p);
			vec e1 = vec_sub(position(positions, next), p);
			/* A repeated corner (zero-length edge) has no angle: skip it. */
			if (vec_length(e0) == 0 || vec_length(e1) == 0)
				continue;
			vec w = corner_contribution(method, normals[f], e0, e1);
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
		if (out_condition)
			out_condition[v] = !contributed ? -1.0 : magnitude > 0 ? (double)(len / magnitude) : 0.0;
	}

	free(fill);
	free(corner_face);
	free(corners);
	free(first);
	free(valid);
	free(normals);
}

void ref_normals(int method, const double* positions, size_t vertex_count, const uint32_t* indices,
                 const uint32_t* face_offsets, size_t face_count, double* out_normals)
{
	ref_normals_ex(method, positions, vertex_count, indices, face_offsets, face_count, out_normals, NULL);
}
