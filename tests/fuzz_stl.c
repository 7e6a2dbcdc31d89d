/*
 * libFuzzer entry point for the STL reader and writer (seed corpus:
 * tests/data/stl): what the reader accepts, written (binary) and read back,
 * has as many triangles.
 */
#include "fuzz_mesh.h"
#include "stl.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	vn_io_mesh m, back;
	if (fuzz_mesh(data, size, vn_io_stl_read_memory, vn_io_stl_write, "fuzz.stl", &m, &back) &&
	    (back.face_count != m.face_count || back.vertex_count > m.vertex_count))
		abort();
	vn_io_mesh_free(&m);
	vn_io_mesh_free(&back);
	return 0;
}
