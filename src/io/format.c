/*
 * The table of file formats: every fact vn has about a format is in its row
 * (vn_io.h, "formats"). Its reader and writer live in the format's own file
 * and are declared in that file's header; vnconvert's dispatch, --help, the
 * messages about formats and the README's "What vnconvert keeps" table are
 * made from the rows. A new format is its own file and one more row.
 */
#include "vn_io.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "draco.h"
#include "gltf.h"
#include "obj.h"
#include "off.h"
#include "ply.h"
#include "stl.h"

/* What the glTF reader (both gltf and glb) brings. */
#define GLTF_READS                                                                                               \
	{{vn_io_holds_texcoords, "TEXCOORD_0", NULL},                                                              \
	 {vn_io_holds_colors, "COLOR_0", NULL},                                                                    \
	 {vn_io_holds_colors | vn_io_holds_color_alpha, "its alpha", "the alpha of COLOR_0 (named)"},              \
	 {vn_io_holds_attributes, "every other vertex attribute in its type (TEXCOORD_n, COLOR_n, JOINTS_n, "      \
	                          "WEIGHTS_n, TANGENT, `_NAME`)",                                                  \
	  "other vertex attributes (named)"}}
#define GLTF_NEVER_READ                                                                                    \
	"materials, nodes, skins, animations, lines (triangle primitives are merged; POINTS ones become vertices " \
	"without faces)"
#define GLTF_DOCUMENT_KEEPS                                                                                      \
	"everything: the document is edited, not rebuilt (see glTF); every extension, known to vn or not; Draco and "  \
	"meshopt compression as the input has it (only the data with new normals encoded again)"
#define GLTF_DOCUMENT_LOSES                                                                                     \
	"TANGENT with `--tangents drop`; Draco compression with `--draco off`; meshopt compression with "          \
	"`--meshopt off`"

