/*
 * PLY (Stanford polygon file format) reader and writer: internal to vnio.
 * Programs reach them through the format table (vn_io_format_by_name("ply")).
 */
#ifndef VN_IO_PLY_H
#define VN_IO_PLY_H

#include "vn_io.h"

/* The vn_io_format read and write entries for PLY. */
vn_io_result vn_io_ply_read(const char* path, vn_io_mesh* mesh, vn_io_error* error);
vn_io_result vn_io_ply_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error);

/* Parses size bytes of PLY (ASCII or binary; data need not be
 * NUL-terminated) into *mesh, which is zeroed first and again on failure.
 * `name` is the file name that error messages start with. */
vn_io_result vn_io_ply_read_memory(const char* data, size_t size, const char* name, vn_io_mesh* mesh,
                                   vn_io_error* error);

/* Frees what vn_io_mesh.ply_extras points to; NULL is fine. */
void vn_io_ply_extras_free(vn_io_ply_extras* extras);

/* Names the face properties and elements of extras ("face list 'texcoord',
 * element 'material' (2)"; comments are not named) into text, truncated to
 * size; returns how many. */
size_t vn_io_ply_extras_describe(const vn_io_ply_extras* extras, char* text, size_t size);

/* Turns the face list 'texcoord' of mesh->ply_extras (a u v pair per
 * corner: MeshLab's and Metashape's textured PLY) into per-vertex
 * texcoords, for a writer that holds texcoords but no face properties
 * (OBJ's vt, glTF's TEXCOORD_0): a vertex whose corners have other pairs
 * than its first is split, one copy per pair, appended
 * (vn_io_mesh_append_vertices), and the list leaves the extras. Nothing is
 * done where the mesh has texcoords already or a face's list is not a pair
 * per corner: the list then stays, and is named as not written. *split:
 * the vertices appended. `name` is the file named in errors; on failure
 * the mesh is as it was. */
vn_io_result vn_io_ply_corner_texcoords(vn_io_mesh* mesh, const char* name, size_t* split, vn_io_error* error);

/* The textures mesh->ply_extras names (MeshLab's and Metashape's "comment
 * TextureFile FILE" lines) as materials, for glTF: one per file, named by
 * it, with the file as its texture (found from the folder of file
 * `beside`, the PLY itself; NULL: the working folder; vn_io_mtl_read_text), each face the one its `texnumber` face
 * property gives (MeshLab's several textures; the property then leaves the
 * extras), else the first. Nothing is done without such a comment, on a
 * mesh without faces or one that has materials. `name` is the file named
 * in messages. */
vn_io_result vn_io_ply_texture_materials(vn_io_mesh* mesh, const char* name, const char* beside, vn_io_error* error);

#endif /* VN_IO_PLY_H */
