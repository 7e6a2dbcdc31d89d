/*
 * Wavefront OBJ.
 *
 * Reader: Draco's ObjDecoder (1.5.5), which keeps v/vt/vn, faces of 3 to 8
 * corners as triangle fans, the `usemtl` and `o` of each face (GENERIC
 * "material" and "sub_obj" attributes, their names in the attribute
 * metadata), and skips every other line (the `g` and `s` of each face,
 * groups and smoothing groups, come from the scan). It checks neither index
 * ranges nor that its two passes over a face line agree ("f 1 2 3 # note"
 * counts 3 triangles, then fills 1), and reads memory out of bounds when
 * they are wrong; so a scan that reads each line as Draco does comes first,
 * and only a file it passes goes to Draco. The scan also gives file:line
 * errors, refuses NaN and infinite numbers, and hands Draco a copy where a
 * comment after a face is blanked, a tab after `v` or `o` is a space and a
 * lone CR ends a line (Draco reads those lines differently or not at all), a
 * face of more than 8 corners is split into faces Draco takes, a vt of one
 * number gets its v (0, as the specification says), a corner's vt or vn
 * index is dropped where the file has no such lines, and `mtllib` is a
 * comment: reading from memory, Draco would look for the .mtl in the current
 * folder, and it only adds names, in another order, from it; the `mtllib`
 * argument is kept instead, with the file's folder (the writer names the
 * libraries from its output's folder). Polygons are put back together from
 * the corner counts the scan saw (Draco's preserve_polygons would do it from
 * an "added_edges" attribute, which splits points further and cannot tell
 * the split pieces of a long face apart).
 *
 * Draco is asked to keep every v, vt and vn line's value (no deduplication),
 * and the scan's doubles replace its floats for v and vn; a vertex is one
 * (v, vt, vn) combination, a v line by its number (equal v lines stay
 * apart, as every other reader keeps them) and vt and vn lines by their
 * values (bit for bit: a repeated value splits nothing), and each v line no
 * face uses is a vertex of its own after those.
 * A file without faces (f) is a point cloud: a vertex a v line, with the vt
 * and vn lines of the same number (Draco's reading; so their counts must be
 * 0 or the v lines'). Lines (l), which Draco skips, are read by the scan:
 * each point the vertex of its v line (the first, where faces split it).
 *
 * Vertex colours are read from v lines of "x y z r g b" (MeshLab, Open3D),
 * when every v line has them, in [0, 1] (Draco skips them); as bytes
 * (colors_are_bytes) when each is one over 255 with 6 decimals or more
 * (vn_io_colors_are_bytes: MeshLab's "%f" of 192 / 255, 0.752941).
 *
 * Writer: v (with "r g b" when the mesh has colours), vt and vn lines, each
 * value once (a vertex split for its normal or texture coordinate shares its
 * v line), then faces as v/vt/vn with `o`, `g`, `usemtl` and `s` where
 * they change, then lines (l) of v numbers. A point cloud: a v line a
 * vertex, and as many vt and vn lines.
 */
#include "obj.h"

extern "C" {
#include "text.h"
}

#include <draco/io/obj_decoder.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cfloat>
#include <cinttypes>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

