/*
 * Wavefront OBJ: read through Draco's ObjDecoder, written by vn (obj.cpp).
 * Internal to vnio: programs reach them through the format table
 * (vn_io_format_by_name("obj")).
 */
#ifndef VN_IO_OBJ_H
#define VN_IO_OBJ_H

#include "vn_io.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The vn_io_format read and write entries for OBJ. */
vn_io_result vn_io_obj_read(const char* path, vn_io_mesh* mesh, vn_io_error* error);
vn_io_result vn_io_obj_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings,
                             vn_io_error* error);

/* Reads size bytes of OBJ text (data is not changed and need not be
 * NUL-terminated) into *mesh, zeroed first and again on failure. `name` is
 * the file name that error messages start with. */
vn_io_result vn_io_obj_read_memory(const char* data, size_t size, const char* name, vn_io_mesh* mesh,
                                   vn_io_error* error);

#ifdef __cplusplus
}
#endif

#endif /* VN_IO_OBJ_H */
