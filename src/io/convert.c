/*
 * vn_io_convert (vn_convert.h): a conversion's checks, its three paths
 * (glTF and Draco documents, and the vn_io_mesh for every other pair), its
 * warnings and its --stats text.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, sysconf */

#include "vn_convert.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "draco.h"
#include "gltf.h"
#include "mtl.h"
#include "ply.h"

/* ------------------------------------------------------------------ options */

static int is(const char* name, const char* a, const char* b)
{
	return !strcmp(name, a) || (b && !strcmp(name, b));
}

int vn_io_convert_option_arity(const char* name)
{
	static const char* const switches[] = {"--no-weld", "--in-place", "--apply-transforms"};
	static const char* const valued[] = {"-m", "--method", "-f", "--format", "--input-format", "-j", "--threads",
	                                     "--weld-epsilon", "--weld-scope", "--tangents", "--crease-angle", "--draco",
	                                     "--meshopt", "--draco-qp", "--draco-qn", "--draco-qt", "--draco-qc",
	                                     "--draco-cl"};
	for (size_t i = 0; i < sizeof switches / sizeof *switches; ++i)
		if (!strcmp(name, switches[i]))
			return 0;
	for (size_t i = 0; i < sizeof valued / sizeof *valued; ++i)
		if (!strcmp(name, valued[i]))
			return 1;
	return -1;
}

/* value, when it is one of the '\0'-separated `choices`, as static text. */
static const char* choice(const char* value, const char* choices)
{
	for (const char* c = choices; *c; c += strlen(c) + 1)
		if (!strcmp(value, c))
			return c;
	return NULL;
}

static vn_io_result set_format(const char* flag, const char* value, const char** field, vn_io_error* error)
{
	const vn_io_format* f = vn_io_format_by_name(value);
	if (!f) {
		char names[128];
		vn_io_format_list(vn_io_list_names, names, sizeof names);
		return vn_io_fail(error, vn_io_error_option, "%s is one of %s, not '%s'", flag, names, value);
	}
	*field = f->name;
	return vn_io_success;
}

vn_io_result vn_io_convert_option(vn_convert_options* o, const char* name, const char* value, vn_io_error* error)
{
	const int arity = vn_io_convert_option_arity(name);
	if (arity < 0)
		return vn_io_fail(error, vn_io_error_option, "unknown option '%s' (see --help)", name);
	if (arity && !value)
		return vn_io_fail(error, vn_io_error_option, "option %s needs a value", name);
	const char* v = value;
	if (is(name, "-m", "--method")) {
		vn_method m;
		if (vn_method_from_name(v, &m) != vn_result_success) {
			char names[128] = "";
			for (unsigned k = 0; k < vn_method_count; ++k) {
				const size_t used = strlen(names);
				snprintf(names + used, sizeof names - used, "%s%s", k ? ", " : "", vn_method_name((vn_method)k));
			}
			return vn_io_fail(error, vn_io_error_option, "%s is one of %s, not '%s' (see --list-methods)", name, names,
			                  v);
		}
		o->method = vn_method_name(m);
	} else if (is(name, "-f", "--format")) {
		return set_format(name, v, &o->output_format, error);
	} else if (is(name, "--input-format", NULL)) {
		return set_format(name, v, &o->input_format, error);
	} else if (is(name, "-j", "--threads")) {
		unsigned long n;
		if (!vn_io_parse_uint(v, 1, 256, &n))
			return vn_io_fail(error, vn_io_error_option, "%s needs a whole number from 1 to 256, not '%s'", name, v);
		o->threads = (unsigned)n;
	} else if (is(name, "--no-weld", NULL)) {
		o->no_weld = 1;
	} else if (is(name, "--in-place", NULL)) {
		o->in_place = 1;
	} else if (is(name, "--apply-transforms", NULL)) {
		o->apply_transforms = 1;
	} else if (is(name, "--weld-epsilon", NULL)) {
		char* end;
		const double e = strtod(v, &end);
		if (!*v || *end || !(e >= 0) || e > 1e300)
			return vn_io_fail(error, vn_io_error_option, "--weld-epsilon needs a finite number >= 0, not '%s'", v);
		o->weld_epsilon = e;
	} else if (is(name, "--crease-angle", NULL)) {
		char* end;
		const double degrees = strtod(v, &end);
		if (!*v || *end || !(degrees >= 0 && degrees <= 180))
			return vn_io_fail(error, vn_io_error_option,
			                  "--crease-angle needs a number of degrees from 0 to 180, not '%s'", v);
		o->crease = 1;
		o->crease_angle = degrees;
	} else if (is(name, "--weld-scope", NULL)) {
		if (!(o->weld_scope = choice(v, "primitive\0mesh\0")))
			return vn_io_fail(error, vn_io_error_option, "--weld-scope is primitive or mesh, not '%s'", v);
	} else if (is(name, "--tangents", NULL)) {
		if (!(o->tangents = choice(v, "keep\0drop\0")))
			return vn_io_fail(error, vn_io_error_option, "--tangents is keep or drop, not '%s'", v);
	} else if (is(name, "--draco", NULL)) {
		if (!(o->draco = choice(v, "keep\0off\0on\0")))
			return vn_io_fail(error, vn_io_error_option, "--draco is keep, off or on, not '%s'", v);
	} else if (is(name, "--meshopt", NULL)) {
		if (!(o->meshopt = choice(v, "keep\0off\0")))
			return vn_io_fail(error, vn_io_error_option, "--meshopt is keep or off, not '%s'", v);
	} else { /* --draco-qp, -qn, -qt, -qc, -cl */
		const int level = !strcmp(name, "--draco-cl"), normal = !strcmp(name, "--draco-qn");
		unsigned long n;
		/* Draco's octahedral normal coding needs 2 bits at least. */
		const unsigned long lowest = level ? 0 : normal ? 2 : 1, highest = level ? 10 : VN_DRC_MAX_BITS;
		if (!vn_io_parse_uint(v, lowest, highest, &n))
			return vn_io_fail(error, vn_io_error_option, "%s needs a whole number%s from %lu to %lu, not '%s'", name,
			                  level ? "" : " of bits", lowest, highest, v);
		int* field[] = {&o->draco_qp, &o->draco_qn, &o->draco_qt, &o->draco_qc, &o->draco_cl};
		*field[strchr("pntcl", name[9]) - "pntcl"] = (int)n;
		o->draco_cl_set |= level;
	}
	return vn_io_success;
}

