/*
 * PLY, the Stanford polygon file format.
 *
 * Reader: ASCII, binary_little_endian and binary_big_endian, every property
 * type (char ... double, or int8 ... float64). The "vertex" element gives
 * positions (x y z), normals (nx ny nz), colours (red green blue [alpha],
 * uchar or float in [0, 1]), texture coordinates (the first pair of s t,
 * u v, texture_u texture_v, texture_s texture_t) and, for every other
 * scalar property, an attribute "_NAME" in the property's own type. The
 * "face" element gives polygons (vertex_indices or vertex_index) and face
 * colours; without faces, a "tristrips" element's strips give triangles
 * (strip_faces), and without either the file is a point cloud: its
 * vertices alone. The face element's other properties, the other elements
 * and the comment and obj_info lines are kept as they are for the writer
 * (vn_io_ply_extras); vertex list properties are read past.
 *
 * Not Draco's PlyReader (1.5.5): it refuses big endian, copies past the end
 * of a truncated binary file (no bounds check), and parses ASCII values as
 * float or int32 (doubles rounded, uint32 above 2^31 refused), without line
 * numbers for errors.
 *
 * Writer: binary_little_endian 1.0, what Blender and MeshLab read: x y z as
 * float, or double when a coordinate is not a float (so PLY to PLY keeps
 * positions exactly), nx ny nz float, colours red green blue alpha, uchar
 * when the source had bytes (else float), s t float, every attribute as
 * properties of its type, faces as "list uchar int vertex_indices" (uint
 * when needed; "element face 0" for a point cloud), face colours, and what
 * vn_io_ply_extras kept: the comments after vn's, the face properties
 * after vn's, the other elements after the faces.
 */
#include "ply.h"
#include "mtl.h"
#include "text.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ property types */

enum { PLY_INT8, PLY_UINT8, PLY_INT16, PLY_UINT16, PLY_INT32, PLY_UINT32, PLY_FLOAT32, PLY_FLOAT64, PLY_TYPES };

static const struct {
	const char* name;  /* as the PLY paper names it */
	const char* sized; /* the other spelling */
	size_t size;
	int gltf; /* vn_io_attribute component type */
	double min, max;
} types[PLY_TYPES] = {
    {"char", "int8", 1, 5120, -128.0, 127.0},
    {"uchar", "uint8", 1, 5121, 0.0, 255.0},
    {"short", "int16", 2, 5122, -32768.0, 32767.0},
    {"ushort", "uint16", 2, 5123, 0.0, 65535.0},
    {"int", "int32", 4, 5124, -2147483648.0, 2147483647.0},
    {"uint", "uint32", 4, 5125, 0.0, 4294967295.0},
    {"float", "float32", 4, 5126, -HUGE_VAL, HUGE_VAL},
    {"double", "float64", 8, 5130, -HUGE_VAL, HUGE_VAL},
};

static int is_real(int type)
{
	return type == PLY_FLOAT32 || type == PLY_FLOAT64;
}

/* A value in host byte order as a double (exact for every type). */
static double get_value(int type, const unsigned char* p)
{
	switch (type) {
	case PLY_INT8: { int8_t v; memcpy(&v, p, 1); return v; }
	case PLY_UINT8: return *p;
	case PLY_INT16: { int16_t v; memcpy(&v, p, 2); return v; }
	case PLY_UINT16: { uint16_t v; memcpy(&v, p, 2); return v; }
	case PLY_INT32: { int32_t v; memcpy(&v, p, 4); return v; }
	case PLY_UINT32: { uint32_t v; memcpy(&v, p, 4); return v; }
	case PLY_FLOAT32: { float v; memcpy(&v, p, 4); return v; }
	default: { double v; memcpy(&v, p, 8); return v; }
	}
}

/* v, in range for type (integral for integers), in host byte order. */
static void put_value(int type, double v, unsigned char* p)
{
	switch (type) {
	case PLY_INT8: { int8_t x = (int8_t)v; memcpy(p, &x, 1); break; }
	case PLY_UINT8: *p = (unsigned char)v; break;
	case PLY_INT16: { int16_t x = (int16_t)v; memcpy(p, &x, 2); break; }
	case PLY_UINT16: { uint16_t x = (uint16_t)v; memcpy(p, &x, 2); break; }
	case PLY_INT32: { int32_t x = (int32_t)v; memcpy(p, &x, 4); break; }
	case PLY_UINT32: { uint32_t x = (uint32_t)v; memcpy(p, &x, 4); break; }
	case PLY_FLOAT32: { float x = (float)v; memcpy(p, &x, 4); break; }
	default: memcpy(p, &v, 8); break;
	}
}

static int host_is_little_endian(void)
{
	const uint16_t one = 1;
	unsigned char first;
	memcpy(&first, &one, 1);
	return first == 1;
}

static void reverse(unsigned char* p, size_t n)
{
	for (size_t i = 0; i < n / 2; i++) {
		unsigned char t = p[i];
		p[i] = p[n - 1 - i];
		p[n - 1 - i] = t;
	}
}

/* ------------------------------------------------------------------ reader state */

/* Room for a property's or element's name (longer ones are cut). */
#define PLY_NAME_MAX 256

typedef struct ply_property {
	char name[PLY_NAME_MAX];
	int type;       /* of the values */
	int count_type; /* of a list's length; -1: not a list */
	/* Kept values in host byte order, else NULL: a scalar's, one an entry;
	 * a list's, its entries' items one after another, entry i's from item
	 * offsets[i] to offsets[i + 1] (count + 1 offsets; NULL for a scalar),
	 * in room for `capacity` items. */
	unsigned char* column;
	size_t* offsets;
	size_t capacity;
} ply_property;

typedef struct ply_element {
	char name[PLY_NAME_MAX];
	uint64_t count;
	ply_property* properties;
	size_t property_count;
	int kept; /* its properties moved to the mesh's vn_io_ply_extras */
} ply_element;

/* What a PLY file holds besides what vn_io_mesh describes, for the PLY
 * writer to write back (vn_io_holds_ply_extras). */
struct vn_io_ply_extras {
	char* comments;   /* the header's comment and obj_info lines, each ending in "\n"; NULL: none */
	ply_element face; /* the face element's other properties (count: the faces), none: property_count 0 */
	ply_element* elements; /* the other elements, whole */
	size_t element_count;
};

static void free_properties(ply_element* e)
{
	for (size_t k = 0; k < e->property_count; k++) {
		free(e->properties[k].column);
		free(e->properties[k].offsets);
	}
	free(e->properties);
}

void vn_io_ply_extras_free(vn_io_ply_extras* extras)
{
	if (!extras)
		return;
	free(extras->comments);
	free_properties(&extras->face);
	for (size_t i = 0; i < extras->element_count; i++)
		free_properties(&extras->elements[i]);
	free(extras->elements);
	free(extras);
}

enum { PLY_ASCII, PLY_LITTLE, PLY_BIG };

typedef struct ply_reader {
	const char* name;
	vn_io_error* error;
	const unsigned char* begin;
	const unsigned char* p;
	const unsigned char* end;
	size_t line; /* of p, in the header and in ASCII data */
	unsigned char newline; /* what ends a line: '\n' ("\r\n" too), or '\r' in old Mac files */
	int format;  /* PLY_ASCII, PLY_LITTLE or PLY_BIG */
	int swap;    /* binary data in the other byte order than the host's */
	int in_data; /* messages name a byte offset for binary data */
	const char* wide; /* the encoding the text was read from (vn_io_utf8_from_wide), or NULL */

	ply_element* elements;
	size_t element_count;
	ply_element* vertex;
	ply_element* face;
	ply_property* indices; /* the face element's vertex_indices list (or the strips') */
	size_t index_capacity;
	/* Without faces, a "tristrips" element (Stanford's and MeshLab's older
	 * files): its vertex_indices, -1 (as UINT32_MAX) between strips. */
	ply_element* strips;
	uint32_t* strip;
	size_t strip_used, strip_capacity;

	char* comments; /* vn_io_ply_extras' */
	char* warnings;
	/* ASCII data: the first entry that left values on its line (NULL
	 * element: none), named where reading then fails. */
	struct {
		const ply_element* element;
		size_t entry, line, values;
	} left;
} ply_reader;

typedef struct token {
	const unsigned char* p;
	size_t n;
} token;

#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static vn_io_result fail(ply_reader* r, vn_io_result result, const char* fmt, ...)
{
	const int byte = r->in_data && r->format != PLY_ASCII;
	va_list args;
	va_start(args, fmt);
	vn_io_fail_at(r->error, result, r->name, byte, byte ? (size_t)(r->p - r->begin) : r->line, fmt, args);
	va_end(args);
	return result;
}

static vn_io_result out_of_memory(ply_reader* r)
{
	return vn_io_fail(r->error, vn_io_error_memory, "%s: out of memory", r->name);
}

static int token_is(token t, const char* word)
{
	return t.n == strlen(word) && memcmp(t.p, word, t.n) == 0;
}

static vn_io_quoted quote(token t)
{
	return vn_io_quote(t.p, t.n);
}

/* ------------------------------------------------------------------ header */

/* Blanks within a line; '\r' too, before the '\n' of "\r\n". */
static int is_space(unsigned char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* The next header line's first words (at most 6; *count is how many the
 * line has); 0 at the end of the input. r->line is that line's number. */
