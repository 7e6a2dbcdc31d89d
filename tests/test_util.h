/* Shared by the cmocka runners: an allocator that counts, and can fail; a
 * jittered grid mesh. */
#ifndef VN_TEST_UTIL_H
#define VN_TEST_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "vn.h"

typedef struct counting {
	int allocations, frees, fail_after; /* fail_after < 0: never fail */
} counting;

static inline void* count_alloc(void* user, size_t size)
{
	counting* c = (counting*)user;
	if (c->fail_after >= 0 && c->allocations >= c->fail_after)
		return NULL;
	c->allocations++;
	return malloc(size);
}

static inline void count_free(void* user, void* ptr)
{
	((counting*)user)->frees++;
	free(ptr);
}

/* Options whose allocator counts into c. */
static inline vn_options counting_options(counting* c)
{
	vn_options o;
	memset(&o, 0, sizeof(o));
	o.allocator.allocate = count_alloc;
	o.allocator.deallocate = count_free;
	o.allocator.user = c;
	return o;
}

/* A jittered height field, n x n vertices, with 2 (n-1)^2 + 1 triangles: the
 * extra one makes the count odd (a scalar tail) and uses the last vertex
 * (groups touching it take the scalar path), and one triangle is degenerate. */
static inline uint32_t* test_grid(size_t n, double* pos, size_t* ni)
{
	uint32_t seed = 12345;
	for (size_t i = 0; i < n * n; ++i) {
		double r[3];
		for (int k = 0; k < 3; ++k) {
			seed ^= seed << 13, seed ^= seed >> 17, seed ^= seed << 5;
			r[k] = (double)seed / 4294967296.0 - 0.5;
		}
		pos[3 * i] = (double)(i % n) + 0.3 * r[0];
		pos[3 * i + 1] = (double)(i / n) + 0.3 * r[1];
		pos[3 * i + 2] = 0.2 * sin(0.3 * (double)i) + 0.3 * r[2];
	}
	uint32_t* idx = (uint32_t*)malloc(sizeof(uint32_t) * (6 * (n - 1) * (n - 1) + 6));
	size_t k = 0;
	for (uint32_t y = 0; y + 1 < n; ++y)
		for (uint32_t x = 0; x + 1 < n; ++x) {
			const uint32_t a = y * (uint32_t)n + x, b = a + 1, c = a + (uint32_t)n + 1, d = a + (uint32_t)n;
			const uint32_t t[6] = {a, b, c, a, c, d};
			memcpy(idx + k, t, sizeof(t));
			k += 6;
		}
	const uint32_t last = (uint32_t)(n * n - 1), extra[6] = {0, last, 1, 5, 5, 6};
	memcpy(idx + k, extra, sizeof(extra));
	*ni = k + 6;
	return idx;
}

#endif /* VN_TEST_UTIL_H */