/* Checks the fields of o as vn_io_convert_option would have set them, with
 * its messages: a caller may fill them directly. */
static vn_io_result check_options(const vn_convert_options* o, vn_io_error* error)
{
	vn_convert_options scratch;
	memset(&scratch, 0, sizeof scratch);
	char n[64];
	const struct {
		const char* flag;
		const char* value;
	} strings[] = {{"--input-format", o->input_format}, {"--format", o->output_format}, {"--method", o->method},
	               {"--weld-scope", o->weld_scope},     {"--tangents", o->tangents},     {"--draco", o->draco},
	               {"--meshopt", o->meshopt}};
	for (size_t i = 0; i < sizeof strings / sizeof *strings; ++i)
		if (strings[i].value && vn_io_convert_option(&scratch, strings[i].flag, strings[i].value, error) != vn_io_success)
			return vn_io_error_option;
	const struct {
		const char* flag;
		int given;
		double value;
	} numbers[] = {{"--threads", o->threads != 0, o->threads},
	               {"--weld-epsilon", o->weld_epsilon != 0, o->weld_epsilon},
	               {"--crease-angle", o->crease, o->crease_angle},
	               {"--draco-qp", o->draco_qp != 0, o->draco_qp},
	               {"--draco-qn", o->draco_qn != 0, o->draco_qn},
	               {"--draco-qt", o->draco_qt != 0, o->draco_qt},
	               {"--draco-qc", o->draco_qc != 0, o->draco_qc},
	               {"--draco-cl", o->draco_cl_set, o->draco_cl}};
	for (size_t i = 0; i < sizeof numbers / sizeof *numbers; ++i) {
		snprintf(n, sizeof n, "%.17g", numbers[i].value);
		if (numbers[i].given && vn_io_convert_option(&scratch, numbers[i].flag, n, error) != vn_io_success)
			return vn_io_error_option;
	}
	return vn_io_success;
}

/* --draco on for this output: glTF from any format is compressed. */
static int draco_on(const vn_convert_options* o, const vn_io_format* out)
{
	return o->draco && !strcmp(o->draco, "on") && out->path == vn_io_path_gltf;
}

/* --apply-transforms applies: a glTF scene written as a format without one. */
static int transforms_apply(const vn_io_format* in, const vn_io_format* out)
{
	return in->path == vn_io_path_gltf && vn_io_conversion_path(in, out) == vn_io_path_mesh;
}

int vn_io_convert_misfit(const vn_convert_options* o, const vn_io_format* in, const vn_io_format* out, char* text,
                         size_t size)
{
	char where[256];
	const vn_io_path path = vn_io_conversion_path(in, out);
	/* The first option given of a group, in the order of the fields. */
	const char* draco_given = o->draco_qp ? "--draco-qp" : o->draco_qn ? "--draco-qn" : o->draco_qt ? "--draco-qt"
	                          : o->draco_qc ? "--draco-qc" : o->draco_cl_set ? "--draco-cl" : NULL;
	const char* gltf_only = o->weld_scope ? "--weld-scope" : o->tangents ? "--tangents" : o->meshopt ? "--meshopt"
	                                                                                     : NULL;
	if (draco_given && !(out->draco & vn_io_draco_output) &&
	    !(path != vn_io_path_mesh && (in->draco & vn_io_draco_document)) && !draco_on(o, out)) {
		vn_io_format_list(vn_io_list_draco, where, sizeof where);
		snprintf(text, size, "%s applies to %s", draco_given, where);
		return 1;
	}
	if (o->draco && out->path != vn_io_path_gltf) {
		snprintf(text, size, "--draco applies to glTF output (.gltf or .glb)");
		return 1;
	}
	if (gltf_only && path != vn_io_path_gltf) {
		vn_io_path_description(vn_io_path_gltf, where, sizeof where);
		snprintf(text, size, "%s applies only to %s", gltf_only, where);
		return 1;
	}
	if (o->apply_transforms && !transforms_apply(in, out)) {
		snprintf(text, size, "%s applies to glTF input written as a format without a scene graph",
		         "--apply-transforms");
		return 1;
	}
	return 0;
}

