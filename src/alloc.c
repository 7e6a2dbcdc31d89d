/* Work memory, at the bottom of libvn: the caller's vn_allocator, or
 * malloc/free when it has no functions. Every file that allocates (the
 * parallel runner, welding, corner normals) resolves its allocator here. */
#include <stdlib.h>

#include "internal.h"

static void* default_allocate(void* user, size_t size)
{
	(void)user;
	return malloc(size);
}

static void default_deallocate(void* user, void* ptr)
{
	(void)user;
	free(ptr);
}

vn_allocator vn_heap(const vn_allocator* a)
{
	if (a && a->allocate && a->deallocate)
		return *a;
	const vn_allocator heap = {default_allocate, default_deallocate, NULL};
	return heap;
}
