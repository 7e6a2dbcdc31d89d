/*
 * OFF, Geomview's Object File Format.
 *
 * Reader: ASCII and binary, header keyword [ST][C][N][4][n]OFF, then BINARY
 * on the same line for binary files; an ASCII file may start with its
 * counts instead, without the keyword, as Geomview allows. A vertex holds
 * its position (x y z, or x y z w with 4), normal (N), colour (C) and
 * texture coordinates (ST), in that order. ASCII is read line by line, the
 * way Geomview reads face colours ("to the end of the line"): one vertex
 * per line, a face's count on one line and its indices there or on the
 * lines after (its colour is the rest of the last one's line), '#' starts a
 * comment anywhere, blank lines are skipped, and a line ends at "\n",
 * "\r\n" or a lone "\r".
 *
 * Writer: ASCII [ST][C][N]OFF (Geomview's prefix order), colours as RGBA.
 */
#include "off.h"
#include "text.h"

#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* Faces without a colour in a file where other faces have one get Geomview's
 * grey, 170/255 ("R,G,B,A=.666"). Geomview also makes them translucent; vn
 * keeps them opaque (A = 1) so that partly coloured meshes stay solid. */
#define OFF_GREY (170.0f / 255.0f)
/* A colour component the file did not give (a missing alpha, or a whole face
 * colour), until all colours of the file are known to be bytes or fractions. */
#define OFF_UNSET (-1.0f)
/* Numbers on a vertex line: x y z w, nx ny nz, r g b a, s t. */
#define OFF_VERTEX_MAX 13

/* ------------------------------------------------------------------ reader state */

typedef struct token {
	const unsigned char* p;
	size_t n;
} token;

/* The data part of one line: from its first non-blank to its end or '#'. */
typedef struct off_line {
	const unsigned char* p;
	const unsigned char* end;
} off_line;

/* The first fractional and the first above-1 colour component of a kind
 * (vertex or face), to name both when a file mixes the two styles. */
typedef struct colour_style {
	int has_fraction, has_byte;
	size_t fraction_index, byte_index;
	double fraction, byte;
} colour_style;

typedef struct off_reader {
	const char* name;
	vn_io_error* error;
	const unsigned char* begin;
	const unsigned char* p;
	const unsigned char* end;
	size_t line;  /* number of the line that starts at p */
	size_t where; /* what messages name: a line, or a byte offset when binary */
	int binary;
	/* The encoding the text was read from (vn_io_utf8_from_wide), or NULL. */
	const char* wide;
	/* Binary as pmp-library writes it: little-endian words (Geomview's are
	 * big-endian) and no colour count after a face's indices. */
	int pmp;
	char* warnings;
	/* The header's whole-line comments (vn_io_mesh.comments), gathered
	 * while `header` is set: until the counts; comments_failed when out of
	 * memory. */
	int header, comments_failed;
	char* comments;
	/* Faces coloured by a colormap index, which vn does not keep. */
	size_t colormap_faces, first_colormap_face;

	char keyword[16]; /* as written, e.g. "CNOFF" */
	char layout[48];  /* the numbers of an ASCII vertex, e.g. "x y z nx ny nz" */
	int st, colour, normal, ndim;
	size_t coords; /* 3, or 4 with a homogeneous w */

	size_t index_capacity;
	colour_style styles[2]; /* [0] vertex colours, [1] face colours */
} off_reader;

#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static vn_io_result fail(off_reader* r, vn_io_result result, const char* fmt, ...)
{
	va_list args;
	va_start(args, fmt);
	vn_io_fail_at(r->error, result, r->name, r->binary, r->where, fmt, args);
	va_end(args);
	return result;
}

static vn_io_result out_of_memory(off_reader* r)
{
	return vn_io_fail(r->error, vn_io_error_memory, "%s: out of memory", r->name);
}

static vn_io_quoted quote(token t)
{
	return vn_io_quote(t.p, t.n);
}

static void* alloc_array(size_t count, size_t size)
{
	if (count > SIZE_MAX / size)
		return NULL;
	/* Never NULL for an empty array: NULL means "absent" in vn_io_mesh. */
	return malloc(count ? count * size : 1);
}

/* ------------------------------------------------------------------ ASCII lexing */

static int is_blank(unsigned char c)
{
	return c == ' ' || c == '\t' || c == '\v' || c == '\f';
}

/* Moves to the next line that holds more than blanks and a comment; 0 at
 * the end of the input. Messages then name that line. */
static int next_line(off_reader* r, off_line* line)
{
	while (r->p < r->end) {
		const unsigned char* start = r->p;
		const unsigned char* stop = start;
		while (stop < r->end && *stop != '\n' && *stop != '\r')
			stop++;
		const unsigned char* hash = memchr(start, '#', (size_t)(stop - start));
		r->where = r->line++;
		r->p = stop;
		if (r->p < r->end && *r->p++ == '\r' && r->p < r->end && *r->p == '\n')
			r->p++;
		line->p = start;
		line->end = hash ? hash : stop;
		while (line->p < line->end && is_blank(*line->p))
			line->p++;
		if (line->p < line->end)
			return 1;
		if (hash && r->header &&
		    !vn_io_append_line(&r->comments, "%.*s", (int)(stop - hash - 1), (const char*)hash + 1))
			r->comments_failed = 1;
	}
	return 0;
}