vn_io_result vn_io_convert_check(const vn_convert_options* o, const vn_io_format* in, const vn_io_format* out,
                                 vn_io_error* error)
{
	char misfit[512];
	if (vn_io_convert_misfit(o, in, out, misfit, sizeof misfit))
		return vn_io_fail(error, vn_io_error_option, "%s, and this one is %s to %s: leave it out", misfit, in->name,
		                  out->name);
	return vn_io_success;
}

/* ------------------------------------------------------------------ the report's text */

/* Lines appended to a growing string; a failed allocation is remembered. */
typedef struct text {
	char* s;
	size_t length, capacity;
	int failed;
} text;

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void add(text* t, const char* fmt, ...)
{
	va_list args;
	va_start(args, fmt);
	const int n = vsnprintf(NULL, 0, fmt, args);
	va_end(args);
	if (n < 0 || t->failed)
		return;
	if (t->length + (size_t)n + 1 > t->capacity) {
		const size_t capacity = 2 * (t->length + (size_t)n + 1);
		char* s = (char*)realloc(t->s, capacity);
		if (!s) {
			t->failed = 1;
			return;
		}
		t->s = s;
		t->capacity = capacity;
	}
	va_start(args, fmt);
	vsnprintf(t->s + t->length, t->capacity - t->length, fmt, args);
	va_end(args);
	t->length += (size_t)n;
}

/* Why a vertex gets no normal, as each conversion's warning says it. */
#define NO_NORMAL_CAUSES "(isolated, only degenerate faces, or faces whose normals cancel)"

/* "1 primitive", "2 primitives": the noun for a count. */
static const char* noun(size_t count, const char* one, const char* many)
{
	return count == 1 ? one : many;
}

static double now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One conversion under way: the checked options, and what it tells. */
typedef struct conversion {
	const char *in, *out;
	const vn_io_format *in_format, *out_format;
	const vn_convert_options* o;
	vn_method method;
	unsigned threads;
	int apply_transforms;
	vn_drc_options draco; /* the bits given, -1 where not */
	vn_convert_report* r;
	text warnings, stats;
} conversion;

static void progress(const conversion* c, const char* what, const char* path)
{
	if (c->o->progress)
		c->o->progress(c->o->progress_context, what, path);
}

/* The reader's warnings about IN ("\n"-separated lines), one line each. */
static void input_warnings(conversion* c, const char* lines)
{
	while (lines && *lines) {
		const size_t n = strcspn(lines, "\n");
		add(&c->warnings, "%s: %.*s\n", c->in, (int)n, lines);
		lines += n + (lines[n] == '\n');
	}
}

static void stats_head(conversion* c)
{
	add(&c->stats, "input:              %s (%s)\n", c->in, c->in_format->name);
	add(&c->stats, "output:             %s (%s)\n", c->out, c->out_format->name);
	add(&c->stats, "method:             %s\n", vn_method_name(c->method));
}

static void report_normal_error(conversion* c, const vn_drc_normal_error* q, int bits)
{
	add(&c->stats, "draco normal quantization error: median %.4f deg, max %.4f deg (qn=%d, %zu %s)\n",
	    q->median_degrees, q->max_degrees, bits, q->compared, noun(q->compared, "normal", "normals"));
	c->r->draco_normals_compared = q->compared;
	c->r->draco_normal_bits = bits;
	c->r->draco_normal_median_degrees = q->median_degrees;
	c->r->draco_normal_max_degrees = q->max_degrees;
}

/* ------------------------------------------------------------------ the three paths */