static const vn_io_format formats[] = {
    {"off", "OFF", "OFF", ".off", "Geomview Object File Format (reads ASCII and binary, writes ASCII)",
     vn_io_off_read, vn_io_off_write,
     vn_io_holds_colors | vn_io_holds_color_alpha | vn_io_holds_texcoords | vn_io_holds_face_colors |
         vn_io_holds_polygons | vn_io_holds_loose_vertices | vn_io_holds_no_faces | vn_io_holds_nothing |
         vn_io_holds_comments,
     vn_io_path_mesh, 0, "the zero vector",
     {{vn_io_holds_colors, "vertex colours", NULL},
      {vn_io_holds_colors | vn_io_holds_color_alpha, "their alpha", "vertex colour alpha (named)"},
      {vn_io_holds_texcoords, "texture coordinates", NULL},
      {vn_io_holds_face_colors, "face colours", "face colours (named)"},
      {vn_io_holds_polygons, "polygons", "polygons (fan-triangulated)"},
      {vn_io_holds_comments, "the header's comments (before the counts)", "the header's comments"}},
     "comments after the counts", NULL, NULL, NULL},
    {"obj", "OBJ", "OBJ", ".obj",
     "Wavefront OBJ (read through Draco: v/vt/vn, polygons, usemtl, o; g and s by vn; the .mtl file's materials into "
     "glTF; written with per-corner vn)",
     vn_io_obj_read, vn_io_obj_write,
     vn_io_holds_colors | vn_io_holds_texcoords | vn_io_holds_polygons | vn_io_holds_loose_vertices |
         vn_io_holds_face_names | vn_io_holds_materials | vn_io_holds_no_faces | vn_io_holds_nothing |
         vn_io_holds_lines | vn_io_holds_comments,
     vn_io_path_mesh, 0, "the zero vector (`vn 0 0 0`, where a face uses the vertex)",
     {{vn_io_holds_texcoords, "texture coordinates", NULL},
      {vn_io_holds_colors, "vertex colours (`v x y z r g b`)", NULL},
      {vn_io_holds_polygons, "polygons", "polygons (fan-triangulated)"},
      {vn_io_holds_materials,
       "materials (`usemtl` names, the `mtllib` line; to glTF, each as the .mtl file defines it: Kd, d, Ns, Pr, Pm, "
       "Ke, and map_Kd, map_Bump and map_Ke as the PNG or JPEG images themselves)",
       "materials (named)"},
      {vn_io_holds_face_names, "object names (`o`, to the first blank)", "object names (named)"},
      {vn_io_holds_face_names, "groups (`g`)", "groups (named)"},
      {vn_io_holds_face_names, "smoothing groups (`s`)",
       "smoothing groups (named where a face has one: `s off` and `s 0` set none)"},
      {vn_io_holds_lines, "lines (`l`, after the faces)", "lines (named)"},
      {vn_io_holds_comments, "the comments at the top (before any other line)", "the comments at the top"}},
     "comments after the first other line, points, curves, the `vt` of a line's points, the rest of the .mtl file "
     "(Ka, Ks, Tr, illum, other maps)",
     NULL, NULL, NULL},
    {"ply", "PLY", "PLY", ".ply",
     "Stanford polygon file (reads ASCII and binary, either byte order; writes binary little-endian)",
     vn_io_ply_read, vn_io_ply_write,
     vn_io_holds_colors | vn_io_holds_color_alpha | vn_io_holds_texcoords | vn_io_holds_attributes |
         vn_io_holds_face_colors | vn_io_holds_polygons | vn_io_holds_loose_vertices | vn_io_holds_no_faces |
         vn_io_holds_nothing | vn_io_holds_ply_extras | vn_io_holds_comments,
     vn_io_path_mesh, 0, "the zero vector",
     {{vn_io_holds_colors, "vertex colours (red green blue)", NULL},
      {vn_io_holds_colors | vn_io_holds_color_alpha, "their alpha", "vertex colour alpha (named)"},
      {vn_io_holds_texcoords,
       "texture coordinates (s t, u v or texture_u texture_v; else a face list `texcoord`, per vertex where the "
       "output has no face properties)",
       NULL},
      {vn_io_holds_attributes, "every other vertex property in its type, as `_NAME` (double as float in glTF)",
       "other vertex properties (named)"},
      {vn_io_holds_face_colors, "face colours", "face colours (named)"},
      {vn_io_holds_polygons, "polygons", "polygons (fan-triangulated)"},
      {vn_io_holds_ply_extras,
       "every other face property in its type (MeshLab's per-corner `texcoord` lists, flags), other elements "
       "whole (edges, materials), comments and `obj_info`",
       "other face properties and other elements (named), comments"}},
     "vertex list properties", NULL, NULL, NULL},
    {"stl", "STL", "STL", ".stl",
     "stereolithography (reads binary and ASCII, corners welded by position; writes binary, face colours as VisCAM's "
     "5 bits a channel; no vertex normals)",
     vn_io_stl_read, vn_io_stl_write, vn_io_holds_nothing | vn_io_holds_face_colors | vn_io_holds_stl_extras,
     vn_io_path_mesh, 0, NULL,
     {{vn_io_holds_face_colors,
       "facet colours (Materialise Magics' with the header's COLOR=, VisCAM's and SolidView's with bit 15 set), as "
       "face colours",
       "facet colours (named)"},
      {vn_io_holds_stl_extras, "the header and attribute bytes", "the header, attribute bytes"}},
     "facet normals (one per triangle, recomputed on writing); corners with equal positions become one vertex", NULL,
     NULL, NULL},
    {"gltf", "glTF", "glTF", ".gltf", "glTF 2.0 JSON (glTF in: the whole document is kept, only normals change)",
     vn_io_gltf_read, vn_io_gltf_write,
     vn_io_holds_colors | vn_io_holds_color_alpha | vn_io_holds_texcoords | vn_io_holds_attributes |
         vn_io_holds_loose_vertices | vn_io_holds_no_faces | vn_io_holds_nothing | vn_io_holds_materials,
     vn_io_path_gltf, vn_io_draco_document, "(0, 0, 1)", GLTF_READS, GLTF_NEVER_READ, GLTF_DOCUMENT_KEEPS,
     GLTF_DOCUMENT_LOSES, "buffers and images"},
    {"glb", "GLB", "glTF", ".glb", "glTF 2.0 binary (as gltf)", vn_io_gltf_read, vn_io_glb_write,
     vn_io_holds_colors | vn_io_holds_color_alpha | vn_io_holds_texcoords | vn_io_holds_attributes |
         vn_io_holds_loose_vertices | vn_io_holds_no_faces | vn_io_holds_nothing | vn_io_holds_materials,
     vn_io_path_gltf, vn_io_draco_document, "(0, 0, 1)", GLTF_READS, GLTF_NEVER_READ, GLTF_DOCUMENT_KEEPS,
     GLTF_DOCUMENT_LOSES, NULL},
    {"drc", "Draco", "Draco", ".drc",
     "Draco mesh or point cloud (triangles; positions, normals, texcoords, colours; quantized)",
     vn_io_drc_read, vn_io_drc_write,
     vn_io_holds_colors | vn_io_holds_color_alpha | vn_io_holds_texcoords | vn_io_holds_attributes |
         vn_io_holds_no_faces,
     vn_io_path_drc, vn_io_draco_output, "the zero vector (Draco's octahedral coding decodes it as (1, 0, 0))",
     {{vn_io_holds_texcoords, "the first TEX_COORD (2 floats)", NULL},
      {vn_io_holds_colors, "the first COLOR", NULL},
      {vn_io_holds_colors | vn_io_holds_color_alpha, "its alpha", "the alpha of the first COLOR (named)"},
      {vn_io_holds_attributes, "every other attribute in its type (TEX_COORD and COLOR sets, GENERIC as `_NAME`)",
       "other attributes (named)"}},
     "metadata",
     "every attribute with its type, unique id, quantization grid and metadata; only NORMAL is replaced (see Draco)",
     "nothing", NULL},
};