/* Sets *t (empty at the end of the line) and returns whether it is a token. */
static int next_token(off_line* line, token* t)
{
	while (line->p < line->end && is_blank(*line->p))
		line->p++;
	t->p = line->p;
	t->n = 0;
	if (line->p == line->end)
		return 0;
	while (line->p < line->end && !is_blank(*line->p))
		line->p++;
	t->n = (size_t)(line->p - t->p);
	return 1;
}

static size_t count_tokens(off_line line)
{
	token t;
	size_t n = 0;
	while (next_token(&line, &t))
		n++;
	return n;
}

/* The whole token as a number; strtod also takes "nan" and "inf", which the
 * core library handles as degenerate input. */
static int parse_real(token t, double* out)
{
	return vn_io_parse_real(t.p, t.n, out);
}

/* Decimal digits only, saturating at UINT64_MAX: callers compare against
 * their limits and quote the token. */
static int parse_natural(token t, uint64_t* out)
{
	uint64_t v = 0;
	for (size_t i = 0; i < t.n; i++) {
		unsigned digit = (unsigned)t.p[i] - '0';
		if (digit > 9)
			return 0;
		v = v > (UINT64_MAX - digit) / 10 ? UINT64_MAX : v * 10 + digit;
	}
	*out = v;
	return 1;
}

/* The next number on a line whose token count the caller has checked. */
static vn_io_result line_real(off_reader* r, off_line* line, const char* kind, size_t index, double* out)
{
	token t;
	next_token(line, &t);
	if (parse_real(t, out))
		return vn_io_success;
	if (t.n > VN_IO_TOKEN_MAX)
		return fail(r, vn_io_error_parse, "%s %zu: '%s' is too long for a number", kind, index, quote(t).text);
	return fail(r, vn_io_error_parse, "%s %zu: '%s' is not a number", kind, index, quote(t).text);
}

/* ------------------------------------------------------------------ shared by ASCII and binary */

/* The length of the header keyword t starts with, and r's layout set from
 * it; 0 when t starts with none. Princeton's ModelNet writes the vertex
 * count right after the keyword ("OFF490 518 0"): digits after "OFF" are
 * the counts' start, not part of the keyword. */
static size_t parse_keyword(off_reader* r, token t)
{
	const unsigned char* s = t.p;
	size_t n = t.n;
	int st = 0, colour = 0, normal = 0, ndim = 0;
	size_t coords = 3;
	if (n >= 2 && s[0] == 'S' && s[1] == 'T')
		st = 1, s += 2, n -= 2;
	if (n >= 1 && *s == 'C')
		colour = 1, s++, n--;
	if (n >= 1 && *s == 'N')
		normal = 1, s++, n--;
	if (n >= 1 && *s == '4')
		coords = 4, s++, n--;
	if (n >= 1 && *s == 'n')
		ndim = 1, s++, n--;
	if (n < 3 || memcmp(s, "OFF", 3) != 0 || (ndim && n > 3))
		return 0;
	for (size_t i = 3; i < n; i++)
		if (s[i] < '0' || s[i] > '9')
			return 0;
	const size_t length = t.n - (n - 3);
	r->st = st, r->colour = colour, r->normal = normal, r->ndim = ndim, r->coords = coords;
	memcpy(r->keyword, t.p, length); /* at most "STCN4nOFF" */
	r->keyword[length] = '\0';
	snprintf(r->layout, sizeof r->layout, "x y z%s%s%s%s", r->coords == 4 ? " w" : "",
	         r->normal ? " nx ny nz" : "", r->colour ? " r g b [a]" : "", r->st ? " s t" : "");
	return length;
}

/* Rejects counts that the rest of the file (`available` bytes) cannot hold,
 * before anything is allocated: "1000000000000 0 0" must not ask for 24 TB. */
static vn_io_result check_counts(off_reader* r, uint64_t vertices, uint64_t faces, uint64_t vertex_bytes,
                                 uint64_t face_bytes, uint64_t available)
{
	if (vertices > available / vertex_bytes || faces > (available - vertices * vertex_bytes) / face_bytes)
		return fail(r, vn_io_error_parse,
		            "the header announces %llu vertices and %llu faces, more than the %llu bytes that follow can hold",
		            (unsigned long long)vertices, (unsigned long long)faces,
		            (unsigned long long)(r->end - r->p));
	if (vertices > UINT32_MAX)
		return fail(r, vn_io_error_unsupported, "%llu vertices are more than 32-bit indices can address",
		            (unsigned long long)vertices);
	if (faces > UINT32_MAX)
		return fail(r, vn_io_error_unsupported, "%llu faces are more than 32-bit offsets can hold",
		            (unsigned long long)faces);
	return vn_io_success;
}