/* glTF to glTF: the document path, which keeps everything but the normals. */
static vn_io_result convert_gltf(conversion* c, vn_io_error* error)
{
	const vn_convert_options* o = c->o;
	vn_gltf_options g;
	memset(&g, 0, sizeof g);
	g.method = c->method;
	g.threads = c->threads;
	g.no_weld = o->no_weld;
	g.weld_epsilon = o->weld_epsilon;
	g.weld_mesh = o->weld_scope && !strcmp(o->weld_scope, "mesh");
	g.drop_tangents = o->tangents && !strcmp(o->tangents, "drop");
	g.crease = o->crease;
	g.crease_angle = o->crease_angle * 3.14159265358979323846 / 180;
	g.draco = !o->draco || !strcmp(o->draco, "keep") ? vn_gltf_draco_keep
	          : !strcmp(o->draco, "off")             ? vn_gltf_draco_off
	                                                 : vn_gltf_draco_on;
	g.meshopt = o->meshopt && !strcmp(o->meshopt, "off") ? vn_gltf_meshopt_off : vn_gltf_meshopt_keep;
	g.draco_options = c->draco;
	g.draco_normal_error = o->stats;
	g.image_names_from_output = o->image_names_from_output;
	vn_gltf_stats st;
	progress(c, "converting", c->in);
	const double t0 = now();
	const vn_io_result res =
	    vn_gltf_convert(c->in, c->out, c->out_format == vn_io_format_by_name("glb"), &g, &st, error);
	if (res != vn_io_success)
		return res;
	const double t1 = now();
	vn_convert_report* r = c->r;
	r->vertices = st.vertices;
	r->faces = r->triangles = st.triangles;
	r->welded_vertices = st.welded_vertices;
	r->hard_edges = st.hard_edges;
	r->split_vertices = st.split_vertices;
	r->zero_normals = st.zero_normals;
	input_warnings(c, st.warnings);
	if (st.zero_normals)
		add(&c->warnings,
		    "%zu of %zu %s %s no normal " NO_NORMAL_CAUSES "; "
		    "the input's normal kept where it is a unit vector, else written as (0, 0, 1)\n",
		    st.zero_normals, st.vertices, noun(st.vertices, "vertex", "vertices"),
		    noun(st.zero_normals, "has", "have"));
	if (st.tangent_primitives && !g.drop_tangents)
		add(&c->warnings,
		    "%zu %s TANGENT data, which no longer matches the new normals (--tangents drop removes it)\n",
		    st.tangent_primitives, noun(st.tangent_primitives, "primitive has", "primitives have"));
	if (st.tangents_needed)
		add(&c->warnings,
		    "%zu %s TANGENT despite --tangents drop: %s material needs a tangent space (an anisotropy texture or "
		    "a clearcoat normal map) and has no normal map to generate one from, so the file would be invalid "
		    "without it (MESH_PRIMITIVE_NO_TANGENT_SPACE); it no longer matches the new normals\n",
		    st.tangents_needed, noun(st.tangents_needed, "primitive keeps", "primitives keep"),
		    st.tangents_needed == 1 ? "its" : "their");
	if (st.draco_uncompressed)
		add(&c->warnings,
		    "%zu %s left uncompressed: %s morph targets keep every vertex, and Draco cannot store more than 3 "
		    "vertices per triangle\n",
		    st.draco_uncompressed, noun(st.draco_uncompressed, "primitive", "primitives"),
		    noun(st.draco_uncompressed, "its", "their"));
	/* Renumbering indices an unknown extension may hold would break it. */
	if (st.unpruned_extension[0])
		add(&c->warnings,
		    "%s uses %s, an extension vn does not know that may refer to accessors or bufferViews by their index, "
		    "so the data vn replaced stay in the file, unused, rather than being removed and the rest renumbered; "
		    "the file is otherwise complete and correct\n",
		    c->out, st.unpruned_extension);
	if (!o->stats)
		return vn_io_success;
	stats_head(c);
	add(&c->stats, "primitives:         %zu processed, %zu skipped (%zu %s, %zu %s, %zu without POSITION)\n",
	    st.primitives, st.skipped_points + st.skipped_lines + st.skipped_no_position, st.skipped_points,
	    noun(st.skipped_points, "point", "points"), st.skipped_lines, noun(st.skipped_lines, "line", "lines"),
	    st.skipped_no_position);
	add(&c->stats, "vertices:           %zu\n", st.vertices);
	add(&c->stats, "triangles:          %zu\n", st.triangles);
	add(&c->stats, "welded vertices:    %zu\n", st.welded_vertices);
	add(&c->stats, "hard edges kept:    %zu\n", st.hard_edges);
	add(&c->stats, "split vertices:     %zu\n", st.split_vertices);
	add(&c->stats, "zero normals:       %zu\n", st.zero_normals);
	if (g.drop_tangents)
		add(&c->stats, "tangent primitives: %zu (%zu dropped, %zu kept: needed)\n", st.tangent_primitives,
		    st.tangent_primitives - st.tangents_needed, st.tangents_needed);
	else
		add(&c->stats, "tangent primitives: %zu (kept)\n", st.tangent_primitives);
	add(&c->stats, "appended accessors: %zu\n", st.appended_accessors);
	add(&c->stats, "removed unused:     %zu %s, %zu %s\n", st.pruned_accessors,
	    noun(st.pruned_accessors, "accessor", "accessors"), st.pruned_views,
	    noun(st.pruned_views, "bufferView", "bufferViews"));
	add(&c->stats, "draco primitives:   %zu (%zu left uncompressed)\n", st.draco_primitives, st.draco_uncompressed);
	add(&c->stats, "meshopt views:      %zu (%zu encoded again)\n", st.meshopt_views, st.meshopt_encoded);
	for (int bits = 0; bits <= VN_DRC_MAX_BITS; ++bits)
		if (st.draco_normal_error[bits].compared)
			report_normal_error(c, &st.draco_normal_error[bits], bits);
	add(&c->stats, "threads:            %u\n", c->threads);
	add(&c->stats, "time:               %.3f ms\n", 1e3 * (t1 - t0));
	return vn_io_success;
}

