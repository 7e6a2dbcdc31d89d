/*
 * libFuzzer entry point for the PLY reader and writer (seed corpus:
 * tests/data/ply): what the reader accepts, written and read back, has the
 * same vertices, faces, indices, optional arrays and attributes, and is
 * written again byte for byte as it was the first time (so the comments,
 * face properties and elements kept come back as they went); its
 * per-corner texcoords made per vertex keep every corner where it was, and
 * its TextureFile comments made materials give every face one of them or
 * none.
 */
#include "fuzz_mesh.h"
#include "ply.h"

/* The PLY writer's bytes for m (the caller frees them). */
static char* written(const vn_io_mesh* m, size_t* length)
{
	char* bytes = NULL;
	vn_io_error error;
	FILE* out = open_memstream(&bytes, length);
	if (!out)
		abort();
	if (vn_io_ply_write(out, "fuzz.ply", m, NULL, &error) != vn_io_success)
		abort();
	fclose(out);
	return bytes;
}

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
		size_t first_length, again_length;
		char* first = written(&m, &first_length);
		char* again = written(&back, &again_length);
		if (first_length != again_length || memcmp(first, again, first_length) != 0)
			abort();
		free(first);
		free(again);
		/* Per-corner texcoords made per vertex: copies appended, each corner
		 * still at its position, and the mesh still written. */
		size_t split;
		vn_io_error error;
		if (vn_io_ply_corner_texcoords(&m, "fuzz.ply", &split, &error) != vn_io_success ||
		    m.vertex_count != back.vertex_count + split || (split && !m.texcoords))
			abort();
		for (size_t c = 0; c < corners; c++)
			if (m.indices[c] >= m.vertex_count ||
			    memcmp(m.positions + 3 * m.indices[c], back.positions + 3 * back.indices[c], 3 * sizeof(double)) != 0)
				abort();
		free(written(&m, &first_length));
		/* Textures as materials (read from the working folder). */
		if (vn_io_ply_texture_materials(&m, "comment TextureFile", NULL, &error) != vn_io_success)
			abort();
		for (size_t f = 0; m.materials.of_face && f < m.face_count; f++)
			if (m.materials.of_face[f] != VN_IO_NO_NAME && m.materials.of_face[f] >= m.materials.count)
				abort();
		for (size_t i = 0; i < m.materials.count; i++)
			if (!m.materials.names[i] || !m.material_defs[i].defined)
				abort();
	}
	vn_io_mesh_free(&m);
	vn_io_mesh_free(&back);
	return 0;
}