#define FORMAT_COUNT (sizeof formats / sizeof formats[0])

/* Formats people try that vn neither reads nor writes: naming a format with
 * --input-format or --format cannot help. */
static const struct {
	const char* extension;
	const char* what;
} foreign[] = {{".fbx", "an FBX"}, {".dae", "a COLLADA"}, {".3ds", "a 3DS"}};

/* ASCII only: extensions and names are ASCII, and tolower() would follow the
 * program's locale. */
static int lower(unsigned char c)
{
	return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c;
}

static int equal_ignoring_case(const char* a, const char* b, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (lower((unsigned char)a[i]) != lower((unsigned char)b[i]))
			return 0;
	return 1;
}

/* True when path ends with extension (case-insensitive). */
static int ends_with(const char* path, size_t length, const char* extension, size_t n)
{
	return n > 0 && n <= length && equal_ignoring_case(path + length - n, extension, n);
}

const vn_io_format* vn_io_format_for_path(const char* path)
{
	if (!path)
		return NULL;
	size_t length = strlen(path);
	for (size_t i = 0; i < FORMAT_COUNT; i++) {
		const char* extension = formats[i].extensions;
		while (*extension) {
			size_t n = strcspn(extension, " ");
			if (ends_with(path, length, extension, n))
				return &formats[i];
			extension += n;
			extension += strspn(extension, " ");
		}
	}
	return NULL;
}

const vn_io_format* vn_io_format_by_name(const char* name)
{
	if (!name)
		return NULL;
	size_t length = strlen(name);
	for (size_t i = 0; i < FORMAT_COUNT; i++)
		if (strlen(formats[i].name) == length && equal_ignoring_case(name, formats[i].name, length))
			return &formats[i];
	return NULL;
}

const vn_io_format* vn_io_format_at(size_t i)
{
	return i < FORMAT_COUNT ? &formats[i] : NULL;
}

vn_io_path vn_io_conversion_path(const vn_io_format* in, const vn_io_format* out)
{
	return in && out && in->path == out->path ? in->path : vn_io_path_mesh;
}

