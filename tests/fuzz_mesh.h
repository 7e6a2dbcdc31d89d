/*
 * Shared by the libFuzzer entry points of the vn_io_mesh readers (fuzz_off.c,
 * fuzz_ply.c, fuzz_stl.c): an accepted input must give a consistent mesh,
 * and writing it and reading that back must work; a refused one an error
 * naming the file and no mesh.
 */
#ifndef VN_FUZZ_MESH_H
#define VN_FUZZ_MESH_H

#define _POSIX_C_SOURCE 200809L /* open_memstream */

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vn_io.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

typedef vn_io_result (*fuzz_writer)(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings,
                                    vn_io_error* error);

static inline void fuzz_check_mesh(const vn_io_mesh* m)
{
	if (!m->positions || !m->face_offsets || !m->indices || m->face_offsets[0] != 0)
		abort();
	for (size_t f = 0; f < m->face_count; f++)
		if (m->face_offsets[f + 1] <= m->face_offsets[f])
			abort();
	for (uint32_t i = 0; i < m->face_offsets[m->face_count]; i++)
		if (m->indices[i] >= m->vertex_count)
			abort();
	for (size_t i = 0; m->colors && i < 4 * m->vertex_count; i++)
		if (!(m->colors[i] >= 0.0f && m->colors[i] <= 1.0f))
			abort();
	for (size_t i = 0; m->face_colors && i < 4 * m->face_count; i++)
		if (!(m->face_colors[i] >= 0.0f && m->face_colors[i] <= 1.0f))
			abort();
}

/* Reads data with `read` into *mesh: 1 when accepted, written with `write`
 * and read back into *back (the caller compares them and frees both), 0
 * when refused; abort() on anything wrong. */
static inline int fuzz_mesh(const uint8_t* data, size_t size, vn_io_memory_reader read, fuzz_writer write,
                            const char* name, vn_io_mesh* mesh, vn_io_mesh* back)
{
	vn_io_error error;
	error.message[0] = '\0';
	memset(back, 0, sizeof *back);
	if (read((const char*)data, size, name, mesh, &error) != vn_io_success) {
		if (strncmp(error.message, name, strlen(name)) != 0 || mesh->positions || mesh->indices)
			abort();
		return 0;
	}
	fuzz_check_mesh(mesh);
	if (mesh->face_count == 0 && mesh->vertex_count && strstr(name, ".stl") != NULL)
		abort(); /* STL reads no point cloud (an empty mesh, from no triangles) */
	char* bytes = NULL;
	size_t length = 0;
	FILE* out = open_memstream(&bytes, &length);
	if (!out)
		return 0;
	const vn_io_result written = write(out, name, mesh, NULL, &error);
	fclose(out);
	if (written != vn_io_success || read(bytes, length, "written", back, &error) != vn_io_success) {
		fprintf(stderr, "%s\n", error.message);
		abort();
	}
	free(bytes);
	return 1;
}

#endif /* VN_FUZZ_MESH_H */
