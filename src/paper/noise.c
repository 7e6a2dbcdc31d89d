/* Ken Perlin's improved noise (SIGGRAPH 2002, "Improving Noise", and his
 * Java reference implementation) with its exact analytic gradient, and the
 * two sums of it the test ensemble uses: fBm for the fractal height fields
 * (Jin et al. 2005 section 3.1.2) and turbulence for the turbulence model
 * (section 3.1.3).
 *
 * The value is computed with the reference code's very operations, in the
 * same order, so it is bit-identical to the Java noise() on doubles. The
 * gradient rides along as a dual number: each corner's dot product
 * grad(hash, x, y, z) is linear with a constant gradient (one of the 12
 * directions), and each lerp(t, a, b) = a + t (b - a) has the derivative
 * da + t (db - da) + t' (b - a) e_axis, t' being the slope of the fade curve
 * 6t^5 - 15t^4 + 10t^3, that is 30t^4 - 60t^3 + 30t^2. */
#include <math.h>

#include "paper.h"

/* Perlin's reference permutation of 0..255. */
#define PERLIN_PERMUTATION                                                                                        \
	151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69, 142, 8, 99, 37, 240, \
	    21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203, 117, 35, 11, 32, 57, 177, 33,  \
	    88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, \
	    231, 83, 111, 229, 122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63,  \
	    161, 1, 216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100,    \
	    109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206, \
	    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153,  \
	    101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218,    \
	    246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107,  \
	    49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205,   \
	    93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180

/* Duplicated so that p[p[X] + Y] never needs a wrap. */
static const unsigned char perm[512] = {PERLIN_PERMUTATION, PERLIN_PERMUTATION};

/* A value with its gradient. */
typedef struct dual {
	double v, g[3];
} dual;

static double fade(double t)
{
	return t * t * t * (t * (t * 6 - 15) + 10);
}

/* d fade / dt = 30t^4 - 60t^3 + 30t^2 = 30 t^2 (t - 1)^2. */
static double fade_slope(double t)
{
	return 30 * t * t * (t - 1) * (t - 1);
}

/* The reference grad(): the low 4 bits of hash pick one of 12 directions
 * (four of them twice), given as the axes u and v with signs; the dot
 * product's gradient is that direction. */
static dual grad(int hash, double x, double y, double z)
{
	const int h = hash & 15;
	const int ua = h < 8 ? 0 : 1;
	const int va = h < 4 ? 1 : h == 12 || h == 14 ? 0 : 2;
	const double c[3] = {x, y, z};
	const double su = (h & 1) == 0 ? 1.0 : -1.0, sv = (h & 2) == 0 ? 1.0 : -1.0;
	/* +-1 times a coordinate is exact: the same sum as the reference's. */
	dual r = {su * c[ua] + sv * c[va], {0, 0, 0}};
	r.g[ua] += su;
	r.g[va] += sv;
	return r;
}

/* lerp(t, a, b) along axis, t having the slope dt along it. */
static dual lerp(double t, double dt, int axis, dual a, dual b)
{
	const double diff = b.v - a.v;
	dual r = {a.v + t * diff, {0, 0, 0}};
	for (int i = 0; i < 3; ++i)
		r.g[i] = a.g[i] + t * (b.g[i] - a.g[i]);
	r.g[axis] += dt * diff;
	return r;
}

/* floor(c) mod 256, exact for every finite c (Java's (int)floor(c) & 255). */
static int cell(double c)
{
	return (int)(c - 256.0 * floor(c / 256.0));
}

double vn_perlin_noise(const double p[3], double* gradient)
{
	double x = p[0], y = p[1], z = p[2];
	/* A non-finite coordinate has no cell; converting it would be undefined. */
	if (!isfinite(x) || !isfinite(y) || !isfinite(z)) {
		if (gradient)
			gradient[0] = gradient[1] = gradient[2] = NAN;
		return NAN;
	}
	const double fx = floor(x), fy = floor(y), fz = floor(z);
	const int X = cell(fx), Y = cell(fy), Z = cell(fz);
	x -= fx, y -= fy, z -= fz;
	const double u = fade(x), v = fade(y), w = fade(z);
	const double du = fade_slope(x), dv = fade_slope(y), dw = fade_slope(z);
	const int A = perm[X] + Y, AA = perm[A] + Z, AB = perm[A + 1] + Z;
	const int B = perm[X + 1] + Y, BA = perm[B] + Z, BB = perm[B + 1] + Z;

	/* The reference's nesting: x first, then y, then z. */
	const dual x00 = lerp(u, du, 0, grad(perm[AA], x, y, z), grad(perm[BA], x - 1, y, z));
	const dual x10 = lerp(u, du, 0, grad(perm[AB], x, y - 1, z), grad(perm[BB], x - 1, y - 1, z));
	const dual x01 = lerp(u, du, 0, grad(perm[AA + 1], x, y, z - 1), grad(perm[BA + 1], x - 1, y, z - 1));
	const dual x11 = lerp(u, du, 0, grad(perm[AB + 1], x, y - 1, z - 1), grad(perm[BB + 1], x - 1, y - 1, z - 1));
	const dual r = lerp(w, dw, 2, lerp(v, dv, 1, x00, x10), lerp(v, dv, 1, x01, x11));
	if (gradient)
		gradient[0] = r.g[0], gradient[1] = r.g[1], gradient[2] = r.g[2];
	return r.v;
}

double vn_fbm_noise(const double p[3], unsigned octaves, double h, double* gradient)
{
	double sum = 0, g[3] = {0, 0, 0}, scale = 1;
	for (unsigned i = 0; i < octaves; ++i, scale *= 2) {
		const double q[3] = {scale * p[0], scale * p[1], scale * p[2]};
		const double weight = exp2(-(double)i * h);
		double gi[3];
		sum += weight * vn_perlin_noise(q, gi);
		/* Chain rule: d/dp noise(2^i p) = 2^i (grad noise)(2^i p). */
		for (int k = 0; k < 3; ++k)
			g[k] += weight * scale * gi[k];
	}
	if (gradient)
		gradient[0] = g[0], gradient[1] = g[1], gradient[2] = g[2];
	return sum;
}

double vn_turbulence_noise(const double p[3], unsigned octaves, double* gradient)
{
	double sum = 0, g[3] = {0, 0, 0}, scale = 1;
	for (unsigned i = 0; i < octaves; ++i, scale *= 2) {
		const double q[3] = {scale * p[0], scale * p[1], scale * p[2]};
		double gi[3];
		const double n = vn_perlin_noise(q, gi);
		const double sign = n < 0 ? -1.0 : 1.0;
		sum += fabs(n) / scale;
		for (int k = 0; k < 3; ++k)
			g[k] += sign * gi[k];
	}
	if (gradient)
		gradient[0] = g[0], gradient[1] = g[1], gradient[2] = g[2];
	return sum;
}