static int header_line(ply_reader* r, token words[6], size_t* count)
{
	if (r->p >= r->end)
		return 0;
	r->line++;
	const unsigned char* stop = memchr(r->p, r->newline, (size_t)(r->end - r->p));
	const unsigned char* line_end = stop ? stop : r->end;
	*count = 0;
	for (const unsigned char* q = r->p; q < line_end;) {
		while (q < line_end && is_space(*q))
			q++;
		if (q == line_end)
			break;
		const unsigned char* w = q;
		while (q < line_end && !is_space(*q))
			q++;
		if (*count < 6)
			words[*count] = (token){w, (size_t)(q - w)};
		++*count;
	}
	r->p = stop ? stop + 1 : r->end;
	return 1;
}

static int parse_type(token t)
{
	for (int i = 0; i < PLY_TYPES; i++)
		if (token_is(t, types[i].name) || token_is(t, types[i].sized))
			return i;
	return -1;
}

static int parse_count(token t, uint64_t* out)
{
	uint64_t v = 0;
	if (t.n == 0)
		return 0;
	for (size_t i = 0; i < t.n; i++) {
		const unsigned digit = (unsigned)t.p[i] - '0';
		if (digit > 9)
			return 0;
		v = v > (UINT64_MAX - digit) / 10 ? UINT64_MAX : v * 10 + digit;
	}
	*out = v;
	return 1;
}

static void copy_name(char name[PLY_NAME_MAX], token t)
{
	const size_t n = t.n < PLY_NAME_MAX - 1 ? t.n : PLY_NAME_MAX - 1;
	memcpy(name, t.p, n);
	name[n] = '\0';
}

/* Names are kept as the file spells them and written back: a control
 * character (a NUL ends one early) would make a header no reader reads. */
static int has_control(token name)
{
	for (size_t i = 0; i < name.n; i++)
		if ((unsigned char)name.p[i] < 0x20 || name.p[i] == 0x7f)
			return 1;
	return 0;
}

