/*
 * The glTF document as the glTF stages edit it (C++ only, internal to
 * vn_io): the original JSON, the buffers in place, the failures thrown on
 * the way, reading and appending accessors (gltf_document.cpp), meshopt
 * compression (gltf_meshopt.cpp), the removal of what the edits left
 * unused (gltf_prune.cpp) and writing the files (gltf_save.cpp). The
 * triangle primitives built on it are in gltf_primitive.h.
 */
#ifndef VN_IO_GLTF_DOCUMENT_H
#define VN_IO_GLTF_DOCUMENT_H

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <new>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
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
 * appends, from tail_start() on: a block per appended view, at its offset
 * from tail_start() (one growing block would be copied as it grows, and
 * hold up to twice its size). No view straddles two parts. A buffer
 * without data (no uri, and not a GLB's BIN chunk: a placeholder, or a
 * meshopt fallback) is `absent`: it is written back as it was, without
 * data. Its meshopt views' decoded data fill it in memory (base and size;
 * gltf_meshopt.cpp), where the stages read them; a view of it that no
 * extension gives data is an error when read. */
struct buffer {
	std::shared_ptr<unsigned char> owner;
	unsigned char* base = nullptr;
	size_t size = 0;
	/* The end of the file's furthest view of it where that is past size
	 * (an invalid file: the validator's BUFFER_VIEW_TOO_LONG), else 0: what
	 * vn appends starts after it, so that no appended view overlaps one of
	 * the file's. */
	size_t reserved = 0;
	bool absent = false;
	std::vector<std::pair<size_t, bytes>> tail;
	size_t tail_start() const { return (std::max(size, reserved) + 3) / 4 * 4; }
	size_t tail_size() const { return tail.empty() ? 0 : tail.back().first + tail.back().second.size(); }
	size_t total() const { return tail.empty() ? size : tail_start() + tail_size(); }
	unsigned char* at(size_t offset) const
	{
		if (offset < size)
			return base + offset;
		offset -= tail_start();
		auto block = std::upper_bound(tail.begin(), tail.end(), offset,
		                              [](size_t o, const std::pair<size_t, bytes>& b) { return o < b.first; }) - 1;
		return const_cast<unsigned char*>(block->second.data()) + (offset - block->first);
	}
};