/* .drc to .drc: the document path of Draco, which keeps every attribute
 * (type, unique id, grid) and the metadata, and replaces only NORMAL. */
static vn_io_result convert_drc(conversion* c, vn_io_error* error)
{
	vn_drc_convert_options o;
	memset(&o, 0, sizeof o);
	o.method = c->method;
	o.threads = c->threads;
	o.given = c->draco;
	o.normal_error = c->o->stats;
	vn_drc_convert_stats st;
	progress(c, "converting", c->in);
	const vn_io_result res = vn_drc_convert(c->in, c->out, &o, &st, error);
	if (res != vn_io_success)
		return res;
	vn_convert_report* r = c->r;
	r->vertices = st.points;
	r->faces = r->triangles = st.normals.faces;
	/* A point cloud gets no normal at any point, as through the other paths. */
	const size_t zero = st.point_cloud ? st.points : st.normals.zero_normals;
	r->zero_normals = zero;
	r->degenerate_faces = st.normals.degenerate_faces;
	r->read_seconds = st.read_seconds;
	r->normals_seconds = st.normals_seconds;
	r->write_seconds = st.write_seconds;
	if (st.point_cloud)
		add(&c->warnings, "%s has no faces (a point cloud): vn computes no normals; %s\n", c->in,
		    st.input_normals ? "the input's are kept" : "it has none, and none are written");
	else if (st.normals.zero_normals)
		add(&c->warnings,
		    "%zu of %zu %s %s no normal " NO_NORMAL_CAUSES "; %s\n",
		    st.normals.zero_normals, st.points, noun(st.points, "vertex", "vertices"),
		    noun(st.normals.zero_normals, "has", "have"),
		    st.input_normals ? "the input's normal kept" : "written as the zero vector");
	if (!c->o->stats)
		return vn_io_success;
	stats_head(c);
	add(&c->stats, "vertices:           %zu\n", st.points);
	add(&c->stats, "faces:              %zu (triangles)\n", st.normals.faces);
	add(&c->stats, "attributes:         %zu (%s)\n", st.attributes,
	    st.point_cloud ? "every one kept: a point cloud" : "NORMAL replaced, the others kept");
	add(&c->stats, "degenerate faces:   %zu\n", st.normals.degenerate_faces);
	add(&c->stats, "zero normals:       %zu%s\n", zero, zero && st.input_normals ? " (the input's kept)" : "");
	add(&c->stats, "non-finite vertices: %zu\n", st.normals.nonfinite_vertices);
	add(&c->stats, "threads:            %u\n", c->threads);
	add(&c->stats, "time read:          %.3f ms\n", 1e3 * st.read_seconds);
	add(&c->stats, "time normals:       %.3f ms\n", 1e3 * st.normals_seconds);
	add(&c->stats, "time write:         %.3f ms\n", 1e3 * st.write_seconds);
	add(&c->stats, "draco settings:     qp=%d qn=%d qt=%d qc=%d cl=%d\n", st.used.position_bits, st.used.normal_bits,
	    st.used.texcoord_bits, st.used.color_bits, st.used.compression_level);
	if (!st.point_cloud)
		report_normal_error(c, &st.normal_error, st.used.normal_bits);
	return vn_io_success;
}