static vn_io_result allocate(off_reader* r, vn_io_mesh* m, size_t vertices, size_t faces)
{
	m->vertex_count = vertices;
	m->face_count = faces;
	/* Most meshes are triangles; other sizes grow the array as needed. */
	r->index_capacity = faces > UINT32_MAX / 3 ? UINT32_MAX : faces * 3;
	m->positions = alloc_array(vertices, 3 * sizeof(double));
	m->normals = r->normal ? alloc_array(vertices, 3 * sizeof(double)) : NULL;
	m->colors = r->colour ? alloc_array(vertices, 4 * sizeof(float)) : NULL;
	m->texcoords = r->st ? alloc_array(vertices, 2 * sizeof(float)) : NULL;
	m->face_offsets = alloc_array(faces + 1, sizeof(uint32_t));
	m->indices = alloc_array(r->index_capacity, sizeof(uint32_t));
	if (!m->positions || (r->normal && !m->normals) || (r->colour && !m->colors) || (r->st && !m->texcoords) ||
	    !m->face_offsets || !m->indices)
		return out_of_memory(r);
	m->face_offsets[0] = 0;
	return vn_io_success;
}

/* Room for face f's `corners` indices after the `used` ones before it. */
static vn_io_result reserve_indices(off_reader* r, vn_io_mesh* m, size_t f, size_t used, uint64_t corners)
{
	if (corners > UINT32_MAX - used)
		return fail(r, vn_io_error_unsupported, "face %zu brings the corner count past 4294967295, the 32-bit limit", f);
	size_t needed = used + (size_t)corners;
	if (needed <= r->index_capacity)
		return vn_io_success;
	size_t capacity = r->index_capacity > UINT32_MAX / 2 ? UINT32_MAX : r->index_capacity * 2;
	if (capacity < needed)
		capacity = needed;
	uint32_t* larger = capacity <= SIZE_MAX / sizeof *larger ? realloc(m->indices, capacity * sizeof *larger) : NULL;
	if (!larger)
		return out_of_memory(r);
	m->indices = larger;
	r->index_capacity = capacity;
	return vn_io_success;
}

/* OFF colours are fractions in [0, 1] or integers 0..255, and a file uses one
 * style throughout (vertex and face colours each on their own): integer
 * components above 1 make the kind bytes, fractional ones make it fractions,
 * and a file with both is an error. */
static vn_io_result check_colour(off_reader* r, int face, size_t index, double v)
{
	static const char* const kinds[2] = {"vertex", "face"};
	colour_style* s = &r->styles[face];
	int integer = v >= 0.0 && v <= 255.0 && v == (double)(int)v;
	if (!(v >= 0.0 && (v <= 1.0 || integer)))
		return fail(r, vn_io_error_parse,
		            "%s %zu has colour component %g; components are fractions in [0, 1] or integers 0..255",
		            kinds[face], index, v);
	if (!integer && !s->has_fraction) {
		s->has_fraction = 1;
		s->fraction_index = index;
		s->fraction = v;
	}
	if (integer && v > 1.0 && !s->has_byte) {
		s->has_byte = 1;
		s->byte_index = index;
		s->byte = v;
	}
	if (s->has_fraction && s->has_byte) {
		int byte_first = s->byte_index < s->fraction_index;
		return fail(r, vn_io_error_parse,
		            "%s %zu has colour component %g, but %s %zu has %g: colours must be all fractions in [0, 1] "
		            "or all integers 0..255",
		            kinds[face], index, v, kinds[face], byte_first ? s->byte_index : s->fraction_index,
		            byte_first ? s->byte : s->fraction);
	}
	return vn_io_success;
}

/* v holds the vertex's numbers in file order, with `colours` colour components. */
static vn_io_result store_vertex(off_reader* r, vn_io_mesh* m, size_t i, const double* v, size_t colours)
{
	double* position = m->positions + 3 * i;
	if (r->coords == 4) {
		if (v[3] == 0.0)
			return fail(r, vn_io_error_parse, "vertex %zu has w = 0; 4OFF coordinates are divided by w", i);
		for (size_t k = 0; k < 3; k++)
			position[k] = v[k] / v[3];
	} else {
		for (size_t k = 0; k < 3; k++)
			position[k] = v[k];
	}
	v += r->coords;
	if (r->normal) {
		for (size_t k = 0; k < 3; k++)
			m->normals[3 * i + k] = v[k];
		v += 3;
	}
	if (r->colour) {
		float* rgba = m->colors + 4 * i;
		rgba[3] = OFF_UNSET;
		for (size_t k = 0; k < colours; k++) {
			vn_io_result result = check_colour(r, 0, i, v[k]);
			if (result != vn_io_success)
				return result;
			rgba[k] = (float)v[k];
		}
		v += colours;
	}
	if (r->st) {
		m->texcoords[2 * i] = (float)v[0];
		m->texcoords[2 * i + 1] = (float)v[1];
	}
	return vn_io_success;
}

