/* vnconvert: recompute a mesh's vertex normals and write it out.
 *
 *   vnconvert IN OUT [--method M] ...
 *
 * Exit status: 0 on success, 1 when the work failed (unreadable or
 * malformed input, unwritable output), 2 on a usage error. Every failure
 * prints exactly one line on stderr and leaves OUT as it was. */
#include "common.h"
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
	        "\n"
	        "Draco output (.drc, and glTF primitives; a primitive that was compressed keeps its\n"
	        "own bits but those given); default: a .drc input's bits, else the value in brackets:\n"
	        "      --draco-qp BITS    position quantization, 1 to 30 bits [14]\n"
	        "      --draco-qn BITS    normals, 2 to 30 [10] (--stats reports the angle this costs)\n"
	        "      --draco-qt BITS    texture coordinates, 1 to 30 [12]\n"
	        "      --draco-qc BITS    float colours, 1 to 30 [8] (byte colours stay lossless)\n"
	        "      --draco-cl LEVEL   compression level, 0 to 10 [7] (draco_encoder's -cl)\n"
	        "\n"
	        "formats:\n",
	        tool_cpu_count());
	for (size_t i = 0; vn_io_format_at(i); ++i) {
		const vn_io_format* f = vn_io_format_at(i);
		fprintf(out, "  %-8s %-12s %s\n", f->name, f->extensions, f->description);
	}
	fprintf(out,
	        "\n"
	        "OUT is written atomically: a temporary file beside it is renamed over it once complete.\n"
	        "A vertex that no face contributes to (isolated, or only degenerate faces) gets the zero\n"
	        "normal in OFF, and a warning.\n"
	        "\n"
	        "glTF to glTF keeps the whole document and recomputes only the NORMAL of each\n"
	        "TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitive, in mesh-local space; a vertex\n"
	        "no face contributes to keeps its unit input normal, else gets (0, 0, 1). glTF to OFF\n"
	        "merges every triangle primitive into one mesh, in mesh-local coordinates (node\n"
	        "transforms are not applied). OFF to glTF writes one mesh with POSITION, NORMAL and\n"
	        "indices (polygons fan-triangulated).\n");
}

#define die(status, fmt, arg) tool_die(prog, status, fmt, arg)

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

static const vn_io_format* need_format(const char* name)
{
	const vn_io_format* f = vn_io_format_by_name(name);
	if (!f)
		die(2, "unknown format '%s' (see --help)", name);
	return f;
}

static int is_gltf(const vn_io_format* f)
{
	return f == vn_io_format_by_name("gltf") || f == vn_io_format_by_name("glb");
}