/* Every other pair: read into a vn_io_mesh, compute, write. */
static vn_io_result convert_mesh(conversion* c, vn_io_mesh* mesh, vn_io_error* error)
{
	const vn_convert_options* o = c->o;
	vn_convert_report* r = c->r;
	progress(c, "reading", c->in);
	const double t0 = now();
	const int gltf_out = c->out_format->path == vn_io_path_gltf;
	/* Draco output: a .drc, or glTF with --draco on (KHR_draco_mesh_compression). */
	const int drc_out = (c->out_format->draco & vn_io_draco_output) || draco_on(o, c->out_format);
	vn_drc_options drc;
	vn_drc_default_options(&drc);
	vn_io_result res = c->apply_transforms ? vn_io_gltf_read_scene(c->in, mesh, error)
	                                       : vn_io_read_file(c->in, c->in_format, mesh, error);
	if (res != vn_io_success)
		return res;
	if (o->input_is_copy) { /* the temporary's folder: an OBJ's mtllib names are written as read */
		free(mesh->material_folder);
		mesh->material_folder = NULL;
	}
	/* glTF writes an OBJ's materials from its library. */
	if (gltf_out && (res = vn_io_mtl_read(mesh, error)) != vn_io_success)
		return res;
	input_warnings(c, mesh->warnings);
	const size_t nonfinite = vn_io_mesh_first_nonfinite(mesh);
	if (nonfinite < mesh->vertex_count) {
		const double* p = mesh->positions + 3 * nonfinite;
		return vn_io_fail(error, vn_io_error_parse,
		                  "%s: vertex %zu is at (%g, %g, %g), and no output format can hold a coordinate that is not "
		                  "a finite number: fix or remove that vertex",
		                  c->in, nonfinite, p[0], p[1], p[2]);
	}
	/* The other writers refuse a mesh without faces, each for a reason of its
	 * own (and Draco's in its own words; its encoder crashes on an empty
	 * one): one message, before any work. */
	if (vn_io_mesh_triangle_count(mesh) == 0 &&
	    !(c->out_format->holds & (mesh->vertex_count ? vn_io_holds_no_faces : vn_io_holds_nothing))) {
		if (!mesh->vertex_count)
			return vn_io_fail(error, vn_io_error_unsupported,
			                  "%s: vn read no vertices and no faces from %s, and %s has no empty file: write OFF, "
			                  "PLY, OBJ, STL or glTF to keep an empty mesh",
			                  c->out, c->in, c->out_format->title);
		return vn_io_fail(error, vn_io_error_unsupported,
		                  "%s: %s has %zu %s and no faces (a point cloud), and vn writes %s only with faces: write "
		                  "OFF, PLY, OBJ, glTF or Draco to keep a point cloud",
		                  c->out, c->in, mesh->vertex_count, noun(mesh->vertex_count, "vertex", "vertices"),
		                  c->out_format->title);
	}
	if (!mesh->vertex_count)
		add(&c->warnings, "%s has no vertices and no faces: %s is written empty\n", c->in, c->out);
	const int given[] = {c->draco.position_bits, c->draco.normal_bits, c->draco.texcoord_bits, c->draco.color_bits,
	                     c->draco.compression_level};
	int* used[] = {&drc.position_bits, &drc.normal_bits, &drc.texcoord_bits, &drc.color_bits,
	               &drc.compression_level};
	for (size_t i = 0; i < sizeof given / sizeof given[0]; ++i)
		if (given[i] >= 0)
			*used[i] = given[i];

	const double t1 = now();
	const vn_io_normals_options no = {c->method, c->threads, o->no_weld, o->weld_epsilon, o->crease,
	                                  o->crease_angle * 3.14159265358979323846 / 180};
	vn_io_normals_stats st;
	const int had_normals = mesh->normals != NULL;
	if ((res = vn_io_mesh_normals(mesh, c->in, &no, &st, error)) != vn_io_success)
		return res;
	/* A PLY's per-corner texture coordinates, per vertex for a format that
	 * has no other place for them; after the normals, which the copies share
	 * (with --no-weld too: the file gave them one vertex). */
	const int had_texcoords = mesh->texcoords != NULL;
	size_t uv_split = 0;
	if ((c->out_format->holds & (vn_io_holds_ply_extras | vn_io_holds_texcoords)) == vn_io_holds_texcoords &&
	    (res = vn_io_ply_corner_texcoords(mesh, c->in, &uv_split, error)) != vn_io_success)
		return res;
	/* A PLY's textures as glTF materials, once its texture coordinates are
	 * per vertex; from IN's folder (the working folder for standard input). */
	if (gltf_out && mesh->ply_extras) {
		const size_t said = mesh->warnings ? strlen(mesh->warnings) : 0;
		res = vn_io_ply_texture_materials(mesh, "comment TextureFile", o->input_is_copy ? NULL : c->in, error);
		if (res != vn_io_success)
			return res;
		input_warnings(c, mesh->warnings ? mesh->warnings + said + (said && mesh->warnings[said] == '\n') : NULL);
	}
	const int made_texcoords = !had_texcoords && mesh->texcoords;
	const double t2 = now();
	r->vertices = st.vertices;
	r->faces = st.faces;
	r->welded_vertices = st.welded_vertices;
	r->hard_edges = st.hard_edges;
	r->split_vertices = st.split_vertices;
	r->zero_normals = st.zero_normals;
	r->degenerate_faces = st.degenerate_faces;

	/* After the normals are computed: a format without vertex normals loses them. */
	char lost[512];
	if (vn_io_mesh_losses(mesh, c->out_format, lost, sizeof lost))
		add(&c->warnings, "%s cannot hold %s: not written\n", c->out, lost);
	/* glTF holds attributes, but no double. */
	for (size_t a = 0; a < mesh->attribute_count && gltf_out; ++a) {
		const vn_io_attribute* at = &mesh->attributes[a];
		size_t beyond;
		const size_t rounded = at->component_type == 5130 ? vn_io_attribute_rounded(mesh, at, &beyond) : 0;
		if (!rounded)
			continue;
		char far[80] = "";
		if (beyond)
			snprintf(far, sizeof far, ", %zu of them beyond float's range (now infinite, or 0)", beyond);
		add(&c->warnings, "%s: %s is double, written as float: %zu of its %zu values rounded%s\n", c->out,
		    at->source_name ? at->source_name : at->name, rounded, mesh->vertex_count * (size_t)at->components, far);
	}
	if (st.zero_normals && c->out_format->no_normal && !mesh->face_count)
		add(&c->warnings, "%s has no faces (a point cloud): vn computes no normals; %s\n", c->in,
		    had_normals ? "the input's are kept" : "it has none, and none are written");
	else if (st.zero_normals && c->out_format->no_normal)
		add(&c->warnings,
		    "%zu of %zu %s %s no normal " NO_NORMAL_CAUSES "; %s%s\n",
		    st.zero_normals, mesh->vertex_count, noun(mesh->vertex_count, "vertex", "vertices"),
		    noun(st.zero_normals, "has", "have"), had_normals ? "the input's normal kept" : "written as ",
		    had_normals ? "" : c->out_format->no_normal);
	const size_t corners = 3 * (size_t)vn_io_mesh_triangle_count(mesh);
	/* Draco 1.5.5's decoder refuses more points than 3 per triangle: the
	 * writer then keeps only the vertices faces use (every one of a point
	 * cloud, written as one). */
	if (!(c->out_format->holds & vn_io_holds_loose_vertices) && mesh->face_count && mesh->vertex_count > corners)
		add(&c->warnings,
		    "%zu vertices and %zu %s: only the vertices faces use are written, as %s cannot store more than 3 "
		    "points per triangle\n",
		    mesh->vertex_count, corners / 3, noun(corners / 3, "triangle", "triangles"), c->out_format->title);
	/* glTF's Draco primitives hold the vertices their triangles use; a
	 * point cloud has no triangles to compress. */
	if (drc_out && gltf_out) {
		if (!mesh->face_count && mesh->vertex_count)
			add(&c->warnings, "%s has no faces (a point cloud): KHR_draco_mesh_compression compresses triangles, so "
			                  "its points are written uncompressed\n", c->in);
		size_t loose = 0;
		if (mesh->face_count) {
			unsigned char* in_face = (unsigned char*)calloc(mesh->vertex_count ? mesh->vertex_count : 1, 1);
			if (!in_face)
				return vn_io_fail(error, vn_io_error_memory, "%s: out of memory", c->in);
			for (size_t f = 0; f < mesh->face_count; ++f)
				if (mesh->face_offsets[f + 1] - mesh->face_offsets[f] >= 3) /* the writer's triangles */
					for (uint32_t k = mesh->face_offsets[f]; k < mesh->face_offsets[f + 1]; ++k)
						in_face[mesh->indices[k]] = 1;
			for (size_t v = 0; v < mesh->vertex_count; ++v)
				loose += !in_face[v];
			free(in_face);
		}
		if (loose)
			add(&c->warnings, "%zu %s no face uses %s not written: a Draco-compressed primitive holds only the "
			                  "vertices its triangles use\n", loose, noun(loose, "vertex", "vertices"),
			    noun(loose, "is", "are"));
	}
	progress(c, "writing", c->out);
	if ((res = vn_io_write_file(c->out, c->out_format, mesh, drc_out ? &drc : NULL, error)) != vn_io_success)
		return res;
	const double t3 = now();
	r->triangles = corners / 3;
	r->read_seconds = t1 - t0;
	r->normals_seconds = t2 - t1;
	r->write_seconds = t3 - t2;
	if (!o->stats)
		return vn_io_success;
	stats_head(c);
	add(&c->stats, "vertices:           %zu\n", st.vertices);
	add(&c->stats, "faces:              %zu (%s)\n", st.faces, vn_io_mesh_is_triangles(mesh) ? "triangles" : "polygons");
	add(&c->stats, "degenerate faces:   %zu\n", st.degenerate_faces);
	add(&c->stats, "welded vertices:    %zu\n", st.welded_vertices);
	add(&c->stats, "hard edges kept:    %zu\n", st.hard_edges);
	add(&c->stats, "split vertices:     %zu\n", st.split_vertices);
	if (made_texcoords)
		add(&c->stats, "split by texcoord:  %zu (the face list 'texcoord' written per vertex)\n", uv_split);
	add(&c->stats, "zero normals:       %zu%s\n", st.zero_normals,
	    st.zero_normals && had_normals ? " (the input's kept)" : "");
	add(&c->stats, "threads:            %u\n", c->threads);
	add(&c->stats, "time read:          %.3f ms\n", 1e3 * (t1 - t0));
	add(&c->stats, "time normals:       %.3f ms\n", 1e3 * (t2 - t1));
	add(&c->stats, "time write:         %.3f ms\n", 1e3 * (t3 - t2));
	if (drc_out) {
		vn_drc_normal_error q;
		if ((res = vn_drc_normal_error_of(mesh, &drc, c->out, &q, error)) != vn_io_success)
			return res;
		add(&c->stats, "draco settings:     qp=%d qn=%d qt=%d qc=%d cl=%d\n", drc.position_bits, drc.normal_bits,
		    drc.texcoord_bits, drc.color_bits, drc.compression_level);
		report_normal_error(c, &q, drc.normal_bits);
	}
	return vn_io_success;
}