static vn_io_result face_colour(off_reader* r, vn_io_mesh* m, size_t f, float** rgba)
{
	if (!m->face_colors) {
		m->face_colors = alloc_array(m->face_count, 4 * sizeof(float));
		if (!m->face_colors)
			return out_of_memory(r);
		for (size_t i = 0; i < 4 * m->face_count; i++)
			m->face_colors[i] = OFF_UNSET;
	}
	*rgba = m->face_colors + 4 * f;
	return vn_io_success;
}

/* Scales colours to [0, 1] now that their style is known, and fills in what
 * the file left out. */
static void finish_colours(float* colours, size_t count, const colour_style* style, int* are_bytes)
{
	*are_bytes = style->has_byte;
	for (size_t i = 0; i < count; i++) {
		float* rgba = colours + 4 * i;
		if (rgba[0] == OFF_UNSET) {
			rgba[0] = rgba[1] = rgba[2] = OFF_GREY;
			rgba[3] = 1.0f;
			continue;
		}
		for (size_t k = 0; k < 3; k++)
			rgba[k] = *are_bytes ? rgba[k] / 255.0f : rgba[k];
		rgba[3] = rgba[3] == OFF_UNSET ? 1.0f : *are_bytes ? rgba[3] / 255.0f : rgba[3];
	}
}

static void finish(off_reader* r, vn_io_mesh* m)
{
	if (m->colors)
		finish_colours(m->colors, m->vertex_count, &r->styles[0], &m->colors_are_bytes);
	if (m->face_colors)
		finish_colours(m->face_colors, m->face_count, &r->styles[1], &m->face_colors_are_bytes);
}

/* ------------------------------------------------------------------ ASCII */

static vn_io_result read_ascii_counts(off_reader* r, off_line rest, uint64_t* vertices, uint64_t* faces)
{
	token t;
	off_line peek = rest;
	if (r->ndim) {
		uint64_t dimension;
		if (!next_token(&rest, &t) && !(next_line(r, &rest) && next_token(&rest, &t)))
			return fail(r, vn_io_error_parse, "the file ends before the nOFF dimension");
		if (!parse_natural(t, &dimension))
			return fail(r, vn_io_error_parse, "expected the nOFF dimension, found '%s'", quote(t).text);
		if (dimension != 3)
			return fail(r, vn_io_error_unsupported,
			            "nOFF dimension %s is not supported: vn reads 3-dimensional vertices only", quote(t).text);
		peek = rest;
	}
	/* The counts follow the keyword (and dimension) on its line, or fill the next line. */
	if (!next_token(&peek, &t) && !next_line(r, &rest))
		return fail(r, vn_io_error_parse, "the file ends before the vertex and face counts");
	size_t n = count_tokens(rest);
	if (n < 2 || n > 3)
		return fail(r, vn_io_error_parse, "expected the counts 'vertices faces [edges]', found %zu value%s", n,
		            n == 1 ? "" : "s");
	/* Geomview ignores the edge count (and many writers omit it), but a
	 * present one must still be a count. */
	static const char* const names[3] = {"vertex", "face", "edge"};
	uint64_t counts[3];
	for (size_t i = 0; i < n; i++) {
		next_token(&rest, &t);
		if (!parse_natural(t, &counts[i]))
			return fail(r, vn_io_error_parse, "the %s count '%s' is not a non-negative integer", names[i],
			            quote(t).text);
		if (counts[i] == UINT64_MAX)
			return fail(r, vn_io_error_parse, "the %s count '%s' is too large", names[i], quote(t).text);
	}
	*vertices = counts[0];
	*faces = counts[1];
	r->header = 0;
	return vn_io_success;
}

static vn_io_result read_ascii_vertex(off_reader* r, vn_io_mesh* m, size_t i, off_line line)
{
	size_t base = r->coords + (r->normal ? 3u : 0u) + (r->st ? 2u : 0u);
	size_t count = count_tokens(line);
	/* Colours have 3 or 4 components; the line's length tells which. */
	if (r->colour ? count != base + 3 && count != base + 4 : count != base) {
		if (r->colour)
			return fail(r, vn_io_error_parse, "vertex %zu has %zu numbers, but %s vertices have %zu or %zu (%s)", i,
			            count, r->keyword, base + 3, base + 4, r->layout);
		return fail(r, vn_io_error_parse, "vertex %zu has %zu numbers, but %s vertices have %zu (%s)", i, count,
		            r->keyword, base, r->layout);
	}
	double v[OFF_VERTEX_MAX];
	for (size_t k = 0; k < count; k++) {
		vn_io_result result = line_real(r, &line, "vertex", i, &v[k]);
		if (result != vn_io_success)
			return result;
	}
	return store_vertex(r, m, i, v, r->colour ? count - base : 0);
}

