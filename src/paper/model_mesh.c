/* The paper library's memory, at the bottom of src/paper/: allocations
 * through the caller's vn_allocator (or malloc/free), and the four arrays of
 * a vn_model_mesh, which both the parameterized models (ensemble.c) and the
 * marching tetrahedra (marching.c) fill. */
#include <stdlib.h>
#include <string.h>

#include "paper.h"

void* vn_paper_allocate(const vn_allocator* heap, size_t size)
{
	return heap->allocate ? heap->allocate(heap->user, size) : malloc(size);
}

void vn_paper_free(const vn_allocator* heap, void* ptr)
{
	if (!ptr)
		return;
	if (heap->deallocate)
		heap->deallocate(heap->user, ptr);
	else
		free(ptr);
}

void vn_mesh_release(const vn_allocator* heap, vn_model_mesh* mesh)
{
	vn_paper_free(heap, mesh->indices);
	vn_paper_free(heap, mesh->boundary);
	vn_paper_free(heap, mesh->normals);
	vn_paper_free(heap, mesh->positions);
	memset(mesh, 0, sizeof(*mesh));
}

vn_result vn_mesh_allocate(const vn_allocator* heap, vn_model_mesh* mesh)
{
	const size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
	mesh->positions = (double*)vn_paper_allocate(heap, 3 * nv * sizeof(double));
	mesh->normals = mesh->positions ? (double*)vn_paper_allocate(heap, 3 * nv * sizeof(double)) : NULL;
	mesh->boundary = mesh->normals ? (uint8_t*)vn_paper_allocate(heap, nv) : NULL;
	mesh->indices = mesh->boundary ? (uint32_t*)vn_paper_allocate(heap, 3 * nt * sizeof(uint32_t)) : NULL;
	if (mesh->indices) {
		memset(mesh->boundary, 0, nv);
		return vn_result_success;
	}
	vn_mesh_release(heap, mesh);
	return vn_result_out_of_memory;
}
