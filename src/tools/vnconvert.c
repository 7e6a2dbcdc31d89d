/* vnconvert: recompute a mesh's vertex normals and write it out.
 *
 *   vnconvert IN OUT [--method M] ...
 *
 * Exit status: 0 on success, 1 when the work failed (unreadable or
 * malformed input, unwritable output), 2 on a usage error. Every failure
 * prints exactly one line on stderr and leaves OUT as it was. */
#include "common.h"

#include <stdarg.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "draco.h"
#include "gltf.h"

static const char* prog = "vnconvert";

static void usage(FILE* out)
{
	fprintf(out,
	        "usage: vnconvert IN OUT [options]\n"
	        "Recomputes the vertex normals of the mesh IN and writes the mesh with them to OUT.\n"
	        "\n"
	        "options:\n"
	        "  -m, --method M         weighting scheme (default mwa, the paper's overall choice);\n"
	        "                         one of mwe mwa mwselr mwaat mwelr mwrelr mewcsa\n"
	        "      --list-methods     list the schemes with a description and reference\n"
	        "      --list-conversions what each pair of formats keeps (a Markdown table)\n"
	        "  -f, --format F         output format, overriding OUT's extension\n"
	        "      --input-format F   input format, overriding IN's extension\n"
	        "  -j, --threads N        worker threads (default: all %u cores; results do not depend on it)\n"
	        "      --in-place         allow OUT to be IN (otherwise refused)\n"
	        "      --stats            print counts, degenerate input and timings\n"
	        "  -q, --quiet            no warnings or progress\n"
	        "  -h, --help             this text\n"
	        "      --version          print the version\n"
	        "\n"
	        "glTF to glTF only (.gltf/.glb in and out):\n"
	        "      --no-weld          compute on the vertices as the file splits them (seams show)\n"
	        "      --weld-epsilon E   weld vertices whose coordinates all differ by at most E\n"
	        "                         (default 0: exactly equal positions only)\n"
	        "      --weld-scope S     primitive (default) or mesh: weld across a mesh's primitives\n"
	        "      --tangents T       keep (default: left as they are, with a warning) or drop\n"
	        "                         (TANGENT removed from primitives and morph targets, and\n"
	        "                         its data with them)\n"
	        "      --crease-angle DEG hard edges where faces meet at more than DEG degrees (0 to 180):\n"
	        "                         per-corner normals, vertices split where they differ\n"
	        "      --draco D          KHR_draco_mesh_compression: keep (default: compressed primitives\n"
	        "                         are re-encoded with their own attributes and bits), off\n"
	        "                         (written uncompressed) or on (every triangle primitive\n"
	        "                         compressed, with the bits below)\n"
	        "      --meshopt M        EXT/KHR_meshopt_compression: keep (default: what was compressed\n"
	        "                         stays so; views with new normals are encoded again) or off\n"
	        "                         (every bufferView written plain, the extensions removed)\n"
	        "\n"
	        "Draco output (.drc, and glTF primitives; a primitive that was compressed keeps its\n"
	        "own bits but those given); default: a .drc input's bits, else the value in brackets:\n"
	        "      --draco-qp BITS    position quantization, 1 to 30 bits [14]\n"
	        "      --draco-qn BITS    normals, 2 to 30 [10] (--stats reports the angle this costs)\n"
	        "      --draco-qt BITS    texture coordinates, 1 to 30 [12]\n"
	        "      --draco-qc BITS    float colours, 1 to 30 [8] (byte colours stay lossless)\n"
	        "      --draco-cl LEVEL   compression level, 0 to 10 [7] (draco_encoder's -cl)\n"
	        "  .drc to .drc keeps every attribute (type, unique id) and the metadata and replaces\n"
	        "  only NORMAL. An attribute kept at its own bits is quantized on the input's own grid,\n"
	        "  so it decodes to the input's values exactly (no generation loss); new bits (these\n"
	        "  flags) mean a new grid, and values move by up to half a step of the new bits.\n"
	        "\n"
	        "formats:\n",
	        tool_cpu_count());
	for (size_t i = 0; vn_io_format_at(i); ++i) {
		const vn_io_format* f = vn_io_format_at(i);
		fprintf(out, "  %-8s %-12s %s\n", f->name, f->extensions, f->description);
	}
	fprintf(out,
	        "\n"
	        "OUT is written atomically: a temporary file beside it takes OUT's place once complete.\n"
	        "On Linux it has no name until then, so nothing is left if vnconvert is killed (even by\n"
	        "SIGKILL; only between the two final calls that put it in place of an existing OUT could\n"
	        "a complete .OUT.XXXXXX remain); elsewhere it is .OUT.XXXXXX, which an interrupt or a\n"
	        "crash removes. A symbolic link is written through to its target; a replaced file keeps\n"
	        "its mode, owner and group.\n"
	        "OUT must be a regular file (not a device, FIFO or folder). Positions must be finite.\n"
	        "A vertex that no face contributes to (isolated, or only degenerate faces) keeps the\n"
	        "input's normal; when the input has none it gets the zero normal in OFF and Draco and\n"
	        "(0, 0, 1) in glTF (whose normals must be unit vectors), and a warning either way.\n"
	        "\n"
	        "glTF to glTF keeps the whole document and recomputes only the NORMAL of each\n"
	        "TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitive, in mesh-local space; a vertex\n"
	        "no face contributes to keeps its unit input normal, else gets (0, 0, 1). glTF to OFF\n"
	        "merges every triangle primitive into one mesh, in mesh-local coordinates (node\n"
	        "transforms are not applied). OFF to glTF writes one mesh with POSITION, NORMAL and\n"
	        "indices (polygons fan-triangulated).\n");
}

