/*
 * STL (stereolithography): triangles, each with its three corners' positions
 * and a facet normal.
 *
 * Reader: binary (an 80-byte header, a 32-bit triangle count, 50 bytes a
 * triangle: normal, three corners as float32, 2 attribute bytes) and ASCII
 * ("solid ... facet normal ... outer loop, vertex x3, endloop, endfacet,
 * endsolid", keywords in any case, several solids in one file; one that ends
 * after a whole facet without its endsolid is read, with a warning). A
 * binary header may start with "solid" too: a file whose size is 84 + 50 *
 * its count is binary, and so is one ASCII cannot read whose triangles fit
 * with padding after them (read_padded); a count of 0 with whole triangles
 * after it (writers that never fill it in) reads those. Corners with equal
 * positions (exactly, -0 = +0) are welded into one vertex, so the mesh is
 * connected and vn's normals are smooth across triangles. The facet normals
 * (one per triangle, not per vertex) are not kept. A binary file's header
 * and attribute bytes are (stl_extras, which the writer writes back), and
 * where they hold colours these are read as face colours: Materialise
 * Magics' where the header has COLOR= or MATERIAL= (a default colour, and
 * each facet's in its attribute bytes), or else VisCAM's and SolidView's
 * where a triangle's attribute bytes have bit 15 set (other writers leave
 * zeros or padding there, as old Blender's "  ").
 *
 * Not Draco's StlDecoder (1.5.5): it refuses binary files whose header
 * starts with "solid ", does not check the triangle count against the file's
 * size (reading past the end), keeps each triangle's corners apart (split
 * by facet normal), and reads no ASCII.
 *
 * Writer: binary, polygons fan-triangulated, positions as float32, each
 * facet normal the unit normal of its triangle's positions ((0, 0, 0) for a
 * degenerate one): STL has no vertex normals, so vn's are not written. The
 * header and attribute bytes are the input's where it was a binary STL of
 * these triangles; else face colours are written as VisCAM's and SolidView's
 * (as MeshLab writes them), 5 bits a channel.
 */
#include "stl.h"
#include "text.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#define STL_HEADER 80
#define STL_TRIANGLE 50

typedef struct stl_reader {
	const char* name;
	vn_io_error* error;
	const unsigned char* p;
	const unsigned char* end;
	size_t line;
	double* corners; /* 3 coordinates per corner, 3 corners per triangle */
	size_t triangles, capacity;
	int binary;        /* read as binary */
	int unended;       /* ASCII that ends after a whole facet, without 'endsolid' */
	uint16_t* attributes; /* binary: each triangle's attribute bytes */
	size_t coloured;      /* triangles whose attribute bytes have bit 15 set */
} stl_reader;

#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static vn_io_result fail(stl_reader* r, vn_io_result result, const char* fmt, ...)
{
	va_list args;
	va_start(args, fmt);
	vn_io_fail_at(r->error, result, r->name, 0, r->line, fmt, args);
	va_end(args);
	return result;
}