static vn_io_result add_property(ply_reader* r, token* w, size_t count)
{
	if (!r->element_count)
		return fail(r, vn_io_error_parse, "a property line before the first element line");
	ply_element* e = &r->elements[r->element_count - 1];
	const int list = count >= 2 && token_is(w[1], "list");
	if (count != (list ? 5u : 3u))
		return fail(r, vn_io_error_parse, "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
	const int type = parse_type(w[list ? 3 : 1]);
	const int count_type = list ? parse_type(w[2]) : -1;
	if (type < 0)
		return fail(r, vn_io_error_parse, "unknown property type '%s'", quote(w[list ? 3 : 1]).text);
	if (list && (count_type < 0 || is_real(count_type)))
		return fail(r, vn_io_error_parse, "'%s' is not an integer type for a list's length", quote(w[2]).text);
	const token name = w[list ? 4 : 2];
	if (has_control(name))
		return fail(r, vn_io_error_parse, "property name '%s' has a control character", quote(name).text);
	ply_property* grown = realloc(e->properties, (e->property_count + 1) * sizeof *grown);
	if (!grown)
		return out_of_memory(r);
	e->properties = grown;
	ply_property* p = &grown[e->property_count++];
	memset(p, 0, sizeof *p);
	copy_name(p->name, name);
	p->type = type;
	p->count_type = count_type;
	return vn_io_success;
}

static vn_io_result add_element(ply_reader* r, token* w, size_t count)
{
	uint64_t n;
	if (count != 3)
		return fail(r, vn_io_error_parse, "expected 'element NAME COUNT'");
	if (!parse_count(w[2], &n))
		return fail(r, vn_io_error_parse, "the count of element '%s' is '%s', not a non-negative integer",
		            quote(w[1]).text, quote(w[2]).text);
	if (has_control(w[1]))
		return fail(r, vn_io_error_parse, "element name '%s' has a control character", quote(w[1]).text);
	ply_element* grown = realloc(r->elements, (r->element_count + 1) * sizeof *grown);
	if (!grown)
		return out_of_memory(r);
	r->elements = grown;
	ply_element* e = &grown[r->element_count++];
	memset(e, 0, sizeof *e);
	copy_name(e->name, w[1]);
	e->count = n;
	return vn_io_success;
}

/* Appends the header line at `start` (a comment or obj_info), after
 * `prefix`, to r->comments, as the file has it, but vn's own "comment
 * written by vn", which its writer writes anyway; 0 when out of memory. */
static int keep_comment(ply_reader* r, const char* prefix, const unsigned char* start)
{
	const unsigned char* stop = start;
	while (stop < r->end && *stop != r->newline)
		stop++;
	/* Blanks at the end stay: MeshLab reads a TextureFile name to the line's end. */
	size_t n = (size_t)(stop - start);
	if (n && r->newline == '\n' && start[n - 1] == '\r')
		n--;
	static const char own[] = "comment written by vn";
	if (n == sizeof own - 1 && !memcmp(start, own, n))
		return 1;
	const size_t p = strlen(prefix);
	size_t used = r->comments ? strlen(r->comments) : 0;
	char* grown = realloc(r->comments, used + p + n + 2);
	if (!grown)
		return 0;
	memcpy(grown + used, prefix, p);
	used += p;
	/* A line break inside the line (a lone '\r' in a '\n' file) would end
	 * it early in the file written, a NUL the text: a blank instead. */
	for (size_t i = 0; i < n; i++)
		grown[used + i] = start[i] == '\r' || start[i] == '\n' || !start[i] ? ' ' : (char)start[i];
	memcpy(grown + used + n, "\n", 2);
	r->comments = grown;
	return 1;
}

static vn_io_result read_header(ply_reader* r)
{
	token w[6];
	size_t count;
	const unsigned char* first = r->p;
	while (first < r->end && *first != '\n' && *first != '\r')
		first++;
	r->newline = first + 1 < r->end && first[0] == '\r' && first[1] != '\n' ? '\r' : '\n';
	if (!header_line(r, w, &count) || count != 1 || !token_is(w[0], "ply"))
		return vn_io_fail(r->error, vn_io_error_parse, "%s: not a PLY file: it does not start with a 'ply' line",
		                  r->name);
	int format = -1;
	for (const unsigned char* start = r->p; header_line(r, w, &count); start = r->p) {
		vn_io_result result = vn_io_success;
		if (count && (token_is(w[0], "comment") || token_is(w[0], "obj_info"))) {
			if (!keep_comment(r, "", start))
				return out_of_memory(r);
			continue;
		}
		/* Blender 2.4x's exporter wrote its credit line ("Created by
		 * Blender3D 247 - www.blender.org, source file: ...") without
		 * "comment": a line of no keyword before the first element is read
		 * as a comment, with a warning (after one, it would hide a
		 * misspelt property). */
		if (count && r->element_count == 0 && !token_is(w[0], "format") && !token_is(w[0], "element") &&
		    !token_is(w[0], "property") && !token_is(w[0], "end_header")) {
			const unsigned char* stop = start;
			while (stop < r->end && *stop != r->newline && *stop != '\r')
				stop++;
			if (!keep_comment(r, "comment ", start) ||
			    !vn_io_append_line(&r->warnings,
			                       "header line %zu ('%s') has no keyword: read as a comment (Blender 2.4x wrote its "
			                       "credit line so)",
			                       r->line, quote((token){start, (size_t)(stop - start)}).text))
				return out_of_memory(r);
			continue;
		}
		if (count == 0)
			continue;
		if (token_is(w[0], "end_header")) {
			if (format < 0)
				return fail(r, vn_io_error_parse, "end_header before a format line");
			r->format = format;
			r->swap = format != PLY_ASCII && (format == PLY_LITTLE) != host_is_little_endian();
			r->line++; /* the data's first line */
			r->in_data = 1;
			return vn_io_success;
		}
		if (token_is(w[0], "format")) {
			static const char* const names[3] = {"ascii", "binary_little_endian", "binary_big_endian"};
			for (int i = 0; i < 3 && count == 3; i++)
				if (token_is(w[1], names[i]))
					format = i;
			if (count != 3 || format < 0)
				return fail(r, vn_io_error_parse,
				            "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
			if (!token_is(w[2], "1.0"))
				return fail(r, vn_io_error_unsupported, "PLY version '%s' is not supported: vn reads 1.0",
				            quote(w[2]).text);
			if (r->wide && format != PLY_ASCII)
				return fail(r, vn_io_error_parse,
				            "the header is %s text (it starts with a byte order mark), but the format is %s: "
				            "binary data cannot be read as text",
				            r->wide, names[format]);
		} else if (token_is(w[0], "element")) {
			result = add_element(r, w, count);
		} else if (token_is(w[0], "property")) {
			result = add_property(r, w, count);
		} else {
			result = fail(r, vn_io_error_parse,
			              "unexpected '%s' in the header: lines are format, comment, obj_info, element, property "
			              "or end_header",
			              quote(w[0]).text);
		}
		if (result != vn_io_success)
			return result;
	}
	return fail(r, vn_io_error_parse, "the file ends in the header, before end_header");
}

/* ------------------------------------------------------------------ data */

/* Where a value is, for messages. */
typedef struct place {
	const ply_element* element;
	size_t entry;
	ply_property* property;
} place;

static const char* type_name(int type)
{
	return types[type].name;
}

/* The next ASCII token, counting lines; empty at the end. */
static token next_token(ply_reader* r)
{
	while (r->p < r->end && (is_space(*r->p) || *r->p == '\n'))
		r->line += *r->p++ == r->newline;
	token t = {r->p, 0};
	while (r->p < r->end && !is_space(*r->p) && *r->p != '\n')
		r->p++;
	t.n = (size_t)(r->p - t.p);
	return t;
}

/* One value of `type` into out (host byte order). */
static vn_io_result read_value(ply_reader* r, int type, const place* at, unsigned char* out)
{
	const size_t size = types[type].size;
	if (r->format != PLY_ASCII) {
		if ((size_t)(r->end - r->p) < size)
			return fail(r, vn_io_error_parse, "the file ends in %s %zu of %llu (property '%s')", at->element->name,
			            at->entry, (unsigned long long)at->element->count, at->property->name);
		memcpy(out, r->p, size);
		if (r->swap)
			reverse(out, size);
		r->p += size;
		return vn_io_success;
	}
	token t = next_token(r);
	double v;
	if (t.n == 0)
		return fail(r, vn_io_error_parse, "the file ends in %s %zu of %llu (property '%s')", at->element->name,
		            at->entry, (unsigned long long)at->element->count, at->property->name);
	if (!vn_io_parse_real(t.p, t.n, &v))
		return fail(r, vn_io_error_parse, "%s %zu, property '%s': '%s' is not a number", at->element->name, at->entry,
		            at->property->name, quote(t).text);
	if (!is_real(type) && !(v >= types[type].min && v <= types[type].max && v == floor(v)))
		return fail(r, vn_io_error_parse, "%s %zu, property '%s': '%s' is not of type %s (a whole number from %.0f to %.0f)",
		            at->element->name, at->entry, at->property->name, quote(t).text, type_name(type), types[type].min,
		            types[type].max);
	put_value(type, v, out);
	return vn_io_success;
}

static vn_io_result reserve_indices(ply_reader* r, vn_io_mesh* m, size_t used, uint64_t corners, size_t face)
{
	if (corners > UINT32_MAX - used)
		return fail(r, vn_io_error_unsupported, "face %zu brings the corner count past 4294967295, the 32-bit limit",
		            face);
	const size_t needed = used + (size_t)corners;
	if (needed <= r->index_capacity)
		return vn_io_success;
	size_t capacity = r->index_capacity > UINT32_MAX / 2 ? UINT32_MAX : 2 * r->index_capacity;
	if (capacity < needed)
		capacity = needed;
	uint32_t* grown = realloc(m->indices, capacity * sizeof *grown);
	if (!grown)
		return out_of_memory(r);
	m->indices = grown;
	r->index_capacity = capacity;
	return vn_io_success;
}

/* The `length` values of a tristrips list, appended to r->strip. */
static vn_io_result read_strip(ply_reader* r, const place* at, size_t length)
{
	if (length > r->strip_capacity - r->strip_used) {
		size_t capacity = r->strip_capacity ? 2 * r->strip_capacity : 64;
		if (capacity - r->strip_used < length)
			capacity = r->strip_used + length;
		uint32_t* grown = realloc(r->strip, capacity * sizeof *grown);
		if (!grown)
			return out_of_memory(r);
		r->strip = grown;
		r->strip_capacity = capacity;
	}
	for (size_t k = 0; k < length; k++) {
		unsigned char v[8];
		vn_io_result result = read_value(r, at->property->type, at, v);
		if (result != vn_io_success)
			return result;
		const double index = get_value(at->property->type, v);
		if (index != -1 && !(index >= 0 && index < (double)r->vertex->count && index == floor(index)))
			return fail(r, vn_io_error_parse, "tristrips %zu has index %.17g, but the file has %llu vertices", at->entry,
			            index, (unsigned long long)r->vertex->count);
		r->strip[r->strip_used++] = index == -1 ? UINT32_MAX : (uint32_t)index;
	}
	/* A list's end ends its strip too. */
	return vn_io_success;
}

/* The triangles of the strips: in each strip (between -1s, or a list's
 * ends) v0 v1 v2, v2 v1 v3, v2 v3 v4, ... (every other one turned, so that
 * all face the same way, as OpenGL and MeshLab read them); one with a
 * repeated index (how strips are joined) has no surface and is left out. */
static vn_io_result strip_faces(ply_reader* r, vn_io_mesh* m)
{
	size_t count = 0;
	for (int pass = 0; pass < 2; pass++) {
		size_t start = 0;
		for (size_t k = 0; k < r->strip_used; k++) {
			if (r->strip[k] == UINT32_MAX) {
				start = k + 1;
				continue;
			}
			if (k < start + 2)
				continue;
			uint32_t t[3] = {r->strip[k - 2], r->strip[k - 1], r->strip[k]};
			if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
				continue;
			if ((k - start) % 2) {
				const uint32_t first = t[0];
				t[0] = t[1], t[1] = first;
			}
			if (pass) {
				memcpy(m->indices + 3 * m->face_count, t, sizeof t);
				m->face_count++;
				m->face_offsets[m->face_count] = (uint32_t)(3 * m->face_count);
			} else if (++count > UINT32_MAX / 3) {
				return fail(r, vn_io_error_unsupported, "the tristrips make more than %u triangles", UINT32_MAX / 3);
			}
		}
		if (pass)
			break;
		if (count == 0)
			return vn_io_fail(r->error, vn_io_error_unsupported,
			                  "%s: has %llu vertices and tristrips with no triangle: a mesh is needed", r->name,
			                  (unsigned long long)r->vertex->count);
		m->face_offsets = malloc((count + 1) * sizeof *m->face_offsets);
		m->indices = malloc(3 * count * sizeof *m->indices);
		if (!m->face_offsets || !m->indices)
			return out_of_memory(r);
		m->face_offsets[0] = 0;
		m->face_count = 0;
	}
	return vn_io_success;
}

/* The `length` values of a list kept for the writer (vn_io_ply_extras),
 * appended to its column. */
static vn_io_result read_kept_list(ply_reader* r, const place* at, size_t length)
{
	ply_property* p = at->property;
	const size_t size = types[p->type].size, used = p->offsets[at->entry];
	if (length > p->capacity - used) {
		size_t capacity = p->capacity ? 2 * p->capacity : 64;
		if (capacity - used < length)
			capacity = used + length;
		unsigned char* grown = realloc(p->column, capacity * size);
		if (!grown)
			return out_of_memory(r);
		p->column = grown;
		p->capacity = capacity;
	}
	for (size_t k = 0; k < length; k++) {
		vn_io_result result = read_value(r, p->type, at, p->column + (used + k) * size);
		if (result != vn_io_success)
			return result;
	}
	p->offsets[at->entry + 1] = used + length;
	return vn_io_success;
}

/* A list property of entry i: its length, then its values (kept when it is
 * the face's vertex_indices, or kept for the writer). */
static vn_io_result read_list(ply_reader* r, vn_io_mesh* m, const place* at)
{
	const ply_property* p = at->property;
	unsigned char v[8];
	vn_io_result result = read_value(r, p->count_type, at, v);
	if (result != vn_io_success)
		return result;
	const double length = get_value(p->count_type, v);
	if (length < 0)
		return fail(r, vn_io_error_parse, "%s %zu, list '%s' has length %.0f", at->element->name, at->entry, p->name,
		            length);
	/* Checked before anything is reserved: the length alone must not allocate. */
	const size_t least = r->format == PLY_ASCII ? 2 : types[p->type].size;
	if (length > (double)((size_t)(r->end - r->p) + 1) / (double)least)
		return fail(r, vn_io_error_parse, "%s %zu, list '%s' has %.0f values, more than the rest of the file holds",
		            at->element->name, at->entry, p->name, length);
	if (p == r->indices && r->strips)
		return read_strip(r, at, (size_t)length);
	if (p->offsets)
		return read_kept_list(r, at, (size_t)length);
	const int kept = p == r->indices;
	const size_t used = kept ? m->face_offsets[at->entry] : 0;
	if (kept && length == 0)
		return fail(r, vn_io_error_parse, "face %zu has no corners", at->entry);
	if (kept && (result = reserve_indices(r, m, used, (uint64_t)length, at->entry)) != vn_io_success)
		return result;
	for (size_t k = 0; k < (size_t)length; k++) {
		if ((result = read_value(r, p->type, at, v)) != vn_io_success)
			return result;
		if (!kept)
			continue;
		const double index = get_value(p->type, v);
		if (!(index >= 0 && index < (double)r->vertex->count && index == floor(index)))
			return fail(r, vn_io_error_parse, "face %zu has index %.17g, but the file has %llu vertices", at->entry,
			            index, (unsigned long long)r->vertex->count);
		m->indices[used + k] = (uint32_t)index;
	}
	if (kept)
		m->face_offsets[at->entry + 1] = (uint32_t)(used + (size_t)length);
	return vn_io_success;
}

/* After an ASCII entry: the values left on its line. Writers put each entry
 * on a line of its own, so where one leaves values there, and reading then
 * fails, the data does not follow the header: the failure names that line. */
static void note_values_left(ply_reader* r, const place* at)
{
	size_t n = 0;
	for (const unsigned char* q = r->p; q < r->end && *q != r->newline && *q != '\n';) {
		if (is_space(*q)) {
			q++;
			continue;
		}
		n++;
		while (q < r->end && *q != r->newline && *q != '\n' && !is_space(*q))
			q++;
	}
	if (n)
		r->left.element = at->element, r->left.entry = at->entry, r->left.line = r->line, r->left.values = n;
}

static vn_io_result read_element(ply_reader* r, vn_io_mesh* m, ply_element* e)
{
	place at = {e, 0, NULL};
	unsigned char scratch[8];
	if (e->property_count == 0)
		return vn_io_success;
	for (at.entry = 0; at.entry < e->count; at.entry++) {
		/* ASCII: the line of the entry's first value, and the first property
		 * read from a later line (an entry shorter than its line's values
		 * shows so where reading then fails). */
		size_t first_line = 0;
		const ply_property* wrapped = NULL;
		for (size_t k = 0; k < e->property_count; k++) {
			ply_property* p = &e->properties[k];
			at.property = p;
			vn_io_result result =
			    p->count_type >= 0
			        ? read_list(r, m, &at)
			        : read_value(r, p->type, &at, p->column ? p->column + at.entry * types[p->type].size : scratch);
			if (k == 0)
				first_line = r->line;
			else if (!wrapped && r->line != first_line)
				wrapped = p;
			if (result == vn_io_success)
				continue;
			const size_t n = strlen(r->error->message);
			if (r->left.element && result == vn_io_error_parse)
				snprintf(r->error->message + n, sizeof r->error->message - n,
				         "; %s %zu ends on line %zu with %zu value%s left on that line: the data does not follow the "
				         "header",
				         r->left.element->name, r->left.entry, r->left.line, r->left.values,
				         r->left.values == 1 ? "" : "s");
			else if (r->format == PLY_ASCII && wrapped && result == vn_io_error_parse)
				snprintf(r->error->message + n, sizeof r->error->message - n,
				         "; %s %zu begins on line %zu, but its property '%s' is read from a later line: the data does "
				         "not follow the header",
				         e->name, at.entry, first_line, wrapped->name);
			return result;
		}
		if (r->format == PLY_ASCII && !r->left.element)
			note_values_left(r, &at);
	}
	return vn_io_success;
}

static ply_property* find(ply_element* e, const char* name)
{
	for (size_t k = 0; e && k < e->property_count; k++)
		if (!strcmp(e->properties[k].name, name))
			return &e->properties[k];
	return NULL;
}

static ply_property* find_scalar(ply_element* e, const char* name)
{
	ply_property* p = find(e, name);
	return p && p->count_type < 0 ? p : NULL;
}

/* Room for p's values: a column for a scalar, offsets for a list (whose
 * items read_kept_list stores); 0 when out of memory. */
static int keep_values(const ply_element* e, ply_property* p)
{
	const size_t count = (size_t)e->count;
	if (p->count_type >= 0)
		return (p->offsets = calloc(count + 1, sizeof *p->offsets)) != NULL;
	return (p->column = malloc(count * types[p->type].size + 1)) != NULL;
}

/* Every property of the elements other than the vertices, the faces and
 * the strips read as faces (edges, materials, a camera), kept whole for the
 * writer. A second element called vertex or face is not: the writer's own
 * would be two of a name. */
static vn_io_result keep_other_elements(ply_reader* r)
{
	for (size_t i = 0; i < r->element_count; i++) {
		ply_element* e = &r->elements[i];
		if (e == r->vertex || e == r->face || e == r->strips || !strcmp(e->name, "vertex") || !strcmp(e->name, "face"))
			continue;
		for (size_t k = 0; k < e->property_count; k++)
			if (!keep_values(e, &e->properties[k]))
				return out_of_memory(r);
		e->kept = 1;
	}
	return vn_io_success;
}

/* Checks the counts against the bytes that follow (so that no count alone
 * allocates much), finds the vertex and face elements and their columns. */
static vn_io_result prepare(ply_reader* r, vn_io_mesh* m)
{
	/* An ASCII value takes at least a character and a separator (the last
	 * one's may be missing), a binary one its size; a list its length. */
	uint64_t available = (uint64_t)(r->end - r->p) + (r->format == PLY_ASCII);
	for (size_t i = 0; i < r->element_count; i++) {
		ply_element* e = &r->elements[i];
		uint64_t least = 0;
		for (size_t k = 0; k < e->property_count; k++) {
			const ply_property* p = &e->properties[k];
			least += r->format == PLY_ASCII ? 2 : types[p->count_type >= 0 ? p->count_type : p->type].size;
		}
		if (least && e->count > available / least)
			return fail(r, vn_io_error_parse,
			            "element '%s' announces %llu entries, more than the %zu bytes after the header can hold",
			            e->name, (unsigned long long)e->count, (size_t)(r->end - r->p));
		available -= least * e->count;
		if (!r->vertex && !strcmp(e->name, "vertex"))
			r->vertex = e;
		if (!r->face && !strcmp(e->name, "face"))
			r->face = e;
	}
	if (!r->vertex)
		return vn_io_fail(r->error, vn_io_error_parse, "%s: has no vertex element", r->name);
	static const char* const xyz[3] = {"x", "y", "z"};
	for (int k = 0; k < 3; k++)
		if (!find_scalar(r->vertex, xyz[k]))
			return vn_io_fail(r->error, vn_io_error_parse, "%s: the vertex element has no '%s' property", r->name,
			                  xyz[k]);
	if (!r->face || r->face->count == 0) { /* triangle strips, or a point cloud */
		for (size_t i = 0; i < r->element_count && !r->strips; i++)
			if (!strcmp(r->elements[i].name, "tristrips") && r->elements[i].count)
				r->strips = &r->elements[i];
		r->indices = find(r->strips, "vertex_indices");
		if (r->strips && (!r->indices || r->indices->count_type < 0 || is_real(r->indices->type)))
			return vn_io_fail(r->error, vn_io_error_unsupported,
			                  "%s: has %llu vertices and tristrips without a vertex_indices list of whole numbers: a "
			                  "mesh is needed",
			                  r->name, (unsigned long long)r->vertex->count);
		if (r->vertex->count > UINT32_MAX - 1)
			return vn_io_fail(r->error, vn_io_error_unsupported, "%s: %llu vertices: vn reads up to %u", r->name,
			                  (unsigned long long)r->vertex->count, UINT32_MAX - 1);
		for (size_t k = 0; k < r->vertex->property_count; k++) {
			ply_property* p = &r->vertex->properties[k];
			if (p->count_type < 0 && !(p->column = malloc((size_t)r->vertex->count * types[p->type].size + 1)))
				return out_of_memory(r);
		}
		/* A point cloud: no faces, as OFF's reader gives them. */
		if (!r->strips && (!(m->face_offsets = calloc(1, sizeof *m->face_offsets)) ||
		                   !(m->indices = malloc(sizeof *m->indices))))
			return out_of_memory(r);
		return keep_other_elements(r);
	}
	r->indices = find(r->face, "vertex_indices");
	if (!r->indices)
		r->indices = find(r->face, "vertex_index");
	if (!r->indices || r->indices->count_type < 0)
		return vn_io_fail(r->error, vn_io_error_parse,
		                  "%s: the face element has no vertex_indices (or vertex_index) list", r->name);
	if (r->vertex->count > UINT32_MAX || r->face->count > UINT32_MAX)
		return vn_io_fail(r->error, vn_io_error_unsupported, "%s: %llu vertices and %llu faces: vn reads up to %u",
		                  r->name, (unsigned long long)r->vertex->count, (unsigned long long)r->face->count,
		                  UINT32_MAX);

	const size_t vertices = (size_t)r->vertex->count, faces = (size_t)r->face->count;
	for (size_t k = 0; k < r->vertex->property_count; k++) {
		ply_property* p = &r->vertex->properties[k];
		if (p->count_type < 0 && !(p->column = malloc(vertices * types[p->type].size + 1)))
			return out_of_memory(r);
	}
	/* Every face property besides the indices: a colour, or kept for the writer. */
	for (size_t k = 0; k < r->face->property_count; k++)
		if (&r->face->properties[k] != r->indices && !keep_values(r->face, &r->face->properties[k]))
			return out_of_memory(r);
	vn_io_result result = keep_other_elements(r);
	if (result != vn_io_success)
		return result;
	m->face_offsets = malloc((faces + 1) * sizeof *m->face_offsets);
	/* Most meshes are triangles; the list values need at least this many bytes. */
	const size_t least = r->format == PLY_ASCII ? 2 : types[r->indices->type].size;
	const size_t bound = (size_t)(r->end - r->p) / least + 1;
	r->index_capacity = faces < bound / 3 ? 3 * faces : bound;
	m->indices = malloc(r->index_capacity * sizeof *m->indices);
	if (!m->face_offsets || !m->indices)
		return out_of_memory(r);
	m->face_offsets[0] = 0;
	return vn_io_success;
}

/* ------------------------------------------------------------------ the mesh from the columns */

static double value_at(const ply_property* p, size_t i)
{
	return get_value(p->type, p->column + i * types[p->type].size);
}

/* Colours of `count` entries: 1 when red, green, blue (and alpha when
 * given) are all uchar, 2 when they are all float or double in [0, 1], 0
 * otherwise (they are then not colours). */
static int colour_kind(ply_property* const c[4], size_t count)
{
	const size_t n = c[3] ? 4 : 3;
	int bytes = 1, reals = 1;
	for (size_t k = 0; k < n; k++) {
		bytes &= c[k]->type == PLY_UINT8;
		reals &= is_real(c[k]->type);
	}
	for (size_t k = 0; k < n && reals; k++)
		for (size_t i = 0; i < count && reals; i++) {
			const double v = value_at(c[k], i);
			reals = v >= 0.0 && v <= 1.0;
		}
	return bytes ? 1 : reals ? 2 : 0;
}

/* The properties of a colour, read and written in this order. */
static const char* const colour_names[4] = {"red", "green", "blue", "alpha"};

/* red green blue [alpha] of `element` into *out (RGBA per entry) when they
 * are colours; the properties used are marked in `used` (NULL: not marked). */
static vn_io_result read_colours(ply_reader* r, ply_element* e, float** out, int* are_bytes, unsigned char* used)
{
	ply_property* c[4] = {find_scalar(e, colour_names[0]), find_scalar(e, colour_names[1]),
	                      find_scalar(e, colour_names[2]), find_scalar(e, colour_names[3])};
	if (!c[0] || !c[1] || !c[2])
		return vn_io_success;
	/* An alpha of another kind than the rest is left as it is. */
	int kind = colour_kind(c, (size_t)e->count);
	if (c[3] && !kind) {
		c[3] = NULL;
		kind = colour_kind(c, (size_t)e->count);
	}
	if (!kind)
		return vn_io_success;
	const size_t count = (size_t)e->count;
	if (!(*out = malloc(4 * sizeof(float) * count + 1)))
		return out_of_memory(r);
	for (size_t i = 0; i < count; i++)
		for (int k = 0; k < 4; k++)
			(*out)[4 * i + k] = !c[k] ? 1.0f : (float)(kind == 1 ? value_at(c[k], i) / 255.0 : value_at(c[k], i));
	*are_bytes = kind == 1;
	for (int k = 0; k < 4 && used; k++)
		if (c[k])
			used[c[k] - e->properties] = 1;
	return vn_io_success;
}

/* The pairs of property names the reader takes as texture coordinates, in
 * its order of preference (the writer writes the first free one). */
static const char* const texcoord_pairs[4][2] = {{"s", "t"}, {"u", "v"}, {"texture_u", "texture_v"},
                                                 {"texture_s", "texture_t"}};

/* "_" and the property's name in upper case, other characters than letters
 * and digits as '_', unique among the mesh's attributes. */
static void attribute_name(const vn_io_mesh* m, const ply_property* p, size_t index, char name[64])
{
	size_t n = 0;
	name[n++] = '_';
	for (const char* s = p->name; *s && n < 63; s++) {
		const unsigned char c = (unsigned char)*s;
		name[n++] = c >= 'a' && c <= 'z' ? (char)(c - 'a' + 'A') : (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ? (char)c : '_';
	}
	name[n] = '\0';
	for (size_t a = 0; a < m->attribute_count; a++)
		if (!strcmp(m->attributes[a].name, name)) {
			char suffix[24];
			const size_t k = (size_t)snprintf(suffix, sizeof suffix, "_%zu", index);
			memcpy(name + (n + k > 63 ? 63 - k : n), suffix, k + 1);
			return;
		}
}

/* Whether the writer writes a face property of p's name: a colour's
 * when the mesh has face colours (an alpha of another kind than the file's
 * red, green and blue, left as it is by read_colours). */
static int face_name_taken(const vn_io_mesh* m, const ply_property* p)
{
	for (int k = 0; k < 4 && m->face_colors; k++)
		if (!strcmp(p->name, colour_names[k]))
			return 1;
	return 0;
}

/* A list of names being made, for one line: text holds those that fit
 * (with room left for a closing ", ..."), more counts those that did not. */
typedef struct name_list {
	char text[480];
	size_t n, items, more;
} name_list;

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void add_name(name_list* l, const char* fmt, ...)
{
	const size_t room = sizeof l->text - 8; /* for a closing ", ..." */
	char item[PLY_NAME_MAX + 64];
	va_list args;
	va_start(args, fmt);
	const int w = vsnprintf(item, sizeof item, fmt, args);
	va_end(args);
	const size_t length = (w > 0 ? (size_t)w : 0) + (l->items ? 2 : 0);
	if (l->n + length >= room) {
		l->more++;
		return;
	}
	l->n += (size_t)snprintf(l->text + l->n, sizeof l->text - l->n, "%s%s", l->items ? ", " : "", item);
	l->items++;
}

/* "face list 'texcoord'", "vertex property 'label'". */
static void add_property_name(name_list* l, const ply_element* e, const ply_property* p)
{
	add_name(l, "%s %s '%s'", e->name, p->count_type >= 0 ? "list" : "property", p->name);
}

/* One warning naming what reading leaves out: vertex list properties, the
 * strips' properties but their indices, a face property whose name the
 * writer takes, and a second element called vertex or face. face_used: the
 * face's colour properties read (NULL with strips or without faces). */
static vn_io_result warn_left_out(ply_reader* r, const vn_io_mesh* m, const unsigned char* face_used)
{
	name_list l = {{0}, 0, 0, 0};
	for (size_t i = 0; i < r->element_count; i++) {
		const ply_element* e = &r->elements[i];
		if (!e->count || e->kept) /* nothing in it to leave out, or all kept */
			continue;
		const int is_vertex = e == r->vertex, is_face = e == r->face || e == r->strips;
		for (size_t k = 0; k < e->property_count && (is_vertex || is_face); k++) {
			const ply_property* p = &e->properties[k];
			if (!(is_vertex && p->count_type < 0) && p != r->indices &&
			    !(e == r->face && face_used && (face_used[k] || !face_name_taken(m, p))))
				add_property_name(&l, e, p);
		}
		if (!is_vertex && !is_face)
			add_name(&l, "element '%s' (%llu)", e->name, (unsigned long long)e->count);
	}
	if (!l.items && !l.more)
		return vn_io_success;
	return vn_io_append_line(&r->warnings, "left out (vn keeps the rest): %s%s", l.text, l.more ? ", ..." : "")
	           ? vn_io_success
	           : out_of_memory(r);
}

size_t vn_io_ply_extras_describe(const vn_io_ply_extras* extras, char* text, size_t size)
{
	name_list l = {{0}, 0, 0, 0};
	for (size_t k = 0; k < extras->face.property_count; k++)
		add_property_name(&l, &extras->face, &extras->face.properties[k]);
	for (size_t i = 0; i < extras->element_count; i++)
		if (extras->elements[i].count) /* an empty one is nothing lost */
			add_name(&l, "element '%s' (%llu)", extras->elements[i].name,
			         (unsigned long long)extras->elements[i].count);
	if (size)
		snprintf(text, size, "%s%s", l.text, l.more ? ", ..." : "");
	return l.items + l.more;
}

/* Removes face property p from x. */
static void drop_face_property(vn_io_ply_extras* x, ply_property* p)
{
	free(p->column);
	free(p->offsets);
	memmove(p, p + 1, (size_t)(x->face.properties + x->face.property_count - (p + 1)) * sizeof *p);
	x->face.property_count--;
}

vn_io_result vn_io_ply_corner_texcoords(vn_io_mesh* m, const char* name, size_t* split, vn_io_error* error)
{
	*split = 0;
	vn_io_ply_extras* x = m->ply_extras;
	ply_property* p = x && !m->texcoords ? find(&x->face, "texcoord") : NULL;
	if (!p || p->count_type < 0 || !is_real(p->type) || x->face.count != m->face_count)
		return vn_io_success;
	for (size_t f = 0; f < m->face_count; f++)
		if (p->offsets[f + 1] - p->offsets[f] != 2 * (size_t)(m->face_offsets[f + 1] - m->face_offsets[f]))
			return vn_io_success;
	/* Every face's pairs in order: corner c's pair is item 2 c. */
	const size_t n = m->vertex_count, corners = m->face_offsets[m->face_count], size = types[p->type].size;
	const uint32_t none = UINT32_MAX;
	float* uv = malloc(2 * sizeof(float) * (n + corners) + 1);
	uint32_t* next = malloc(sizeof(uint32_t) * (n + corners) + 1); /* vertex v's next copy, or none */
	uint32_t* source = malloc(sizeof(uint32_t) * corners + 1);      /* what each appended vertex copies */
	uint32_t* corner_vertex = malloc(sizeof(uint32_t) * corners + 1);
	unsigned char* has = calloc(n + 1, 1); /* a face gave vertex v its pair */
	vn_io_result result = vn_io_success;
	size_t added = 0;
	if (!uv || !next || !source || !corner_vertex || !has)
		result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	for (size_t v = 0; v < n && result == vn_io_success; v++) {
		uv[2 * v] = uv[2 * v + 1] = 0; /* a vertex no face uses */
		next[v] = none;
	}
	for (size_t c = 0; c < corners && result == vn_io_success; c++) {
		const uint32_t v = m->indices[c];
		const float t[2] = {(float)get_value(p->type, p->column + 2 * c * size),
		                    (float)get_value(p->type, p->column + (2 * c + 1) * size)};
		if (!has[v]) {
			has[v] = 1;
			memcpy(&uv[2 * (size_t)v], t, sizeof t);
			corner_vertex[c] = v;
			continue;
		}
		uint32_t u = v;
		while (u != none && memcmp(&uv[2 * (size_t)u], t, sizeof t) != 0) /* bit for bit: -0 and NaN stay */
			u = next[u];
		if (u == none) {
			if (n + added >= UINT32_MAX) {
				result = vn_io_fail(error, vn_io_error_unsupported,
				                    "%s: splitting vertices by their corners' texture coordinates makes more than "
				                    "%u vertices",
				                    name, UINT32_MAX - 1);
				break;
			}
			u = (uint32_t)(n + added);
			source[added++] = v;
			memcpy(&uv[2 * (size_t)u], t, sizeof t);
			next[u] = next[v];
			next[v] = u;
		}
		corner_vertex[c] = u;
	}
	if (result == vn_io_success) {
		if (!vn_io_mesh_append_vertices(m, source, added)) {
			result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
		} else {
			float* fitted = realloc(uv, 2 * sizeof(float) * (n + added) + 1);
			m->texcoords = fitted ? fitted : uv;
			uv = NULL;
			memcpy(m->indices, corner_vertex, sizeof(uint32_t) * corners);
			drop_face_property(x, p);
			*split = added;
		}
	}
	free(uv);
	free(next);
	free(source);
	free(corner_vertex);
	free(has);
	return result;
}

/* The file a comment line names after `key` (k bytes), without blanks at
 * either end (*n its length), or NULL when the line is no such comment or
 * names nothing. */
static const char* texture_file(const char* line, const char* key, size_t k, size_t* n)
{
	if (strncmp(line, key, k))
		return NULL;
	const char* start = line + k;
	const char* end = strchr(start, '\n');
	while (start < end && (*start == ' ' || *start == '\t'))
		start++;
	while (end > start && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\r'))
		end--;
	if (n)
		*n = (size_t)(end - start);
	return end > start ? start : NULL;
}

/* A TextureFile comment's file (n bytes at start, inside the comments) and
 * its place among those comments. */
typedef struct texture_comment {
	const char* start;
	size_t n, at;
} texture_comment;

static int same_file(const texture_comment* x, const texture_comment* y)
{
	return x->n == y->n && memcmp(x->start, y->start, x->n) == 0;
}

/* By file, and one file's comments by place. */
static int by_file(const void* a, const void* b)
{
	const texture_comment *x = a, *y = b;
	const int c = memcmp(x->start, y->start, x->n < y->n ? x->n : y->n);
	if (c)
		return c;
	if (x->n != y->n)
		return x->n < y->n ? -1 : 1;
	return (x->at > y->at) - (x->at < y->at);
}

vn_io_result vn_io_ply_texture_materials(vn_io_mesh* m, const char* name, const char* beside, vn_io_error* error)
{
	vn_io_ply_extras* x = m->ply_extras;
	static const char key[] = "comment TextureFile ";
	const size_t k = sizeof key - 1;
	size_t count = 0, bytes = 0;
	for (const char* line = x ? x->comments : NULL; line && *line; line = strchr(line, '\n') + 1)
		if (texture_file(line, key, k, NULL))
			count++, bytes += 2 * (size_t)(strchr(line, '\n') - (line + k)) + 16;
	if (!count || m->materials.count || !m->face_count)
		return vn_io_success;
	/* The library "newmtl FILE / map_Kd FILE" of each file once, in order of
	 * first mention: a file named twice (two texnumbers, one image) is one
	 * material, which both numbers pick. */
	char* text = malloc(bytes + 1);
	texture_comment* comments = malloc(sizeof *comments * count);
	texture_comment* sorted = malloc(sizeof *sorted * count);
	size_t* first = malloc(sizeof *first * count);         /* each comment's first mention of its file */
	uint32_t* material = malloc(sizeof *material * count); /* each comment's material */
	m->materials.names = calloc(count, sizeof(char*));
	m->materials.of_face = malloc(sizeof(uint32_t) * m->face_count);
	vn_io_result r = vn_io_success;
	if (!text || !comments || !sorted || !first || !material || !m->materials.names || !m->materials.of_face) {
		r = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
		goto done;
	}
	size_t c = 0;
	for (const char* line = x->comments; *line; line = strchr(line, '\n') + 1) {
		size_t n;
		const char* start = texture_file(line, key, k, &n);
		if (start)
			comments[c] = (texture_comment){start, n, c}, c++;
	}
	/* Sorted (O(count log count): a header may hold many comments), each
	 * file's run starts with its first mention. */
	memcpy(sorted, comments, sizeof *sorted * count);
	qsort(sorted, count, sizeof *sorted, by_file);
	for (size_t i = 0; i < count; i++)
		first[sorted[i].at] = i && same_file(&sorted[i], &sorted[i - 1]) ? first[sorted[i - 1].at] : sorted[i].at;
	size_t used = 0;
	for (size_t i = 0; i < count; i++) {
		if (first[i] != i) {
			material[i] = material[first[i]];
			continue;
		}
		char* file = malloc(comments[i].n + 1);
		if (!file) {
			r = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
			goto done;
		}
		memcpy(file, comments[i].start, comments[i].n);
		file[comments[i].n] = '\0';
		material[i] = (uint32_t)m->materials.count;
		m->materials.names[m->materials.count++] = file;
		used += (size_t)sprintf(text + used, "newmtl %s\nmap_Kd %s\n", file, file);
	}
	/* Each face's texture: texnumber (MeshLab's several textures), else the first. */
	ply_property* t = find_scalar(&x->face, "texnumber");
	if (t && x->face.count != m->face_count)
		t = NULL;
	for (size_t f = 0; f < m->face_count; f++) {
		const double v = t ? get_value(t->type, t->column + f * types[t->type].size) : 0.0;
		m->materials.of_face[f] = v >= 0 && v < (double)count && v == floor(v) ? material[(size_t)v] : VN_IO_NO_NAME;
	}
	if (t)
		drop_face_property(x, t);
	r = vn_io_mtl_read_text(m, text, used, name, beside, error);
done:
	free(comments);
	free(sorted);
	free(first);
	free(material);
	free(text);
	return r;
}

/* Moves what the writer writes back into m->ply_extras (which the mesh
 * frees): the comments, the face properties that are no colour and whose
 * names the writer leaves free, the other elements kept. */
static vn_io_result collect_extras(ply_reader* r, vn_io_mesh* m, const unsigned char* face_used)
{
	vn_io_ply_extras* x = calloc(1, sizeof *x);
	if (!x)
		return out_of_memory(r);
	m->ply_extras = x;
	x->comments = r->comments;
	r->comments = NULL;
	if (face_used && r->face->count) {
		if (!(x->face.properties = malloc(r->face->property_count * sizeof *x->face.properties)))
			return out_of_memory(r);
		memcpy(x->face.name, r->face->name, sizeof x->face.name);
		x->face.count = r->face->count;
		for (size_t k = 0; k < r->face->property_count; k++) {
			ply_property* p = &r->face->properties[k];
			if (p == r->indices || face_used[k] || face_name_taken(m, p))
				continue;
			x->face.properties[x->face.property_count++] = *p;
			p->column = NULL;
			p->offsets = NULL;
		}
	}
	size_t kept = 0;
	for (size_t i = 0; i < r->element_count; i++)
		kept += (size_t)r->elements[i].kept;
	if (kept && !(x->elements = malloc(kept * sizeof *x->elements)))
		return out_of_memory(r);
	for (size_t i = 0; i < r->element_count; i++) {
		ply_element* e = &r->elements[i];
		if (!e->kept)
			continue;
		x->elements[x->element_count++] = *e;
		e->properties = NULL;
		e->property_count = 0;
	}
	if (!x->comments && !x->face.property_count && !x->element_count) {
		vn_io_ply_extras_free(x);
		m->ply_extras = NULL;
	}
	return vn_io_success;
}

static vn_io_result to_mesh(ply_reader* r, vn_io_mesh* m)
{
	ply_element* v = r->vertex;
	const size_t n = (size_t)v->count;
	unsigned char* used = calloc(v->property_count + 1, 1);
	if (!used)
		return out_of_memory(r);
	vn_io_result result = vn_io_success;
	m->vertex_count = n;
	if (!r->strips)
		m->face_count = r->face ? (size_t)r->face->count : 0;

	/* Positions and normals: three properties each into doubles. */
	static const char* const names[2][3] = {{"x", "y", "z"}, {"nx", "ny", "nz"}};
	for (int group = 0; group < 2 && result == vn_io_success; group++) {
		ply_property* p[3] = {find_scalar(v, names[group][0]), find_scalar(v, names[group][1]),
		                      find_scalar(v, names[group][2])};
		if (!p[0] || !p[1] || !p[2])
			continue;
		double* values = malloc(3 * sizeof(double) * n + 1);
		if (!values) {
			result = out_of_memory(r);
			break;
		}
		for (size_t i = 0; i < n; i++)
			for (int k = 0; k < 3; k++)
				values[3 * i + k] = value_at(p[k], i);
		*(group ? &m->normals : &m->positions) = values;
		for (int k = 0; k < 3; k++)
			used[p[k] - v->properties] = 1;
	}
	if (result == vn_io_success)
		result = read_colours(r, v, &m->colors, &m->colors_are_bytes, used);
	for (int k = 0; k < 4 && result == vn_io_success && !m->texcoords; k++) {
		ply_property* s = find_scalar(v, texcoord_pairs[k][0]);
		ply_property* t = find_scalar(v, texcoord_pairs[k][1]);
		if (!s || !t || !is_real(s->type) || !is_real(t->type))
			continue;
		if (!(m->texcoords = malloc(2 * sizeof(float) * n + 1))) {
			result = out_of_memory(r);
			break;
		}
		for (size_t i = 0; i < n; i++) {
			m->texcoords[2 * i] = (float)value_at(s, i);
			m->texcoords[2 * i + 1] = (float)value_at(t, i);
		}
		used[s - v->properties] = used[t - v->properties] = 1;
	}
	/* Every other scalar vertex property as an attribute of its type. */
	for (size_t k = 0; k < v->property_count && result == vn_io_success; k++) {
		const ply_property* p = &v->properties[k];
		if (used[k] || p->count_type >= 0)
			continue;
		char name[64];
		attribute_name(m, p, k, name);
		vn_io_attribute* a = vn_io_mesh_add_attribute(m, name, vn_io_semantic_generic, types[p->type].gltf, 1, 0);
		const size_t length = strlen(p->name) + 1;
		if (!a || !(a->source_name = malloc(length))) {
			result = out_of_memory(r);
			break;
		}
		memcpy(a->source_name, p->name, length);
		memcpy(a->data, p->column, n * types[p->type].size);
	}
	unsigned char* face_used = NULL;
	if (result == vn_io_success && r->face && !r->strips) {
		if (!(face_used = calloc(r->face->property_count + 1, 1)))
			result = out_of_memory(r);
		else
			result = read_colours(r, r->face, &m->face_colors, &m->face_colors_are_bytes, face_used);
	}
	if (result == vn_io_success)
		result = warn_left_out(r, m, face_used);
	if (result == vn_io_success)
		result = collect_extras(r, m, face_used);
	free(used);
	free(face_used);
	return result;
}

/* ------------------------------------------------------------------ entry points */

static vn_io_result read_ply(ply_reader* r, vn_io_mesh* m)
{
	vn_io_result result = read_header(r);
	if (result == vn_io_success)
		result = prepare(r, m);
	for (size_t i = 0; i < r->element_count && result == vn_io_success; i++)
		result = read_element(r, m, &r->elements[i]);
	if (result != vn_io_success)
		return result;
	if (r->format == PLY_ASCII)
		next_token(r); /* up to the next token, if any */
	if (r->p < r->end) {
		if (!vn_io_append_line(&r->warnings, "%zu bytes after the last element, not read", (size_t)(r->end - r->p)))
			return out_of_memory(r);
	}
	if (r->strips && (result = strip_faces(r, m)) != vn_io_success)
		return result;
	return to_mesh(r, m);
}

/* The reader of the size bytes at data, text decoded from `wide` (or NULL). */
static vn_io_result read_memory(const char* data, size_t size, const char* name, const char* wide, vn_io_mesh* mesh,
                                vn_io_error* error)
{
	memset(mesh, 0, sizeof *mesh);
	ply_reader r;
	memset(&r, 0, sizeof r);
	r.name = name;
	r.error = error;
	r.wide = wide;
	r.begin = (const unsigned char*)(data ? data : "");
	r.end = r.begin + (data ? size : 0);
	r.p = r.begin + vn_io_utf8_bom(r.begin, (size_t)(r.end - r.begin));
	const vn_io_result lfs = vn_io_refuse_lfs_pointer(r.p, (size_t)(r.end - r.p), name, error);
	if (lfs != vn_io_success)
		return lfs;
	vn_io_c_locale locale;
	if (!vn_io_c_locale_enter(&locale))
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	vn_io_result result = read_ply(&r, mesh);
	vn_io_c_locale_leave(&locale);
	for (size_t i = 0; i < r.element_count; i++)
		free_properties(&r.elements[i]);
	free(r.elements);
	free(r.strip);
	free(r.comments);
	mesh->warnings = r.warnings;
	if (result != vn_io_success)
		vn_io_mesh_free(mesh);
	return result;
}

vn_io_result vn_io_ply_read_memory(const char* data, size_t size, const char* name, vn_io_mesh* mesh,
                                   vn_io_error* error)
{
	return vn_io_read_text(data, size, name, read_memory, mesh, error);
}

vn_io_result vn_io_ply_read(const char* path, vn_io_mesh* mesh, vn_io_error* error)
{
	return vn_io_read_with(path, vn_io_ply_read_memory, mesh, error);
}

/* ------------------------------------------------------------------ writer */

/* A record being built: values in little-endian order. */
typedef struct record {
	unsigned char* bytes;
	size_t used;
} record;

/* size bytes of one value in host byte order, as they are (a float NaN
 * keeps its payload, which a trip through double would change). */
static void put_bytes(record* b, const unsigned char* value, size_t size)
{
	unsigned char* p = b->bytes + b->used;
	memcpy(p, value, size);
	if (!host_is_little_endian())
		reverse(p, size);
	b->used += size;
}

static void put(record* b, int type, double v)
{
	unsigned char value[8];
	put_value(type, v, value);
	put_bytes(b, value, types[type].size);
}

static int colour_byte(float c)
{
	return !(c > 0.0f) ? 0 : c >= 1.0f ? 255 : (int)(c * 255.0f + 0.5f);
}

/* Always RGBA, as OFF: vn_io_mesh does not tell whether the source had
 * alpha, and readers take an opaque alpha as well as none. */
static void put_colour(record* b, const float* rgba, int bytes)
{
	for (int k = 0; k < 4; k++)
		put(b, bytes ? PLY_UINT8 : PLY_FLOAT32, bytes ? colour_byte(rgba[k]) : rgba[k]);
}

static void header_colour(FILE* out, int bytes)
{
	for (int k = 0; k < 4; k++)
		fprintf(out, "property %s %s\n", bytes ? "uchar" : "float", colour_names[k]);
}

/* The PLY type of a vn_io_attribute component type (int32 and float64 included). */
static int ply_type_of(int component_type)
{
	for (int t = 0; t < PLY_TYPES; t++)
		if (types[t].gltf == component_type)
			return t;
	return -1;
}

/* Names the writer gives the mesh's texture coordinates: the first pair
 * the reader knows that no attribute read from a PLY was called (a file's
 * `short s` next to its `u v` keeps its name, and the pair is u v). */
static const char* const* texcoord_names(const vn_io_mesh* m)
{
	for (int k = 0; k < 4; k++) {
		int free_pair = 1;
		for (size_t a = 0; a < m->attribute_count && free_pair; a++)
			for (int c = 0; c < 2 && m->attributes[a].source_name; c++)
				free_pair &= strcmp(m->attributes[a].source_name, texcoord_pairs[k][c]) != 0;
		if (free_pair)
			return texcoord_pairs[k];
	}
	return texcoord_pairs[0];
}

/* Whether the writer gives name a meaning in this file (x, y, z, and the
 * normals', colours' and texture coordinates' (tex) names where it writes
 * them), or, with every_role, whether any reader role has it. */
static int role_name(const vn_io_mesh* m, const char* const* tex, const char* name, int every_role)
{
	static const char* const roles[] = {"x",     "y", "z", "nx",  "ny",        "nz",        "red",       "green",
	                                    "blue",  "alpha", "s", "t", "u",      "v",         "texture_u", "texture_v",
	                                    "texture_s", "texture_t"};
	const size_t n = sizeof roles / sizeof roles[0];
	for (size_t i = 0; i < n; i++) {
		if (strcmp(name, roles[i]))
			continue;
		if (every_role || i < 3 || (i < 6 && m->normals) || (i < 10 && i >= 6 && m->colors))
			return 1;
		return i >= 10 && m->texcoords && (!strcmp(name, tex[0]) || !strcmp(name, tex[1]));
	}
	return 0;
}

/* Room for a written property name: a PLY name and the suffixes below. */
#define PROPERTY_NAME_SIZE (PLY_NAME_MAX + 32)

/* Every attribute component's property name, in attribute then component
 * order, PROPERTY_NAME_SIZE bytes each (NULL when out of memory): the name
 * of the property the attribute was read from (source_name), else its name
 * in lower case without the leading '_' ("_CONFIDENCE" is "confidence"),
 * "_c" after it for more than one component; "_<a>" after that where the
 * name is taken (by what the writer writes, or an earlier component), and
 * "_<a + 1>", ... while that is taken too (two attributes named "x_1" and
 * "x": the second's "x_1" was). */
static char* property_names(const vn_io_mesh* m, const char* const* tex)
{
	size_t total = 0;
	for (size_t a = 0; a < m->attribute_count; a++)
		total += (size_t)m->attributes[a].components;
	char* names = malloc(PROPERTY_NAME_SIZE * total + 1);
	if (!names)
		return NULL;
	char* name = names;
	for (size_t a = 0; a < m->attribute_count; a++)
		for (int c = 0; c < m->attributes[a].components; c++, name += PROPERTY_NAME_SIZE) {
			const vn_io_attribute* at = &m->attributes[a];
			const int own = at->source_name && at->components == 1;
			const char* s = own ? at->source_name : at->name[0] == '_' && at->name[1] ? at->name + 1 : at->name;
			size_t n = 0;
			for (; *s && n + 1 < PROPERTY_NAME_SIZE; s++)
				name[n++] = own || !(*s >= 'A' && *s <= 'Z') ? *s : (char)(*s - 'A' + 'a');
			name[n] = '\0';
			if (at->components > 1)
				snprintf(name + n, PROPERTY_NAME_SIZE - n, "_%d", c);
			/* Room for a suffix of up to 20 digits, so that each try differs. */
			const size_t base = strlen(name) < PROPERTY_NAME_SIZE - 22 ? strlen(name) : PROPERTY_NAME_SIZE - 22;
			for (size_t k = a;; k++) {
				int taken = role_name(m, tex, name, !own);
				for (const char* other = names; other < name && !taken; other += PROPERTY_NAME_SIZE)
					taken = !strcmp(other, name);
				if (!taken)
					break;
				snprintf(name + base, PROPERTY_NAME_SIZE - base, "_%zu", k);
			}
		}
	return names;
}

/* The header lines of e's kept properties. */
static void header_properties(FILE* out, const ply_element* e)
{
	for (size_t k = 0; k < e->property_count; k++) {
		const ply_property* p = &e->properties[k];
		if (p->count_type >= 0)
			fprintf(out, "property list %s %s %s\n", types[p->count_type].name, types[p->type].name, p->name);
		else
			fprintf(out, "property %s %s\n", types[p->type].name, p->name);
	}
}

/* Bytes of entry i of e's kept properties. */
static size_t entry_size(const ply_element* e, size_t i)
{
	size_t n = 0;
	for (size_t k = 0; k < e->property_count; k++) {
		const ply_property* p = &e->properties[k];
		n += p->count_type < 0 ? types[p->type].size
		                       : types[p->count_type].size + (p->offsets[i + 1] - p->offsets[i]) * types[p->type].size;
	}
	return n;
}

static size_t largest_entry(const ply_element* e)
{
	size_t largest = 0;
	for (size_t i = 0; i < e->count; i++) {
		const size_t n = entry_size(e, (size_t)i);
		largest = n > largest ? n : largest;
	}
	return largest;
}

/* Entry i of e's kept properties, appended to b (room: entry_size). */
static void put_entry(record* b, const ply_element* e, size_t i)
{
	for (size_t k = 0; k < e->property_count; k++) {
		const ply_property* p = &e->properties[k];
		const size_t size = types[p->type].size;
		if (p->count_type < 0) {
			put_bytes(b, p->column + i * size, size);
			continue;
		}
		const size_t first = p->offsets[i], n = p->offsets[i + 1] - first;
		put(b, p->count_type, (double)n);
		for (size_t j = 0; j < n; j++)
			put_bytes(b, p->column + (first + j) * size, size);
	}
}

/* Whether some of the count values would not come back from a float (so
 * are written as double). */
static int float_rounds(const double* v, size_t count)
{
	for (size_t i = 0; i < count; i++)
		if ((double)(float)v[i] != v[i])
			return 1;
	return 0;
}

vn_io_result vn_io_ply_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings,
                             vn_io_error* error)
{
	(void)settings; /* PLY has none */
	const size_t n = mesh->vertex_count;
	const int doubles = float_rounds(mesh->positions, 3 * n);
	uint32_t largest = 0;
	for (size_t f = 0; f < mesh->face_count; f++)
		if (mesh->face_offsets[f + 1] - mesh->face_offsets[f] > largest)
			largest = mesh->face_offsets[f + 1] - mesh->face_offsets[f];
	const int count_type = largest > 255 ? PLY_UINT32 : PLY_UINT8;
	const int index_type = n > INT32_MAX ? PLY_UINT32 : PLY_INT32;

	/* A point cloud's normals are the file's (vn computes none): double
	 * where float would round them. */
	const int double_normals = mesh->normals && !mesh->face_count && float_rounds(mesh->normals, 3 * n);
	const vn_io_ply_extras* extras = mesh->ply_extras;
	fprintf(out, "ply\nformat binary_little_endian 1.0\ncomment written by vn\n%s",
	        extras && extras->comments ? extras->comments : "");
	/* An OFF's or OBJ's comments (text after '#'), a comment line each. */
	for (const char* c = mesh->comments; c;) {
		const int k = (int)strcspn(c, "\n");
		fprintf(out, "comment%s%.*s\n", *c == ' ' || *c == '\t' ? "" : " ", k, c);
		c = c[k] ? c + k + 1 : NULL;
	}
	fprintf(out, "element vertex %zu\n", n);
	const char* position = doubles ? "double" : "float";
	fprintf(out, "property %s x\nproperty %s y\nproperty %s z\n", position, position, position);
	const char* normal = double_normals ? "double" : "float";
	if (mesh->normals)
		fprintf(out, "property %s nx\nproperty %s ny\nproperty %s nz\n", normal, normal, normal);
	if (mesh->colors)
		header_colour(out, mesh->colors_are_bytes);
	const char* const* tex = texcoord_names(mesh);
	if (mesh->texcoords)
		fprintf(out, "property float %s\nproperty float %s\n", tex[0], tex[1]);
	char* names = property_names(mesh, tex);
	if (!names)
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	const char* name = names;
	size_t record_size = 3 * (doubles ? 8u : 4u) + (mesh->normals ? (double_normals ? 24u : 12u) : 0u) +
	                     (mesh->colors ? (mesh->colors_are_bytes ? 4u : 16u) : 0u) +
	                     (mesh->texcoords ? 8u : 0u);
	for (size_t a = 0; a < mesh->attribute_count; a++) {
		const vn_io_attribute* at = &mesh->attributes[a];
		const int type = ply_type_of(at->component_type);
		if (type < 0) {
			free(names);
			return vn_io_fail(error, vn_io_error_unsupported, "%s: attribute %s has component type %d, which PLY lacks",
			                  path, at->name, at->component_type);
		}
		for (int c = 0; c < at->components; c++, name += PROPERTY_NAME_SIZE)
			fprintf(out, "property %s %s\n", types[type].name, name);
		record_size += types[type].size * (size_t)at->components;
	}
	fprintf(out, "element face %zu\nproperty list %s %s vertex_indices\n", mesh->face_count,
	        types[count_type].name, types[index_type].name);
	if (mesh->face_colors)
		header_colour(out, mesh->face_colors_are_bytes);
	for (size_t i = 0; extras && i <= extras->element_count; i++) {
		if (i)
			fprintf(out, "element %s %llu\n", extras->elements[i - 1].name,
			        (unsigned long long)extras->elements[i - 1].count);
		header_properties(out, i ? &extras->elements[i - 1] : &extras->face);
	}
	fprintf(out, "end_header\n");
	free(names);

	record b = {malloc(record_size + 32), 0};
	if (!b.bytes)
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	int failed = 0;
	for (size_t i = 0; i < n && !failed; i++) {
		b.used = 0;
		for (int k = 0; k < 3; k++)
			put(&b, doubles ? PLY_FLOAT64 : PLY_FLOAT32, mesh->positions[3 * i + k]);
		for (int k = 0; k < 3 && mesh->normals; k++)
			put(&b, double_normals ? PLY_FLOAT64 : PLY_FLOAT32, mesh->normals[3 * i + k]);
		if (mesh->colors)
			put_colour(&b, mesh->colors + 4 * i, mesh->colors_are_bytes);
		for (int k = 0; k < 2 && mesh->texcoords; k++)
			put(&b, PLY_FLOAT32, mesh->texcoords[2 * i + k]);
		for (size_t a = 0; a < mesh->attribute_count; a++) {
			const vn_io_attribute* at = &mesh->attributes[a];
			const int type = ply_type_of(at->component_type);
			const size_t size = types[type].size;
			for (size_t c = 0; c < (size_t)at->components; c++)
				put_bytes(&b, (const unsigned char*)at->data + (i * (size_t)at->components + c) * size, size);
		}
		failed = fwrite(b.bytes, 1, b.used, out) != b.used;
	}
	free(b.bytes);
	/* The faces' own properties, then the other elements' entries. */
	size_t room = 4 + (mesh->face_colors ? 16u : 0u) + (size_t)largest * 4 + (extras ? largest_entry(&extras->face) : 0);
	for (size_t i = 0; extras && i < extras->element_count; i++) {
		const size_t entry = largest_entry(&extras->elements[i]);
		room = entry > room ? entry : room;
	}
	b.bytes = malloc(room);
	if (!b.bytes)
		return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", path);
	for (size_t f = 0; f < mesh->face_count && !failed; f++) {
		b.used = 0;
		const uint32_t begin = mesh->face_offsets[f], end = mesh->face_offsets[f + 1];
		put(&b, count_type, end - begin);
		for (uint32_t k = begin; k < end; k++)
			put(&b, index_type, mesh->indices[k]);
		if (mesh->face_colors)
			put_colour(&b, mesh->face_colors + 4 * f, mesh->face_colors_are_bytes);
		if (extras)
			put_entry(&b, &extras->face, f);
		failed = fwrite(b.bytes, 1, b.used, out) != b.used;
	}
	for (size_t e = 0; extras && e < extras->element_count; e++)
		for (size_t i = 0; i < extras->elements[e].count && !failed; i++) {
			b.used = 0;
			put_entry(&b, &extras->elements[e], i);
			failed = fwrite(b.bytes, 1, b.used, out) != b.used;
		}
	free(b.bytes);
	if (failed || ferror(out))
		return vn_io_fail(error, vn_io_error_write, "%s: cannot write", path);
	return vn_io_success;
}