static vn_io_result read_ascii_face(off_reader* r, vn_io_mesh* m, size_t f, off_line line)
{
	token t;
	uint64_t corners;
	size_t count = count_tokens(line);
	next_token(&line, &t);
	if (!parse_natural(t, &corners))
		return fail(r, vn_io_error_parse, "face %zu: expected the number of corners, found '%s'", f, quote(t).text);
	if (corners == 0)
		return fail(r, vn_io_error_parse, "face %zu has 0 corners", f);
	/* Each index takes at least two characters: the count alone must not
	 * allocate much. */
	if (corners > (uint64_t)(r->end - r->p) / 2 + count)
		return fail(r, vn_io_error_parse, "face %zu has %llu corners, more than the rest of the file holds", f,
		            (unsigned long long)corners);
	size_t used = m->face_offsets[f];
	vn_io_result result = reserve_indices(r, m, f, used, corners);
	if (result != vn_io_success)
		return result;
	for (size_t k = 0; k < corners; k++) {
		uint64_t index;
		/* The indices may go on on the next lines (Geomview reads them as
		 * words; libigl writes long faces so); the colour is the rest of
		 * the line of the last one. */
		while (!next_token(&line, &t))
			if (!next_line(r, &line))
				return fail(r, vn_io_error_parse, "the file ends in face %zu, after %zu of its %llu indices", f, k,
				            (unsigned long long)corners);
		token magnitude = {t.p + 1, t.n - 1};
		if (t.p[0] == '-' && t.n > 1 && parse_natural(magnitude, &index))
			return fail(r, vn_io_error_parse, "face %zu has a negative index %s", f, quote(t).text);
		if (!parse_natural(t, &index))
			return fail(r, vn_io_error_parse, "face %zu: '%s' is not a vertex index", f, quote(t).text);
		if (index >= m->vertex_count)
			return fail(r, vn_io_error_parse, "face %zu has index %s, but the file has %zu vertices", f,
			            quote(t).text, m->vertex_count);
		m->indices[used + k] = (uint32_t)index;
	}
	m->face_offsets[f + 1] = (uint32_t)(used + corners);

	const size_t extra = count_tokens(line);
	if (extra == 1) {
		/* One integer is an index into Geomview's colormap, which vn does not
		 * have: the face is read as if uncoloured. */
		uint64_t index;
		next_token(&line, &t);
		if (!parse_natural(t, &index))
			return fail(r, vn_io_error_parse, "face %zu: '%s' after the indices is not a colormap index", f,
			            quote(t).text);
		if (!r->colormap_faces++)
			r->first_colormap_face = f;
	} else if (extra == 3 || extra == 4) {
		float* rgba = NULL;
		result = face_colour(r, m, f, &rgba);
		for (size_t k = 0; k < extra && result == vn_io_success; k++) {
			double v;
			result = line_real(r, &line, "face", f, &v);
			if (result == vn_io_success)
				result = check_colour(r, 1, f, v);
			if (result == vn_io_success)
				rgba[k] = (float)v;
		}
	} else if (extra != 0) {
		result = fail(r, vn_io_error_parse,
		              "face %zu has %zu numbers after its %llu indices; a face colour is 1 colormap index, "
		              "3 (RGB) or 4 (RGBA) numbers",
		              f, extra, (unsigned long long)corners);
	}
	return result;
}

static vn_io_result read_ascii(off_reader* r, vn_io_mesh* m, off_line rest)
{
	uint64_t vertices = 0, faces = 0;
	vn_io_result result = read_ascii_counts(r, rest, &vertices, &faces);
	/* Each number takes at least one character and one separator: a vertex
	 * at least 2 per number, a face "1 0\n"; the last line break may be
	 * missing. */
	size_t least = r->coords + (r->normal ? 3u : 0u) + (r->colour ? 3u : 0u) + (r->st ? 2u : 0u);
	if (result == vn_io_success)
		result = check_counts(r, vertices, faces, 2 * least, 4, (uint64_t)(r->end - r->p) + 1);
	if (result == vn_io_success)
		result = allocate(r, m, (size_t)vertices, (size_t)faces);
	off_line line;
	for (size_t i = 0; result == vn_io_success && i < vertices; i++) {
		if (!next_line(r, &line))
			return fail(r, vn_io_error_parse, "the file ends after %zu of the %zu vertices the header announces", i,
			            (size_t)vertices);
		result = read_ascii_vertex(r, m, i, line);
	}
	for (size_t f = 0; result == vn_io_success && f < faces; f++) {
		if (!next_line(r, &line))
			return fail(r, vn_io_error_parse, "the file ends after %zu of the %zu faces the header announces", f,
			            (size_t)faces);
		result = read_ascii_face(r, m, f, line);
	}
	if (result != vn_io_success)
		return result;
	if (next_line(r, &line)) {
		token t;
		next_token(&line, &t);
		return fail(r, vn_io_error_parse, "unexpected '%s' after the last of the %zu faces the header announces",
		            quote(t).text, (size_t)faces);
	}
	finish(r, m);
	return vn_io_success;
}

