/*
 * libFuzzer entry point for the OFF reader (seed corpus: tests/data/off).
 *
 * Besides the sanitizers' checks, every accepted input must give a
 * consistent mesh, and writing that mesh and reading it back must give the
 * same counts and indices.
 */
#include "fuzz_mesh.h"
#include "off.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	vn_io_mesh m, back;
	if (fuzz_mesh(data, size, vn_io_off_read_memory, vn_io_off_write, "fuzz.off", &m, &back)) {
		const uint32_t corners = m.face_offsets[m.face_count];
		if (back.vertex_count != m.vertex_count || back.face_count != m.face_count ||
		    memcmp(back.face_offsets, m.face_offsets, (m.face_count + 1) * sizeof(uint32_t)) != 0 ||
		    memcmp(back.indices, m.indices, corners * sizeof(uint32_t)) != 0 || !back.normals != !m.normals ||
		    !back.colors != !m.colors || !back.texcoords != !m.texcoords || !back.face_colors != !m.face_colors)
			abort();
	}
	vn_io_mesh_free(&m);
	vn_io_mesh_free(&back);
	return 0;
}
