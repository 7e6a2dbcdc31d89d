/*
 * libFuzzer entry point for the OFF reader (seed corpus: tests/data/off).
 *
 * Besides the sanitizers' checks, every accepted input must give a
 * consistent mesh, and writing that mesh and reading it back must give the
 * same counts and indices.
 */
#define _POSIX_C_SOURCE 200809L /* open_memstream */

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "off.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

static void check_mesh(const vn_io_mesh* m)
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

static void check_round_trip(const vn_io_mesh* m)
{
	char* text = NULL;
	size_t size = 0;
	FILE* out = open_memstream(&text, &size);
	vn_io_error error;
	if (!out)
		return;
	vn_io_result written = vn_io_off_write(out, "fuzz.off", m, NULL, &error);
	fclose(out);
	if (written != vn_io_success)
		abort();
	vn_io_mesh back;
	if (vn_io_off_read_memory(text, size, "written.off", &back, &error) != vn_io_success) {
		fprintf(stderr, "%s\n", error.message);
		abort();
	}
	uint32_t corners = m->face_offsets[m->face_count];
	if (back.vertex_count != m->vertex_count || back.face_count != m->face_count ||
	    memcmp(back.face_offsets, m->face_offsets, (m->face_count + 1) * sizeof(uint32_t)) != 0 ||
	    memcmp(back.indices, m->indices, corners * sizeof(uint32_t)) != 0 || !back.normals != !m->normals ||
	    !back.colors != !m->colors || !back.texcoords != !m->texcoords || !back.face_colors != !m->face_colors)
		abort();
	vn_io_mesh_free(&back);
	free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	vn_io_mesh mesh;
	vn_io_error error;
	error.message[0] = '\0';
	if (vn_io_off_read_memory((const char*)data, size, "fuzz.off", &mesh, &error) == vn_io_success) {
		check_mesh(&mesh);
		check_round_trip(&mesh);
	} else if (strncmp(error.message, "fuzz.off", 8) != 0 || mesh.positions || mesh.indices) {
		abort();
	}
	vn_io_mesh_free(&mesh);
	return 0;
}