static args parse(int argc, char** argv)
{
	args a;
	memset(&a, 0, sizeof(a));
	a.method = vn_method_mwa;
	a.threads = tool_cpu_count();
	a.drc = (vn_drc_options){-1, -1, -1, -1, -1};
	int drc_given = 0, gltf_given = 0;
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
		} else if (!strcmp(s, "-m") || !strcmp(s, "--method")) {
			const char* v = need_value(argc, argv, &i);
			if (vn_method_from_name(v, &a.method) != vn_result_success)
				die(2, "unknown method '%s' (see --list-methods)", v);
		} else if (!strcmp(s, "-f") || !strcmp(s, "--format")) {
			a.out_format = need_format(need_value(argc, argv, &i));
		} else if (!strcmp(s, "--input-format")) {
			a.in_format = need_format(need_value(argc, argv, &i));
		} else if (!strcmp(s, "-j") || !strcmp(s, "--threads")) {
			const char* v = need_value(argc, argv, &i);
			unsigned long n;
			if (!tool_parse_uint(v, 1, 256, &n))
				die(2, "--threads needs a whole number from 1 to 256, not '%s'", v);
			a.threads = (unsigned)n;
		} else if (!strcmp(s, "--no-weld")) {
			a.gltf.no_weld = 1;
		} else if (!strcmp(s, "--weld-epsilon")) {
			const char* v = need_value(argc, argv, &i);
			char* end;
			a.gltf.weld_epsilon = strtod(v, &end);
			if (!*v || *end || !(a.gltf.weld_epsilon >= 0) || a.gltf.weld_epsilon > 1e300)
				die(2, "--weld-epsilon needs a finite number >= 0, not '%s'", v);
		} else if (!strcmp(s, "--weld-scope")) {
			const char* v = need_value(argc, argv, &i);
			if (strcmp(v, "primitive") && strcmp(v, "mesh"))
				die(2, "--weld-scope is primitive or mesh, not '%s'", v);
			a.gltf.weld_mesh = !strcmp(v, "mesh");
		} else if (!strcmp(s, "--tangents")) {
			const char* v = need_value(argc, argv, &i);
			if (strcmp(v, "keep") && strcmp(v, "drop"))
				die(2, "--tangents is keep or drop, not '%s'", v);
			a.gltf.drop_tangents = !strcmp(v, "drop");
		} else if (!strcmp(s, "--crease-angle")) {
			const char* v = need_value(argc, argv, &i);
			char* end;
			const double degrees = strtod(v, &end);
			if (!*v || *end || !(degrees >= 0 && degrees <= 180))
				die(2, "--crease-angle needs a number of degrees from 0 to 180, not '%s'", v);
			a.gltf.crease = 1;
			a.gltf.crease_angle = degrees * 3.14159265358979323846 / 180;
		} else if (!strcmp(s, "--draco")) {
			const char* v = need_value(argc, argv, &i);
			if (strcmp(v, "keep") && strcmp(v, "off") && strcmp(v, "on"))
				die(2, "--draco is keep, off or on, not '%s'", v);
			a.gltf.draco = !strcmp(v, "off") ? vn_gltf_draco_off : !strcmp(v, "on") ? vn_gltf_draco_on : vn_gltf_draco_keep;
			gltf_given = 1;
		} else if (!strcmp(s, "--draco-qp") || !strcmp(s, "--draco-qn") || !strcmp(s, "--draco-qt") ||
		           !strcmp(s, "--draco-qc") || !strcmp(s, "--draco-cl")) {
			const int level = !strcmp(s, "--draco-cl"), normal = !strcmp(s, "--draco-qn");
			const char* v = need_value(argc, argv, &i);
			unsigned long n;
			/* Draco's octahedral normal coding needs 2 bits at least. */
			if (!tool_parse_uint(v, level ? 0 : normal ? 2 : 1, level ? 10 : VN_DRC_MAX_BITS, &n))
				die(2, level    ? "--draco-cl needs a whole number from 0 to 10, not '%s'"
				       : normal ? "--draco-qn needs a whole number of bits from 2 to 30, not '%s'"
				                : "Draco quantization needs a whole number of bits from 1 to 30, not '%s'",
				    v);
			int* field[] = {&a.drc.position_bits, &a.drc.normal_bits, &a.drc.texcoord_bits, &a.drc.color_bits,
			                &a.drc.compression_level};
			*field[strchr("pntcl", s[9]) - "pntcl"] = (int)n;
			drc_given = 1;
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
		die(2, "cannot tell the format of '%s' from its extension; use --input-format", a.in);
	if (!a.out_format && !(a.out_format = vn_io_format_for_path(a.out)))
		die(2, "cannot tell the format of '%s' from its extension; use --format", a.out);
	if (drc_given && a.out_format != vn_io_format_by_name("drc") && !(is_gltf(a.in_format) && is_gltf(a.out_format)))
		die(2, "the --draco-* options are for .drc or glTF to glTF output, not '%s'", a.out);
	if (gltf_given && !(is_gltf(a.in_format) && is_gltf(a.out_format)))
		die(2, "--draco is for glTF to glTF, not '%s'", a.out);
	return a;
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
	if (st.zero_normals && !a->quiet)
		fprintf(stderr,
		        "%s: warning: %zu of %zu vertices have no normal (isolated, or only degenerate faces); "
		        "written as the input's unit normal, else (0, 0, 1)\n",
		        prog, st.zero_normals, st.vertices);
	if (st.tangent_primitives && !a->quiet && !a->gltf.drop_tangents)
		fprintf(stderr,
		        "%s: warning: %zu primitives have TANGENT data, which no longer matches the new normals "
		        "(--tangents drop removes it)\n",
		        prog, st.tangent_primitives);
	if (st.draco_uncompressed && !a->quiet)
		fprintf(stderr,
		        "%s: warning: %zu primitives left uncompressed: their morph targets keep every vertex, and Draco "
		        "cannot store more than 3 vertices per triangle\n",
		        prog, st.draco_uncompressed);
	if (st.unpruned_extension[0] && !a->quiet)
		fprintf(stderr,
		        "%s: warning: data vn replaced stay in the file, unused: it uses %s, which may refer "
		        "to accessors or bufferViews by index, so vn does not renumber them\n",
		        prog, st.unpruned_extension);
	if (a->stats) {
		printf("input:              %s (%s)\n", a->in, a->in_format->name);
		printf("output:             %s (%s)\n", a->out, a->out_format->name);
		printf("method:             %s\n", vn_method_name(a->method));
		printf("primitives:         %zu processed, %zu skipped (%zu points, %zu lines, %zu without POSITION)\n",
		       st.primitives, st.skipped_points + st.skipped_lines + st.skipped_no_position, st.skipped_points,
		       st.skipped_lines, st.skipped_no_position);
		printf("vertices:           %zu\n", st.vertices);
		printf("triangles:          %zu\n", st.triangles);
		printf("welded vertices:    %zu\n", st.welded_vertices);
		printf("hard edges kept:    %zu\n", st.hard_edges);
		printf("split vertices:     %zu\n", st.split_vertices);
		printf("zero normals:       %zu\n", st.zero_normals);
		printf("tangent primitives: %zu (%s)\n", st.tangent_primitives, a->gltf.drop_tangents ? "dropped" : "kept");
		printf("appended accessors: %zu\n", st.appended_accessors);
		printf("removed unused:     %zu accessors, %zu bufferViews\n", st.pruned_accessors, st.pruned_views);
		printf("draco primitives:   %zu (%zu left uncompressed)\n", st.draco_primitives, st.draco_uncompressed);
		for (int bits = 0; bits <= VN_DRC_MAX_BITS; ++bits)
			if (st.draco_normal_error[bits].compared)
				printf("draco normal quantization error: median %.4f deg, max %.4f deg (qn=%d, %zu normals)\n",
				       st.draco_normal_error[bits].median_degrees, st.draco_normal_error[bits].max_degrees, bits,
				       st.draco_normal_error[bits].compared);
		printf("threads:            %u\n", a->threads);
		printf("time:               %.3f ms\n", 1e3 * (t1 - t0));
	}
	return 0;
}