/* ------------------------------------------------------------------ text */

/* Appends printf-style text to text[size], truncating. */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static void append(char* text, size_t size, const char* fmt, ...)
{
	const size_t used = strlen(text);
	if (used + 1 >= size)
		return;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(text + used, size - used, fmt, ap);
	va_end(ap);
}

/* The first row of each family, in table order: i is such a row. */
static int first_of_family(size_t i)
{
	for (size_t k = 0; k < i; k++)
		if (!strcmp(formats[k].family, formats[i].family))
			return 0;
	return 1;
}

/* The separator before item k of n in an English list: "", ", " or " and ". */
static const char* separator(size_t k, size_t n)
{
	return k == 0 ? "" : k + 1 == n ? " and " : ", ";
}

/* The extensions of a family, as "(.gltf, .glb)" or ".gltf or .glb". */
static void family_extensions(const char* family, const char* between, char* text, size_t size)
{
	size_t k = 0;
	for (size_t i = 0; i < FORMAT_COUNT; i++) {
		if (strcmp(formats[i].family, family))
			continue;
		const char* extension = formats[i].extensions;
		while (*extension) {
			const size_t n = strcspn(extension, " ");
			append(text, size, "%s%.*s", k++ ? between : "", (int)n, extension);
			extension += n;
			extension += strspn(extension, " ");
		}
	}
}

void vn_io_format_list(vn_io_listing style, char* text, size_t size)
{
	if (!size)
		return;
	text[0] = '\0';
	size_t families = 0, draco = 0;
	for (size_t i = 0; i < FORMAT_COUNT; i++) {
		families += first_of_family(i);
		/* A document path's family counts twice: its conversions, and its
		 * output with --draco on from other formats. */
		draco += (formats[i].draco & vn_io_draco_output) ? 1u
		         : (formats[i].draco & vn_io_draco_document) && first_of_family(i) ? 2u : 0u;
	}
	size_t k = 0;
	for (size_t i = 0; i < FORMAT_COUNT; i++) {
		const vn_io_format* f = &formats[i];
		switch (style) {
		case vn_io_list_names:
			append(text, size, "%s%s", i ? ", " : "", f->name);
			break;
		case vn_io_list_titles:
			append(text, size, "%s%s", separator(i, FORMAT_COUNT), f->title);
			break;
		case vn_io_list_extensions:
			append(text, size, "%s%s", i ? " " : "", f->extensions);
			break;
		case vn_io_list_families:
			if (first_of_family(i)) {
				append(text, size, "%s%s (", separator(k++, families), f->family);
				family_extensions(f->family, ", ", text, size);
				append(text, size, ")");
			}
			break;
		case vn_io_list_draco:
			if (f->draco & vn_io_draco_output)
				append(text, size, "%s%s (%s) output", separator(k++, draco), f->title, f->extensions);
			break;
		}
	}
	/* Then the document paths: "... output, to glTF to glTF conversions and
	 * to glTF output with --draco on". */
	for (size_t i = 0; style == vn_io_list_draco && i < FORMAT_COUNT; i++)
		if ((formats[i].draco & vn_io_draco_document) && first_of_family(i)) {
			append(text, size, "%s%s%s to %s conversions", separator(k, draco), k ? "to " : "", formats[i].family,
			       formats[i].family);
			k++;
			append(text, size, "%sto %s output with --draco on", separator(k, draco), formats[i].family);
			k++;
		}
}

void vn_io_path_description(vn_io_path p, char* text, size_t size)
{
	if (!size)
		return;
	text[0] = '\0';
	for (size_t i = 0; i < FORMAT_COUNT; i++)
		if (formats[i].path == p && first_of_family(i)) {
			append(text, size, "%s to %s conversions (", formats[i].family, formats[i].family);
			family_extensions(formats[i].family, " or ", text, size);
			append(text, size, " in and out)");
			return;
		}
}

