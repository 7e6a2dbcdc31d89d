/*
 * vn_io_mesh helpers and error reporting shared by every format.
 */
#include "vn_io.h"
#include "ply.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char* vn_io_result_string(vn_io_result r)
{
	switch (r) {
	case vn_io_success: return "success";
	case vn_io_error_open: return "cannot open or read the input file";
	case vn_io_error_write: return "cannot write the output file";
	case vn_io_error_parse: return "malformed file";
	case vn_io_error_unsupported: return "file uses a feature vn does not support";
	case vn_io_error_format: return "unknown file format";
	case vn_io_error_memory: return "out of memory";
	case vn_io_error_same_file: return "the output is the input file";
	case vn_io_error_option: return "an option that is out of range or does not apply";
	case vn_io_result_count_: break;
	}
	return "unknown vn_io result";
}

int vn_io_parse_uint(const char* s, unsigned long lo, unsigned long hi, unsigned long* out)
{
	if (!s || !*s || *s == '-' || *s == '+')
		return 0;
	char* end;
	errno = 0;
	unsigned long v = strtoul(s, &end, 10);
	if (errno || *end || v < lo || v > hi)
		return 0;
	*out = v;
	return 1;
}

vn_io_result vn_io_fail(vn_io_error* error, vn_io_result r, const char* fmt, ...)
{
	if (error) {
		va_list args;
		va_start(args, fmt);
		vsnprintf(error->message, sizeof error->message, fmt, args);
		va_end(args);
	}
	return r;
}

void vn_io_mesh_free(vn_io_mesh* mesh)
{
	if (!mesh)
		return;
	free(mesh->positions);
	free(mesh->normals);
	free(mesh->colors);
	free(mesh->texcoords);
	free(mesh->position_lines);
	free(mesh->comments);
	free(mesh->face_offsets);
	free(mesh->indices);
	free(mesh->face_colors);
	for (size_t i = 0; i < mesh->attribute_count; i++)
		free(mesh->attributes[i].data), free(mesh->attributes[i].source_name);
	free(mesh->attributes);
	vn_io_face_names* sets[4] = {&mesh->materials, &mesh->objects, &mesh->groups, &mesh->smoothing};
	for (size_t k = 0; k < 4; k++) {
		for (size_t i = 0; i < sets[k]->count; i++)
			free(sets[k]->names[i]);
		free(sets[k]->names);
		free(sets[k]->of_face);
	}
	free(mesh->face_untextured);
	for (size_t i = 0; mesh->material_defs && i < mesh->materials.count; i++)
		for (int k = 0; k < vn_io_texture_kinds; k++)
			free(mesh->material_defs[i].textures[k]);
	free(mesh->material_defs);
	free(mesh->material_library);
	free(mesh->material_folder);
	vn_io_ply_extras_free(mesh->ply_extras);
	if (mesh->stl_extras)
		free(mesh->stl_extras->attributes);
	free(mesh->stl_extras);
	free(mesh->line_offsets);
	free(mesh->line_indices);
	free(mesh->warnings);
	memset(mesh, 0, sizeof *mesh);
}

size_t vn_io_component_size(int component_type)
{
	switch (component_type) {
	case 5120: case 5121: return 1;
	case 5122: case 5123: return 2;
	case 5124: case 5125: case 5126: return 4;
	case 5130: return 8;
	default: return 0;
	}
}

size_t vn_io_attribute_rounded(const vn_io_mesh* mesh, const vn_io_attribute* a, size_t* beyond)
{
	const double* x = (const double*)a->data;
	size_t rounded = 0;
	*beyond = 0;
	for (size_t i = 0; i < mesh->vertex_count * (size_t)a->components; i++) {
		const float f = (float)x[i];
		rounded += (double)f != x[i] && x[i] == x[i];
		*beyond += (isinf(f) && !isinf(x[i])) || (f == 0 && x[i] != 0);
	}
	return rounded;
}

int vn_io_colors_are_bytes(const float* rgba, size_t count)
{
	for (size_t i = 0; i < 4 * count; i++) {
		const double k = 255.0 * rgba[i];
		if (!(fabs(k - nearbyint(k)) <= 2e-4)) /* NaN too */
			return 0;
	}
	return 1;
}

int vn_io_mesh_set_empty(vn_io_mesh* mesh)
{
	mesh->positions = malloc(sizeof(double));
	mesh->face_offsets = calloc(1, sizeof(uint32_t));
	mesh->indices = malloc(sizeof(uint32_t));
	if (mesh->positions && mesh->face_offsets && mesh->indices)
		return 1;
	vn_io_mesh_free(mesh);
	return 0;
}

/* Grows *data (n elements of `size` bytes; NULL: none to grow) by a copy
 * of each element source[e]. */
static int append_copies(void** data, size_t size, size_t n, const uint32_t* source, size_t count)
{
	if (!*data)
		return 1;
	unsigned char* grown = realloc(*data, (n + count) * size);
	if (!grown)
		return 0;
	*data = grown;
	for (size_t e = 0; e < count; e++)
		memcpy(grown + (n + e) * size, grown + (size_t)source[e] * size, size);
	return 1;
}

int vn_io_mesh_append_vertices(vn_io_mesh* mesh, const uint32_t* source, size_t count)
{
	const size_t n = mesh->vertex_count;
	int grown = append_copies((void**)&mesh->positions, 3 * sizeof(double), n, source, count) &&
	            append_copies((void**)&mesh->normals, 3 * sizeof(double), n, source, count) &&
	            append_copies((void**)&mesh->colors, 4 * sizeof(float), n, source, count) &&
	            append_copies((void**)&mesh->texcoords, 2 * sizeof(float), n, source, count) &&
	            append_copies((void**)&mesh->position_lines, sizeof(uint32_t), n, source, count);
	for (size_t i = 0; grown && i < mesh->attribute_count; i++) {
		vn_io_attribute* a = &mesh->attributes[i];
		grown = append_copies(&a->data, vn_io_component_size(a->component_type) * (size_t)a->components, n, source,
		                      count);
	}
	if (grown)
		mesh->vertex_count = n + count;
	return grown;
}

