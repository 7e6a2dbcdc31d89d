/*
 * The glTF document as gltf.cpp edits it, shared with gltf_prune.cpp (C++
 * only, internal to vn_io): the original JSON, the buffers in place, and the
 * removal of what the edits left unused.
 */
#ifndef VN_IO_GLTF_DOCUMENT_H
#define VN_IO_GLTF_DOCUMENT_H

#include <cstdlib>
#include <memory>
#include <new>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gltf.h"

namespace vn_gltf {

using json = nlohmann::ordered_json;
using bytes = std::vector<unsigned char>;

/* A malloc'ed block of n bytes, freed with the last shared_ptr to it. */
inline std::shared_ptr<unsigned char> block(size_t n)
{
	unsigned char* p = (unsigned char*)malloc(n ? n : 1);
	if (!p)
		throw std::bad_alloc();
	return std::shared_ptr<unsigned char>(p, free);
}

/* A buffer's bytes: `size` bytes at `base`, inside `owner` (a malloc'ed
 * block: for a GLB's BIN chunk, the whole file as read), then what vn
 * appends, from tail_start() on. No view straddles the two parts. */
struct buffer {
	std::shared_ptr<unsigned char> owner;
	unsigned char* base = nullptr;
	size_t size = 0;
	bytes tail;
	size_t tail_start() const { return (size + 3) / 4 * 4; }
	size_t total() const { return tail.empty() ? size : tail_start() + tail.size(); }
	unsigned char* at(size_t offset) const
	{
		return offset < size ? base + offset : const_cast<unsigned char*>(tail.data()) + (offset - tail_start());
	}
};

struct document {
	bool glb = false;
	std::string folder;
	json j;
	std::vector<buffer> buffers;
	size_t input_views = 0; /* the file's bufferViews (lie in the buffers' first parts) */
};

inline constexpr const char* draco_name = "KHR_draco_mesh_compression";

/* A primitive's KHR_draco_mesh_compression object, or null. */
inline const json* draco_extension(const json& prim)
{
	auto e = prim.find("extensions");
	if (e == prim.end() || !e->is_object())
		return nullptr;
	auto k = e->find(draco_name);
	return k == e->end() ? nullptr : &*k;
}

/* Which accessors and bufferViews the document uses (directly, or through
 * a used accessor). */
struct usage {
	std::vector<bool> accessors, views;
};

usage used(json& j);

/* The first extension the document uses whose data may hold accessor,
 * bufferView or buffer indices that vn does not know of (so vn must not
 * renumber or merge them), or "". */
std::string unknown_extension(const json& j);

/* Removes what vn's changes left unused: accessors and bufferViews the
 * input used (before: used() of the document as loaded) and the output
 * does not, with their bytes; see gltf_prune.cpp. */
void prune(document& d, const usage& before, vn_gltf_stats& st, std::string* unknown);

} // namespace vn_gltf

#endif /* VN_IO_GLTF_DOCUMENT_H */