/* isspace() in the C locale, as Draco's parser tests it. */
bool space(char c)
{
	return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

/* parser::ParseUnsignedInt and ParseSignedInt, the text up to end: uint32
 * arithmetic, wrapping as Draco's does; *overflow tells when it wrapped. */
bool draco_signed(const char*& q, const char* end, int32_t* value, bool* overflow)
{
	int sign = 1;
	if (q < end && (*q == '-' || *q == '+'))
		sign = *q++ == '-' ? -1 : 1;
	uint32_t v = 0;
	uint64_t exact = 0;
	const char* digits = q;
	for (; q < end && *q >= '0' && *q <= '9'; q++) {
		v = v * 10 + uint32_t(*q - '0');
		exact = std::min<uint64_t>(exact * 10 + uint64_t(*q - '0'), UINT64_C(1) << 32);
	}
	if (q == digits)
		return false;
	*value = int32_t(sign < 0 ? 0u - v : v);
	if (overflow)
		*overflow = exact > INT32_MAX;
	return true;
}

/* parser::ParseFloat's arithmetic after the sign (so the same value): digits,
 * '.', digits, then an exponent; *digits says whether there was a digit
 * (if not, *out is 0 and the exponent is not read). False when an exponent
 * has no digits. */
bool draco_magnitude(const char*& q, const char* end, double* out, bool* digits)
{
	double v = 0.0;
	*digits = false;
	for (; q < end && *q >= '0' && *q <= '9'; q++, *digits = true)
		v = v * 10.0 + (*q - '0');
	if (q < end && *q == '.') {
		double fraction = 1.0;
		for (q++; q < end && *q >= '0' && *q <= '9'; q++, *digits = true) {
			fraction *= 0.1;
			v += (*q - '0') * fraction;
		}
	}
	if (*digits && q < end && (*q == 'e' || *q == 'E')) {
		int32_t exponent;
		if (!draco_signed(++q, end, &exponent, nullptr))
			return false;
		v *= std::pow(10.0, exponent);
	}
	*out = v;
	return true;
}

/* Draco's face limit (ObjDecoder::ParseFace, kMaxCorners): longer faces
 * are split for it (scanner::rewritten). */
const int max_corners = 8;

/* Reads an OBJ the way Draco's ObjDecoder does (ParseDefinition and the
 * parser_utils it calls), line by line: a first pass counts v, vt and vn
 * lines and triangles, a second checks every number and index against
 * those counts. */
/* A corner as an f line writes it: v, v/vt, v/vt/vn or v//vn. */
std::string corner_text(const std::array<int32_t, 3>& c)
{
	std::string t = std::to_string(c[0]);
	if (c[1] || c[2])
		t += "/" + (c[1] ? std::to_string(c[1]) : std::string());
	if (c[2])
		t += "/" + std::to_string(c[2]);
	return t;
}

struct scanner {
	const char* name;
	vn_io_error* error;
	char* begin;
	char* end;
	bool counting = true;

	/* Totals from the counting pass, and counts so far in this pass. */
	int64_t total[3] = {0, 0, 0};
	int64_t seen[3] = {0, 0, 0};
	uint64_t triangles = 0;
	uint64_t short_faces = 0; /* f lines of fewer than 3 corners, skipped */
	size_t first_short_face = 0;
	/* The l lines (the checking pass): their points' v lines (0-based),
	 * line_offsets[k] the first of line k's (one more entry than lines);
	 * and the lines skipped (polyline). */
	std::vector<uint32_t> line_points, line_offsets;
	uint64_t skipped_lines = 0;
	size_t first_skipped_line = 0;
	int64_t first_material = -1, first_object = -1; /* triangles before the first usemtl and o */
	std::string library;
	/* Corners of each face, in order, and whether one has a vt (the
	 * checking pass). */
	std::vector<uint32_t> face_corners;
	std::vector<unsigned char> face_textured;
	/* Faces of more than max_corners corners: where their f line is, and
	 * their corners as Draco parses them. */
	struct long_face {
		size_t begin, end;
		std::vector<std::array<int32_t, 3>> corners;
	};
	std::vector<long_face> long_faces;
	/* Where a vt line of one number ends it: " 0" goes there (the
	 * specification's default v; Draco reads two numbers). */
	std::vector<size_t> short_texcoords;
	/* Corners that refer to vt or vn lines (kind 1, 2) of a file that has
	 * none (an exporter wrote the indices but not the lines): read without
	 * them, with a warning; the first one's line. */
	uint64_t dangling[3] = {0, 0, 0};
	size_t first_dangling[3] = {0, 0, 0};
	/* The numbers of the v and vn lines (exact[0], exact[2]; 3 a line) as
	 * doubles, in the checking pass: Draco reads floats, which would move
	 * a georeferenced 4123456.11 to 4123456. */
	std::vector<double> exact[3];
	/* The r g b of v lines that have them (MeshLab's and Open3D's vertex
	 * colours: three numbers in [0, 1] after x y z), 3 a line; used when
	 * every v line has them (coloured()). */
	std::vector<float> colours;
	/* Lines whose data Draco skips, by keyword (in order of first
	 * appearance, at most left_out_max kinds), counted in the checking
	 * pass; v lines with more than x y z (colours, or w); vt lines with
	 * numbers after u v other than a w of 0 (w's default: exporters write
	 * "vt u v 0"); and which vt lines a face uses (1 a line). */
	static const size_t left_out_max = 8;
	std::vector<std::pair<std::string, uint64_t>> left_out;
	uint64_t left_out_kinds = 0, extra_vertex_numbers = 0, extra_texcoord_numbers = 0;
	std::vector<char> texcoord_used;
	size_t first_left_out = 0; /* its line */
	/* The arguments of `g` or `s` lines as written ("" for a bare `g`: the
	 * default group), and each face's (the checking pass): Draco skips
	 * those lines. */
	struct face_sets {
		std::vector<std::string> names;
		std::unordered_map<std::string, uint32_t> index;
		uint32_t current = VN_IO_NO_NAME; /* before the first line */
		std::vector<uint32_t> of_face;
		void clear() { *this = face_sets(); }
		void start(const std::string& argument)
		{
			current = index.emplace(argument, uint32_t(names.size())).first->second;
			if (current == names.size())
				names.push_back(argument);
		}
	};
	face_sets groups, smoothing;

	size_t line = 1;
	const char* line_end = nullptr;
	vn_io_result result = vn_io_success; /* of the first failure */

#if defined(__GNUC__)
	__attribute__((format(printf, 3, 4)))
#endif
	bool fail(vn_io_result r, const char* fmt, ...)
	{
		char what[400];
		va_list args;
		va_start(args, fmt);
		vsnprintf(what, sizeof what, fmt, args);
		va_end(args);
		result = vn_io_fail(error, r, "%s:%zu: %s", name, line, what);
		return false;
	}

	/* The token at q (to the next blank), for messages. */
	int token_length(const char* q) const
	{
		const char* t = q;
		while (t < line_end && !space(*t) && t - q < 40)
			t++;
		return int(t - q);
	}

	void skip_blanks(const char*& q) const
	{
		while (q < line_end && space(*q))
			q++;
	}

	/* parser::ParseUnsignedInt and ParseSignedInt: uint32 arithmetic,
	 * wrapping as Draco's does; *overflow tells when it wrapped. */
	bool parse_signed(const char*& q, int32_t* value, bool* overflow = nullptr) const
	{
		return draco_signed(q, line_end, value, overflow);
	}

	/* An index: as Draco reads it, or 0 (refused) when it wrapped. */
	bool parse_index(const char*& q, int32_t* value) const
	{
		bool overflow;
		return parse_signed(q, value, &overflow) && !overflow && *value != 0;
	}

	/* parser::ParseFloat, with the same arithmetic (so the same value); a
	 * word it reads for "inf" or "nan" has to be on the line. */
	bool parse_float(const char*& q, float* value) const
	{
		int sign = 1;
		if (q < line_end && (*q == '-' || *q == '+'))
			sign = *q++ == '-' ? -1 : 1;
		bool digits;
		double v;
		if (!draco_magnitude(q, line_end, &v, &digits))
			return false;
		if (!digits) {
			skip_blanks(q);
			const int n = token_length(q);
			const std::string word(q, size_t(n));
			q += n;
			if (word == "inf" || word == "Inf")
				v = HUGE_VAL;
			else if (word == "nan" || word == "NaN")
				v = NAN;
			else
				return false;
		}
		*value = sign < 0 ? float(-v) : float(v);
		return true;
	}

	/* ObjDecoder::ParseVertexIndices: "v", "v/vt", "v/vt/vn" or "v//vn";
	 * also "v/", "v//" and "v/vt/" (exporters write them for an empty
	 * slot), which Draco refuses: face() blanks their last slashes. */
	bool parse_corner(const char*& q, int32_t* index) const
	{
		while (q < line_end && (*q == ' ' || *q == '\t'))
			q++;
		if (!parse_index(q, &index[0]))
			return false;
		index[1] = index[2] = 0;
		if (q == line_end || *q != '/')
			return true;
		if (++q == line_end || space(*q))
			return true;
		if (*q != '/' && !parse_index(q, &index[1]))
			return false;
		if (q == line_end || *q != '/')
			return true;
		if (++q == line_end || space(*q))
			return true;
		return parse_index(q, &index[2]);
	}

	/* A v, vt or vn line (kind 0, 1, 2) after its keyword. A vt may have
	 * one number (u; v is then 0, as the specification says). */
	bool numbers(const char* q, int kind)
	{
		static const char* const kinds[3] = {"vertex", "texture coordinate", "normal"};
		static const int needed[3] = {3, 2, 3};
		const int64_t index = ++seen[kind];
		if (counting)
			return true;
		for (int i = 0; i < needed[kind]; i++) {
			const char* after = q;
			skip_blanks(q);
			if (kind == 1 && i == 1 && (q == line_end || *q == '#')) {
				short_texcoords.push_back(size_t(after - begin));
				break;
			}
			if (q == line_end)
				return fail(vn_io_error_parse, "%s %" PRId64 " has %d numbers; it needs %d", kinds[kind], index, i,
				            kind == 1 ? 1 : needed[kind]);
			const char* start = q;
			float v;
			/* Draco stops at the first character that is not part of a
			 * number: "3,5" (a decimal comma) would read as 3. */
			if (!parse_float(q, &v) || (q < line_end && !space(*q) && *q != '#'))
				return fail(vn_io_error_parse, "%s %" PRId64 ": '%.*s' is not a number", kinds[kind], index,
				            token_length(start), start);
			/* strtod's correctly rounded double where it reads the whole
			 * number as Draco did; Draco's float where it reads another
			 * spelling (none is known). Not finite in either (Draco's float
			 * of 1e3914896774291992 is finite, the double is not): refused. */
			double d;
			const double x =
			    kind != 1 && vn_io_parse_real(reinterpret_cast<const unsigned char*>(start), size_t(q - start), &d)
			        ? d
			        : double(v);
			if (!std::isfinite(v) || !std::isfinite(x))
				return fail(vn_io_error_parse,
				            "%s %" PRId64 " has the number '%.*s', which is not finite: fix or remove that line",
				            kinds[kind], index, token_length(start), start);
			if (kind != 1)
				exact[kind].push_back(x);
		}
		skip_blanks(q);
		if (kind == 0 && q < line_end && *q != '#' && !colour(q))
			extra_vertex_numbers++;
		if (kind == 1 && q < line_end && *q != '#' && !zero_w(q))
			extra_texcoord_numbers++;
		return true;
	}

	/* The number at q, to the next blank or '#' (q moves past it and the
	 * blanks after); false where that text is not one. */
	bool real_token(const char*& q, double* x) const
	{
		const char* t = q;
		while (q < line_end && !space(*q) && *q != '#')
			q++;
		const bool ok = vn_io_parse_real(reinterpret_cast<const unsigned char*>(t), size_t(q - t), x);
		skip_blanks(q);
		return ok;
	}

	/* Whether the rest of a vt line, at q, is one number, 0. */
	bool zero_w(const char* q) const
	{
		double w;
		return real_token(q, &w) && w == 0.0 && (q == line_end || *q == '#');
	}

	/* "r g b" at q, to the end of a v line: appended to colours. */
	bool colour(const char* q)
	{
		float rgb[3];
		for (int k = 0; k < 3; k++) {
			double c;
			if (!real_token(q, &c) || !(c >= 0.0 && c <= 1.0))
				return false;
			rgb[k] = float(c);
		}
		if (q < line_end && *q != '#')
			return false;
		colours.insert(colours.end(), rgb, rgb + 3);
		return true;
	}

	/* Whether every v line has a colour (read as the vertex colours). */
	bool coloured() const { return total[0] > 0 && colours.size() == 3 * size_t(total[0]); }

	/* Whether index i (1-based, or negative: counted back from the last
	 * one so far) of a kind names a line the file has. */
	bool names_line(int32_t i, int kind) const
	{
		return (i > 0 && i <= total[kind]) || (i < 0 && seen[kind] + i >= 0);
	}

	/* A face corner's index: 0 (no vt or vn) or names_line, else a fail
	 * naming the corner. */
	bool check_index(int32_t i, int kind, int corner)
	{
		static const char* const kinds[3] = {"vertex", "texture coordinate", "normal"};
		static const char* const plurals[3] = {"vertices (v)", "texture coordinates (vt)", "normals (vn)"};
		if (i == 0 || names_line(i, kind))
			return true;
		if (i > 0)
			return fail(vn_io_error_parse, "face corner %d refers to %s %" PRId32 ", but the file has %" PRId64 " %s",
			            corner, kinds[kind], i, total[kind], plurals[kind]);
		return fail(vn_io_error_parse,
		            "face corner %d refers to %s %" PRId32 " (counting back), but only %" PRId64 " %s come before it",
		            corner, kinds[kind], i, seen[kind], plurals[kind]);
	}

	/* An f line after the 'f'. Draco counts its blank-separated entries,
	 * then parses up to 8 corners: both must agree. */
	bool face(char* q)
	{
		char* f = q - 1;
		int entries = 0;
		for (const char* t = q; t < line_end;) {
			if (space(*t)) {
				t++;
				continue;
			}
			entries++;
			while (t < line_end && !space(*t))
				t++;
		}
		if (entries < 3) {
			/* No surface: skipped (as a comment for Draco), with a warning. */
			if (counting && !short_faces++)
				first_short_face = line;
			*f = '#';
			return true;
		}
		triangles += uint64_t(entries - 2);
		if (triangles > INT32_MAX / 3)
			return fail(vn_io_error_unsupported, "more than %d triangles, more than Draco's OBJ reader holds",
			            INT32_MAX / 3);
		if (counting)
			return true;
		const bool long_face_ = entries > max_corners;
		if (long_face_)
			long_faces.push_back({size_t(f - begin), size_t(line_end - begin), {}});
		const char* c = q;
		int corners = 0;
		bool textured = false;
		for (; corners <= entries; corners++) {
			while (c < line_end && (*c == ' ' || *c == '\t'))
				c++;
			const char* start = c;
			std::array<int32_t, 3> index;
			if (!parse_corner(c, index.data())) {
				if (corners == entries)
					break;
				return fail(vn_io_error_parse,
				            "face corner %d, '%.*s', is not v, v/vt, v/vt/vn or v//vn with indices from 1 (or -1) to 2147483647",
				            corners + 1, token_length(start), start);
			}
			bool dropped = false;
			for (int k = 1; k < 3; k++)
				if (index[k] != 0 && total[k] == 0) {
					index[k] = 0, dropped = true;
					if (!dangling[k]++)
						first_dangling[k] = line;
				}
			for (int k = 0; k < 3; k++)
				if (!check_index(index[k], k, corners + 1))
					return false;
			textured = textured || index[1] != 0;
			if (index[1] != 0)
				texcoord_used[size_t(index[1] > 0 ? index[1] - 1 : seen[1] + index[1])] = 1;
			if (c < line_end && !space(*c)) /* "3x4": Draco would read 3 */
				return fail(vn_io_error_parse,
				            "face corner %d, '%.*s', is not v, v/vt, v/vt/vn or v//vn with indices from 1 (or -1) to 2147483647",
				            corners + 1, token_length(start), start);
			if (dropped) { /* the corner without them, in place: never longer */
				const std::string t = corner_text(index);
				char* at = q + (start - q);
				std::memcpy(at, t.data(), t.size());
				std::memset(at + t.size(), ' ', size_t(c - start) - t.size());
			}
			if (long_face_)
				long_faces.back().corners.push_back(index);
			for (char* slash = q + (c - q); slash > q && slash[-1] == '/'; *--slash = ' ')
				;
		}
		if (corners != entries)
			return fail(vn_io_error_parse, "a face has %d entries, but they read as %d corners", entries, corners);
		face_corners.push_back(uint32_t(entries));
		face_textured.push_back(textured);
		groups.of_face.push_back(groups.current);
		smoothing.of_face.push_back(smoothing.current);
		return true;
	}

	/* The text with every long face written as faces of at most
	 * max_corners corners that fan-triangulate as the whole face does: the
	 * first corner, then the corners from the last one of the piece before. */
	/* The text Draco gets: faces of more than max_corners corners split, " 0"
	 * after each vt of one number (both lists are in file order). */
	std::vector<char> rewritten() const
	{
		std::vector<char> out;
		size_t copied = 0, pad = 0;
		auto pad_until = [&](size_t at) {
			for (; pad < short_texcoords.size() && short_texcoords[pad] <= at; pad++) {
				out.insert(out.end(), begin + copied, begin + short_texcoords[pad]);
				out.insert(out.end(), {' ', '0'});
				copied = short_texcoords[pad];
			}
		};
		for (const long_face& l : long_faces) {
			pad_until(l.begin);
			out.insert(out.end(), begin + copied, begin + l.begin);
			copied = l.end;
			const size_t k = l.corners.size();
			auto corner = [](const std::array<int32_t, 3>& c) { return " " + corner_text(c); };
			for (size_t first = 1;;) {
				const size_t last = std::min(first + size_t(max_corners) - 1, k);
				std::string piece = (first > 1 ? "\nf" : "f") + corner(l.corners[0]);
				for (size_t i = first; i < last; i++)
					piece += corner(l.corners[i]);
				out.insert(out.end(), piece.begin(), piece.end());
				if (last == k)
					break;
				first = last - 1;
			}
		}
		pad_until(size_t(end - begin));
		out.insert(out.end(), begin + copied, end);
		return out;
	}

	/* The rest of a line after its keyword, from its first non-blank to
	 * its end (without a CR) or a NUL: names are C strings, and a blank
	 * left before a NUL, which the text after it kept from being trimmed,
	 * would be written and read back without. */
	std::string rest(const char* q) const
	{
		skip_blanks(q);
		const char* e = q;
		while (e < line_end && *e)
			e++;
		while (e > q && (e[-1] == '\r' || e[-1] == ' ' || e[-1] == '\t'))
			e--;
		return std::string(q, size_t(e - q));
	}

	/* One line, at its first non-blank, as ObjDecoder::ParseDefinition
	 * tells what it is. */
	bool definition(char* p)
	{
		const size_t left = size_t(end - p);
		auto starts = [&](const char* s) { return left >= std::strlen(s) && !std::memcmp(p, s, std::strlen(s)); };
		if (left >= 2 && (p[0] == 'v' || p[0] == 'o') && p[1] == '\t')
			p[1] = ' ';
		if (*p == '#')
			return true;
		if (starts("v "))
			return numbers(p + 2, 0);
		if (starts("vn"))
			return numbers(p + 2, 2);
		if (starts("vt"))
			return numbers(p + 2, 1);
		if (*p == 'f') {
			char* hash = static_cast<char*>(std::memchr(p, '#', size_t(line_end - p)));
			if (hash)
				std::memset(hash, ' ', size_t(line_end - hash));
			return face(p + 1);
		}
		/* Draco's ParseMaterial and ParseObject read an empty name's line,
		 * then fail, and the line after is skipped as unknown (in one of
		 * its two passes only: it then writes past its arrays). Such a line
		 * names nothing: a comment. */
		if (starts("usemtl")) {
			if (rest(p + 6).empty())
				*p = '#';
			else if (first_material < 0)
				first_material = int64_t(triangles);
			return true;
		}
		if (starts("mtllib")) {
			const std::string files = rest(p + 6);
			if (!files.empty())
				library += (library.empty() ? "" : " ") + files;
			*p = '#';
			return true;
		}
		if (starts("o ")) {
			if (rest(p + 1).empty())
				*p = '#';
			else if (first_object < 0)
				first_object = int64_t(triangles);
			return true;
		}
		if ((*p == 'g' || *p == 's') && (left == 1 || space(p[1]))) {
			if (!counting)
				(*p == 'g' ? groups : smoothing).start(left == 1 ? std::string() : rest(p + 1));
			return true;
		}
		if (*p == 'l' && (left == 1 || space(p[1])))
			return counting || polyline(p + 1);
		if (!counting)
			note_left_out(p);
		return true;
	}

	/* An l line after the 'l': each point's v line (the vt and vn of
	 * v/vt/vn are not kept, nor checked: Draco skips l lines). A line of
	 * fewer than 2 points, or with a point that is not a v line the file
	 * has, is skipped and counted: before vn read lines, it was read
	 * without them, and a file it read is not refused for them now. */
	bool polyline(const char* q)
	{
		const size_t first = line_points.size();
		bool usable = true;
		for (;;) {
			skip_blanks(q);
			if (q == line_end || *q == '#')
				break;
			std::array<int32_t, 3> index;
			const int32_t i = parse_corner(q, index.data()) && (q == line_end || space(*q)) ? index[0] : 0;
			usable = usable && names_line(i, 0);
			if (usable)
				line_points.push_back(uint32_t(i > 0 ? i - 1 : seen[0] + i));
			while (q < line_end && !space(*q))
				q++;
		}
		if (usable && line_points.size() - first >= 2) {
			line_offsets.push_back(uint32_t(line_points.size()));
			return true;
		}
		line_points.resize(first);
		if (!skipped_lines++)
			first_skipped_line = line;
		return true;
	}

	/* A line of a kind Draco skips and the scan does not read: counted by
	 * its keyword. */
	void note_left_out(const char* p)
	{
		const std::string keyword(p, size_t(token_length(p)));
		for (auto& k : left_out)
			if (k.first == keyword) {
				k.second++;
				return;
			}
		if (left_out.empty())
			first_left_out = line;
		if (left_out.size() < left_out_max)
			left_out.push_back({keyword, 1});
		left_out_kinds++;
	}

	/* One warning line naming what the file has that vn leaves out, or "". */
	std::string left_out_warning() const
	{
		static const std::pair<const char*, const char*> meanings[] = {
		    {"p", "points"}, {"mg", "merging groups"},
		    {"curv", "curves"}, {"surf", "surfaces"}};
		std::string text;
		for (const auto& k : left_out) {
			text += (text.empty() ? "" : ", ") + std::to_string(k.second) + " '" + k.first + "' line" +
			        (k.second == 1 ? "" : "s");
			for (const auto& m : meanings)
				if (k.first == m.first)
					text += std::string(" (") + m.second + ")";
		}
		if (left_out_kinds > left_out.size())
			text += ", lines of " + std::to_string(left_out_kinds - left_out.size()) + " more kinds";
		/* Colours of some v lines only are left out too. */
		const uint64_t extra = extra_vertex_numbers + (coloured() ? 0 : colours.size() / 3);
		if (extra)
			text += (text.empty() ? "" : ", ") + std::string("numbers after x y z on ") +
			        std::to_string(extra) + " 'v' line" + (extra == 1 ? "" : "s") +
			        " (w, or colours not on every v line or not in [0, 1])";
		if (extra_texcoord_numbers)
			text += (text.empty() ? "" : ", ") + std::string("numbers after u v on ") +
			        std::to_string(extra_texcoord_numbers) + " 'vt' line" + (extra_texcoord_numbers == 1 ? "" : "s") +
			        " (w, not 0)";
		/* A point cloud reads a vt line for each v line. */
		const uint64_t unused = triangles ? uint64_t(std::count(texcoord_used.begin(), texcoord_used.end(), 0)) : 0;
		if (unused)
			text += (text.empty() ? "" : ", ") + std::to_string(unused) + " 'vt' line" + (unused == 1 ? "" : "s") +
			        " no face uses";
		return text.empty() ? text : "left out (vn reads v, vt, vn, f, l, o, g, s, usemtl and mtllib): " + text;
	}

	bool pass(bool count)
	{
		counting = count;
		seen[0] = seen[1] = seen[2] = 0;
		triangles = 0;
		first_material = first_object = -1;
		face_corners.clear();
		face_textured.clear();
		long_faces.clear();
		short_texcoords.clear();
		std::fill(std::begin(dangling), std::end(dangling), 0);
		exact[0].clear();
		exact[2].clear();
		colours.clear();
		left_out.clear();
		left_out_kinds = extra_vertex_numbers = extra_texcoord_numbers = 0;
		texcoord_used.assign(count ? 0 : size_t(total[1]), 0);
		line_points.clear();
		line_offsets.assign(1, 0);
		skipped_lines = 0;
		groups.clear();
		smoothing.clear();
		line = 1;
		for (char* p = begin;;) {
			while (p < end && space(*p))
				line += *p++ == '\n';
			if (p == end)
				return true;
			char* stop = static_cast<char*>(std::memchr(p, '\n', size_t(end - p)));
			line_end = stop ? stop : end;
			if (!definition(p))
				return false;
			p = const_cast<char*>(line_end);
		}
	}
};

/* The attribute ObjDecoder named `label` in its metadata, or null. */
const draco::PointAttribute* named(const draco::Mesh& m, const char* label)
{
	const draco::AttributeMetadata* metadata = m.GetAttributeMetadataByStringEntry("name", label);
	return metadata ? m.GetAttributeByUniqueId(metadata->att_unique_id()) : nullptr;
}

template <typename T>
T* copy_out(const std::vector<T>& v)
{
	T* out = static_cast<T*>(std::malloc(sizeof(T) * v.size() + 1));
	if (out && !v.empty())
		std::memcpy(out, v.data(), sizeof(T) * v.size());
	return out;
}

char* copy_string(const std::string& s)
{
	char* out = static_cast<char*>(std::malloc(s.size() + 1));
	if (out)
		std::memcpy(out, s.c_str(), s.size() + 1);
	return out;
}

/* Names and each face's (VN_IO_NO_NAME: none) into *out; nothing where
 * no face has a name (a name no face has, such as an `o` after the last
 * face, would be written by no writer). False when out of memory. */
bool names_out(const std::vector<std::string>& names, const std::vector<uint32_t>& of_face, vn_io_face_names* out)
{
	if (std::all_of(of_face.begin(), of_face.end(), [](uint32_t i) { return i == VN_IO_NO_NAME; }))
		return true;
	out->names = static_cast<char**>(std::calloc(names.size(), sizeof(char*)));
	if (!out->names || !(out->of_face = copy_out(of_face)))
		return false;
	for (const std::string& n : names)
		if (!(out->names[out->count++] = copy_string(n)))
			return false;
	return true;
}

/* The names of ObjDecoder's `label` attribute ("material", "sub_obj") and
 * the one of each face (of its first triangle); faces from before the
 * first triangle that had one (`first`) have none, where Draco gives them
 * the first name. False when out of memory. */
bool face_names(const draco::Mesh& m, const char* label, const std::vector<uint32_t>& first_triangle, int64_t first,
                vn_io_face_names* out)
{
	const draco::PointAttribute* a = named(m, label);
	if (!a || a->size() == 0)
		return true;
	std::vector<std::string> names(a->size());
	for (const auto& entry : m.GetAttributeMetadataByStringEntry("name", label)->entries()) {
		int id;
		if (entry.second.GetValue(&id) && id >= 0 && size_t(id) < names.size())
			names[size_t(id)] = entry.first;
	}
	/* An empty name, as C text (a name of NUL bytes: names are copied to
	 * their first NUL), names nothing. */
	std::vector<uint32_t> of_face(first_triangle.size());
	for (size_t f = 0; f < first_triangle.size(); f++) {
		int id = 0;
		const draco::FaceIndex t(first_triangle[f]);
		of_face[f] = int64_t(first_triangle[f]) < first || !a->ConvertValue<int>(a->mapped_index(m.face(t)[0]), &id) ||
		                     id < 0 || size_t(id) >= names.size() || names[size_t(id)].c_str()[0] == '\0'
		                 ? VN_IO_NO_NAME
		                 : uint32_t(id);
	}
	return names_out(names, of_face, out);
}

/* A corner's lines: v, vt (NO_TEX: none), vn. */
using corner_key = std::array<uint32_t, 3>;

/* Keys (std::array of integers) numbered from 0 in the order they first
 * come, equal keys sharing a number: open addressing in a flat table sized
 * once for the most keys there can be. std::unordered_map allocated a node
 * a key: a quarter of writing an OBJ, 7% of reading one. */
template <typename K>
class first_index {
public:
	explicit first_index(size_t most) : slots_(table_size(most), 0) { keys_.reserve(most); }
	/* key's number; *fresh where it is new (then keys() ends with it). */
	uint32_t of(const K& key, bool* fresh)
	{
		const size_t mask = slots_.size() - 1;
		for (size_t i = hash(key) & mask;; i = (i + 1) & mask) {
			const uint32_t slot = slots_[i]; /* 0: empty, else the key's number + 1 */
			if (slot == 0) {
				keys_.push_back(key);
				slots_[i] = uint32_t(keys_.size());
				*fresh = true;
				return uint32_t(keys_.size() - 1);
			}
			if (keys_[slot - 1] == key) {
				*fresh = false;
				return slot - 1;
			}
		}
	}
	const std::vector<K>& keys() const { return keys_; }

private:
	std::vector<K> keys_;
	std::vector<uint32_t> slots_;
	/* A power of 2, at least twice the keys: short probes. */
	static size_t table_size(size_t most)
	{
		size_t n = 2;
		while (n < 2 * most)
			n *= 2;
		return n;
	}
	/* FNV-style over the words, then murmur3's finalizer: the table takes
	 * the low bits, and a float's bits as a double's end in 29 zeros. */
	static size_t hash(const K& key)
	{
		uint64_t h = 0;
		for (const auto x : key)
			h = (h ^ uint64_t(x)) * 0x100000001b3ull + (h >> 31);
		h ^= h >> 33, h *= 0xff51afd7ed558ccdull, h ^= h >> 33, h *= 0xc4ceb9fe1a85ec53ull, h ^= h >> 33;
		return size_t(h);
	}
};

/* A corner without a texture coordinate (corner_key's [1]); a vertex no
 * face uses, without a normal ([2]). */
constexpr uint32_t NO_TEX = UINT32_MAX, NO_NRM = UINT32_MAX;

uint64_t bits(double x)
{
	uint64_t b;
	std::memcpy(&b, &x, sizeof b);
	return b;
}

/* For each of `count` lines, the first line of the same value (bit for bit;
 * bits_of(i) gives line i's), as Draco's deduplication of values merges
 * them; vn has Draco keep every line (its values are floats) and merges on
 * the exact ones. */
template <size_t N, typename F>
std::vector<uint32_t> first_equal(size_t count, F bits_of)
{
	first_index<std::array<uint64_t, N>> numbers(count);
	std::vector<uint32_t> first(count), out(count);
	for (size_t i = 0; i < count; i++) {
		bool fresh;
		const uint32_t k = numbers.of(bits_of(i), &fresh);
		if (fresh)
			first[k] = uint32_t(i);
		out[i] = first[k];
	}
	return out;
}

/* Draco's attributes of an OBJ read without deduplication (a value a line)
 * and, with `merged`, for each vt and vn line the first equal line. */
struct obj_attributes {
	const draco::PointAttribute *pos, *tex, *nrm;
	std::vector<uint32_t> first_tex, first_nrm;
};

obj_attributes attributes_of(const draco::Mesh& m, const scanner& s, bool textured, bool merged)
{
	using draco::GeometryAttribute;
	obj_attributes a{m.GetNamedAttribute(GeometryAttribute::POSITION),
	                 textured ? m.GetNamedAttribute(GeometryAttribute::TEX_COORD) : nullptr,
	                 m.GetNamedAttribute(GeometryAttribute::NORMAL), {}, {}};
	if (!merged)
		return a;
	a.first_nrm = first_equal<3>(s.exact[2].size() / 3, [&s](size_t i) {
		const double* n = &s.exact[2][3 * i];
		return std::array<uint64_t, 3>{bits(n[0]), bits(n[1]), bits(n[2])};
	});
	if (a.tex)
		a.first_tex = first_equal<3>(a.tex->size(), [&a](size_t i) {
			float t[2];
			a.tex->ConvertValue<float, 2>(draco::AttributeValueIndex(uint32_t(i)), t);
			return std::array<uint64_t, 3>{bits(double(t[0])), bits(double(t[1])), 0};
		});
	return a;
}

/* The key of Draco's point p: its v line (equal v lines are distinct
 * vertices, as Blender, MeshLab and Assimp read them and as OFF and PLY keep
 * theirs; --no-weld computes on them apart), the first lines of its vt and
 * vn values, without the texture coordinate where untextured (or without
 * texture coordinates). */
corner_key key_of(draco::PointIndex p, const obj_attributes& a, bool untextured)
{
	return {{a.pos->mapped_index(p).value(),
	         a.tex && !untextured ? a.first_tex[a.tex->mapped_index(p).value()] : NO_TEX,
	         a.nrm ? a.first_nrm[a.nrm->mapped_index(p).value()] : 0}};
}

/* The vertices' values, a vertex a key: positions and normals as the
 * file's doubles (3 each; no normals without vn lines, 0 for a key without
 * one), texture coordinates (2; none without them, left 0 for a key without one),
 * colours (RGBA, opaque; none unless every v line has one). */
struct vertex_values {
	std::vector<double> positions, normals;
	std::vector<float> texcoords, colours;
	std::vector<uint32_t> lines; /* each vertex's v line */
};

vertex_values values_of(const std::vector<corner_key>& vertices, const obj_attributes& a, const scanner& s)
{
	const size_t n = vertices.size();
	vertex_values out{std::vector<double>(3 * n), std::vector<double>(a.nrm ? 3 * n : 0),
	                  std::vector<float>(a.tex ? 2 * n : 0), std::vector<float>(s.coloured() ? 4 * n : 0),
	                  std::vector<uint32_t>(n)};
	for (size_t i = 0; i < n; i++) {
		out.lines[i] = vertices[i][0];
		std::copy_n(&s.exact[0][3 * size_t(vertices[i][0])], 3, &out.positions[3 * i]);
		if (s.coloured()) {
			std::copy_n(&s.colours[3 * size_t(vertices[i][0])], 3, &out.colours[4 * i]);
			out.colours[4 * i + 3] = 1.0f;
		}
		if (a.tex && vertices[i][1] != NO_TEX)
			a.tex->ConvertValue<float, 2>(draco::AttributeValueIndex(vertices[i][1]), &out.texcoords[2 * i]);
		if (a.nrm && vertices[i][2] != NO_NRM)
			std::copy_n(&s.exact[2][3 * size_t(vertices[i][2])], 3, &out.normals[3 * i]);
	}
	return out;
}

vn_io_result out_of_memory(const char* name, vn_io_error* error)
{
	return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
}

/* mesh->face_untextured where some face has no vt but others have
 * (texcoords are read only when some face has one); false when out of
 * memory. */
bool untextured_faces(const scanner& s, vn_io_mesh* mesh)
{
	if (std::find(s.face_textured.begin(), s.face_textured.end(), 0) == s.face_textured.end())
		return true;
	mesh->face_untextured = static_cast<unsigned char*>(std::malloc(s.face_textured.size()));
	if (!mesh->face_untextured)
		return false;
	for (size_t f = 0; f < s.face_textured.size(); f++)
		mesh->face_untextured[f] = !s.face_textured[f];
	return true;
}

/* The l lines into *mesh, vertex[i] the vertex of v line i; false when
 * out of memory. */
bool lines_out(const scanner& s, const std::vector<uint32_t>& vertex, vn_io_mesh* mesh)
{
	if (s.line_offsets.size() < 2)
		return true;
	std::vector<uint32_t> points(s.line_points.size());
	for (size_t k = 0; k < points.size(); k++)
		points[k] = vertex[s.line_points[k]];
	mesh->line_count = s.line_offsets.size() - 1;
	return (mesh->line_offsets = copy_out(s.line_offsets)) && (mesh->line_indices = copy_out(points));
}

/* A file without v lines: the empty mesh, with its mtllib line. */
vn_io_result empty_mesh(const scanner& s, vn_io_mesh* mesh, vn_io_error* error)
{
	if (!vn_io_mesh_set_empty(mesh) || (!s.library.empty() && !(mesh->material_library = copy_string(s.library))))
		return out_of_memory(s.name, error);
	return vn_io_success;
}

/* A point cloud: Draco's points are the v lines, in order. */
vn_io_result cloud_to_mesh(const draco::Mesh& m, const scanner& s, vn_io_mesh* mesh, vn_io_error* error)
{
	const obj_attributes a = attributes_of(m, s, true, false);
	const size_t n = m.num_points();
	if (!a.pos || int64_t(n) != s.total[0])
		return vn_io_fail(error, vn_io_error_parse, "%s: Draco's OBJ reader found %zu of its %" PRId64 " vertices",
		                  s.name, a.pos ? n : 0, s.total[0]);
	/* Every v line a vertex, equal ones too. */
	std::vector<corner_key> points(n);
	for (size_t i = 0; i < n; i++) {
		const draco::PointIndex p(static_cast<uint32_t>(i));
		points[i] = {{a.pos->mapped_index(p).value(), a.tex ? a.tex->mapped_index(p).value() : NO_TEX,
		              a.nrm ? a.nrm->mapped_index(p).value() : 0}};
	}
	const vertex_values values = values_of(points, a, s);
	mesh->vertex_count = n;
	if (!(mesh->positions = copy_out(values.positions)) ||
	    !(mesh->face_offsets = copy_out(std::vector<uint32_t>{0})) ||
	    !(mesh->indices = copy_out(std::vector<uint32_t>{})) || (a.nrm && !(mesh->normals = copy_out(values.normals))) ||
	    (a.tex && !(mesh->texcoords = copy_out(values.texcoords))) ||
	    (s.coloured() && !(mesh->colors = copy_out(values.colours))))
		return out_of_memory(s.name, error);
	std::vector<uint32_t> vertex(n);
	for (size_t i = 0; i < n; i++)
		vertex[i] = uint32_t(i);
	if (!lines_out(s, vertex, mesh))
		return out_of_memory(s.name, error);
	return vn_io_success;
}

/* Draco's mesh into *mesh: a vertex per (v, vt, vn), polygons as the file
 * had them; then a vertex per v line no face uses, in file order. */
vn_io_result to_mesh(const draco::Mesh& m, const scanner& s, vn_io_mesh* mesh, vn_io_error* error)
{
	/* vt lines no face uses give no texture coordinates (Draco would give
	 * every corner the first). */
	const bool textured = std::find(s.face_textured.begin(), s.face_textured.end(), 1) != s.face_textured.end();
	const obj_attributes a = attributes_of(m, s, textured, true);
	if (!a.pos || m.num_faces() == 0)
		return vn_io_fail(error, vn_io_error_parse, "%s: Draco's OBJ reader found no faces", s.name);

	std::vector<uint32_t> vertex_of_point;
	/* A vertex a distinct key; there are at most two keys a point. */
	first_index<corner_key> vertex_of(2 * size_t(m.num_points()));
	/* A corner of a face without vt is Draco's point with the first vt, but
	 * a vertex of its own (no texture coordinate, NO_TEX), so that it is not
	 * merged with the first vt's corners of textured faces. */
	std::vector<uint32_t> untextured_vertex_of_point;
	auto vertex = [&](draco::PointIndex p, bool untextured) {
		std::vector<uint32_t>& cache = untextured ? untextured_vertex_of_point : vertex_of_point;
		if (cache.empty())
			cache.assign(m.num_points(), UINT32_MAX);
		uint32_t& v = cache[p.value()];
		bool fresh;
		if (v == UINT32_MAX)
			v = vertex_of.of(key_of(p, a, untextured), &fresh);
		return v;
	};
	/* Draco fans a face of k corners into k - 2 triangles, in file order:
	 * the first one's corners, then the last corner of each other one. */
	std::vector<uint32_t> offsets{0}, indices, first_triangle;
	uint32_t t = 0;
	for (size_t face = 0; face < s.face_corners.size(); face++) {
		const uint32_t k = s.face_corners[face];
		const bool untextured = !s.face_textured[face];
		if (t + (k - 2) > m.num_faces())
			return vn_io_fail(error, vn_io_error_parse, "%s: Draco's OBJ reader found fewer faces than the file has",
			                  s.name);
		const draco::Mesh::Face& f = m.face(draco::FaceIndex(t));
		first_triangle.push_back(t);
		indices.insert(indices.end(), {vertex(f[0], untextured), vertex(f[1], untextured), vertex(f[2], untextured)});
		for (uint32_t j = 1; j < k - 2; j++)
			indices.push_back(vertex(m.face(draco::FaceIndex(t + j))[2], untextured));
		offsets.push_back(uint32_t(indices.size()));
		t += k - 2;
	}

	/* v lines no face uses are vertices too (loose points of a scan, a
	 * model's pivots), as OFF and PLY keep theirs: without a texture
	 * coordinate or normal, which only a face corner gives. And each v
	 * line's first vertex, which a line's point is. */
	const std::vector<corner_key>& face_keys = vertex_of.keys();
	std::vector<uint32_t> vertex_of_line(s.exact[0].size() / 3, UINT32_MAX);
	for (size_t k = face_keys.size(); k-- > 0;)
		vertex_of_line[face_keys[k][0]] = uint32_t(k);
	std::vector<corner_key> with_loose; /* the faces' keys and these, where there are any */
	for (size_t i = 0; i < vertex_of_line.size(); i++)
		if (vertex_of_line[i] == UINT32_MAX) {
			if (with_loose.empty())
				with_loose = face_keys;
			vertex_of_line[i] = uint32_t(with_loose.size());
			with_loose.push_back({{uint32_t(i), NO_TEX, NO_NRM}});
		}
	const std::vector<corner_key>& keys = with_loose.empty() ? face_keys : with_loose;
	const vertex_values values = values_of(keys, a, s);
	mesh->vertex_count = keys.size();
	mesh->face_count = first_triangle.size();
	if (!(mesh->positions = copy_out(values.positions)) || !(mesh->position_lines = copy_out(values.lines)) ||
	    !(mesh->face_offsets = copy_out(offsets)) ||
	    !(mesh->indices = copy_out(indices)) || (a.nrm && !(mesh->normals = copy_out(values.normals))) ||
	    (a.tex && !(mesh->texcoords = copy_out(values.texcoords))) ||
	    (s.coloured() && !(mesh->colors = copy_out(values.colours))) || (a.tex && !untextured_faces(s, mesh)) ||
	    !face_names(m, "material", first_triangle, s.first_material, &mesh->materials) ||
	    !face_names(m, "sub_obj", first_triangle, s.first_object, &mesh->objects) ||
	    !names_out(s.groups.names, s.groups.of_face, &mesh->groups) ||
	    !names_out(s.smoothing.names, s.smoothing.of_face, &mesh->smoothing) || !lines_out(s, vertex_of_line, mesh) ||
	    (!s.library.empty() && !(mesh->material_library = copy_string(s.library))))
		return out_of_memory(s.name, error);
	return vn_io_success;
}

/* The text after '#' of each comment line before the first other line
 * (blank lines skipped), "\n"-separated, into out; false when there is none.
 * Exporters put their credits and the model's licence there. */
bool leading_comments(const std::vector<char>& text, std::string& out)
{
	bool any = false;
	for (size_t i = 0; i < text.size();) {
		size_t end = i, b = i;
		while (end < text.size() && text[end] != '\n')
			end++;
		while (b < end && space(text[b]))
			b++;
		if (b < end) {
			if (text[b] != '#')
				break;
			size_t e = end;
			while (e > b + 1 && text[e - 1] == '\r')
				e--;
			out.append(any ? "\n" : "").append(&text[b + 1], e - b - 1);
			any = true;
		}
		i = end + 1;
	}
	return any;
}

/* A line ending in a backslash goes on on the next one (the OBJ
 * specification; exporters break long faces so). The two are made one line
 * in place, and the newline taken out is put after it (before the blanks
 * that fill its place), so that the lines after keep their numbers. */
void join_continued_lines(std::vector<char>& text)
{
	for (size_t i = 0; i < text.size(); i++) {
		if (text[i] != '\\')
			continue;
		size_t k = i + 1;
		if (k < text.size() && text[k] == '\r')
			k++;
		if (k == text.size() || text[k] != '\n')
			continue;
		const size_t taken = k + 1 - i; /* the backslash, a CR, the LF */
		const auto next = std::find(text.begin() + long(k) + 1, text.end(), '\n');
		const size_t e = size_t(next - text.begin()); /* the end of the next line */
		std::memmove(&text[i], &text[k + 1], e - (k + 1));
		text[e - taken] = '\n';
		std::fill(text.begin() + long(e - taken) + 1, text.begin() + long(e), ' ');
		i--; /* the joined line may end in a backslash too */
	}
}

vn_io_result read(const char* data, size_t size, const char* name, vn_io_mesh* mesh, vn_io_error* error)
{
	const unsigned char* bytes = reinterpret_cast<const unsigned char*>(data);
	const size_t bom = vn_io_utf8_bom(bytes, size);
	const vn_io_result lfs = vn_io_refuse_lfs_pointer(data, size, name, error);
	if (lfs != vn_io_success)
		return lfs;
	data += bom, size -= bom;
	if (size == 0)
		return vn_io_fail(error, vn_io_error_parse, "%s: the file is empty", name);
	std::vector<char> text(data, data + size);
	/* A lone CR ends a line, as a LF (Draco would read on to the next LF). */
	for (size_t i = 0; i < size; i++)
		if (text[i] == '\r' && (i + 1 == size || text[i + 1] != '\n'))
			text[i] = '\n';
	join_continued_lines(text);
	std::string comments;
	const bool commented = leading_comments(text, comments);
	scanner s;
	s.name = name;
	s.error = error;
	s.begin = text.data();
	s.end = text.data() + size;
	if (!s.pass(true))
		return s.result;
	std::memcpy(s.total, s.seen, sizeof s.total);
	if (!s.pass(false))
		return s.result;
	if (!s.long_faces.empty() || !s.short_texcoords.empty()) {
		std::vector<char> copy = s.rewritten();
		text.swap(copy);
	}
	if (s.triangles == 0) {
		/* Nothing OBJ defines but lines it does not: another format under
		 * the .obj extension (the MNI surfaces of brain imaging, "P 0.3 0.3
		 * 0.4 10 1 40962"), which an empty output would pass off as read. */
		if (!s.total[0] && !s.total[1] && !s.total[2] && !s.left_out.empty()) {
			const std::string& first = s.left_out[0].first;
			return vn_io_fail(error, vn_io_error_parse,
			                  "%s: not a Wavefront OBJ file: no v, vt, vn or f line, and line %zu starts with '%s', "
			                  "which OBJ does not define%s",
			                  name, s.first_left_out, first.c_str(),
			                  first == "P" || first == "L" ? " (an MNI surface .obj starts so: another format)" : "");
		}
		for (int k = 1; k < 3; k++)
			if (s.total[k] && s.total[k] != s.total[0])
				return vn_io_fail(error, vn_io_error_unsupported,
				                  "%s: a point cloud (no faces) of %" PRId64 " v lines and %" PRId64
				                  " %s lines: without faces, vn (and Draco) read one %s line for each v line",
				                  name, s.total[0], s.total[k], k == 1 ? "vt" : "vn", k == 1 ? "vt" : "vn");
	}
	/* Text without v lines (comments, mtllib, groups): an empty mesh, as an
	 * OFF of 0 vertices is. */
	draco::Mesh m;
	if (s.total[0]) {
		draco::DecoderBuffer buffer;
		buffer.Init(text.data(), text.size());
		draco::ObjDecoder decoder;
		decoder.set_use_metadata(true);
		decoder.set_deduplicate_input_values(false); /* a value a line: vn keys on lines and exact numbers */
		const draco::Status status = decoder.DecodeFromBuffer(&buffer, &m);
		if (!status.ok())
			return vn_io_fail(error, vn_io_error_parse, "%s: Draco's OBJ reader: %s", name, status.error_msg());
	}
	const vn_io_result r = s.triangles  ? to_mesh(m, s, mesh, error)
	                       : s.total[0] ? cloud_to_mesh(m, s, mesh, error)
	                                    : empty_mesh(s, mesh, error);
	if (r != vn_io_success)
		return r;
	mesh->colors_are_bytes = mesh->colors && vn_io_colors_are_bytes(mesh->colors, mesh->vertex_count);
	if (commented && !(mesh->comments = copy_string(comments)))
		return out_of_memory(name, error);
	std::string warnings;
	if (s.short_faces)
		warnings = std::to_string(s.short_faces) + " face" + (s.short_faces == 1 ? "" : "s") +
		           " (f) of fewer than 3 corners skipped (the first on line " + std::to_string(s.first_short_face) +
		           "): such a face has no surface";
	if (s.skipped_lines)
		warnings += (warnings.empty() ? "" : "\n") + std::to_string(s.skipped_lines) + " line" +
		            (s.skipped_lines == 1 ? "" : "s") +
		            " (l) skipped: fewer than 2 points, or a point that is not a v line the file has (the first on "
		            "line " + std::to_string(s.first_skipped_line) + ")";
	for (int k = 1; k < 3; k++)
		if (s.dangling[k])
			warnings += (warnings.empty() ? "" : "\n") + std::to_string(s.dangling[k]) + " face corner" +
			            (s.dangling[k] == 1 ? " refers" : "s refer") + " to " +
			            (k == 1 ? "texture coordinates (vt)" : "normals (vn)") +
			            ", but the file has none: read without them (the first on line " +
			            std::to_string(s.first_dangling[k]) + ")";
	const std::string left_out = s.left_out_warning();
	if (!left_out.empty())
		warnings += (warnings.empty() ? "" : "\n") + left_out;
	if (!warnings.empty() && !(mesh->warnings = copy_string(warnings)))
		return out_of_memory(name, error);
	return r;
}

/* ------------------------------------------------------------------ writer */

/* " v": the shortest of 6 to 12 significant digits that both Draco's
 * parser and a correctly rounding reader (Blender's, MeshLab's) read back
 * as v, else 9. Draco's arithmetic (draco_magnitude) can land one float
 * away from strtof's: in exponent style (2.376662e+08, 0.07% of random
 * floats), a text only Draco read as v gave every other reader the float
 * next to it. */
void put_obj_float(vn_io_text_out* w, float v)
{
	char text[VN_IO_NUMBER_SIZE + 1] = " ";
	for (int digits = 6; digits <= 12; digits++) {
		/* From 9 digits on, every correctly rounding reader gets v. */
		const size_t n =
		    digits <= 9 ? vn_io_format_float(text + 1, v, digits) : vn_io_format_g(text + 1, double(v), digits);
		if (n == 0)
			continue;
		const char* q = text + 1 + (text[1] == '-');
		const char* end = text + 1 + n;
		double back;
		bool any;
		if (draco_magnitude(q, end, &back, &any) && any && q == end &&
		    (text[1] == '-' ? float(-back) : float(back)) == v) {
			vn_io_put(w, text);
			return;
		}
	}
	vn_io_put_float9(w, double(v));
}

/* A value read from a float (OBJ, glTF, Draco) as the shortest text that
 * reads back as that float, which a float reader (every OBJ reader) gets
 * exactly; any other double in full. */
void put_coordinate(vn_io_text_out* w, double x)
{
	if (std::fabs(x) <= FLT_MAX && double(float(x)) == x)
		put_obj_float(w, float(x));
	else
		vn_io_put_exact(w, 1, x);
}

/* realpath() of the folder holding `file` (malloc'd), or NULL. */
char* real_folder(const char* file)
{
	const char* slash = std::strrchr(file, '/');
	const std::string folder = !slash ? "." : slash == file ? "/" : std::string(file, size_t(slash - file));
	return realpath(folder.c_str(), nullptr);
}

/* The components of `path` ("/a/b" -> a, b; blank ones and "." left out). */
std::vector<std::string> components(const std::string& path)
{
	std::vector<std::string> v;
	for (size_t at = 0, end; at < path.size(); at = end + 1) {
		end = std::min(path.find('/', at), path.size());
		if (end > at && path.compare(at, end - at, ".") != 0)
			v.push_back(path.substr(at, end - at));
	}
	return v;
}

/* Relative path `name`, which starts from folder `at`, as a path from
 * folder `from` (both as realpath() gives them, as components). The real
 * folders are no links: a ".." after them goes back one, and a way through
 * `from`'s own folders is cut short ("../A/m.mtl" read in B, written in A:
 * "m.mtl"). */
std::string seen_from(const std::vector<std::string>& from, std::vector<std::string> at, const std::string& name)
{
	bool real = true; /* every folder in `at` so far is */
	for (const std::string& c : components(name)) {
		if (c == ".." && real) {
			if (!at.empty())
				at.pop_back();
			continue;
		}
		real = false;
		at.push_back(c);
	}
	if (at.empty())
		return name;
	size_t common = 0;
	while (common < from.size() && common + 1 < at.size() && from[common] == at[common])
		common++;
	std::string way;
	for (size_t i = common; i < from.size(); i++)
		way += "../";
	for (size_t i = common; i < at.size(); i++)
		way += at[i] + (i + 1 < at.size() ? "/" : "");
	return way;
}

/* The `mtllib` arguments written to `path`: each relative one (OBJ
 * separates them by blanks) as a path from the output's folder (where its
 * links lead), so that they name the input's .mtl files wherever the output
 * is; absolute ones ("/x.mtl", "C:\\x.mtl") and all of them in the input's
 * own folder as read. */
std::string library_names(const char* path, const vn_io_mesh* mesh)
{
	const std::string names = mesh->material_library;
	char* target;
	vn_io_error ignored;
	if (!mesh->material_folder || vn_io_output_check(path, &target, &ignored) != vn_io_success)
		return names;
	char* folder = real_folder(target);
	std::free(target);
	if (!folder)
		return names;
	const std::vector<std::string> from = components(folder), at = components(mesh->material_folder);
	std::free(folder);
	if (from == at)
		return names;
	std::string text;
	for (size_t i = 0; i < names.size();) {
		const size_t end = std::min(names.find_first_of(" \t", i), names.size());
		const std::string name = names.substr(i, end - i);
		const bool absolute = name.empty() || name[0] == '/' || name[0] == '\\' || (name.size() > 1 && name[1] == ':');
		text += absolute ? name : seen_from(from, at, name);
		if (end < names.size())
			text += names[end];
		i = end + 1;
	}
	return text;
}

/* The end of a line whose text ends with `last`: a blank before the
 * newline where it is a backslash, which would otherwise carry the line on
 * to the next (join_continued_lines); the reader drops the blank. A name
 * can end so where the file it was read from had a blank or a NUL after
 * the backslash. */
void end_line(vn_io_text_out* w, const char* last)
{
	const size_t n = strlen(last);
	vn_io_put(w, n && last[n - 1] == '\\' ? " \n" : "\n");
}

/* "o NAME", "g NAME", "s NAME" or "usemtl NAME" before face f when its
 * name differs from the face before ("g" alone for the empty name). */
void put_name(vn_io_text_out* w, const char* keyword, const vn_io_face_names& names, size_t f)
{
	if (!names.of_face)
		return;
	const uint32_t id = names.of_face[f];
	if (id == VN_IO_NO_NAME || id >= names.count || (f > 0 && names.of_face[f - 1] == id))
		return;
	vn_io_put(w, keyword);
	if (names.names[id][0]) {
		vn_io_put(w, " ");
		vn_io_put(w, names.names[id]);
	}
	end_line(w, names.names[id]);
}

vn_io_result write(FILE* out, const char* path, const vn_io_mesh* mesh, vn_io_error* error)
{
	const size_t n = mesh->vertex_count;
	const bool cloud = mesh->face_count == 0; /* every vertex its own v, vt and vn lines, in order */
	std::vector<char> used(n, 0), textured(n, 0); /* used by a face; by one written with vt */
	auto untextured = [&](size_t f) { return mesh->face_untextured && mesh->face_untextured[f]; };
	for (size_t f = 0; f < mesh->face_count; f++)
		for (uint32_t c = mesh->face_offsets[f]; c < mesh->face_offsets[f + 1]; c++)
			used[mesh->indices[c]] = 1, textured[mesh->indices[c]] |= !untextured(f);
	vn_io_text_out w = {out, 0, 0, 0, {}};
	vn_io_put_comments(&w, mesh->comments, "#");
	/* A file of no bytes reads as a failed download: say what it is. */
	if (n == 0 && !mesh->comments)
		vn_io_put(&w, "# no vertices and no faces\n");
	if (mesh->material_library) {
		const std::string names = library_names(path, mesh);
		vn_io_put(&w, "mtllib ");
		vn_io_put(&w, names.c_str());
		end_line(&w, names.c_str());
	}
	/* Every vertex's position, loose ones too; texture coordinates and
	 * normals of the vertices faces use. */
	std::vector<uint32_t> v(n), vt(mesh->texcoords ? n : 0), vn(mesh->normals ? n : 0);
	/* 1-based numbers for values, equal values (bit for bit) sharing one;
	 * positions from an OBJ by their v lines (vn_io_mesh.position_lines), so
	 * that equal v lines stay two. */
	first_index<std::array<uint64_t, 6>> positions(cloud ? 0 : n);
	for (size_t i = 0; i < n && !w.failed; i++) {
		const double* p = mesh->positions + 3 * i;
		const float* rgb = mesh->colors ? mesh->colors + 4 * i : nullptr;
		bool fresh = true;
		v[i] = cloud                  ? uint32_t(i + 1)
		       : mesh->position_lines ? positions.of({mesh->position_lines[i], 0, 0, 0, 0, 0}, &fresh) + 1
		                              : positions.of({bits(p[0]), bits(p[1]), bits(p[2]), rgb ? bits(rgb[0]) : 0,
		                                              rgb ? bits(rgb[1]) : 0, rgb ? bits(rgb[2]) : 0},
		                                             &fresh) + 1;
		if (!fresh)
			continue;
		vn_io_put(&w, "v");
		for (int k = 0; k < 3; k++)
			put_coordinate(&w, p[k]);
		for (int k = 0; rgb && k < 3; k++)
			put_obj_float(&w, rgb[k]);
		vn_io_put(&w, "\n");
	}
	first_index<std::array<uint64_t, 2>> texcoords(cloud || !mesh->texcoords ? 0 : n);
	for (size_t i = 0; mesh->texcoords && i < n && !w.failed; i++) {
		const float* t = mesh->texcoords + 2 * i;
		bool fresh;
		if (!cloud && (!textured[i] || (vt[i] = texcoords.of({bits(t[0]), bits(t[1])}, &fresh) + 1, !fresh)))
			continue;
		vn_io_put(&w, "vt");
		put_obj_float(&w, t[0]);
		put_obj_float(&w, t[1]);
		vn_io_put(&w, "\n");
	}
	first_index<std::array<uint64_t, 3>> normals(cloud || !mesh->normals ? 0 : n);
	for (size_t i = 0; mesh->normals && i < n && !w.failed; i++) {
		const double* d = mesh->normals + 3 * i;
		bool fresh;
		if (!cloud && (!used[i] || (vn[i] = normals.of({bits(d[0]), bits(d[1]), bits(d[2])}, &fresh) + 1, !fresh)))
			continue;
		vn_io_put(&w, "vn");
		for (int k = 0; k < 3; k++)
			vn_io_put_float9(&w, d[k]);
		vn_io_put(&w, "\n");
	}
	for (size_t f = 0; f < mesh->face_count && !w.failed; f++) {
		put_name(&w, "o", mesh->objects, f);
		put_name(&w, "g", mesh->groups, f);
		put_name(&w, "usemtl", mesh->materials, f);
		put_name(&w, "s", mesh->smoothing, f);
		vn_io_put(&w, "f");
		const bool tex = mesh->texcoords && !untextured(f);
		for (uint32_t c = mesh->face_offsets[f]; c < mesh->face_offsets[f + 1]; c++) {
			const uint32_t i = mesh->indices[c];
			vn_io_put_uint(&w, " ", v[i]);
			if (tex)
				vn_io_put_uint(&w, "/", vt[i]);
			if (mesh->normals)
				vn_io_put_uint(&w, tex ? "/" : "//", vn[i]);
		}
		vn_io_put(&w, "\n");
	}
	for (size_t l = 0; l < mesh->line_count && !w.failed; l++) {
		vn_io_put(&w, "l");
		for (uint32_t c = mesh->line_offsets[l]; c < mesh->line_offsets[l + 1]; c++)
			vn_io_put_uint(&w, " ", v[mesh->line_indices[c]]);
		vn_io_put(&w, "\n");
	}
	if (!vn_io_flush(&w))
		return vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", path, std::strerror(w.error_number));
	return vn_io_success;
}

} // namespace

