/*
 * libFuzzer entry point for the STL reader and writer (seed corpus:
 * tests/data/stl): what the reader accepts, written (binary) and read back,
 * has as many triangles, and a binary file's header and attribute bytes.
 */
#include "fuzz_mesh.h"
#include "stl.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	vn_io_mesh m, back;
	if (fuzz_mesh(data, size, vn_io_stl_read_memory, vn_io_stl_write, "fuzz.stl", &m, &back) &&
	    (back.face_count != m.face_count || back.vertex_count > m.vertex_count))
		abort();
	const vn_io_stl_extras *a = m.stl_extras, *b = back.stl_extras;
	if (a && (!b || b->count != a->count || memcmp(a->header, b->header, sizeof a->header) ||
	          memcmp(a->attributes, b->attributes, a->count * sizeof *a->attributes)))
		abort();
	vn_io_mesh_free(&m);
	vn_io_mesh_free(&back);
	return 0;
}
