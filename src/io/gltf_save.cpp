/*
 * Writing the document (gltf_document.h): a GLB (every buffer and image
 * merged into the BIN chunk) or a .gltf with its buffers in files beside it
 * (data URIs stay data URIs) and its external images copied, all written
 * to temporaries and renamed once complete.
 */
#include "gltf_document.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <map>
#include <set>

namespace vn_gltf {

static std::string base64(const bytes& data)
{
	static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
	std::string out;
	out.reserve((data.size() + 2) / 3 * 4);
	for (size_t i = 0; i < data.size(); i += 3) {
		uint32_t v = (uint32_t)data[i] << 16;
		if (i + 1 < data.size())
			v |= (uint32_t)data[i + 1] << 8;
		if (i + 2 < data.size())
			v |= data[i + 2];
		out += digits[v >> 18 & 63];
		out += digits[v >> 12 & 63];
		out += i + 1 < data.size() ? digits[v >> 6 & 63] : '=';
		out += i + 2 < data.size() ? digits[v & 63] : '=';
	}
	return out;
}

static std::string uri_encode(const std::string& s)
{
	std::string out;
	for (unsigned char c : s) {
		if (isalnum(c) || strchr("-._~", c))
			out += (char)c;
		else
			out += str("%%%02X", c);
	}
	return out;
}

/* True when o's "uri" is a data URI. */
static bool has_data_uri(const json& o)
{
	auto it = o.find("uri");
	return it != o.end() && it->is_string() && is_data_uri(it->get_ref<const std::string&>());
}

std::string data_uri(const json& buffer, const bytes& data)
{
	std::string type = "application/octet-stream";
	bytes ignored;
	std::string old;
	if (has_data_uri(buffer) && decode_data_uri(buffer["uri"].get<std::string>(), ignored, old) && !old.empty())
		type = old;
	return "data:" + type + ";base64," + base64(data);
}

static std::string le32_text(std::initializer_list<size_t> values)
{
	std::string out;
	for (size_t v : values)
		for (int i = 0; i < 4; ++i)
			out.push_back((char)(v >> (8 * i) & 0xff));
	return out;
}

/* A GLB of JSON j and the BIN chunk bin (null: none). */
pieces glb_file(const json& j, const buffer* bin)
{
	std::string text = j.dump();
	text.resize((text.size() + 3) / 4 * 4, ' ');
	const size_t bin_padded = bin ? (bin->total() + 3) / 4 * 4 : 0;
	const size_t total = 12 + 8 + text.size() + (bin ? 8 + bin_padded : 0);
	if (total > UINT32_MAX)
		fail(vn_io_error_unsupported, "the GLB would exceed 4 GiB");
	pieces out;
	out.add(le32_text({glb_magic, 2, total, text.size(), chunk_json}));
	out.add(std::move(text));
	if (bin) {
		out.add(le32_text({bin_padded, chunk_bin}));
		out.add(*bin, true);
	}
	return out;
}

namespace {

/* Output files written as temporaries beside their final paths, then all
 * put in place; the temporaries of an unfinished set are removed. vn_io_output
 * does what every output file needs: links followed, devices refused, mode
 * and owner kept, temporaries removed on a fatal signal too. */
struct file_set {
	std::vector<vn_io_output> files;
	~file_set()
	{
		for (vn_io_output& f : files)
			vn_io_output_discard(&f);
	}
	void add(const std::string& path, const pieces& contents)
	{
		files.reserve(files.size() + 1); /* push_back below cannot throw with the temporary open */
		vn_io_output output;
		vn_io_error e;
		vn_io_result r = vn_io_output_open(&output, path.c_str(), &e);
		if (r != vn_io_success)
			fail_named(r, e.message);
		files.push_back(output);
		vn_io_output& f = files.back();
		bool ok = true;
		for (const auto& piece : contents.list)
			for (size_t done = 0; ok && done < piece.second;) {
				ssize_t n = write(f.fd, piece.first + done, piece.second - done);
				if (n < 0 && errno == EINTR)
					continue;
				ok = n > 0;
				done += ok ? (size_t)n : 0;
			}
		if (!ok)
			fail_named(vn_io_error_write, str("%s: cannot write: %s", path.c_str(), strerror(errno)));
		/* Open until commit, a temporary keeps no name (vn_io_output): past
		 * a few hundred files, descriptors are scarcer than that. */
		if (files.size() > 256 && (r = vn_io_output_close(&f, &e)) != vn_io_success)
			fail_named(r, e.message);
	}
	void add(const std::string& path, const std::string& text)
	{
		pieces p;
		p.add(text.data(), text.size());
		add(path, p);
	}
	void commit()
	{
		for (vn_io_output& f : files) {
			vn_io_error e;
			vn_io_result r = vn_io_output_commit(&f, &e);
			if (r != vn_io_success)
				fail_named(r, e.message);
		}
		files.clear();
	}
};

} // namespace

static bool read_file(const std::string& path, bytes& out)
{
	char* raw;
	size_t size;
	vn_io_error e;
	if (vn_io_read_all(path.c_str(), &raw, &size, &e) != vn_io_success)
		return false;
	out.assign(raw, raw + size);
	free(raw);
	return true;
}

static bool same_folder(const std::string& a, const std::string& b)
{
	struct stat sa, sb;
	return stat(a.empty() ? "." : a.c_str(), &sa) == 0 && stat(b.empty() ? "." : b.c_str(), &sb) == 0 &&
	       sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* True when relative path `name` stays inside its folder: not absolute, no
 * ".." component. */
static bool stays_inside(const std::string& name)
{
	if (name.empty() || name[0] == '/')
		return false;
	for (size_t at = 0; at <= name.size();) {
		size_t end = name.find('/', at);
		if (end == std::string::npos)
			end = name.size();
		if (name.compare(at, end - at, "..") == 0)
			return false;
		at = end + 1;
	}
	return true;
}

/* An image's media type from its first bytes, "" when not one glTF uses. */
static std::string image_type(const bytes& data)
{
	auto starts = [&](const char* magic, size_t n, size_t at = 0) {
		return data.size() >= at + n && memcmp(data.data() + at, magic, n) == 0;
	};
	if (starts("\x89PNG\r\n\x1a\n", 8))
		return "image/png";
	if (starts("\xff\xd8\xff", 3))
		return "image/jpeg";
	if (starts("RIFF", 4) && starts("WEBP", 4, 8))
		return "image/webp";
	if (starts("\xabKTX 20\xbb\r\n\x1a\n", 12))
		return "image/ktx2";
	if (starts("ftypavif", 8, 4))
		return "image/avif";
	if (starts("DDS ", 4))
		return "image/vnd-ms.dds";
	return "";
}

/* The image media types a bufferView may hold in this document: PNG and
 * JPEG, and those its extensions add. The validator rejects any other in a
 * bufferView (where a URI only earns a warning), so such images stay as the
 * input has them. */
static std::set<std::string> embeddable_types(const json& j)
{
	std::set<std::string> types = {"image/png", "image/jpeg"};
	static const std::pair<const char*, const char*> by_extension[] = {{"KHR_texture_basisu", "image/ktx2"},
	                                                                   {"EXT_texture_webp", "image/webp"},
	                                                                   {"EXT_texture_avif", "image/avif"},
	                                                                   {"MSFT_texture_dds", "image/vnd-ms.dds"}};
	auto used = j.find("extensionsUsed");
	if (used != j.end() && used->is_array())
		for (const auto& e : by_extension)
			if (std::find(used->begin(), used->end(), json(e.first)) != used->end())
				types.insert(e.second);
	return types;
}

/* A GLB holds its data in the BIN chunk: every buffer with data is appended
 * to it (each at a multiple of 4, so views keep their alignment), and every
 * image a bufferView may hold goes into one with its mimeType. Merging
 * changes only bufferView.buffer and byteOffset and the buffers array, so
 * extensions that refer to accessors, bufferViews or images stay right;
 * the buffer indices EXT/KHR_meshopt_compression hold are rewritten too.
 * Buffers without data (fallbacks, placeholders) stay, as they were,
 * after the BIN chunk's. */
static void merge_for_glb(document& d)
{
	std::vector<size_t> start(d.buffers.size()), to(d.buffers.size());
	size_t size = 0, present = 0;
	for (size_t b = 0; b < d.buffers.size(); ++b)
		if (!d.buffers[b].absent) {
			start[b] = (size + 3) / 4 * 4;
			size = start[b] + d.buffers[b].total();
			to[b] = 0;
			++present;
		}
	for (size_t b = 0, next = 1; b < d.buffers.size(); ++b)
		if (d.buffers[b].absent)
			to[b] = next++;
	/* Images: read first, so the block is allocated once. */
	const std::set<std::string> allowed = embeddable_types(d.j);
	std::vector<std::pair<size_t, bytes>> images;
	auto ji = d.j.find("images");
	for (size_t i = 0; ji != d.j.end() && ji->is_array() && i < ji->size(); ++i) {
		json& image = (*ji)[i];
		if (!image.is_object() || !image.contains("uri") || !image["uri"].is_string())
			continue;
		bytes data;
		std::string type;
		if (has_data_uri(image)) {
			if (!decode_data_uri(image["uri"].get<std::string>(), data, type))
				continue; /* stays as the input has it */
		} else {
			const std::string name = file_uri(image);
			if (name.empty() || d.missing_images.count(i))
				continue; /* a URL, or a file not there: stays by URI */
			if (!read_file(d.folder + name, data))
				fail_named(vn_io_error_open, str("%s: cannot read images[%zu] ('%s') to put it into the GLB",
				                                 (d.folder + name).c_str(), i, name.c_str()));
		}
		if (data.empty())
			continue; /* nothing to embed (a bufferView holds a byte at least): stays as it is */
		/* What the bytes are, else what the file says they are. */
		std::string sniffed = image_type(data);
		if (sniffed.empty())
			sniffed = type != "application/octet-stream" && !type.empty() ? type
			          : image.contains("mimeType") && image["mimeType"].is_string() ? image["mimeType"].get<std::string>()
			                                                                         : "";
		if (!allowed.count(sniffed))
			continue; /* kept by URI: copied beside the GLB when it is a file (save) */
		image["mimeType"] = sniffed;
		images.emplace_back(i, std::move(data));
	}
	std::vector<size_t> image_start;
	for (const auto& im : images) {
		image_start.push_back((size + 3) / 4 * 4);
		size = image_start.back() + im.second.size();
	}
	if (!present && images.empty()) {
		if (!d.buffers.empty())
			fail(vn_io_error_unsupported,
			     "buffers[0] has no data (no uri, and no extension that gives it), and buffer 0 without uri is a GLB's "
			     "BIN chunk: write .gltf to keep the file as it is");
		return; /* no buffers, no data: none are made */
	}
	auto jb = d.j.find("buffers");
	if (present == 1 && images.empty() && !d.buffers[0].absent) {
		(*jb)[0].erase("uri"); /* buffer 0 becomes the BIN chunk as it is */
		return;
	}
	buffer merged;
	merged.owner = block(size);
	merged.base = merged.owner.get();
	merged.size = size;
	memset(merged.base, 0, size);
	for (size_t b = 0; b < d.buffers.size(); ++b) {
		const buffer& from = d.buffers[b];
		if (from.absent)
			continue;
		if (from.size) /* a buffer of no bytes (one vn made for new data holds only its tail) */
			memcpy(merged.base + start[b], from.base, from.size);
		for (const auto& block : from.tail)
			if (!block.second.empty())
				memcpy(merged.base + start[b] + from.tail_start() + block.first, block.second.data(), block.second.size());
	}
	/* ref is holder's buffer index. It is written before byteOffset, whose
	 * insertion into holder would move ref. */
	auto relocate = [&](json& ref, json& holder, const std::string& what) {
		const long long b = ref.get<long long>();
		if (b < 0 || (size_t)b >= start.size())
			return;
		const size_t offset = start[(size_t)b] + (size_t)get_int(holder, "byteOffset", 0, what);
		ref = to[(size_t)b];
		if (!d.buffers[(size_t)b].absent)
			holder["byteOffset"] = offset;
	};
	auto views = d.j.find("bufferViews");
	for (size_t v = 0; views != d.j.end() && views->is_array() && v < views->size(); ++v) {
		json& view = (*views)[v];
		if (!view.is_object())
			continue;
		const std::string what = str("bufferViews[%zu]", v);
		extension_buffers(view, [&](json& ref, json& ext) { relocate(ref, ext, what + ".extensions"); });
		/* Any non-negative integer: a reference vn renumbered is signed in
		 * the JSON (remove_buffers), the file's are unsigned. */
		if (view.contains("buffer") && view["buffer"].is_number_integer() && view["buffer"].get<long long>() >= 0)
			relocate(view["buffer"], view, what);
	}
	json kept = json::array();
	std::vector<buffer> buffers;
	json first = json::object();
	for (size_t b = 0; jb != d.j.end() && b < d.buffers.size(); ++b)
		if (!d.buffers[b].absent) {
			first = (*jb)[b];
			break;
		}
	first.erase("uri");
	first["byteLength"] = size;
	kept.push_back(first);
	buffers.push_back(std::move(merged));
	for (size_t b = 0; b < d.buffers.size(); ++b)
		if (d.buffers[b].absent) {
			kept.push_back((*jb)[b]);
			buffers.push_back(std::move(d.buffers[b]));
		}
	d.j["buffers"] = std::move(kept);
	d.buffers = std::move(buffers);
	for (size_t k = 0; k < images.size(); ++k) {
		memcpy(d.buffers[0].base + image_start[k], images[k].second.data(), images[k].second.size());
		if (!d.j.contains("bufferViews"))
			d.j["bufferViews"] = json::array();
		d.j["bufferViews"].push_back(json{{"buffer", 0}, {"byteOffset", image_start[k]}, {"byteLength", images[k].second.size()}});
		json& image = d.j["images"][images[k].first];
		image.erase("uri");
		image["bufferView"] = d.j["bufferViews"].size() - 1;
	}
}

/* Creates the folders of relative path `name` below `folder` that are
 * missing. */
static void make_folders(const std::string& folder, const std::string& name)
{
	for (size_t slash = name.find('/'); slash != std::string::npos; slash = name.find('/', slash + 1)) {
		const std::string sub = folder + name.substr(0, slash);
		if (mkdir(sub.c_str(), 0777) != 0 && errno != EEXIST)
			fail_named(vn_io_error_write, str("%s: cannot create the folder: %s", sub.c_str(), strerror(errno)));
	}
}

/* External images keep their URIs when they stay inside the output's
 * folder (copied there when it is another folder, folders made as needed;
 * one whose file the input lacks keeps its URI, load's warning);
 * one that would land outside it ("../tex/a.png") is copied into it under
 * its own name. A prefix goes before each copy's file name
 * ("tex/a.png" -> "tex/PREFIXa.png"). */
static void copy_images(document& d, const std::string& folder, const std::string& prefix, file_set& files)
{
	auto images = d.j.find("images");
	if (images == d.j.end() || !images->is_array() || same_folder(d.folder, folder))
		return;
	std::map<std::string, bytes> placed; /* name in the output folder -> contents */
	for (size_t i = 0; i < images->size(); ++i) {
		json& image = (*images)[i];
		const std::string name = image.is_object() ? file_uri(image) : "";
		if (name.empty() || d.missing_images.count(i))
			continue;
		bytes data, existing;
		if (!read_file(d.folder + name, data))
			fail_named(vn_io_error_open, str("%s: cannot read the image '%s'", (d.folder + name).c_str(), name.c_str()));
		const bool outside = !stays_inside(name);
		std::string to = outside ? name.substr(name.rfind('/') == std::string::npos ? 0 : name.rfind('/') + 1) : name;
		to.insert(to.rfind('/') == std::string::npos ? 0 : to.rfind('/') + 1, prefix);
		if (outside) {
			const std::string base = to;
			const size_t ext = base.rfind('.');
			for (size_t n = 1; placed.count(to) && placed[to] != data; ++n)
				to = (ext == std::string::npos || ext == 0 ? base : base.substr(0, ext)) + str("_%zu", n) +
				     (ext == std::string::npos || ext == 0 ? "" : base.substr(ext));
		}
		if (to != name)
			image["uri"] = uri_encode(to);
		if (placed.count(to))
			continue;
		placed[to] = data;
		if (read_file(folder + to, existing)) {
			if (existing != data)
				fail_named(vn_io_error_write, str("%s exists and differs from the input's image; not overwritten",
				                                  (folder + to).c_str()));
			continue;
		}
		make_folders(folder, to);
		files.add(folder + to, std::string(data.begin(), data.end()));
	}
}

/* Writes the document to path: a GLB with every buffer and the images it
 * may hold in its BIN chunk, or a .gltf with its buffers in files beside it
 * (the input's own names when writing in place, else OUTSTEM.bin,
 * OUTSTEM_1.bin, ...); buffers without data stay without; images kept by
 * URI are copied next to it when the folder differs, never outside path's
 * folder. */
void save(document& d, const std::string& path, bool glb, bool in_place, bool stem_images)
{
	file_set files;
	const std::string folder = folder_of(path);
	std::string stem = path.substr(folder.size());
	size_t dot = stem.rfind('.');
	if (dot != std::string::npos && dot > 0)
		stem.resize(dot);
	const std::string image_prefix = stem_images ? stem + "_" : "";
	if (glb) {
		merge_for_glb(d);
		copy_images(d, folder, image_prefix, files);
		const bool bin = !d.buffers.empty() && !d.buffers[0].absent;
		files.add(path, glb_file(d.j, bin ? &d.buffers[0] : nullptr));
		files.commit();
		return;
	}
	auto jb = d.j.find("buffers");
	/* A new buffer file must not replace one of the input's (also one the
	 * edits left unused). */
	auto is_input = [&](const std::string& p) {
		return std::any_of(d.buffer_files.begin(), d.buffer_files.end(),
		                   [&](const std::string& q) { return vn_io_same_file(p.c_str(), q.c_str()); });
	};
	size_t k = 0;
	for (size_t i = 0; i < d.buffers.size(); ++i) {
		json& b = (*jb)[i];
		if (d.buffers[i].absent)
			continue;
		if (has_data_uri(b)) {
			pieces p;
			p.add(d.buffers[i], false);
			b["uri"] = data_uri(b, p.joined());
			continue;
		}
		/* In place, a buffer keeps its file; one that had none (a meshopt
		 * fallback --meshopt off fills) gets a new name, as others do. */
		std::string name = in_place ? file_uri(b) : "";
		const bool kept = !name.empty();
		while (!kept && (name.empty() || is_input(folder + name)))
			name = stem + (k ? str("_%zu", k) : "") + ".bin", ++k;
		if (!kept)
			b["uri"] = uri_encode(name);
		pieces contents;
		contents.add(d.buffers[i], false);
		files.add(folder + name, contents);
	}
	copy_images(d, folder, image_prefix, files);
	files.add(path, d.j.dump(2) + "\n");
	files.commit();
}

} // namespace vn_gltf