/* The reader for vn_io_read_text: OBJ is text throughout, so text decoded
 * from UTF-16 or UTF-32 (wide) reads as any other. */
static vn_io_result read_text(const char* data, size_t size, const char* name, const char* wide, vn_io_mesh* mesh,
                              vn_io_error* error)
{
	(void)wide;
	std::memset(mesh, 0, sizeof *mesh);
	vn_io_c_locale locale;
	if (!vn_io_c_locale_enter(&locale))
		return out_of_memory(name, error);
	vn_io_result r;
	try {
		r = read(data ? data : "", data ? size : 0, name, mesh, error);
	} catch (const std::bad_alloc&) {
		r = out_of_memory(name, error);
	}
	vn_io_c_locale_leave(&locale);
	if (r != vn_io_success)
		vn_io_mesh_free(mesh);
	return r;
}

extern "C" {

vn_io_result vn_io_obj_read_memory(const char* data, size_t size, const char* name, vn_io_mesh* mesh,
                                   vn_io_error* error)
{
	return vn_io_read_text(data, size, name, read_text, mesh, error);
}

vn_io_result vn_io_obj_read(const char* path, vn_io_mesh* mesh, vn_io_error* error)
{
	const vn_io_result r = vn_io_read_with(path, vn_io_obj_read_memory, mesh, error);
	/* Without its folder, the names are written as read. */
	if (r == vn_io_success && mesh->material_library && !(mesh->material_folder = real_folder(path)) &&
	    errno == ENOMEM) {
		vn_io_mesh_free(mesh);
		return out_of_memory(path, error);
	}
	return r;
}

vn_io_result vn_io_obj_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings,
                             vn_io_error* error)
{
	(void)settings; /* OBJ has none */
	vn_io_c_locale locale;
	if (!vn_io_c_locale_enter(&locale))
		return out_of_memory(path, error);
	vn_io_result r;
	try {
		r = write(out, path, mesh, error);
	} catch (const std::bad_alloc&) {
		r = out_of_memory(path, error);
	}
	vn_io_c_locale_leave(&locale);
	return r;
}

} // extern "C"
