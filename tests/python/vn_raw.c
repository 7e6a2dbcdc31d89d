/* The C side of tests/python's bit-for-bit comparisons: vn's normals of a
 * mesh given as raw binary files, written raw (float64 x, y, z) to stdout,
 * through vn.h only, as a C program calls it.
 *   vn_raw vertex METHOD POSITIONS INDICES [OFFSETS]
 *   vn_raw corner METHOD POSITIONS INDICES [OFFSETS] CREASE_RADIANS
 * POSITIONS: float64 x, y, z per vertex; INDICES and OFFSETS: uint32. No
 * OFFSETS: triangles (vn_triangle_normals, vn_corner_normals), else
 * polygons (vn_polygon_normals, vn_polygon_corner_normals). One thread. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vn.h"

static void* slurp(const char* path, size_t unit, size_t* count)
{
	FILE* f = fopen(path, "rb");
	if (!f || fseek(f, 0, SEEK_END) || ftell(f) < 0) {
		fprintf(stderr, "%s: cannot read\n", path);
		exit(1);
	}
	size_t bytes = (size_t)ftell(f);
	rewind(f);
	void* data = malloc(bytes ? bytes : 1);
	if (!data || fread(data, 1, bytes, f) != bytes) {
		fprintf(stderr, "%s: cannot read\n", path);
		exit(1);
	}
	fclose(f);
	*count = bytes / unit;
	return data;
}

int main(int argc, char** argv)
{
	int corner = argc > 1 && !strcmp(argv[1], "corner");
	int polygons = argc == 6 + corner;
	vn_method method;
	if (argc < 5 + corner || argc > 6 + corner || vn_method_from_name(argv[2], &method) != vn_result_success) {
		fprintf(stderr, "usage: vn_raw vertex|corner METHOD POSITIONS INDICES [OFFSETS] [CREASE_RADIANS]\n");
		return 2;
	}
	size_t n, m, f = 0;
	double* p = (double*)slurp(argv[3], 3 * sizeof(double), &n);
	uint32_t* idx = (uint32_t*)slurp(argv[4], sizeof(uint32_t), &m);
	uint32_t* off = polygons ? (uint32_t*)slurp(argv[5], sizeof(uint32_t), &f) : NULL;
	double crease = corner ? strtod(argv[argc - 1], NULL) : 0;
	size_t rows = corner ? m : n;
	double* out = (double*)malloc(3 * sizeof(double) * (rows ? rows : 1));
	vn_positions pos = {p, n, 0, vn_scalar_float64};
	vn_vectors vec = {out, 0, vn_scalar_float64};
	vn_result r;
	if (corner)
		r = polygons ? vn_polygon_corner_normals(&vec, &pos, idx, off, f - 1, method, crease, NULL, NULL, NULL)
		             : vn_corner_normals(&vec, &pos, idx, m, method, crease, NULL, NULL, NULL);
	else
		r = polygons ? vn_polygon_normals(&vec, &pos, idx, off, f - 1, method, NULL, NULL)
		             : vn_triangle_normals(&vec, &pos, idx, m, method, NULL, NULL);
	if (r != vn_result_success) {
		fprintf(stderr, "vn_raw: %s\n", vn_result_string(r));
		return 1;
	}
	fwrite(out, 3 * sizeof(double), rows, stdout);
	free(out);
	free(off);
	free(idx);
	free(p);
	return 0;
}
