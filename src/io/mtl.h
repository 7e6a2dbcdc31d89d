/*
 * An OBJ's material library (.mtl), read for writers of materials (glTF):
 * internal to vnio.
 */
#ifndef VN_IO_MTL_H
#define VN_IO_MTL_H

#include <stdio.h>

#include "vn_io.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads the .mtl files an OBJ mesh names (material_library: one file, or
 * several separated by blanks; relative names from material_folder, else
 * from the working folder) into mesh->material_defs, one entry per name in
 * mesh->materials: Kd, d (else 1 - Tr) and map_Kd. What cannot be used (a
 * library or texture that cannot be read, a texture neither PNG nor JPEG,
 * a material the library does not define, map_Kd options) is a warning
 * line appended to mesh->warnings, naming the file; the material keeps
 * what else it has. Does nothing for a mesh without materials or library.
 * Fails only when out of memory. */
vn_io_result vn_io_mtl_read(vn_io_mesh* mesh, vn_io_error* error);

/* Parses size bytes of one library (data need not be NUL-terminated) into
 * mesh->material_defs (allocated here when NULL), textures found from
 * `folder` (NULL: the working folder); warnings go to `warnings`, each line
 * starting with `name`. Returns 0 when out of memory. */
int vn_io_mtl_parse(const char* data, size_t size, const char* name, const char* folder, vn_io_mesh* mesh,
                    FILE* warnings);

#ifdef __cplusplus
}
#endif

#endif /* VN_IO_MTL_H */
