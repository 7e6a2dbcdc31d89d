/* Shared by the cmocka runners: an allocator that counts, and can fail. */
#ifndef VN_TEST_UTIL_H
#define VN_TEST_UTIL_H

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

#endif /* VN_TEST_UTIL_H */
