/*
 * libFuzzer entry point for the PLY reader and writer (seed corpus:
 * tests/data/ply): what the reader accepts, written and read back, has the
 * same vertices, faces, indices, optional arrays and attributes.
 */
#include "fuzz_mesh.h"
#include "ply.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	vn_io_mesh m, back;
	if (fuzz_mesh(data, size, vn_io_ply_read_memory, vn_io_ply_write, "fuzz.ply", &m, &back)) {
		const size_t corners = m.face_offsets[m.face_count];
		if (back.vertex_count != m.vertex_count || back.face_count != m.face_count ||
		    memcmp(back.face_offsets, m.face_offsets, (m.face_count + 1) * sizeof(uint32_t)) != 0 ||
		    memcmp(back.indices, m.indices, corners * sizeof(uint32_t)) != 0 ||
		    memcmp(back.positions, m.positions, 3 * m.vertex_count * sizeof(double)) != 0 ||
		    !back.normals != !m.normals || !back.colors != !m.colors || !back.texcoords != !m.texcoords ||
		    !back.face_colors != !m.face_colors || back.attribute_count != m.attribute_count)
			abort();
		for (size_t a = 0; a < m.attribute_count; a++)
			if (memcmp(back.attributes[a].data, m.attributes[a].data,
			           m.vertex_count * vn_io_component_size(m.attributes[a].component_type)) != 0)
				abort();
	}
	vn_io_mesh_free(&m);
	vn_io_mesh_free(&back);
	return 0;
}