/* ------------------------------------------------------------------ binary */

/* Geomview binary OFF: after the header line, big-endian 32-bit words:
 * [dimension] vertices faces edges, the vertices as floats (position, normal,
 * RGBA colour, texture coordinates), then per face: corner count, indices,
 * colour count, colour floats. pmp-library writes little-endian words and no
 * colour count (read so when only then do the counts fit the file). */

static uint32_t word_at(const unsigned char* p, int little)
{
	return little ? (uint32_t)p[3] << 24 | (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0]
	              : (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static uint32_t take_word(off_reader* r)
{
	uint32_t w = word_at(r->p, r->pmp);
	r->p += 4;
	return w;
}

/* Whether the words after the header, read in that order, make a dimension
 * of 3 (nOFF) and counts whose vertices and faces the file can hold. */
static int counts_fit(const off_reader* r, int little, uint64_t vertex_bytes)
{
	const unsigned char* p = r->p;
	const size_t words = 3 + (r->ndim != 0);
	if ((size_t)(r->end - p) < 4 * words || (r->ndim && word_at(p, little) != 3))
		return 0;
	p += 4 * (r->ndim != 0);
	const uint64_t vertices = word_at(p, little), faces = word_at(p + 4, little);
	const uint64_t available = (uint64_t)(r->end - p) - 12;
	return vertices <= INT32_MAX && faces <= INT32_MAX && vertices * vertex_bytes + faces * 12 <= available;
}

/* Marks the position for messages; 1 when `words` more words are there. */
static int expect_words(off_reader* r, uint64_t words)
{
	r->where = (size_t)(r->p - r->begin);
	return words <= (uint64_t)(r->end - r->p) / 4;
}

static int64_t as_int32(uint32_t w)
{
	return w <= INT32_MAX ? (int64_t)w : (int64_t)w - INT64_C(4294967296);
}

static float as_float(uint32_t w)
{
	float f;
	memcpy(&f, &w, sizeof f);
	return f;
}

static vn_io_result read_binary_face(off_reader* r, vn_io_mesh* m, size_t f)
{
	if (!expect_words(r, 1))
		return fail(r, vn_io_error_parse, "the file ends before face %zu of %zu", f, m->face_count);
	int64_t corners = as_int32(take_word(r));
	if (corners <= 0)
		return fail(r, vn_io_error_parse, "face %zu has %lld corners", f, (long long)corners);
	/* Checked before reserving: the count alone must not allocate. */
	if (!expect_words(r, (uint64_t)corners + !r->pmp))
		return fail(r, vn_io_error_parse, "face %zu has %lld corners, more than the rest of the file holds", f,
		            (long long)corners);
	size_t used = m->face_offsets[f];
	vn_io_result result = reserve_indices(r, m, f, used, (uint64_t)corners);
	if (result != vn_io_success)
		return result;
	for (size_t k = 0; k < (size_t)corners; k++) {
		int64_t index = as_int32(take_word(r));
		if (index < 0)
			return fail(r, vn_io_error_parse, "face %zu has a negative index %lld", f, (long long)index);
		if ((uint64_t)index >= m->vertex_count)
			return fail(r, vn_io_error_parse, "face %zu has index %lld, but the file has %zu vertices", f,
			            (long long)index, m->vertex_count);
		m->indices[used + k] = (uint32_t)index;
	}
	m->face_offsets[f + 1] = (uint32_t)(used + (size_t)corners);
	if (r->pmp)
		return vn_io_success;

	int64_t colours = as_int32(take_word(r));
	if (colours < 0 || colours == 2 || colours > 4)
		return fail(r, vn_io_error_parse,
		            "face %zu has %lld colour components; a face colour is 0, 1 (colormap index), 3 or 4 numbers", f,
		            (long long)colours);
	if (!expect_words(r, (uint64_t)colours))
		return fail(r, vn_io_error_parse, "the file ends inside the colour of face %zu", f);
	if (colours == 1) {
		r->p += 4; /* colormap index: see read_ascii_face */
		if (!r->colormap_faces++)
			r->first_colormap_face = f;
	} else if (colours >= 3) {
		float* rgba = NULL;
		result = face_colour(r, m, f, &rgba);
		for (int64_t k = 0; k < colours && result == vn_io_success; k++) {
			double v = as_float(take_word(r));
			result = check_colour(r, 1, f, v);
			if (result == vn_io_success)
				rgba[k] = (float)v;
		}
	}
	return result;
}

static vn_io_result read_binary(off_reader* r, vn_io_mesh* m)
{
	/* Binary vertex colours are always 4 floats (RGBA). */
	size_t words = r->coords + (r->normal ? 3u : 0u) + (r->colour ? 4u : 0u) + (r->st ? 2u : 0u);
	if (!counts_fit(r, 0, 4 * words) && counts_fit(r, 1, 4 * words)) {
		r->pmp = 1;
		if (!vn_io_append_line(&r->warnings, "binary OFF as pmp-library writes it (little-endian words, no face colour "
		                                     "counts; Geomview's are big-endian): read so, as its counts fit the file "
		                                     "only so"))
			return out_of_memory(r);
	}
	if (r->ndim) {
		if (!expect_words(r, 1))
			return fail(r, vn_io_error_parse, "the file ends before the nOFF dimension");
		int64_t dimension = as_int32(take_word(r));
		if (dimension != 3)
			return fail(r, vn_io_error_unsupported,
			            "nOFF dimension %lld is not supported: vn reads 3-dimensional vertices only",
			            (long long)dimension);
	}
	static const char* const names[3] = {"vertex", "face", "edge"};
	int64_t counts[3];
	size_t counts_at = (size_t)(r->p - r->begin);
	for (size_t i = 0; i < 3; i++) {
		if (!expect_words(r, 1))
			return fail(r, vn_io_error_parse, "the file ends before the %s count", names[i]);
		counts[i] = as_int32(take_word(r));
		if (counts[i] < 0)
			return fail(r, vn_io_error_parse, "the %s count %lld is negative", names[i], (long long)counts[i]);
	}
	/* A face is at least 3 words: 1 corner, its index, 0 colours. */
	r->where = counts_at;
	vn_io_result result =
	    check_counts(r, (uint64_t)counts[0], (uint64_t)counts[1], 4 * words, 12, (uint64_t)(r->end - r->p));
	if (result == vn_io_success)
		result = allocate(r, m, (size_t)counts[0], (size_t)counts[1]);
	/* Vertices have a fixed size, so check_counts has made sure they are all there. */
	for (size_t i = 0; i < m->vertex_count && result == vn_io_success; i++) {
		double v[OFF_VERTEX_MAX];
		r->where = (size_t)(r->p - r->begin);
		for (size_t k = 0; k < words; k++)
			v[k] = as_float(take_word(r));
		result = store_vertex(r, m, i, v, r->colour ? 4 : 0);
	}
	for (size_t f = 0; f < m->face_count && result == vn_io_success; f++)
		result = read_binary_face(r, m, f);
	if (result != vn_io_success)
		return result;
	if (r->p != r->end) {
		r->where = (size_t)(r->p - r->begin);
		return fail(r, vn_io_error_parse, "%zu unexpected bytes after the last face", (size_t)(r->end - r->p));
	}
	finish(r, m);
	return vn_io_success;
}

/* ------------------------------------------------------------------ entry points */

static vn_io_result read_off(off_reader* r, vn_io_mesh* m)
{
	off_line line;
	token t;
	if (!next_line(r, &line))
		return vn_io_fail(r->error, vn_io_error_parse, "%s: expected an OFF header keyword, but the file is %s",
		                  r->name, r->end == r->begin ? "empty" : "only blanks and comments");
	next_token(&line, &t);
	const size_t keyword = parse_keyword(r, t);
	if (keyword) {
		line.p = t.p + keyword;
	} else if (t.p[0] >= '0' && t.p[0] <= '9') {
		/* Geomview: the keyword is "recommended but optional, as many
		 * existing files lack this keyword"; the counts start the file. */
		parse_keyword(r, (token){(const unsigned char*)"OFF", 3});
		line.p = t.p;
	} else {
		return fail(r, vn_io_error_parse,
		            "expected an OFF header keyword ([ST][C][N][4][n]OFF) or the counts, found '%s'", quote(t).text);
	}
	off_line rest = line;
	if (next_token(&rest, &t) && t.n == 6 && memcmp(t.p, "BINARY", 6) == 0) {
		if (next_token(&rest, &t))
			return fail(r, vn_io_error_parse, "unexpected '%s' after BINARY", quote(t).text);
		if (r->wide)
			return fail(r, vn_io_error_parse,
			            "the header is %s text (it starts with a byte order mark), but says BINARY: binary data "
			            "cannot be read as text",
			            r->wide);
		/* Binary data starts right after the header line's line break. */
		r->binary = 1;
		r->header = 0;
		return read_binary(r, m);
	}
	return read_ascii(r, m, line);
}

/* The reader of the size bytes at data, text decoded from `wide` (or NULL). */
static vn_io_result read_memory(const char* data, size_t size, const char* name, const char* wide, vn_io_mesh* mesh,
                                vn_io_error* error)
{
	memset(mesh, 0, sizeof *mesh);
	off_reader r;
	memset(&r, 0, sizeof r);
	r.name = name;
	r.error = error;
	r.wide = wide;
	r.header = 1;
	r.begin = (const unsigned char*)(data ? data : "");
	r.p = r.begin;
	r.end = r.begin + (data ? size : 0);
	r.line = 1;
	r.coords = 3;
	r.p += vn_io_utf8_bom(r.p, (size_t)(r.end - r.p));
	const vn_io_result lfs = vn_io_refuse_lfs_pointer(r.p, (size_t)(r.end - r.p), name, error);
	if (lfs != vn_io_success)
		return lfs;

	vn_io_c_locale locale;
	if (!vn_io_c_locale_enter(&locale))
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	vn_io_result result = read_off(&r, mesh);
	vn_io_c_locale_leave(&locale);
	if (result == vn_io_success && r.colormap_faces &&
	    !(r.colormap_faces == 1
	          ? vn_io_append_line(&r.warnings,
	                              "face %zu gives its colour as an index into Geomview's colormap, which vn does not "
	                              "have: it is read as an uncoloured face",
	                              r.first_colormap_face)
	          : vn_io_append_line(&r.warnings,
	                              "%zu faces (the first: face %zu) give their colour as an index into Geomview's "
	                              "colormap, which vn does not have: they are read as uncoloured faces",
	                              r.colormap_faces, r.first_colormap_face)))
		result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	if (result == vn_io_success && r.comments_failed)
		result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	if (result != vn_io_success)
		vn_io_mesh_free(mesh);
	if (result == vn_io_success) {
		mesh->warnings = r.warnings;
		mesh->comments = r.comments;
	} else {
		free(r.warnings);
		free(r.comments);
	}
	return result;
}

vn_io_result vn_io_off_read_memory(const char* data, size_t size, const char* name, vn_io_mesh* mesh,
                                   vn_io_error* error)
{
	return vn_io_read_text(data, size, name, read_memory, mesh, error);
}

vn_io_result vn_io_off_read(const char* path, vn_io_mesh* mesh, vn_io_error* error)
{
	return vn_io_read_with(path, vn_io_off_read_memory, mesh, error);
}

/* ------------------------------------------------------------------ writer */

static int colour_byte(float c)
{
	return !(c > 0.0f) ? 0 : c >= 1.0f ? 255 : (int)(c * 255.0f + 0.5f);
}

/* Always RGBA: Geomview defines a vertex colour as 4 numbers (it reads the
 * 4th from the next line when a line has 3), and a file whose alphas are all
 * opaque keeps them. */
static void put_colour(vn_io_text_out* w, const float* rgba, int bytes)
{
	for (size_t k = 0; k < 4; k++) {
		if (bytes) {
			vn_io_put_uint(w, " ", (uint64_t)colour_byte(rgba[k]));
		} else {
			vn_io_put_float(w, rgba[k]);
		}
	}
}

vn_io_result vn_io_off_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings, vn_io_error* error)
{
	(void)settings; /* OFF has none */
	vn_io_c_locale locale;
	if (!vn_io_c_locale_enter(&locale))
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	vn_io_text_out w = {out, 0, 0, 0, {0}};

	char text[64];
	/* The edge count is not used by anyone; 0 is what most writers put. */
	snprintf(text, sizeof text, "%s%s%sOFF\n", mesh->texcoords ? "ST" : "", mesh->colors ? "C" : "",
	         mesh->normals ? "N" : "");
	vn_io_put(&w, text);
	vn_io_put_comments(&w, mesh->comments, "#");
	snprintf(text, sizeof text, "%zu %zu 0\n", mesh->vertex_count, mesh->face_count);
	vn_io_put(&w, text);
	for (size_t i = 0; i < mesh->vertex_count && !w.failed; i++) {
		for (size_t k = 0; k < 3; k++)
			vn_io_put_exact(&w, k != 0, mesh->positions[3 * i + k]);
		/* Normals are unit vectors made for rendering: float precision; a
		 * point cloud's are the input's (vn computes none): as they are. */
		for (size_t k = 0; k < 3 && mesh->normals; k++) {
			if (mesh->face_count)
				vn_io_put_float9(&w, mesh->normals[3 * i + k]);
			else
				vn_io_put_exact(&w, 1, mesh->normals[3 * i + k]);
		}
		if (mesh->colors)
			put_colour(&w, mesh->colors + 4 * i, mesh->colors_are_bytes);
		if (mesh->texcoords)
			for (size_t k = 0; k < 2; k++)
				vn_io_put_float(&w, mesh->texcoords[2 * i + k]);
		vn_io_put(&w, "\n");
	}
	for (size_t f = 0; f < mesh->face_count && !w.failed; f++) {
		uint32_t begin = mesh->face_offsets[f], end = mesh->face_offsets[f + 1];
		vn_io_put_uint(&w, "", end - begin);
		for (uint32_t k = begin; k < end; k++)
			vn_io_put_uint(&w, " ", mesh->indices[k]);
		if (mesh->face_colors)
			put_colour(&w, mesh->face_colors + 4 * f, mesh->face_colors_are_bytes);
		vn_io_put(&w, "\n");
	}
	vn_io_c_locale_leave(&locale);
	if (!vn_io_flush(&w))
		return vn_io_fail(error, vn_io_error_write, "%s: cannot write: %s", path, strerror(w.error_number));
	return vn_io_success;
}