/* ------------------------------------------------------------------ the entry point */

/* The format named, else the one path's extension names. */
static vn_io_result resolve_format(const char* name, const char* path, int input, const vn_io_format** format,
                                   vn_io_error* error)
{
	if ((*format = name ? vn_io_format_by_name(name) : vn_io_format_for_path(path)))
		return vn_io_success;
	vn_io_unknown_format(path, input, error->message, sizeof error->message);
	return vn_io_error_format;
}

/* The checks before any work, then the conversion's path. */
static vn_io_result run(conversion* c, vn_io_error* error)
{
	const vn_convert_options* o = c->o;
	vn_io_result res;
	if ((res = check_options(o, error)) != vn_io_success ||
	    (res = resolve_format(o->input_format, c->in, 1, &c->in_format, error)) != vn_io_success ||
	    (res = resolve_format(o->output_format, c->out, 0, &c->out_format, error)) != vn_io_success)
		return res;
	c->r->input_format = c->in_format->name;
	c->r->output_format = c->out_format->name;
	c->r->method = vn_method_name(c->method);
	c->r->threads = c->threads;
	if (!o->ignore_misfits && (res = vn_io_convert_check(o, c->in_format, c->out_format, error)) != vn_io_success)
		return res;
	c->apply_transforms = o->apply_transforms && transforms_apply(c->in_format, c->out_format);
	if (!o->in_place && (!strcmp(c->in, c->out) || vn_io_same_file(c->in, c->out)))
		return vn_io_fail(error, vn_io_error_same_file, "output '%s' is the input; pass --in-place to overwrite it",
		                  c->out);
	/* A missing folder or an OUT that is a device is told before any work. */
	if ((res = vn_io_output_check(c->out, NULL, error)) != vn_io_success)
		return res;
	switch (vn_io_conversion_path(c->in_format, c->out_format)) {
	case vn_io_path_gltf:
		return convert_gltf(c, error);
	case vn_io_path_drc:
		return convert_drc(c, error);
	case vn_io_path_mesh:
		break;
	}
	vn_io_mesh mesh;
	memset(&mesh, 0, sizeof mesh);
	res = convert_mesh(c, &mesh, error);
	vn_io_mesh_free(&mesh);
	return res;
}