int main(int argc, char** argv)
{
	tool_check_version(prog);
	args a = parse(argc, argv);

	if (!a.in_place && (!strcmp(a.in, a.out) || vn_io_same_file(a.in, a.out)))
		die(2, "output '%s' is the input; pass --in-place to overwrite it", a.out);
	if (is_gltf(a.in_format) && is_gltf(a.out_format))
		return convert_gltf(&a);

	vn_io_error err;
	vn_io_mesh mesh;
	memset(&mesh, 0, sizeof(mesh));

	progress(&a, "reading", a.in);
	const double t0 = tool_now();
	const int drc_out = a.out_format == vn_io_format_by_name("drc");
	vn_drc_options drc;
	vn_drc_default_options(&drc);
	const vn_io_result read = a.in_format == vn_io_format_by_name("drc")
	                              ? vn_drc_read_file(a.in, &mesh, &drc, &err)
	                              : vn_io_read_file(a.in, a.in_format, &mesh, &err);
	if (read != vn_io_success)
		die(1, "%s", err.message);
	int* given[] = {&a.drc.position_bits, &a.drc.normal_bits, &a.drc.texcoord_bits, &a.drc.color_bits,
	                &a.drc.compression_level};
	int* used[] = {&drc.position_bits, &drc.normal_bits, &drc.texcoord_bits, &drc.color_bits,
	               &drc.compression_level};
	for (size_t i = 0; i < sizeof given / sizeof given[0]; ++i)
		if (*given[i] >= 0)
			*used[i] = *given[i];

	const double t1 = tool_now();
	vn_stats st;
	const vn_result r = tool_compute(&mesh, a.method, a.threads, &st);
	if (r != vn_result_success) {
		fprintf(stderr, "%s: error: %s: %s\n", prog, a.in, vn_result_string(r));
		vn_io_mesh_free(&mesh);
		return 1;
	}
	const double t2 = tool_now();

	if (st.zero_normals && !a.quiet)
		fprintf(stderr,
		        "%s: warning: %zu of %zu vertices have no normal (isolated, or only degenerate faces); "
		        "written as %s\n",
		        prog, st.zero_normals, mesh.vertex_count, is_gltf(a.out_format) ? "(0, 0, 1)" : "the zero vector");

	if (drc_out && !a.quiet) {
		/* Draco 1.5.5's decoder refuses more points than 3 per triangle: the writer
		 * then keeps only the vertices faces use. */
		size_t corners = 0;
		for (size_t f = 0; f < mesh.face_count; f++) {
			const size_t k = mesh.face_offsets[f + 1] - mesh.face_offsets[f];
			corners += k >= 3 ? 3 * (k - 2) : 0;
		}
		if (mesh.vertex_count > corners)
			fprintf(stderr,
			        "%s: warning: %zu vertices and %zu triangles: only the vertices faces use are written, as Draco "
			        "cannot store more than 3 points per triangle\n",
			        prog, mesh.vertex_count, corners / 3);
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
			printf("draco normal quantization error: median %.4f deg, max %.4f deg (qn=%d, %zu normals)\n",
			       q.median_degrees, q.max_degrees, drc.normal_bits, q.compared);
		}
	}
	vn_io_mesh_free(&mesh);
	return 0;
}