void vn_io_unknown_format(const char* path, int input, char* text, size_t size)
{
	if (!size)
		return;
	text[0] = '\0';
	const char* advice = input ? "convert it to one of these first (e.g. with meshlabserver or Blender)"
	                           : "write one of these and convert that (e.g. with meshlabserver or Blender)";
	char list[256];
	const size_t length = path ? strlen(path) : 0;
	for (size_t i = 0; i < sizeof foreign / sizeof foreign[0]; ++i)
		if (ends_with(path, length, foreign[i].extension, strlen(foreign[i].extension))) {
			vn_io_format_list(vn_io_list_titles, list, sizeof list);
			append(text, size, "'%s' is %s file, and vn %s only %s files: %s", path, foreign[i].what,
			       input ? "reads" : "writes", list, advice);
			return;
		}
	vn_io_format_list(vn_io_list_families, list, sizeof list);
	append(text, size,
	       "cannot tell the format of '%s' from its extension: vn %s %s; name the format with %s if the file is one "
	       "of these, else %s",
	       path, input ? "reads" : "writes", list, input ? "--input-format" : "--format", advice);
}

/* ------------------------------------------------------------------ the README's table */

static int item_kept(const vn_io_item* it, const vn_io_format* out)
{
	return it->needs && (out->holds & it->needs) == it->needs;
}

/* True when `it` needs all that another left-out item needs, and more:
 * "their alpha" of vertex colours not written goes without saying. */
static int part_of_lost(const vn_io_format* in, const vn_io_item* it, const vn_io_format* out)
{
	for (const vn_io_item* o = in->reads; o < in->reads + VN_IO_MAX_ITEMS && o->text; ++o)
		if (o->needs && o->needs != it->needs && (o->needs & it->needs) == o->needs && !item_kept(o, out))
			return 1;
	return 0;
}

/* The items of `in`'s reader that `out`'s writer keeps (keep 1) or leaves out
 * (keep 0), then, when leaving out, what reading never brings; "nothing"
 * when there are none. */
static void items(const vn_io_format* in, const vn_io_format* out, int keep, char* text, size_t size)
{
	text[0] = '\0';
	size_t n = 0;
	for (const vn_io_item* it = in->reads; it < in->reads + VN_IO_MAX_ITEMS && it->text; ++it) {
		const int kept = item_kept(it, out);
		if (kept == keep && (keep || !part_of_lost(in, it, out)))
			append(text, size, "%s%s", n++ ? ", " : "", keep || !it->lost ? it->text : it->lost);
	}
	if (!keep && in->never_read)
		append(text, size, "%s%s", n++ ? ", " : "", in->never_read);
	if (!n)
		append(text, size, "nothing");
}

void vn_io_conversions_table(FILE* out)
{
	fprintf(out, "| input → output | kept | left out (vnconvert names the attributes it leaves out, in a warning) |\n");
	fprintf(out, "|---|---|---|\n");
	for (size_t i = 0; i < FORMAT_COUNT; i++) {
		if (!first_of_family(i))
			continue;
		for (size_t o = 0; o < FORMAT_COUNT; o++) {
			if (!first_of_family(o))
				continue;
			const vn_io_format *a = &formats[i], *b = &formats[o];
			char kept[512], lost[512];
			if (vn_io_conversion_path(a, b) != vn_io_path_mesh) {
				snprintf(kept, sizeof kept, "%s", a->document_keeps);
				snprintf(lost, sizeof lost, "%s", a->document_loses);
			} else {
				items(a, b, 1, kept, sizeof kept);
				items(a, b, 0, lost, sizeof lost);
				if (!b->no_normal) {
					const int none = !strcmp(lost, "nothing");
					char rest[sizeof lost];
					snprintf(rest, sizeof rest, "%s", none ? "" : lost);
					snprintf(lost, sizeof lost, "the vertex normals (%s holds none)", b->title);
					append(lost, sizeof lost, "%s%s", none ? "" : ", ", rest);
				}
			}
			fprintf(out, "| %s → %s | %s | %s |\n", a->family, b->family, kept, lost);
		}
	}
}
