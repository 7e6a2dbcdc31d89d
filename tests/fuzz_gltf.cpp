/*
 * libFuzzer entry point for the glTF/GLB reader (seed corpus:
 * tests/data/gltf). The reader takes a path, so each input is written to a
 * temporary file first; external buffers and images resolve relative to it
 * and are absent, which is an error path worth fuzzing too.
 *
 * Besides the sanitizers' checks, every accepted input must give a
 * consistent triangle mesh, and converting it as a document (normals,
 * Draco re-encoding, pruning, writing) must succeed or fail with one line.
 */
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

static char path[] = "/tmp/vn-fuzz-gltf-XXXXXX";
static char out[] = "/tmp/vn-fuzz-gltf-out-XXXXXX";

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	static int fd = -1;
	if (fd < 0) {
		int o = mkstemp(out);
		if ((fd = mkstemp(path)) < 0 || o < 0)
			abort();
		close(o);
		atexit([] { unlink(path), unlink(out); });
	}
	if (ftruncate(fd, 0) != 0 || pwrite(fd, data, size, 0) != (ssize_t)size)
		abort();
	vn_io_mesh m;
	vn_io_error error;
	if (vn_io_gltf_read(path, &m, &error) == vn_io_success) {
		if (!m.positions || !m.face_offsets || !m.indices)
			abort();
		for (size_t f = 0; f <= m.face_count; f++)
			if (m.face_offsets[f] != 3 * f)
				abort();
		for (size_t i = 0; i < 3 * m.face_count; i++)
			if (m.indices[i] >= m.vertex_count)
				abort();
		vn_io_mesh_free(&m);
		vn_gltf_options o;
		memset(&o, 0, sizeof o);
		o.method = vn_method_mwselr;
		o.draco_options = {-1, -1, -1, -1, -1};
		if (vn_gltf_convert(path, out, 1, &o, nullptr, &error) != vn_io_success &&
		    (!memchr(error.message, '\0', sizeof error.message) || strchr(error.message, '\n')))
			abort();
	} else if (!memchr(error.message, '\0', sizeof error.message) || strchr(error.message, '\n')) {
		abort(); /* one line */
	}
	return 0;
}