vn_io_result vn_io_convert(const char* in, const char* out, const vn_convert_options* options,
                           vn_convert_report* report, vn_io_error* error)
{
	static const vn_convert_options defaults;
	vn_convert_report scratch;
	vn_io_error scratch_error;
	conversion c;
	memset(&c, 0, sizeof c);
	c.in = in;
	c.out = out;
	c.o = options ? options : &defaults;
	c.r = report ? report : &scratch;
	error = error ? error : &scratch_error;
	memset(c.r, 0, sizeof *c.r);
	error->message[0] = '\0';
	if (!in || !out)
		return vn_io_fail(error, vn_io_error_open, "vn_io_convert needs an input and an output path");
	const double start = now();
	if (vn_method_from_name(c.o->method ? c.o->method : "mwa", &c.method) != vn_result_success)
		c.method = vn_method_mwa; /* check_options refuses it */
	const long cores = sysconf(_SC_NPROCESSORS_ONLN);
	c.threads = c.o->threads ? c.o->threads : cores > 0 ? (unsigned)cores : 1;
	c.draco = (vn_drc_options){c.o->draco_qp ? c.o->draco_qp : -1, c.o->draco_qn ? c.o->draco_qn : -1,
	                           c.o->draco_qt ? c.o->draco_qt : -1, c.o->draco_qc ? c.o->draco_qc : -1,
	                           c.o->draco_cl_set ? c.o->draco_cl : -1};
	vn_io_result res = run(&c, error);
	c.r->warnings = c.warnings.s;
	c.r->stats = c.stats.s;
	c.r->seconds = now() - start;
	if (res == vn_io_success && (c.warnings.failed || c.stats.failed))
		res = vn_io_fail(error, vn_io_error_memory, "%s: out of memory for the conversion's report", in);
	if (c.r == &scratch)
		vn_io_convert_report_free(&scratch);
	return res;
}

void vn_io_convert_report_free(vn_convert_report* report)
{
	if (!report)
		return;
	free(report->warnings);
	free(report->stats);
	memset(report, 0, sizeof *report);
}