/* One line on stderr, "vnconvert: error: ...", then exit(status). */
#if defined(__GNUC__)
__attribute__((format(printf, 2, 3), noreturn))
#endif
static void die(int status, const char* fmt, ...)
{
	va_list args;
	va_start(args, fmt);
	fprintf(stderr, "%s: error: ", prog);
	vfprintf(stderr, fmt, args);
	fputc('\n', stderr);
	va_end(args);
	exit(status);
}

/* "1 primitive", "2 primitives": the noun for a count. */
static const char* noun(size_t count, const char* one, const char* many)
{
	return count == 1 ? one : many;
}

typedef struct args {
	const char* in;
	const char* out;
	const vn_io_format* in_format;
	const vn_io_format* out_format;
	vn_method method;
	unsigned threads;
	int in_place, stats, quiet;
	vn_gltf_options gltf;
	/* Draco flags as given, -1 when not: a .drc input's own bits or the
	 * defaults fill the rest once the input is read. */
	vn_drc_options drc;
} args;

static const char* need_value(int argc, char** argv, int* i)
{
	if (*i + 1 >= argc)
		die(2, "option %s needs a value", argv[*i]);
	return argv[++*i];
}

static const vn_io_format* need_format(const char* flag, const char* name)
{
	const vn_io_format* f = vn_io_format_by_name(name);
	if (!f) {
		char names[128];
		vn_io_format_list(vn_io_list_names, names, sizeof names);
		die(2, "%s is one of %s, not '%s'", flag, names, name);
	}
	return f;
}

/* IN or OUT whose extension names no format vn knows. */
static void unknown_extension(const char* path, int input)
{
	char text[512];
	vn_io_unknown_format(path, input, text, sizeof text);
	die(2, "%s", text);
}

