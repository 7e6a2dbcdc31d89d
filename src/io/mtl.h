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
 * several, see read_libraries; relative names from material_folder, else
 * from the working folder; a file not there is looked for beside the OBJ)
 * into mesh->material_defs, one entry per name in mesh->materials: Kd, d,
 * Ns, Pr, Pm, Ke and the maps map_Kd, map_Ke and map_Bump (bump, norm).
 * What cannot be used (a library or texture that
 * cannot be read, a texture neither PNG nor JPEG or without texture
 * coordinates to draw it, a material the library does not define, a
 * map's options) is a warning line appended to mesh->warnings, naming the file;
 * the material keeps what else it has. Does nothing for a mesh without
 * materials or library. Fails only when out of memory. */
vn_io_result vn_io_mtl_read(vn_io_mesh* mesh, vn_io_error* error);

/* Parses size bytes of one library (data need not be NUL-terminated) into
 * mesh->material_defs (allocated here when NULL), textures found from
 * `folder` (NULL: the working folder); warnings go to `warnings`, each line
 * starting with `name`. Returns 0 when out of memory. */
int vn_io_mtl_parse(const char* data, size_t size, const char* name, const char* folder, vn_io_mesh* mesh,
                    FILE* warnings);

/* Library text held in memory (`size` bytes; `name` its origin in
 * warnings, textures found from the folder of file `beside`, NULL: the
 * working folder), as vn_io_mtl_read reads a file: a PLY's TextureFile
 * comments are given as one. */
vn_io_result vn_io_mtl_read_text(vn_io_mesh* mesh, const char* data, size_t size, const char* name, const char* beside,
                                 vn_io_error* error);

#ifdef __cplusplus
}
#endif

#endif /* VN_IO_MTL_H */
