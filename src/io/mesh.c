/*
 * vn_io_mesh helpers and error reporting shared by every format.
 */
#include "vn_io.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

const char* vn_io_result_string(vn_io_result r)
{
	switch (r) {
	case vn_io_success: return "success";
	case vn_io_error_open: return "cannot open or read the input file";
	case vn_io_error_write: return "cannot write the output file";
	case vn_io_error_parse: return "malformed file";
	case vn_io_error_unsupported: return "file uses a feature vn does not support";
	case vn_io_error_format: return "unknown file format";
	case vn_io_error_memory: return "out of memory";
	case vn_io_error_same_file: return "the output is the input file";
	case vn_io_result_count_: break;
	}
	return "unknown vn_io result";
}

vn_io_result vn_io_fail(vn_io_error* error, vn_io_result r, const char* fmt, ...)
{
	if (error) {
		va_list args;
		va_start(args, fmt);
		vsnprintf(error->message, sizeof error->message, fmt, args);
		va_end(args);
	}
	return r;
}

void vn_io_mesh_free(vn_io_mesh* mesh)
{
	if (!mesh)
		return;
	free(mesh->positions);
	free(mesh->normals);
	free(mesh->colors);
	free(mesh->texcoords);
	free(mesh->face_offsets);
	free(mesh->indices);
	free(mesh->face_colors);
	memset(mesh, 0, sizeof *mesh);
}

int vn_io_mesh_is_triangles(const vn_io_mesh* mesh)
{
	if (!mesh || mesh->face_count == 0 || !mesh->face_offsets)
		return 0;
	for (size_t f = 0; f < mesh->face_count; f++)
		if (mesh->face_offsets[f + 1] - mesh->face_offsets[f] != 3)
			return 0;
	return 1;
}