static args parse(int argc, char** argv)
{
	args a;
	memset(&a, 0, sizeof(a));
	a.method = vn_method_mwa;
	a.threads = tool_cpu_count();
	a.drc = (vn_drc_options){-1, -1, -1, -1, -1};
	/* The first option given that applies only to some conversions. */
	const char *drc_given = NULL, *gltf_only = NULL;
	for (int i = 1; i < argc; ++i) {
		const char* s = argv[i];
		if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
			usage(stdout);
			exit(0);
		} else if (!strcmp(s, "--version")) {
			printf("vnconvert %s (libvn %s)\n", VN_VERSION_STRING, vn_version_string());
			exit(0);
		} else if (!strcmp(s, "--list-methods")) {
			tool_list_methods(stdout);
			exit(0);
		} else if (!strcmp(s, "--list-conversions")) {
			vn_io_conversions_table(stdout);
			exit(0);
		} else if (!strcmp(s, "-m") || !strcmp(s, "--method")) {
			const char* v = need_value(argc, argv, &i);
			if (vn_method_from_name(v, &a.method) != vn_result_success) {
				char names[128] = "";
				for (unsigned m = 0; m < vn_method_count; ++m) {
					const size_t used = strlen(names);
					snprintf(names + used, sizeof names - used, "%s%s", m ? ", " : "", vn_method_name((vn_method)m));
				}
				die(2, "%s is one of %s, not '%s' (see --list-methods)", s, names, v);
			}
		} else if (!strcmp(s, "-f") || !strcmp(s, "--format")) {
			a.out_format = need_format(s, need_value(argc, argv, &i));
		} else if (!strcmp(s, "--input-format")) {
			a.in_format = need_format(s, need_value(argc, argv, &i));
		} else if (!strcmp(s, "-j") || !strcmp(s, "--threads")) {
			const char* v = need_value(argc, argv, &i);
			unsigned long n;
			if (!tool_parse_uint(v, 1, 256, &n))
				die(2, "%s needs a whole number from 1 to 256, not '%s'", s, v);
			a.threads = (unsigned)n;
		} else if (!strcmp(s, "--no-weld")) {
			a.gltf.no_weld = 1;
			gltf_only = gltf_only ? gltf_only : s;
		} else if (!strcmp(s, "--weld-epsilon")) {
			const char* v = need_value(argc, argv, &i);
			char* end;
			a.gltf.weld_epsilon = strtod(v, &end);
			if (!*v || *end || !(a.gltf.weld_epsilon >= 0) || a.gltf.weld_epsilon > 1e300)
				die(2, "--weld-epsilon needs a finite number >= 0, not '%s'", v);
			gltf_only = gltf_only ? gltf_only : s;
		} else if (!strcmp(s, "--weld-scope")) {
			const char* v = need_value(argc, argv, &i);
			if (strcmp(v, "primitive") && strcmp(v, "mesh"))
				die(2, "--weld-scope is primitive or mesh, not '%s'", v);
			a.gltf.weld_mesh = !strcmp(v, "mesh");
			gltf_only = gltf_only ? gltf_only : s;
		} else if (!strcmp(s, "--tangents")) {
			const char* v = need_value(argc, argv, &i);
			if (strcmp(v, "keep") && strcmp(v, "drop"))
				die(2, "--tangents is keep or drop, not '%s'", v);
			a.gltf.drop_tangents = !strcmp(v, "drop");
			gltf_only = gltf_only ? gltf_only : s;
		} else if (!strcmp(s, "--crease-angle")) {
			const char* v = need_value(argc, argv, &i);
			char* end;
			const double degrees = strtod(v, &end);
			if (!*v || *end || !(degrees >= 0 && degrees <= 180))
				die(2, "--crease-angle needs a number of degrees from 0 to 180, not '%s'", v);
			a.gltf.crease = 1;
			a.gltf.crease_angle = degrees * 3.14159265358979323846 / 180;
			gltf_only = gltf_only ? gltf_only : s;
		} else if (!strcmp(s, "--draco")) {
			const char* v = need_value(argc, argv, &i);
			if (strcmp(v, "keep") && strcmp(v, "off") && strcmp(v, "on"))
				die(2, "--draco is keep, off or on, not '%s'", v);
			a.gltf.draco = !strcmp(v, "off") ? vn_gltf_draco_off : !strcmp(v, "on") ? vn_gltf_draco_on : vn_gltf_draco_keep;
			gltf_only = gltf_only ? gltf_only : s;
		} else if (!strcmp(s, "--meshopt")) {
			const char* v = need_value(argc, argv, &i);
			if (strcmp(v, "keep") && strcmp(v, "off"))
				die(2, "--meshopt is keep or off, not '%s'", v);
			a.gltf.meshopt = !strcmp(v, "off") ? vn_gltf_meshopt_off : vn_gltf_meshopt_keep;
			gltf_only = gltf_only ? gltf_only : s;
		} else if (!strcmp(s, "--draco-qp") || !strcmp(s, "--draco-qn") || !strcmp(s, "--draco-qt") ||
		           !strcmp(s, "--draco-qc") || !strcmp(s, "--draco-cl")) {
			const int level = !strcmp(s, "--draco-cl"), normal = !strcmp(s, "--draco-qn");
			const char* v = need_value(argc, argv, &i);
			unsigned long n;
			/* Draco's octahedral normal coding needs 2 bits at least. */
			const unsigned long lowest = level ? 0 : normal ? 2 : 1, highest = level ? 10 : VN_DRC_MAX_BITS;
			if (!tool_parse_uint(v, lowest, highest, &n))
				die(2, "%s needs a whole number%s from %lu to %lu, not '%s'", s, level ? "" : " of bits", lowest,
				    highest, v);
			int* field[] = {&a.drc.position_bits, &a.drc.normal_bits, &a.drc.texcoord_bits, &a.drc.color_bits,
			                &a.drc.compression_level};
			*field[strchr("pntcl", s[9]) - "pntcl"] = (int)n;
			drc_given = drc_given ? drc_given : s;
		} else if (!strcmp(s, "--in-place")) {
			a.in_place = 1;
		} else if (!strcmp(s, "--stats")) {
			a.stats = 1;
		} else if (!strcmp(s, "-q") || !strcmp(s, "--quiet")) {
			a.quiet = 1;
		} else if (s[0] == '-' && s[1]) {
			die(2, "unknown option '%s' (see --help)", s);
		} else if (!a.in) {
			a.in = s;
		} else if (!a.out) {
			a.out = s;
		} else {
			die(2, "unexpected argument '%s': give one input and one output", s);
		}
	}
	if (!a.in || !a.out)
		die(2, "%s", "usage: vnconvert IN OUT [--method M] (see --help)");
	if (!a.in_format && !(a.in_format = vn_io_format_for_path(a.in)))
		unknown_extension(a.in, 1);
	if (!a.out_format && !(a.out_format = vn_io_format_for_path(a.out)))
		unknown_extension(a.out, 0);
	const vn_io_path path = vn_io_conversion_path(a.in_format, a.out_format);
	if (drc_given && !(a.out_format->draco & vn_io_draco_output) &&
	    !(path != vn_io_path_mesh && (a.in_format->draco & vn_io_draco_document))) {
		char where[256];
		vn_io_format_list(vn_io_list_draco, where, sizeof where);
		die(2, "%s applies to %s, and this one is %s to %s: leave it out", drc_given, where, a.in_format->name,
		    a.out_format->name);
	}
	if (gltf_only && path != vn_io_path_gltf) {
		char where[256];
		vn_io_path_description(vn_io_path_gltf, where, sizeof where);
		die(2, "%s applies only to %s, and this one is %s to %s: leave it out", gltf_only, where,
		    a.in_format->name, a.out_format->name);
	}
	return a;
}

