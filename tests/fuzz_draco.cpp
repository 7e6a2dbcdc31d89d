/*
 * libFuzzer entry point for the Draco decoder glue (seed corpus:
 * tests/data/draco). Debian's libdraco is not instrumented, so coverage
 * guides only through vn's side; a crash inside libdraco still shows.
 *
 * Besides the sanitizers' checks, every accepted stream (a mesh or a point
 * cloud) must give a consistent geometry: indices within the points,
 * attribute data present; and encoding it again (its grids and metadata)
 * must not crash.
 */
#include <cstdint>
#include <cstdlib>

#include "draco.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	vn_drc_geometry g;
	vn_io_error error;
	if (vn_drc_decode_any(data, size, "fuzz.drc", &g, &error) == vn_io_success) {
		for (size_t i = 0; i < 3 * g.triangle_count; i++)
			if (g.indices[i] >= g.point_count)
				abort();
		for (size_t a = 0; a < g.attribute_count; a++)
			if (!g.attributes[a].data || g.attributes[a].components < 1 || g.attributes[a].components > 4)
				abort();
		void* encoded = nullptr;
		size_t encoded_size = 0;
		if (vn_drc_encode(&g, 7, 0, "fuzz.drc", &encoded, &encoded_size, &error) == vn_io_success && !encoded)
			abort();
		std::free(encoded);
		vn_drc_geometry_free(&g);
	}
	return 0;
}