vn_io_attribute* vn_io_mesh_add_attribute(vn_io_mesh* mesh, const char* name, int semantic, int component_type,
                                          int components, int normalized)
{
	const size_t size = vn_io_component_size(component_type);
	if (!size || components < 1 || components > 4)
		return NULL;
	vn_io_attribute* grown = realloc(mesh->attributes, (mesh->attribute_count + 1) * sizeof *grown);
	if (!grown)
		return NULL;
	mesh->attributes = grown;
	vn_io_attribute* a = &grown[mesh->attribute_count];
	memset(a, 0, sizeof *a);
	a->data = calloc(mesh->vertex_count ? mesh->vertex_count : 1, size * (size_t)components);
	if (!a->data)
		return NULL;
	snprintf(a->name, sizeof a->name, "%s", name);
	a->semantic = semantic;
	a->component_type = component_type;
	a->components = components;
	a->normalized = normalized;
	mesh->attribute_count++;
	return a;
}

size_t vn_io_mesh_first_nonfinite(const vn_io_mesh* mesh)
{
	for (size_t i = 0; i < mesh->vertex_count; i++) {
		const double* p = mesh->positions + 3 * i;
		/* x - x is 0 for finite x and NaN for NaN and infinities. */
		if (p[0] - p[0] != 0 || p[1] - p[1] != 0 || p[2] - p[2] != 0)
			return i;
	}
	return mesh->vertex_count;
}

/* True when a vertex colour is not opaque: only then does a writer without
 * alpha lose something. */
static int has_alpha(const vn_io_mesh* mesh)
{
	for (size_t i = 0; i < mesh->vertex_count; i++)
		if (mesh->colors[4 * i + 3] != 1.0f)
			return 1;
	return 0;
}

/* True when some face is in a smoothing group: "s off" and "s 0" (every
 * face of Blender's flat-shaded objects) put it in none, so leaving them
 * out loses nothing. */
static int smoothing_groups(const vn_io_mesh* mesh)
{
	const vn_io_face_names* s = &mesh->smoothing;
	for (size_t f = 0; s->of_face && f < mesh->face_count; f++) {
		const uint32_t id = s->of_face[f];
		if (id < s->count && strcmp(s->names[id], "off") && strcmp(s->names[id], "0"))
			return 1;
	}
	return 0;
}

size_t vn_io_mesh_losses(const vn_io_mesh* mesh, const vn_io_format* format, char* text, size_t size)
{
	size_t lost = 0, used = 0;
	if (size)
		text[0] = '\0';
	const unsigned holds = format ? format->holds : 0;
	const int names_lost = !(holds & vn_io_holds_face_names), materials_lost = !(holds & vn_io_holds_materials);
	const int colors_kept = mesh->colors && (holds & vn_io_holds_colors);
	const char* names[] = {
	    mesh->normals && format && !format->no_normal ? "vertex normals" : NULL,
	    mesh->colors && !colors_kept ? "vertex colours" : NULL,
	    colors_kept && !(holds & vn_io_holds_color_alpha) && has_alpha(mesh) ? "vertex colour alpha" : NULL,
	    mesh->texcoords && !(holds & vn_io_holds_texcoords) ? "texture coordinates" : NULL,
	    mesh->face_colors && !(holds & vn_io_holds_face_colors) ? "face colours" : NULL,
	    mesh->materials.of_face && materials_lost ? "materials" : NULL,
	    mesh->objects.of_face && names_lost ? "object names" : NULL,
	    mesh->groups.of_face && names_lost ? "groups" : NULL,
	    names_lost && smoothing_groups(mesh) ? "smoothing groups" : NULL,
	    mesh->line_count && !(holds & vn_io_holds_lines) ? "lines" : NULL,
	};
	const size_t fixed = sizeof names / sizeof names[0];
	for (size_t i = 0; i < mesh->attribute_count + fixed; i++) {
		const char* name = i < fixed ? names[i] : !(holds & vn_io_holds_attributes) ? mesh->attributes[i - fixed].name : NULL;
		if (!name)
			continue;
		if (used < size) {
			int n = snprintf(text + used, size - used, "%s%s", lost ? ", " : "", name);
			used += n > 0 ? (size_t)n : 0;
		}
		lost++;
	}
	char extras[480];
	const size_t more =
	    mesh->ply_extras && !(holds & vn_io_holds_ply_extras)
	        ? vn_io_ply_extras_describe(mesh->ply_extras, extras, sizeof extras)
	        : 0;
	if (more && used < size)
		snprintf(text + used, size - used, "%s%s", lost ? ", " : "", extras);
	return lost + more;
}

int vn_io_mesh_is_triangles(const vn_io_mesh* mesh)
{
	if (!mesh || mesh->face_count == 0 || !mesh->face_offsets)
		return 0;
	for (size_t f = 0; f < mesh->face_count; f++)
		if (mesh->face_offsets[f + 1] - mesh->face_offsets[f] != 3)
			return 0;
	return 1;
}

uint64_t vn_io_mesh_triangle_count(const vn_io_mesh* mesh)
{
	uint64_t n = 0;
	for (size_t f = 0; f < mesh->face_count; f++) {
		const uint32_t k = mesh->face_offsets[f + 1] - mesh->face_offsets[f];
		n += k >= 3 ? k - 2 : 0;
	}
	return n;
}