/* The reader's warnings about IN ("\n"-separated lines), one line each. */
static void input_warnings(const args* a, const char* text)
{
	while (text && *text && !a->quiet) {
		const size_t n = strcspn(text, "\n");
		fprintf(stderr, "%s: warning: %s: %.*s\n", prog, a->in, (int)n, text);
		text += n + (text[n] == '\n');
	}
}

static void progress(const args* a, const char* what, const char* path)
{
	if (!a->quiet && isatty(STDERR_FILENO))
		fprintf(stderr, "%s: %s %s\n", prog, what, path);
}

/* glTF to glTF: the document path, which keeps everything but the normals. */
static int convert_gltf(args* a)
{
	a->gltf.method = a->method;
	a->gltf.threads = a->threads;
	a->gltf.draco_options = a->drc;
	a->gltf.draco_normal_error = a->stats;
	vn_gltf_stats st;
	vn_io_error err;
	progress(a, "converting", a->in);
	const double t0 = tool_now();
	if (vn_gltf_convert(a->in, a->out, a->out_format == vn_io_format_by_name("glb"), &a->gltf, &st, &err) !=
	    vn_io_success)
		die(1, "%s", err.message);
	const double t1 = tool_now();
	input_warnings(a, st.warnings);
	if (st.zero_normals && !a->quiet)
		fprintf(stderr,
		        "%s: warning: %zu of %zu %s %s no normal (isolated, or only degenerate faces); "
		        "the input's normal kept where it is a unit vector, else written as (0, 0, 1)\n",
		        prog, st.zero_normals, st.vertices, noun(st.vertices, "vertex", "vertices"),
		        noun(st.zero_normals, "has", "have"));
	if (st.tangent_primitives && !a->quiet && !a->gltf.drop_tangents)
		fprintf(stderr,
		        "%s: warning: %zu %s TANGENT data, which no longer matches the new normals "
		        "(--tangents drop removes it)\n",
		        prog, st.tangent_primitives, noun(st.tangent_primitives, "primitive has", "primitives have"));
	if (st.draco_uncompressed && !a->quiet)
		fprintf(stderr,
		        "%s: warning: %zu %s left uncompressed: %s morph targets keep every vertex, and Draco "
		        "cannot store more than 3 vertices per triangle\n",
		        prog, st.draco_uncompressed, noun(st.draco_uncompressed, "primitive", "primitives"),
		        noun(st.draco_uncompressed, "its", "their"));
	/* Renumbering indices an unknown extension may hold would break it. */
	if (st.unpruned_extension[0] && !a->quiet)
		fprintf(stderr,
		        "%s: warning: %s uses %s, an extension vn does not know that may refer to accessors or "
		        "bufferViews by their index, so the data vn replaced stay in the file, unused, rather than being "
		        "removed and the rest renumbered; the file is otherwise complete and correct\n",
		        prog, a->out, st.unpruned_extension);
	if (a->stats) {
		printf("input:              %s (%s)\n", a->in, a->in_format->name);
		printf("output:             %s (%s)\n", a->out, a->out_format->name);
		printf("method:             %s\n", vn_method_name(a->method));
		printf("primitives:         %zu processed, %zu skipped (%zu %s, %zu %s, %zu without POSITION)\n",
		       st.primitives, st.skipped_points + st.skipped_lines + st.skipped_no_position, st.skipped_points,
		       noun(st.skipped_points, "point", "points"), st.skipped_lines, noun(st.skipped_lines, "line", "lines"),
		       st.skipped_no_position);
		printf("vertices:           %zu\n", st.vertices);
		printf("triangles:          %zu\n", st.triangles);
		printf("welded vertices:    %zu\n", st.welded_vertices);
		printf("hard edges kept:    %zu\n", st.hard_edges);
		printf("split vertices:     %zu\n", st.split_vertices);
		printf("zero normals:       %zu\n", st.zero_normals);
		printf("tangent primitives: %zu (%s)\n", st.tangent_primitives, a->gltf.drop_tangents ? "dropped" : "kept");
		printf("appended accessors: %zu\n", st.appended_accessors);
		printf("removed unused:     %zu %s, %zu %s\n", st.pruned_accessors,
		       noun(st.pruned_accessors, "accessor", "accessors"), st.pruned_views,
		       noun(st.pruned_views, "bufferView", "bufferViews"));
		printf("draco primitives:   %zu (%zu left uncompressed)\n", st.draco_primitives, st.draco_uncompressed);
		printf("meshopt views:      %zu (%zu encoded again)\n", st.meshopt_views, st.meshopt_encoded);
		for (int bits = 0; bits <= VN_DRC_MAX_BITS; ++bits)
			if (st.draco_normal_error[bits].compared)
				printf("draco normal quantization error: median %.4f deg, max %.4f deg (qn=%d, %zu %s)\n",
				       st.draco_normal_error[bits].median_degrees, st.draco_normal_error[bits].max_degrees, bits,
				       st.draco_normal_error[bits].compared, noun(st.draco_normal_error[bits].compared, "normal", "normals"));
		printf("threads:            %u\n", a->threads);
		printf("time:               %.3f ms\n", 1e3 * (t1 - t0));
	}
	return 0;
}

