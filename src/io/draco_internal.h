/*
 * What the two halves of vn's Draco glue share (C++ only, internal to
 * vn_io): draco.cpp (the bitstream: decoding, encoding, quantization grids)
 * defines these, draco_mesh.cpp (Draco to and from vn_io_mesh, .drc to .drc,
 * the normal error) uses them.
 */
#ifndef VN_IO_DRACO_INTERNAL_H
#define VN_IO_DRACO_INTERNAL_H

#include <cstddef>
#include <vector>

#include "draco.h"

namespace vn_drc {

/* Bytes per point of attribute a. */
size_t value_bytes(const vn_drc_attribute& a);

/* Component i (point i / components) of attribute a, as a double (which
 * holds every value of the 32-bit types exactly). */
double component(const vn_drc_attribute& a, size_t i);

/* Draco's name of each attribute type (vn_drc_semantic). */
extern const char* const semantic_names[vn_drc_semantic_count];

/* g Draco-encoded into *bytes: vn_drc_encode without the copy. */
vn_io_result encode(const vn_drc_geometry* g, int level, bool keep_order, const char* name, std::vector<char>* bytes,
                    vn_io_error* error);

} // namespace vn_drc

#endif /* VN_IO_DRACO_INTERNAL_H */