static uint32_t get_u32(const unsigned char* p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float get_float(const unsigned char* p)
{
	const uint32_t w = get_u32(p);
	float f;
	memcpy(&f, &w, sizeof f);
	return f;
}

static void put_float(unsigned char* p, float f)
{
	uint32_t w;
	memcpy(&w, &f, sizeof w);
	for (int k = 0; k < 4; k++)
		p[k] = (unsigned char)(w >> 8 * k);
}

/* Room for one more triangle's corners. */
static int grow(stl_reader* r)
{
	if (r->triangles < r->capacity)
		return 1;
	const size_t capacity = r->capacity ? 2 * r->capacity : 1024;
	double* grown = capacity <= SIZE_MAX / (9 * sizeof(double)) ? realloc(r->corners, capacity * 9 * sizeof(double)) : NULL;
	if (!grown)
		return 0;
	r->corners = grown;
	r->capacity = capacity;
	return 1;
}

/* ------------------------------------------------------------------ ASCII */

static int is_space(unsigned char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

typedef struct token {
	const unsigned char* p;
	size_t n;
} token;

/* The next token, counting lines (r->line is the token's); empty at the end. */
static token next_token(stl_reader* r)
{
	while (r->p < r->end && is_space(*r->p))
		r->line += *r->p++ == '\n';
	token t = {r->p, 0};
	while (r->p < r->end && !is_space(*r->p))
		r->p++;
	t.n = (size_t)(r->p - t.p);
	return t;
}

/* Case-insensitive: exporters write "solid" and "SOLID". */
static int token_is(token t, const char* word)
{
	if (t.n != strlen(word))
		return 0;
	for (size_t i = 0; i < t.n; i++) {
		const unsigned char c = t.p[i] >= 'A' && t.p[i] <= 'Z' ? (unsigned char)(t.p[i] - 'A' + 'a') : t.p[i];
		if (c != (unsigned char)word[i])
			return 0;
	}
	return 1;
}

/* Skips the rest of the line (a solid's name). */
static void skip_line(stl_reader* r)
{
	while (r->p < r->end && *r->p != '\n')
		r->p++;
}

static vn_io_result expect(stl_reader* r, const char* word)
{
	const token t = next_token(r);
	if (token_is(t, word))
		return vn_io_success;
	if (!t.n)
		return fail(r, vn_io_error_parse, "the file ends where '%s' was expected (triangle %zu)", word, r->triangles);
	return fail(r, vn_io_error_parse, "expected '%s', found '%s' (triangle %zu)", word, vn_io_quote(t.p, t.n).text,
	            r->triangles);
}

static vn_io_result numbers(stl_reader* r, const char* what, double* out)
{
	for (int k = 0; k < 3; k++) {
		const token t = next_token(r);
		if (!vn_io_parse_real(t.p, t.n, &out[k]))
			return fail(r, vn_io_error_parse, "triangle %zu: %s '%s' is not a number", r->triangles, what,
			            vn_io_quote(t.p, t.n).text);
	}
	return vn_io_success;
}

static vn_io_result read_facet(stl_reader* r)
{
	double normal[3];
	vn_io_result result = expect(r, "normal");
	if (result == vn_io_success)
		result = numbers(r, "facet normal", normal);
	if (result == vn_io_success)
		result = expect(r, "outer");
	if (result == vn_io_success)
		result = expect(r, "loop");
	if (result == vn_io_success && !grow(r))
		return vn_io_fail(r->error, vn_io_error_memory, "%s: out of memory", r->name);
	for (int c = 0; c < 3 && result == vn_io_success; c++) {
		result = expect(r, "vertex");
		if (result == vn_io_success)
			result = numbers(r, "vertex", r->corners + 9 * r->triangles + 3 * c);
	}
	if (result == vn_io_success)
		result = expect(r, "endloop");
	if (result == vn_io_success)
		result = expect(r, "endfacet");
	if (result == vn_io_success)
		r->triangles++;
	return result;
}

static vn_io_result read_ascii(stl_reader* r)
{
	vn_io_result result = expect(r, "solid");
	skip_line(r);
	while (result == vn_io_success) {
		const token t = next_token(r);
		if (token_is(t, "facet")) {
			result = read_facet(r);
		} else if (token_is(t, "endsolid")) {
			skip_line(r);
			const token next = next_token(r);
			if (!next.n)
				return vn_io_success;
			if (!token_is(next, "solid"))
				return fail(r, vn_io_error_parse, "expected the end of the file or another 'solid', found '%s'",
				            vn_io_quote(next.p, next.n).text);
			skip_line(r);
		} else if (!t.n) {
			/* A writer that leaves 'endsolid' out, or a file cut after a
			 * whole triangle: its triangles are read (with a warning). With
			 * none, it may be a binary file whose header starts with
			 * "solid". */
			if (!r->triangles)
				return fail(r, vn_io_error_parse, "the file ends after 0 triangles, before 'endsolid'");
			r->unended = 1;
			return vn_io_success;
		} else {
			return fail(r, vn_io_error_parse, "expected 'facet' or 'endsolid', found '%s'", vn_io_quote(t.p, t.n).text);
		}
	}
	return result;
}

/* ------------------------------------------------------------------ binary */

static vn_io_result read_binary(stl_reader* r, const unsigned char* data, size_t triangles)
{
	r->corners = malloc(triangles * 9 * sizeof(double) + 1);
	r->attributes = malloc(triangles * sizeof *r->attributes + 1);
	if (!r->corners || !r->attributes)
		return vn_io_fail(r->error, vn_io_error_memory, "%s: out of memory", r->name);
	for (size_t t = 0; t < triangles; t++) {
		const unsigned char* record = data + STL_HEADER + 4 + STL_TRIANGLE * t;
		for (int k = 0; k < 9; k++)
			r->corners[9 * t + (size_t)k] = get_float(record + 12 + 4 * k); /* after the facet normal */
		r->attributes[t] = (uint16_t)(record[48] | record[49] << 8);
		r->coloured += (record[49] & 0x80) != 0;
	}
	r->triangles = triangles;
	r->binary = 1;
	return vn_io_success;
}

/* Where `key` (Magics' "COLOR=", "MATERIAL=") ends in the header, or NULL. */
static const unsigned char* header_find(const unsigned char* header, const char* key)
{
	const size_t n = strlen(key);
	for (size_t i = 0; i + n <= STL_HEADER; i++)
		if (!memcmp(header + i, key, n))
			return header + i + n;
	return NULL;
}

/* A colour channel of 5 bits as the byte it stands for (31: 255). */
static float channel(unsigned bits)
{
	return (float)((bits * 255 + 15) / 31) / 255.0f;
}

/* A binary STL's header and attribute bytes kept, and the colours they hold
 * read as face colours: Materialise Magics' where the header has COLOR= or
 * MATERIAL= (bits 0-4 red, 5-9 green, 10-14 blue; bit 15 set: the
 * object's colour, the 4 bytes RGBA after COLOR=, white without), else
 * VisCAM's and SolidView's where any triangle has bit 15 set, which marks
 * a colour (bits 10-14 red, 5-9 green, 0-4 blue; white where it is clear).
 * 0 when out of memory. */
static int keep_extras(stl_reader* r, const unsigned char* header, vn_io_mesh* mesh)
{
	vn_io_stl_extras* extras = malloc(sizeof *extras);
	if (!extras)
		return 0;
	memcpy(extras->header, header, STL_HEADER);
	extras->attributes = r->attributes;
	extras->count = r->triangles;
	r->attributes = NULL;
	mesh->stl_extras = extras;
	const unsigned char* object = header_find(header, "COLOR=");
	const int magics = object || header_find(header, "MATERIAL=");
	if (!magics && !r->coloured)
		return 1;
	mesh->face_colors = malloc(4 * sizeof(float) * r->triangles + 1);
	if (!mesh->face_colors)
		return 0;
	mesh->face_colors_are_bytes = 1;
	const float white[4] = {1, 1, 1, 1};
	float fallback[4] = {1, 1, 1, 1};
	if (object && object + 4 <= header + STL_HEADER)
		for (int k = 0; k < 4; k++)
			fallback[k] = (float)object[k] / 255.0f;
	for (size_t t = 0; t < r->triangles; t++) {
		const unsigned a = extras->attributes[t], own = magics ? !(a & 0x8000) : (a & 0x8000) != 0;
		float* c = mesh->face_colors + 4 * t;
		if (own) {
			c[magics ? 0 : 2] = channel(a & 31);
			c[1] = channel(a >> 5 & 31);
			c[magics ? 2 : 0] = channel(a >> 10 & 31);
			c[3] = 1;
		} else {
			memcpy(c, magics ? fallback : white, sizeof white);
		}
	}
	return 1;
}

/* ------------------------------------------------------------------ entry points */

/* The corners welded by exact position into the mesh's vertices, in the
 * order of their first corner. */
static vn_io_result weld(stl_reader* r, vn_io_mesh* m)
{
	if (r->triangles == 0) /* "solid x endsolid x", or a binary count of 0: an empty mesh */
		return vn_io_mesh_set_empty(m) ? vn_io_success
		                               : vn_io_fail(r->error, vn_io_error_memory, "%s: out of memory", r->name);
	if (r->triangles > UINT32_MAX / 3)
		return vn_io_fail(r->error, vn_io_error_unsupported, "%s: %zu triangles are more than vn reads (%u)", r->name,
		                  r->triangles, UINT32_MAX / 3);
	const size_t corners = 3 * r->triangles;
	uint32_t* remap = malloc(corners * sizeof *remap);
	m->indices = malloc(corners * sizeof *m->indices);
	m->face_offsets = malloc((r->triangles + 1) * sizeof *m->face_offsets);
	if (!remap || !m->indices || !m->face_offsets) {
		free(remap);
		return vn_io_fail(r->error, vn_io_error_memory, "%s: out of memory", r->name);
	}
	const vn_positions positions = {r->corners, corners, 0, vn_scalar_float64};
	const vn_result welded = vn_weld_positions(remap, &positions, 0.0, NULL);
	if (welded != vn_result_success) {
		free(remap);
		return vn_io_fail(r->error, vn_io_error_memory, "%s: %s", r->name, vn_result_string(welded));
	}
	/* A corner's vertex is numbered at its group's first corner, which is
	 * its representative: vertex v <= corner c, so moving positions down in
	 * place never overwrites a corner still to be read. */
	size_t vertices = 0;
	for (size_t c = 0; c < corners; c++) {
		if (remap[c] == c) {
			memmove(r->corners + 3 * vertices, r->corners + 3 * c, 3 * sizeof(double));
			remap[c] = (uint32_t)vertices++;
			m->indices[c] = remap[c];
		} else {
			m->indices[c] = remap[remap[c]];
		}
	}
	free(remap);
	for (size_t f = 0; f <= r->triangles; f++)
		m->face_offsets[f] = (uint32_t)(3 * f);
	double* shrunk = realloc(r->corners, 3 * sizeof(double) * vertices);
	m->positions = shrunk ? shrunk : r->corners;
	r->corners = NULL;
	m->vertex_count = vertices;
	m->face_count = r->triangles;
	return vn_io_success;
}

/* A binary STL's count triangles, then `padding` bytes (as some exporters
 * write them), with a warning saying so. */
static vn_io_result read_padded(stl_reader* r, uint64_t count, size_t padding, vn_io_mesh* mesh)
{
	vn_io_result result = read_binary(r, r->p, (size_t)count);
	if (result == vn_io_success &&
	    !vn_io_append_line(&mesh->warnings, "%zu bytes after the last triangle, not read", padding))
		result = vn_io_fail(r->error, vn_io_error_memory, "%s: out of memory", r->name);
	return result;
}

/* Starts with "solid" after blanks, in any case. */
static int starts_with_solid(const unsigned char* p, const unsigned char* end)
{
	while (p < end && is_space(*p))
		p++;
	return end - p >= 5 && token_is((token){p, 5}, "solid");
}

/* Whether the size bytes at p are a binary STL by their size: the 84-byte
 * header, then as many 50-byte triangles as it announces. */
static int binary_sized(const unsigned char* p, size_t size)
{
	return size >= STL_HEADER + 4 && STL_HEADER + 4 + STL_TRIANGLE * (uint64_t)get_u32(p + STL_HEADER) == size;
}

/* The reader of the size bytes at data; `wide` (or NULL) names the encoding
 * of text they were decoded from, which only an ASCII STL can be. */
static vn_io_result read_memory(const char* data, size_t size, const char* name, const char* wide, vn_io_mesh* mesh,
                                vn_io_error* error)
{
	memset(mesh, 0, sizeof *mesh);
	stl_reader r;
	memset(&r, 0, sizeof r);
	r.name = name;
	r.error = error;
	r.p = (const unsigned char*)(data ? data : "");
	r.end = r.p + (data ? size : 0);
	r.line = 1;
	const uint64_t count = size >= STL_HEADER + 4 ? get_u32(r.p + STL_HEADER) : 0;
	const uint64_t binary_size = STL_HEADER + 4 + STL_TRIANGLE * count;
	const size_t after = size >= STL_HEADER + 4 ? size - (STL_HEADER + 4) : 0; /* bytes after the header */
	vn_io_result result;
	const size_t bom = vn_io_utf8_bom(r.p, size);
	const int binary = !wide && binary_sized(r.p, size);
	if (!binary) {
		const vn_io_result lfs = vn_io_refuse_lfs_pointer(r.p, size, name, error);
		if (lfs != vn_io_success)
			return lfs;
	}
	if (binary) {
		result = read_binary(&r, r.p, (size_t)count);
	} else if (wide && !starts_with_solid(r.p, r.end)) {
		result = vn_io_fail(error, vn_io_error_parse,
		                    "%s: the text is %s (it starts with a byte order mark), but does not start with 'solid', "
		                    "as an ASCII STL does",
		                    name, wide);
	} else if (starts_with_solid(r.p + bom, r.end)) {
		r.p += bom;
		vn_io_c_locale locale;
		if (!vn_io_c_locale_enter(&locale))
			return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
		result = read_ascii(&r);
		vn_io_c_locale_leave(&locale);
		if (result == vn_io_success && r.unended &&
		    !vn_io_append_line(&mesh->warnings,
		                       "the file ends after %zu triangle%s without 'endsolid': read (a writer left it out, "
		                       "or the file was cut after a whole triangle)",
		                       r.triangles, r.triangles == 1 ? "" : "s"))
			result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
		/* Not ASCII after all: a binary STL whose header starts with
		 * "solid" and whose triangles are followed by padding. */
		if (result != vn_io_success && result != vn_io_error_memory && !wide && count > 0 && binary_size <= size) {
			free(r.corners);
			free(r.attributes);
			r.corners = NULL, r.attributes = NULL, r.triangles = 0, r.capacity = 0;
			r.p = (const unsigned char*)data;
			result = read_padded(&r, count, size - (size_t)binary_size, mesh);
		}
	} else if (size < STL_HEADER + 4) {
		result = vn_io_fail(error, vn_io_error_parse,
		                    "%s: not an STL file: %zu bytes, too short for a binary STL's 84-byte header, and it "
		                    "does not start with 'solid'",
		                    name, size);
	} else if (count == 0 && after > 0 && after % STL_TRIANGLE == 0) {
		/* A writer that never filled in the count (streaming ones do so):
		 * the triangles that follow are read. */
		const size_t n = after / STL_TRIANGLE;
		result = read_binary(&r, r.p, n);
		if (result == vn_io_success &&
		    !vn_io_append_line(&mesh->warnings,
		                       "binary STL announces 0 triangles, but %zu triangle%s follow%s its header: read", n,
		                       n == 1 ? "" : "s", n == 1 ? "s" : ""))
			result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	} else if (binary_size > size) {
		result = vn_io_fail(error, vn_io_error_parse,
		                    "%s: binary STL announces %llu triangles (%llu bytes), but the file has %zu bytes: it is "
		                    "cut short",
		                    name, (unsigned long long)count, (unsigned long long)binary_size, size);
	} else {
		result = read_padded(&r, count, size - (size_t)binary_size, mesh);
	}
	if (result == vn_io_success && r.binary && !keep_extras(&r, (const unsigned char*)data, mesh))
		result = vn_io_fail(error, vn_io_error_memory, "%s: out of memory", name);
	if (result == vn_io_success)
		result = weld(&r, mesh);
	free(r.corners);
	free(r.attributes);
	if (result != vn_io_success)
		vn_io_mesh_free(mesh);
	return result;
}

vn_io_result vn_io_stl_read_memory(const char* data, size_t size, const char* name, vn_io_mesh* mesh,
                                   vn_io_error* error)
{
	/* A binary STL's header may start with a byte order mark's bytes. */
	if (data && binary_sized((const unsigned char*)data, size))
		return read_memory(data, size, name, NULL, mesh, error);
	return vn_io_read_text(data, size, name, read_memory, mesh, error);
}

vn_io_result vn_io_stl_read(const char* path, vn_io_mesh* mesh, vn_io_error* error)
{
	return vn_io_read_with(path, vn_io_stl_read_memory, mesh, error);
}

/* ------------------------------------------------------------------ writer */

static void facet(unsigned char* record, const double* a, const double* b, const double* c)
{
	const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
	const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
	double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
	const double length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	for (int k = 0; k < 3; k++) {
		put_float(record + 4 * k, length > 0 && isfinite(length) ? (float)(n[k] / length) : 0.0f);
		put_float(record + 12 + 4 * k, (float)a[k]);
		put_float(record + 24 + 4 * k, (float)b[k]);
		put_float(record + 36 + 4 * k, (float)c[k]);
	}
}

vn_io_result vn_io_stl_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings,
                             vn_io_error* error)
{
	(void)settings; /* STL has none */
	const uint64_t triangles = vn_io_mesh_triangle_count(mesh);
	/* An STL without triangles holds no vertices: an empty mesh only. */
	if (triangles == 0 && mesh->vertex_count)
		return vn_io_fail(error, vn_io_error_unsupported,
		                  "%s: the mesh has no faces, and STL holds only triangles: write OFF or PLY for a point cloud",
		                  path);
	if (triangles > UINT32_MAX)
		return vn_io_fail(error, vn_io_error_unsupported, "%s: %llu triangles are more than STL's 32-bit count holds",
		                  path, (unsigned long long)triangles);
	/* The input's header and attribute bytes where these are its triangles. */
	const vn_io_stl_extras* extras = mesh->stl_extras;
	if (extras && (extras->count != mesh->face_count || (mesh->face_count && !vn_io_mesh_is_triangles(mesh))))
		extras = NULL;
	/* Else not "solid ...": readers would take the file for ASCII. */
	unsigned char header[STL_HEADER + 4];
	memset(header, ' ', STL_HEADER);
	if (extras)
		memcpy(header, extras->header, STL_HEADER);
	else
		memcpy(header, "binary STL written by vn", 24);
	for (int k = 0; k < 4; k++)
		header[STL_HEADER + k] = (unsigned char)(triangles >> 8 * k);
	int failed = fwrite(header, 1, sizeof header, out) != sizeof header;
	unsigned char record[STL_TRIANGLE];
	for (size_t f = 0; f < mesh->face_count && !failed; f++) {
		const uint32_t first = mesh->face_offsets[f];
		unsigned attribute = 0;
		if (extras) {
			attribute = extras->attributes[f];
		} else if (mesh->face_colors) { /* VisCAM's: bit 15, then red, green, blue in 5 bits each */
			attribute = 0x8000;
			for (int k = 0; k < 3; k++) {
				const float v = mesh->face_colors[4 * f + (size_t)k];
				const unsigned byte = v > 0 ? v < 1 ? (unsigned)lroundf(v * 255) : 255 : 0;
				attribute |= (byte * 31 + 127) / 255 << 5 * (2 - k);
			}
		}
		record[48] = (unsigned char)attribute;
		record[49] = (unsigned char)(attribute >> 8);
		for (uint32_t c = first + 2; c < mesh->face_offsets[f + 1] && !failed; c++) {
			facet(record, mesh->positions + 3 * (size_t)mesh->indices[first],
			      mesh->positions + 3 * (size_t)mesh->indices[c - 1], mesh->positions + 3 * (size_t)mesh->indices[c]);
			failed = fwrite(record, 1, sizeof record, out) != sizeof record;
		}
	}
	if (failed || ferror(out))
		return vn_io_fail(error, vn_io_error_write, "%s: cannot write", path);
	return vn_io_success;
}