/* .drc to .drc: the document path of Draco, which keeps every attribute
 * (type, unique id, grid) and the metadata, and replaces only NORMAL. */
static int convert_drc(const args* a)
{
	vn_drc_convert_options o;
	memset(&o, 0, sizeof o);
	o.method = a->method;
	o.threads = a->threads;
	o.given = a->drc;
	o.normal_error = a->stats;
	vn_drc_convert_stats st;
	vn_io_error err;
	progress(a, "converting", a->in);
	if (vn_drc_convert(a->in, a->out, &o, &st, &err) != vn_io_success)
		die(1, "%s", err.message);
	if (st.normals.zero_normals && !a->quiet)
		fprintf(stderr,
		        "%s: warning: %zu of %zu %s %s no normal (isolated, or only degenerate faces); %s\n",
		        prog, st.normals.zero_normals, st.points, noun(st.points, "vertex", "vertices"),
		        noun(st.normals.zero_normals, "has", "have"),
		        st.input_normals ? "the input's normal kept" : "written as the zero vector");
	if (a->stats) {
		printf("input:              %s (%s)\n", a->in, a->in_format->name);
		printf("output:             %s (%s)\n", a->out, a->out_format->name);
		printf("method:             %s\n", vn_method_name(a->method));
		printf("vertices:           %zu\n", st.points);
		printf("faces:              %zu (triangles)\n", st.normals.faces);
		printf("attributes:         %zu (NORMAL replaced, the others kept)\n", st.attributes);
		printf("degenerate faces:   %zu\n", st.normals.degenerate_faces);
		printf("zero normals:       %zu\n", st.normals.zero_normals);
		printf("non-finite vertices: %zu\n", st.normals.nonfinite_vertices);
		printf("threads:            %u\n", a->threads);
		printf("time read:          %.3f ms\n", 1e3 * st.read_seconds);
		printf("time normals:       %.3f ms\n", 1e3 * st.normals_seconds);
		printf("time write:         %.3f ms\n", 1e3 * st.write_seconds);
		printf("draco settings:     qp=%d qn=%d qt=%d qc=%d cl=%d\n", st.used.position_bits, st.used.normal_bits,
		       st.used.texcoord_bits, st.used.color_bits, st.used.compression_level);
		printf("draco normal quantization error: median %.4f deg, max %.4f deg (qn=%d, %zu %s)\n",
		       st.normal_error.median_degrees, st.normal_error.max_degrees, st.used.normal_bits,
		       st.normal_error.compared, noun(st.normal_error.compared, "normal", "normals"));
	}
	return 0;
}

