/*
 * The table of file formats. A new format is one more row: its reader and
 * writer live in their own file and are declared in their own internal header.
 */
#include "vn_io.h"

#include <string.h>

#include "draco.h"
#include "gltf.h"
#include "off.h"

static const vn_io_format formats[] = {
	{"off", ".off", "Geomview Object File Format (reads ASCII and binary, writes ASCII)", vn_io_off_read,
	 vn_io_off_write, vn_io_holds_colors | vn_io_holds_texcoords | vn_io_holds_face_colors | vn_io_holds_polygons},
	{"gltf", ".gltf", "glTF 2.0 JSON (glTF in: the whole document is kept, only normals change)", vn_io_gltf_read,
	 vn_io_gltf_write, vn_io_holds_colors | vn_io_holds_texcoords | vn_io_holds_attributes},
	{"glb", ".glb", "glTF 2.0 binary (as gltf)", vn_io_gltf_read, vn_io_glb_write,
	 vn_io_holds_colors | vn_io_holds_texcoords | vn_io_holds_attributes},
	{"drc", ".drc", "Draco mesh (triangles; positions, normals, texcoords, colours; quantized)", vn_io_drc_read,
	 vn_io_drc_write, vn_io_holds_colors | vn_io_holds_texcoords | vn_io_holds_attributes},
};

#define FORMAT_COUNT (sizeof formats / sizeof formats[0])

/* ASCII only: extensions and names are ASCII, and tolower() would follow the
 * program's locale. */
static int lower(unsigned char c)
{
	return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c;
}

static int equal_ignoring_case(const char* a, const char* b, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (lower((unsigned char)a[i]) != lower((unsigned char)b[i]))
			return 0;
	return 1;
}

const vn_io_format* vn_io_format_for_path(const char* path)
{
	if (!path)
		return NULL;
	size_t length = strlen(path);
	for (size_t i = 0; i < FORMAT_COUNT; i++) {
		const char* extension = formats[i].extensions;
		while (*extension) {
			size_t n = strcspn(extension, " ");
			if (n > 0 && n <= length && equal_ignoring_case(path + length - n, extension, n))
				return &formats[i];
			extension += n;
			extension += strspn(extension, " ");
		}
	}
	return NULL;
}

const vn_io_format* vn_io_format_by_name(const char* name)
{
	if (!name)
		return NULL;
	size_t length = strlen(name);
	for (size_t i = 0; i < FORMAT_COUNT; i++)
		if (strlen(formats[i].name) == length && equal_ignoring_case(name, formats[i].name, length))
			return &formats[i];
	return NULL;
}

const vn_io_format* vn_io_format_at(size_t i)
{
	return i < FORMAT_COUNT ? &formats[i] : NULL;
}
