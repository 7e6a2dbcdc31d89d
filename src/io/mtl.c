/*
 * An OBJ's material library (.mtl): of each material the mesh uses, what
 * glTF's metallic-roughness material takes from the Phong model the library
 * describes: the diffuse colour (Kd) and texture (map_Kd), the opacity (d;
 * not Tr, which writers mean both ways: MeshLab writes "Tr 1" for opaque,
 * others for clear, and Blender ignores it), the shininess (Ns) as a
 * roughness, 1 - sqrt(Ns / 1000), as Blender reads it, the emission (Ke,
 * map_Ke) and the normal map (map_Bump, bump or norm, with its -bm scale,
 * as Blender and obj2gltf read them); the PBR extension's Pr and Pm where
 * given. Ka, Ks, illum and the other maps have no counterpart there and are
 * not read. (How they become a glTF material: gltf_material,
 * gltf_mesh.cpp.)
 */
#define _GNU_SOURCE /* open_memstream */

#include "mtl.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "text.h"

static int blank(char c)
{
	return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* The next blank-separated token of [*p, end): its start, and its length in
 * *n (0 at the end); *p moves past it. */
static const char* token(const char** p, const char* end, size_t* n)
{
	const char* s = *p;
	while (s < end && blank(*s))
		s++;
	const char* e = s;
	while (e < end && !blank(*e))
		e++;
	*n = (size_t)(e - s);
	*p = e;
	return s;
}

/* [p, end) without blanks at either end, as a string; NULL when out of memory. */
static char* trimmed(const char* p, const char* end)
{
	while (p < end && blank(*p))
		p++;
	while (end > p && blank(end[-1]))
		end--;
	char* s = malloc((size_t)(end - p) + 1);
	if (s) {
		memcpy(s, p, (size_t)(end - p));
		s[end - p] = '\0';
	}
	return s;
}

static int keyword(const char* t, size_t n, const char* word)
{
	const size_t k = strlen(word);
	if (n != k)
		return 0;
	for (size_t i = 0; i < n; i++)
		if ((t[i] | 0x20) != (word[i] | 0x20)) /* exporters differ in case: map_kd, KD */
			return 0;
	return 1;
}

/* Up to `most` numbers from *p on into v; returns how many (a token that is
 * not a finite number ends them, and is not consumed). */
static int numbers(const char** p, const char* end, double* v, int most)
{
	int got = 0;
	while (got < most) {
		const char* before = *p;
		size_t n;
		const char* t = token(p, end, &n);
		if (!n || !vn_io_parse_real((const unsigned char*)t, n, &v[got]) || !isfinite(v[got])) {
			*p = before;
			break;
		}
		got++;
	}
	return got;
}

static double unit(double x)
{
	return x < 0 ? 0 : x > 1 ? 1 : x;
}

/* `name` from `folder` (NULL or an absolute name: as it is); NULL when out
 * of memory. */
static char* from_folder(const char* folder, const char* name)
{
	const size_t f = folder && name[0] != '/' ? strlen(folder) : 0, n = strlen(name);
	char* s = malloc(f + 1 + n + 1);
	if (!s)
		return NULL;
	if (f) {
		memcpy(s, folder, f);
		s[f] = '/';
	}
	memcpy(s + (f ? f + 1 : 0), name, n + 1);
	return s;
}

/* The folder part of path ("a/b.mtl": "a"; "b.mtl": NULL), or NULL when out
 * of memory (*failed set). */
static char* folder_of(const char* path, int* failed)
{
	const char* slash = strrchr(path, '/');
	if (!slash)
		return NULL;
	const size_t n = slash == path ? 1 : (size_t)(slash - path);
	char* s = malloc(n + 1);
	if (!s) {
		*failed = 1;
		return NULL;
	}
	memcpy(s, path, n);
	s[n] = '\0';
	return s;
}

/* A readable regular file; else errno says why (0: it is no regular file,
 * a folder or a device). */
static int is_file(const char* path)
{
	struct stat st;
	if (stat(path, &st) != 0)
		return 0;
	if (!S_ISREG(st.st_mode)) {
		errno = 0;
		return 0;
	}
	return access(path, R_OK) == 0;
}

/* Why is_file said no. */
static const char* why_not(int error_number)
{
	return error_number ? strerror(error_number) : "not a regular file";
}

/* Where file `name` (as a .obj or .mtl file names it) is, from `folder`:
 * as written; with '\\' read as '/' (written on Windows: "tex\\wood.png");
 * else, where `last` is set, its last part in `folder` itself (files moved
 * from their author's machine: "C:\\Users\\a\\wood.png", "/home/a/wood.png";
 * *moved then set). NULL where none is a file (*error_number: errno of the
 * first try) or out of memory (*failed set). */
static char* locate(const char* folder, const char* name, int last, int* moved, int* error_number, int* failed)
{
	*moved = 0;
	char* path = from_folder(folder, name);
	if (!path) {
		*failed = 1;
		return NULL;
	}
	if (is_file(path))
		return path;
	*error_number = errno;
	if (strstr(path, "\\ ")) { /* blanks escaped ("my\\ lib.mtl", as tinyobjloader reads them) */
		char* to = path;
		for (const char* c = path; *c; c++)
			if (!(c[0] == '\\' && c[1] == ' '))
				*to++ = *c;
		*to = '\0';
		if (is_file(path))
			return path;
	}
	for (char* c = path; *c; c++)
		*c = *c == '\\' ? '/' : *c;
	if (is_file(path))
		return path;
	const char* base = last ? strrchr(path, '/') : NULL;
	char* there = base ? from_folder(folder, base + 1) : NULL;
	free(path);
	if (base && !there)
		*failed = 1;
	if (there && is_file(there)) {
		*moved = 1;
		return there;
	}
	free(there);
	return NULL;
}

/* The first bytes of an image that glTF holds: 1 PNG, 2 JPEG, 0 another
 * kind (a TGA, a BMP) or unreadable. */
static int image_kind(const char* path)
{
	FILE* in = fopen(path, "rb");
	if (!in)
		return 0;
	unsigned char b[8] = {0};
	const size_t got = fread(b, 1, sizeof b, in);
	fclose(in);
	if (got == 8 && !memcmp(b, "\x89PNG\r\n\x1a\n", 8))
		return 1;
	return got >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF ? 2 : 0;
}

/* A map's options (MTL specification; -colorspace, tinyobjloader's) and
 * how many arguments each takes: -o, -s and -t one to three numbers. */
static int option_arguments(const char* t, size_t n)
{
	static const char* const one[] = {"-blendu", "-blendv", "-cc", "-clamp", "-texres", "-bm", "-boost", "-imfchan",
	                                  "-type", "-colorspace"};
	for (size_t i = 0; i < sizeof one / sizeof one[0]; i++)
		if (keyword(t, n, one[i]))
			return 1;
	if (keyword(t, n, "-mm"))
		return 2;
	if (keyword(t, n, "-o") || keyword(t, n, "-s") || keyword(t, n, "-t"))
		return 3;
	return -1;
}

/* A map's arguments [p, end) (`map`: its keyword as written) for texture
 * `kind` of material m: its options skipped (named in a warning; a normal
 * map's -bm is its scale), then the file, from `folder`. 0 when out of
 * memory. */
static int texture(const char* p, const char* end, const char* map, int kind, const char* name, const char* folder,
                   const char* material, vn_io_material* m, FILE* warnings)
{
	char skipped[200] = "";
	size_t used = 0;
	for (;;) {
		const char* q = p;
		size_t n;
		const char* t = token(&q, end, &n);
		const int k = n > 1 && t[0] == '-' ? option_arguments(t, n) : -1;
		if (k < 0)
			break;
		double v[3];
		if (kind == vn_io_texture_normal && keyword(t, n, "-bm") && numbers(&q, end, v, 1)) {
			m->normal_scale = v[0];
		} else {
			if (k == 3)
				numbers(&q, end, v, 3);
			for (int i = 0; k < 3 && i < k; i++)
				token(&q, end, &n);
			const int wrote = snprintf(skipped + used, sizeof skipped - used, "%s%.*s", used ? " " : "",
			                           (int)(q - t), t);
			used += wrote > 0 && (size_t)wrote < sizeof skipped - used ? (size_t)wrote : 0;
		}
		p = q;
	}
	char* file = trimmed(p, end);
	if (!file)
		return 0;
	if (!file[0]) {
		fprintf(warnings, "%s: material %s: %s names no file\n", name, material, map);
		free(file);
		return 1;
	}
	if (used)
		fprintf(warnings, "%s: material %s: %s's options (%s) are not carried: its texture is used as it is\n", name,
		        material, map, skipped);
	int moved = 0, error_number = 0, failed = 0;
	char* path = locate(folder, file, 1, &moved, &error_number, &failed);
	const int image = path ? image_kind(path) : 0;
	if (image) {
		if (moved)
			fprintf(warnings, "%s: material %s: texture %s is not there: %s is used\n", name, material, file, path);
		free(m->textures[kind]);
		m->textures[kind] = path;
		m->jpeg[kind] = image == 2;
	} else if (path) {
		fprintf(warnings, "%s: material %s: texture %s is neither PNG nor JPEG, the images glTF holds: written "
		                  "without it\n",
		        name, material, file);
		free(path);
	} else if (!failed) {
		fprintf(warnings, "%s: material %s: texture %s cannot be read (%s): written without it\n", name, material, file,
		        why_not(error_number));
	}
	free(file);
	return !failed;
}

/* The index of material `name` in mesh->materials, or -1. */
static long material_index(const vn_io_mesh* mesh, const char* name)
{
	for (size_t i = 0; i < mesh->materials.count; i++)
		if (!strcmp(mesh->materials.names[i], name))
			return (long)i;
	return -1;
}

static int allocate_defs(vn_io_mesh* mesh)
{
	if (mesh->material_defs)
		return 1;
	mesh->material_defs = calloc(mesh->materials.count ? mesh->materials.count : 1, sizeof(vn_io_material));
	if (!mesh->material_defs)
		return 0;
	for (size_t i = 0; i < mesh->materials.count; i++) {
		for (int c = 0; c < 4; c++)
			mesh->material_defs[i].color[c] = 1.0;
		mesh->material_defs[i].roughness = -1.0;
		mesh->material_defs[i].normal_scale = 1.0;
	}
	return 1;
}

int vn_io_mtl_parse(const char* data, size_t size, const char* name, const char* folder, vn_io_mesh* mesh,
                    FILE* warnings)
{
	if (vn_io_wide_bom((const unsigned char*)data, size)) {
		char* utf8 = NULL;
		size_t n;
		vn_io_error e;
		const vn_io_result r = vn_io_utf8_from_wide((const unsigned char*)data, size, name, &utf8, &n, &e);
		if (r == vn_io_success) {
			const int ok = vn_io_mtl_parse(utf8, n, name, folder, mesh, warnings);
			free(utf8);
			return ok;
		}
		if (r != vn_io_error_memory)
			fprintf(warnings, "%s: its materials are written by name only\n", e.message);
		return r != vn_io_error_memory;
	}
	const size_t bom = vn_io_utf8_bom((const unsigned char*)data, size); /* Windows editors write one */
	data += bom, size -= bom;
	if (!allocate_defs(mesh))
		return 0;
	const char* end = data + size;
	long current = -1; /* the material being defined, when the mesh uses it */
	char* current_name = NULL;
	int roughness_given = 0; /* Pr, which Ns does not override */
	for (const char* line = data; line < end;) {
		const char* stop = memchr(line, '\n', (size_t)(end - line));
		if (!stop)
			stop = end;
		const char* p = line;
		line = stop + 1;
		size_t n;
		const char* t = token(&p, stop, &n);
		if (!n || t[0] == '#')
			continue;
		if (keyword(t, n, "newmtl")) {
			free(current_name);
			if (!(current_name = trimmed(p, stop)))
				return 0;
			/* A name defined again goes on with the same material (as
			 * Blender reads it). */
			current = material_index(mesh, current_name);
			if (current >= 0)
				mesh->material_defs[current].defined = 1;
			roughness_given = 0;
			continue;
		}
		if (current < 0)
			continue;
		vn_io_material* m = &mesh->material_defs[current];
		double v[3];
		if (keyword(t, n, "Kd")) {
			const int got = numbers(&p, stop, v, 3);
			if (got == 1 || got == 3)
				for (int c = 0; c < 3; c++)
					m->color[c] = unit(v[got == 1 ? 0 : c]);
		} else if (keyword(t, n, "d")) {
			const char* q = p;
			const char* h = token(&q, stop, &n);
			if (keyword(h, n, "-halo"))
				p = q;
			if (numbers(&p, stop, v, 1))
				m->color[3] = unit(v[0]);
		} else if (keyword(t, n, "Ns")) {
			if (numbers(&p, stop, v, 1) && !roughness_given)
				m->roughness = 1.0 - sqrt(unit(v[0] / 1000.0));
		} else if (keyword(t, n, "Pr")) {
			if (numbers(&p, stop, v, 1))
				m->roughness = unit(v[0]), roughness_given = 1;
		} else if (keyword(t, n, "Pm")) {
			if (numbers(&p, stop, v, 1))
				m->metallic = unit(v[0]);
		} else if (keyword(t, n, "Ke")) {
			const int got = numbers(&p, stop, v, 3);
			if (got == 1 || got == 3)
				for (int c = 0; c < 3; c++)
					m->emissive[c] = unit(v[got == 1 ? 0 : c]);
		} else {
			/* The maps glTF has a place for (map_Bump, bump, norm: the
			 * normal map, as Blender and obj2gltf read them). */
			const int kind = keyword(t, n, "map_Kd")                              ? vn_io_texture_base
			                 : keyword(t, n, "map_Ke")                            ? vn_io_texture_emissive
			                 : keyword(t, n, "map_Bump") || keyword(t, n, "bump") ||
			                         keyword(t, n, "norm")                        ? vn_io_texture_normal
			                                                                      : -1;
			char map[16];
			snprintf(map, sizeof map, "%.*s", (int)n, t);
			if (kind >= 0 && !texture(p, stop, map, kind, name, folder, current_name, m, warnings)) {
				free(current_name);
				return 0;
			}
		}
	}
	free(current_name);
	return 1;
}

/* Library file `file` (as the OBJ names it; `last`: as locate) into mesh;
 * 0 when out of memory. Where it cannot be read, why->message says why
 * (else it is ""). */
static int read_library(vn_io_mesh* mesh, const char* file, int last, FILE* warnings, vn_io_error* why)
{
	why->message[0] = '\0';
	int moved = 0, error_number = 0, failed = 0;
	char* path = locate(mesh->material_folder, file, last, &moved, &error_number, &failed);
	if (!path) {
		if (!failed)
			vn_io_fail(why, vn_io_error_open, "material library %s cannot be read (%s)", file, why_not(error_number));
		return !failed;
	}
	char* data;
	size_t size;
	if (vn_io_read_all(path, &data, &size, why) != vn_io_success) {
		free(path);
		return 1;
	}
	if (moved)
		fprintf(warnings, "material library %s is not there: %s is used\n", file, path);
	char* folder = folder_of(path, &failed);
	const int ok = !failed && vn_io_mtl_parse(data, size, file, folder, mesh, warnings);
	free(folder);
	free(data);
	free(path);
	return ok;
}

/* The names of a mtllib line that is not one file's: those ending in
 * ".mtl" (several mtllib lines, names with blanks: "box mtllib red.mtl box
 * mtllib green.mtl"), each that is not a file split at its blanks. *read
 * counts the files read; 0 when out of memory. */
static int read_pieces(vn_io_mesh* mesh, const char* library, FILE* warnings, int* read)
{
	int ok = 1;
	for (const char *p = library, *end = library + strlen(library); ok && p < end;) {
		const char* cut = p;
		while (cut < end && !(cut + 4 <= end && keyword(cut, 4, ".mtl") && (cut + 4 == end || blank(cut[4]))))
			cut++;
		cut = cut < end ? cut + 4 : end;
		char* piece = trimmed(p, cut);
		p = cut;
		if (!piece)
			return 0;
		const char* stop = piece + strlen(piece);
		vn_io_error why;
		ok = !piece[0] || read_library(mesh, piece, 1, warnings, &why);
		const int split = ok && piece[0] && why.message[0] && strpbrk(piece, " \t") && !strstr(piece, "\\ ");
		if (ok && piece[0] && !split) {
			if (why.message[0])
				fprintf(warnings, "%s: its materials are written by name only\n", why.message);
			*read += !why.message[0];
		}
		for (const char* q = piece; ok && split;) {
			size_t n;
			const char* t = token(&q, stop, &n);
			if (!n)
				break;
			char* part = trimmed(t, t + n);
			ok = part && read_library(mesh, part, 1, warnings, &why);
			if (ok && why.message[0])
				fprintf(warnings, "%s: its materials are written by name only\n", why.message);
			*read += ok && !why.message[0];
			free(part);
		}
		free(piece);
	}
	return ok;
}

/* A texture needs coordinates (glTF's validator: an error): without them,
 * none is kept, and a warning names each. */
static void drop_untextured(vn_io_mesh* mesh, FILE* warnings)
{
	for (size_t i = 0; !mesh->texcoords && i < mesh->materials.count; i++)
		for (int k = 0; k < vn_io_texture_kinds; k++) {
			vn_io_material* m = &mesh->material_defs[i];
			if (m->textures[k])
				fprintf(warnings, "material %s: texture %s not written: the mesh has no texture coordinates\n",
				        mesh->materials.names[i], m->textures[k]);
			free(m->textures[k]);
			m->textures[k] = NULL;
		}
}

/* Warns of the materials faces use that no library read defines. 0 when
 * out of memory. */
static int warn_undefined(const vn_io_mesh* mesh, FILE* warnings)
{
	unsigned char* used = calloc(mesh->materials.count, 1);
	if (!used)
		return 0;
	for (size_t f = 0; f < mesh->face_count; f++)
		if (mesh->materials.of_face[f] < mesh->materials.count)
			used[mesh->materials.of_face[f]] = 1;
	size_t undefined = 0;
	for (size_t i = 0; i < mesh->materials.count; i++)
		if (used[i] && !mesh->material_defs[i].defined)
			fprintf(warnings, "%s%s", undefined++ ? ", " : "the material library defines no ", mesh->materials.names[i]);
	if (undefined)
		fprintf(warnings, ": written by name only\n");
	free(used);
	return 1;
}

/* The libraries mesh->material_library names: one file whose name may
 * hold blanks; else the names ending in ".mtl" (several mtllib lines, names
 * with blanks: "box mtllib red.mtl box mtllib green.mtl"), each else split
 * at its blanks (unless it escapes them: "my\\ lib.mtl"). 0 when out of
 * memory. */
static int read_libraries(vn_io_mesh* mesh, const void* unused, FILE* warnings)
{
	(void)unused;
	const char* library = mesh->material_library;
	vn_io_error why;
	const int blanks = strpbrk(library, " \t") != NULL;
	int ok = read_library(mesh, library, !blanks, warnings, &why);
	int read = !why.message[0];
	if (ok && !read && !blanks)
		fprintf(warnings, "%s: its materials are written by name only\n", why.message);
	else if (ok && !read)
		ok = read_pieces(mesh, library, warnings, &read);
	return ok && (!read || warn_undefined(mesh, warnings));
}

/* Library text in memory (vn_io_mtl_read_text's arguments). */
typedef struct library_text {
	const char *data, *name, *beside;
	size_t size;
} library_text;

static int read_text(vn_io_mesh* mesh, const void* what, FILE* warnings)
{
	const library_text* t = (const library_text*)what;
	int failed = 0;
	char* folder = t->beside ? folder_of(t->beside, &failed) : NULL;
	const int ok = !failed && vn_io_mtl_parse(t->data, t->size, t->name, folder, mesh, warnings);
	free(folder);
	return ok;
}

/* read(mesh, what, warnings) in the C locale, then the textures that
 * cannot be drawn dropped, the warnings appended to mesh->warnings. */
static vn_io_result with_warnings(vn_io_mesh* mesh, int (*read)(vn_io_mesh*, const void*, FILE*), const void* what,
                                  vn_io_error* error)
{
	char* text = NULL;
	size_t length = 0;
	FILE* warnings = open_memstream(&text, &length);
	vn_io_c_locale locale;
	int ok = warnings && allocate_defs(mesh) && vn_io_c_locale_enter(&locale);
	if (ok) {
		ok = read(mesh, what, warnings);
		vn_io_c_locale_leave(&locale);
		if (ok)
			drop_untextured(mesh, warnings);
	}
	if (warnings && fclose(warnings))
		ok = 0;
	while (ok && length && text[length - 1] == '\n')
		text[--length] = '\0';
	ok = ok && (!length || vn_io_append_line(&mesh->warnings, "%s", text));
	free(text);
	return ok ? vn_io_success : vn_io_fail(error, vn_io_error_memory, "out of memory reading the materials");
}

vn_io_result vn_io_mtl_read(vn_io_mesh* mesh, vn_io_error* error)
{
	if (!mesh->materials.count || !mesh->material_library || !mesh->materials.of_face)
		return vn_io_success;
	return with_warnings(mesh, read_libraries, NULL, error);
}

vn_io_result vn_io_mtl_read_text(vn_io_mesh* mesh, const char* data, size_t size, const char* name, const char* beside,
                                 vn_io_error* error)
{
	const library_text t = {data, name, beside, size};
	return with_warnings(mesh, read_text, &t, error);
}