int main(int argc, char** argv)
{
	tool_check_version(prog);
#ifdef __GLIBC__
	/* glibc raises its trim and mmap thresholds as large blocks are freed,
	 * after which freed memory stays resident: a fixed trim threshold (which
	 * keeps both) took a sixth to a quarter off the peak memory of large
	 * Draco conversions (docs/PERFORMANCE.md). */
	mallopt(M_TRIM_THRESHOLD, 1 << 20);
#endif
	/* A crash (in a library too) or an interrupt leaves no temporary file. */
	vn_io_remove_temporaries_on_signal();
	args a = parse(argc, argv);

	if (!a.in_place && (!strcmp(a.in, a.out) || vn_io_same_file(a.in, a.out)))
		die(2, "output '%s' is the input; pass --in-place to overwrite it", a.out);
	vn_io_error err;
	/* A missing folder or an OUT that is a device is told before any work. */
	if (vn_io_output_check(a.out, NULL, &err) != vn_io_success)
		die(1, "%s", err.message);
	switch (vn_io_conversion_path(a.in_format, a.out_format)) {
	case vn_io_path_gltf:
		return convert_gltf(&a);
	case vn_io_path_drc:
		return convert_drc(&a);
	case vn_io_path_mesh:
		break;
	}

	vn_io_mesh mesh;
	memset(&mesh, 0, sizeof(mesh));

	progress(&a, "reading", a.in);
	const double t0 = tool_now();
	const int drc_out = (a.out_format->draco & vn_io_draco_output) != 0;
	vn_drc_options drc;
	vn_drc_default_options(&drc);
	if (vn_io_read_file(a.in, a.in_format, &mesh, &err) != vn_io_success)
		die(1, "%s", err.message);
	input_warnings(&a, mesh.warnings);
	const size_t nonfinite = vn_io_mesh_first_nonfinite(&mesh);
	if (nonfinite < mesh.vertex_count) {
		const double* p = mesh.positions + 3 * nonfinite;
		fprintf(stderr,
		        "%s: error: %s: vertex %zu is at (%g, %g, %g), and no output format can hold a coordinate that is "
		        "not a finite number: fix or remove that vertex\n",
		        prog, a.in, nonfinite, p[0], p[1], p[2]);
		vn_io_mesh_free(&mesh);
		return 1;
	}
	int* given[] = {&a.drc.position_bits, &a.drc.normal_bits, &a.drc.texcoord_bits, &a.drc.color_bits,
	                &a.drc.compression_level};
	int* used[] = {&drc.position_bits, &drc.normal_bits, &drc.texcoord_bits, &drc.color_bits,
	               &drc.compression_level};
	for (size_t i = 0; i < sizeof given / sizeof given[0]; ++i)
		if (*given[i] >= 0)
			*used[i] = *given[i];

	const double t1 = tool_now();
	vn_stats st;
	const int had_normals = mesh.normals != NULL;
	const vn_result r = tool_compute(&mesh, a.method, a.threads, &st);
	if (r != vn_result_success) {
		fprintf(stderr, "%s: error: %s: %s\n", prog, a.in, vn_result_string(r));
		vn_io_mesh_free(&mesh);
		return 1;
	}
	const double t2 = tool_now();

	/* After the normals are computed: a format without vertex normals loses them. */
	char lost[512];
	if (vn_io_mesh_losses(&mesh, a.out_format, lost, sizeof lost) && !a.quiet)
		fprintf(stderr, "%s: warning: %s cannot hold %s: not written\n", prog, a.out, lost);
	if (st.zero_normals && a.out_format->no_normal && !a.quiet)
		fprintf(stderr,
		        "%s: warning: %zu of %zu %s %s no normal (isolated, or only degenerate faces); "
		        "%s%s\n",
		        prog, st.zero_normals, mesh.vertex_count, noun(mesh.vertex_count, "vertex", "vertices"),
		        noun(st.zero_normals, "has", "have"), had_normals ? "the input's normal kept" : "written as ",
		        had_normals ? "" : a.out_format->no_normal);

	if (!(a.out_format->holds & vn_io_holds_loose_vertices) && !a.quiet) {
		/* Draco 1.5.5's decoder refuses more points than 3 per triangle: the writer
		 * then keeps only the vertices faces use. */
		size_t corners = 0;
		for (size_t f = 0; f < mesh.face_count; f++) {
			const size_t k = mesh.face_offsets[f + 1] - mesh.face_offsets[f];
			corners += k >= 3 ? 3 * (k - 2) : 0;
		}
		if (mesh.vertex_count > corners)
			fprintf(stderr,
			        "%s: warning: %zu vertices and %zu %s: only the vertices faces use are written, as %s "
			        "cannot store more than 3 points per triangle\n",
			        prog, mesh.vertex_count, corners / 3, noun(corners / 3, "triangle", "triangles"),
			        a.out_format->title);
	}
	progress(&a, "writing", a.out);
	if (vn_io_write_file(a.out, a.out_format, &mesh, drc_out ? &drc : NULL, &err) !=
	    vn_io_success) {
		fprintf(stderr, "%s: error: %s\n", prog, err.message);
		vn_io_mesh_free(&mesh);
		return 1;
	}
	const double t3 = tool_now();

	if (a.stats) {
		printf("input:              %s (%s)\n", a.in, a.in_format->name);
		printf("output:             %s (%s)\n", a.out, a.out_format->name);
		printf("method:             %s\n", vn_method_name(a.method));
		printf("vertices:           %zu\n", mesh.vertex_count);
		printf("faces:              %zu (%s)\n", st.faces,
		       vn_io_mesh_is_triangles(&mesh) ? "triangles" : "polygons");
		printf("degenerate faces:   %zu\n", st.degenerate_faces);
		printf("zero normals:       %zu\n", st.zero_normals);
		printf("non-finite vertices: %zu\n", st.nonfinite_vertices);
		printf("threads:            %u\n", a.threads);
		printf("time read:          %.3f ms\n", 1e3 * (t1 - t0));
		printf("time normals:       %.3f ms\n", 1e3 * (t2 - t1));
		printf("time write:         %.3f ms\n", 1e3 * (t3 - t2));
		vn_drc_normal_error q;
		if (drc_out && vn_drc_normal_error_of(&mesh, &drc, a.out, &q, &err) != vn_io_success) {
			fprintf(stderr, "%s: error: %s\n", prog, err.message);
			vn_io_mesh_free(&mesh);
			return 1;
		}
		if (drc_out) {
			printf("draco settings:     qp=%d qn=%d qt=%d qc=%d cl=%d\n", drc.position_bits, drc.normal_bits,
			       drc.texcoord_bits, drc.color_bits, drc.compression_level);
			printf("draco normal quantization error: median %.4f deg, max %.4f deg (qn=%d, %zu %s)\n",
			       q.median_degrees, q.max_degrees, drc.normal_bits, q.compared, noun(q.compared, "normal", "normals"));
		}
	}
	vn_io_mesh_free(&mesh);
	return 0;
}