struct document {
	bool glb = false;
	std::string folder;
	json j;
	std::vector<buffer> buffers;
	size_t input_views = 0; /* the file's bufferViews (lie in the buffers' first parts) */
	std::vector<std::string> buffer_files; /* the paths of the file's buffers read from files */
	/* Buffers in which vn's edits left bytes that nothing refers to (meshopt
	 * data encoded again or no longer written): prune packs them. */
	std::set<size_t> repack;
	std::vector<std::string> warnings; /* about the input, read anyway ("the GLB has 4 bytes after ...") */
	std::set<size_t> missing_images; /* images whose file cannot be read: kept by URI */
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

/* The meshopt compression extensions: on a bufferView, where its
 * compressed data lie (buffer, byteOffset, byteLength) and how to decode
 * them; on a buffer, the fallback marker. */
inline constexpr const char* meshopt_names[] = {"EXT_meshopt_compression", "KHR_meshopt_compression"};

/* The buffer indices that extensions known to hold them keep in bufferViews:
 * the meshopt extensions' compressed data. f(ref, ext) for each, ref the
 * json of ext's buffer index. */
template <typename F> void extension_buffers(json& view, F f)
{
	auto ext = view.find("extensions");
	if (ext == view.end() || !ext->is_object())
		return;
	for (const char* name : meshopt_names) {
		auto e = ext->find(name);
		if (e != ext->end() && e->is_object() && e->contains("buffer") && (*e)["buffer"].is_number_unsigned())
			f((*e)["buffer"], *e);
	}
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

/* ------------------------------------------------------------------ failures (gltf_document.cpp) */

/* Every failure is thrown as one of these and turned into a vn_io_error at
 * the C boundary. msg never names the file: the boundary prefixes it. */
struct failure {
	vn_io_result result;
	std::string msg;
	bool names_file; /* msg starts with the file it is about */
};

/* A failure about the file being read (the caller prefixes its name). */
[[noreturn]] void fail(vn_io_result r, const std::string& msg);

/* A failure whose message names its own file ("out.bin: cannot write"). */
[[noreturn]] void fail_named(vn_io_result r, const std::string& msg);

/* printf into a std::string (up to 511 characters). */
std::string str(const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* f as a vn_io_error about path (unless its message names its own file). */
vn_io_result to_error(const failure& f, const char* path, vn_io_error* error);

/* Runs body, turning every failure and exception into a vn_io_result. */
template <typename F> vn_io_result guarded(const char* path, vn_io_error* error, F body)
{
	try {
		body();
		return vn_io_success;
	} catch (const failure& f) {
		return to_error(f, path, error);
	} catch (const std::bad_alloc&) {
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	} catch (const std::exception& x) {
		return vn_io_fail(error, vn_io_error_parse, "%s: %s", path, x.what());
	}
}

/* ------------------------------------------------------------------ the document (gltf_document.cpp) */

const uint32_t glb_magic = 0x46546C67, chunk_json = 0x4E4F534A, chunk_bin = 0x004E4942;

/* The folder part of path, with its final '/' ("" for none). */
std::string folder_of(const std::string& path);
/* A URI's %XX escapes decoded. */
std::string uri_decode(const std::string& s);
/* True when uri is a data URI ("data:", any case). */
bool is_data_uri(const std::string& uri);
/* An external resource's URI (not a data URI, not another scheme's URL such
 * as https://, which vn neither reads nor copies), decoded; "" otherwise. */
std::string file_uri(const json& o);
/* Decodes a data URI as RFC 2397 defines it: "data:[type][;params][;base64],
 * data", the data base64 or percent-encoded. Sets the media type ("" when
 * the URI gives none); false when it is not a well-formed data URI. */
bool decode_data_uri(const std::string& uri, bytes& data, std::string& media_type);

long long get_int(const json& o, const char* key, long long def, const std::string& what);
/* A non-negative integer property, or -1 (absent or anything else): for
 * reading what may be invalid without failing. */
long long index_or_none(const json& o, const char* key);
/* doc[array][i], which must exist and be an object. */
const json& element(const json& doc, const char* array, long long i, const std::string& what);
/* Bytes per component of glTF component type `type` (0: not one). */
size_t component_size(long long type);

/* Where an accessor's or sparse part's elements lie in a buffer. */
struct span {
	int buffer = -1; /* -1: no bufferView (zeros) */
	size_t offset = 0, stride = 0;
};

struct accessor {
	long long count = 0, component = 0;
	size_t components = 0, element = 0;
	bool normalized = false;
	span data;
	/* sparse */
	long long sparse_count = 0, sparse_index_component = 0;
	span sparse_indices, sparse_values;
};

unsigned char* element_at(const document& d, const span& s, size_t i);
span view_span(const document& d, long long view, size_t offset, size_t needed, size_t element_size,
               const std::string& what);
/* Accessor `index`, checked against its bufferViews and buffers. */
accessor get_accessor(const document& d, long long index);
double read_component(const unsigned char* p, long long type, bool normalized);
double normalized_value(double v, long long type);
void write_component(unsigned char* p, long long type, double v);
std::vector<double> read_accessor(const document& d, const accessor& a);

/* Reads the .gltf or .glb file at path with its buffers. */
document load(const std::string& path);
/* d's warnings, one a line. */
std::string warning_lines(const document& d);

/* An accessor's min and max replaced, where it has them. */
void set_bounds(json& a, const std::vector<double>& lo, const std::vector<double>& hi, long long component);
void set_bounds(json& j, const bytes& data, size_t stride, const accessor& a, size_t count);

/* data appended to buffer b (at a multiple of 4): its offset. */
size_t append_bytes(document& d, size_t b, bytes data);
/* A new bufferView holding data, a new accessor: their indices. */
size_t append_view(document& d, bytes data, size_t stride, int target);
long long append_accessor(document& d, json a);
/* a, a new indices accessor for primitive prim, with the name and extras of
 * the one it replaces (when prim has indices), which the file gave it. */
json with_indices_label(const document& d, const json& prim, json a);

/* ------------------------------------------------------------------ meshopt (gltf_meshopt.cpp) */

/* bufferView `view`'s EXT_ or KHR_meshopt_compression object, or null;
 * *name is its extension's. A view with both is malformed. */
inline const json* meshopt_extension(const json& view, const char** name, const std::string& what)
{
	auto ext = view.find("extensions");
	if (ext == view.end() || !ext->is_object())
		return nullptr;
	const json* found = nullptr;
	for (const char* n : meshopt_names) {
		auto e = ext->find(n);
		if (e == ext->end())
			continue;
		if (found)
			fail(vn_io_error_parse, what + " has both EXT_meshopt_compression and KHR_meshopt_compression");
		found = &*e;
		*name = n;
	}
	return found;
}

/* Every meshopt-compressed bufferView of the input decoded into its own
 * range of its (fallback) buffer, so that the stages read plain data; see
 * gltf_meshopt.cpp. st (may be null) counts them. Returns the names of the
 * extensions they use. */
std::set<std::string> decode_meshopt(document& d, vn_gltf_stats* st);

/* After the normals: --meshopt keep encodes again the views whose decoded
 * data changed (the others keep their compressed bytes), off leaves every
 * view plain; see gltf_meshopt.cpp. */
void write_meshopt(document& d, vn_gltf_meshopt mode, vn_gltf_stats& st);

/* After prune: each of `names` (the input's meshopt extensions) that no
 * bufferView uses any more (none, with --meshopt off) leaves
 * extensionsUsed, extensionsRequired and the buffers' fallback markers. */
void tidy_meshopt(document& d, const std::set<std::string>& names);

/* ------------------------------------------------------------------ writing (gltf_save.cpp) */

/* A file's contents: byte ranges written one after the other, and the
 * small pieces (headers, JSON, padding) they include, owned here. */
struct pieces {
	std::vector<std::pair<const unsigned char*, size_t>> list;
	std::vector<std::unique_ptr<std::string>> owned;
	void add(const void* data, size_t n)
	{
		if (n)
			list.emplace_back((const unsigned char*)data, n);
	}
	void add(std::string text)
	{
		owned.emplace_back(new std::string(std::move(text)));
		add(owned.back()->data(), owned.back()->size());
	}
	/* Buffer b, padded with zeros to a multiple of 4 bytes when `pad`. */
	void add(const buffer& b, bool pad)
	{
		add(b.base, b.size);
		size_t at = b.size;
		for (const auto& block : b.tail) {
			add(std::string(b.tail_start() + block.first - at, '\0'));
			add(block.second.data(), block.second.size());
			at = b.tail_start() + block.first + block.second.size();
		}
		if (pad)
			add(std::string((4 - b.total() % 4) % 4, '\0'));
	}
	/* The pieces in one block (for a data URI). */
	bytes joined() const
	{
		bytes out;
		for (const auto& piece : list)
			out.insert(out.end(), piece.first, piece.first + piece.second);
		return out;
	}
};

/* buffer's "uri" for data, as a base64 data URI (with its media type when
 * it had one). */
std::string data_uri(const json& buffer, const bytes& data);

/* A GLB of JSON j and the BIN chunk bin (null: none). */
pieces glb_file(const json& j, const buffer* bin);

/* Writes the document to path as GLB or .gltf; see gltf_save.cpp. Images
 * copied into path's folder are named PATHSTEM_NAME with stem_images. */
void save(document& d, const std::string& path, bool glb, bool in_place, bool stem_images);

} // namespace vn_gltf

#endif /* VN_IO_GLTF_DOCUMENT_H */
