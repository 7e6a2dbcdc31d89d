/* vnbench: times the normal computation alone (no file I/O).
 *
 *   vnbench MESH [--method M|all] [--threads N] [--repeat K] [--csv]
 *
 * Positions are handed to the library as packed float32, as the peer
 * benchmark in shared/bench/peers does, so rows compare like for like. Each
 * method runs once to warm up, then K timed times; the median is reported. */
#include "common.h"

static const char* prog = "vnbench";

static void usage(FILE* out)
{
	fprintf(out,
	        "usage: vnbench MESH [options]\n"
	        "Times vertex-normal computation on MESH (any format vnconvert reads), excluding I/O.\n"
	        "\n"
	        "options:\n"
	        "  -m, --method M|all     scheme to time (default all)\n"
	        "  -j, --threads N        worker threads (default 1)\n"
	        "  -r, --repeat K         timed repetitions after one warm-up (default 9)\n"
	        "      --float64          pass positions as float64 instead of float32\n"
	        "      --alloc            let every call allocate its work memory (default: one\n"
	        "                         workspace reused by all calls, as an application would)\n"
	        "      --csv              print CSV: method,threads,triangles,median_ns_per_tri,mtri_per_s\n"
	        "      --list-methods     list the schemes\n"
	        "  -h, --help             this text\n"
	        "      --version          print the version\n"
	        "\n"
	        "Polygon meshes are timed through the polygon entry point; 'triangles' then counts\n"
	        "the triangles of a fan triangulation, so ns per triangle stays comparable.\n");
}

#define die(status, fmt, arg) tool_die(prog, status, fmt, arg)

static int cmp_double(const void* a, const void* b)
{
	const double x = *(const double*)a, y = *(const double*)b;
	return (x > y) - (x < y);
}

int main(int argc, char** argv)
{
	tool_check_version(prog);
	const char* path = NULL;
	int all = 1, csv = 0, f64 = 0, alloc = 0;
	vn_method method = vn_method_mwe;
	unsigned long threads = 1, repeat = 9;

	for (int i = 1; i < argc; ++i) {
		const char* s = argv[i];
		const int has_value = i + 1 < argc;
		if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
			usage(stdout);
			return 0;
		} else if (!strcmp(s, "--version")) {
			printf("vnbench %s (libvn %s)\n", VN_VERSION_STRING, vn_version_string());
			return 0;
		} else if (!strcmp(s, "--list-methods")) {
			tool_list_methods(stdout);
			return 0;
		} else if ((!strcmp(s, "-m") || !strcmp(s, "--method")) && has_value) {
			const char* v = argv[++i];
			all = !strcmp(v, "all");
			if (!all && vn_method_from_name(v, &method) != vn_result_success)
				die(2, "unknown method '%s' (see --list-methods)", v);
		} else if ((!strcmp(s, "-j") || !strcmp(s, "--threads")) && has_value) {
			if (!tool_parse_uint(argv[++i], 1, 256, &threads))
				die(2, "--threads needs a whole number from 1 to 256, not '%s'", argv[i]);
		} else if ((!strcmp(s, "-r") || !strcmp(s, "--repeat")) && has_value) {
			if (!tool_parse_uint(argv[++i], 1, 100000, &repeat))
				die(2, "--repeat needs a whole number from 1 to 100000, not '%s'", argv[i]);
		} else if (!strcmp(s, "--csv")) {
			csv = 1;
		} else if (!strcmp(s, "--float64")) {
			f64 = 1;
		} else if (!strcmp(s, "--alloc")) {
			alloc = 1;
		} else if (s[0] == '-' && s[1]) {
			die(2, "unknown option or missing value: '%s' (see --help)", s);
		} else if (!path) {
			path = s;
		} else {
			die(2, "unexpected argument '%s': give one mesh", s);
		}
	}
	if (!path)
		die(2, "%s", "usage: vnbench MESH [--method M|all] [--threads N] [--repeat K] [--csv]");

	vn_io_mesh mesh;
	vn_io_error err;
	memset(&mesh, 0, sizeof(mesh));
	if (vn_io_read_file(path, NULL, &mesh, &err) != vn_io_success)
		die(1, "%s", err.message);
	if (!mesh.face_count)
		die(1, "%s: the mesh has no faces to time", path);

	const size_t nv = mesh.vertex_count, nf = mesh.face_count;
	const int tri = vn_io_mesh_is_triangles(&mesh);
	size_t triangles = 0;
	for (size_t f = 0; f < nf; ++f) {
		const uint32_t k = mesh.face_offsets[f + 1] - mesh.face_offsets[f];
		triangles += k >= 3 ? k - 2 : 0;
	}
	if (!triangles)
		die(1, "%s: every face has fewer than 3 corners", path);
	float* pos32 = f64 ? NULL : (float*)malloc(3 * sizeof(float) * nv);
	float* normals = (float*)malloc(3 * sizeof(float) * (nv ? nv : 1));
	double* times = (double*)malloc(sizeof(double) * repeat);
	if ((!f64 && !pos32) || !normals || !times)
		die(1, "%s", "out of memory");
	if (!f64)
		for (size_t i = 0; i < 3 * nv; ++i)
			pos32[i] = (float)mesh.positions[i];

	const vn_positions pos = {f64 ? (const void*)mesh.positions : (const void*)pos32, nv, 0,
	                          f64 ? vn_scalar_float64 : vn_scalar_float32};
	const vn_vectors out = {normals, 0, vn_scalar_float32};
	vn_options opt;
	memset(&opt, 0, sizeof(opt));
	opt.threads = (unsigned)threads;
	if (!alloc) {
		opt.workspace_size = vn_workspace_size(nv, &opt);
		if (!(opt.workspace = malloc(opt.workspace_size)))
			die(1, "%s", "out of memory");
	}

	if (csv)
		printf("method,threads,triangles,median_ns_per_tri,mtri_per_s\n");
	else
		printf("%s: %zu vertices, %zu %s, %lu thread(s), median of %lu after 1 warm-up\n", path, nv, nf,
		       tri ? "triangles" : "polygons", threads, repeat);

	for (unsigned m = 0; m < vn_method_count; ++m) {
		if (!all && m != (unsigned)method)
			continue;
		for (unsigned long k = 0; k <= repeat; ++k) {
			const double t0 = tool_now();
			const vn_result r = tri ? vn_triangle_normals(&out, &pos, mesh.indices, 3 * nf, (vn_method)m, &opt, NULL)
			                        : vn_polygon_normals(&out, &pos, mesh.indices, mesh.face_offsets, nf,
			                                             (vn_method)m, &opt, NULL);
			const double t = tool_now() - t0;
			if (r != vn_result_success)
				die(1, "%s", vn_result_string(r));
			if (k)
				times[k - 1] = t; /* k == 0 is the warm-up */
		}
		qsort(times, repeat, sizeof(double), cmp_double);
		const double med = repeat & 1 ? times[repeat / 2] : 0.5 * (times[repeat / 2 - 1] + times[repeat / 2]);
		const double ns = 1e9 * med / (double)triangles;
		if (csv)
			printf("%s,%lu,%zu,%.3f,%.2f\n", vn_method_name((vn_method)m), threads, triangles, ns, 1e3 / ns);
		else
			printf("%-7s %8.2f ns/triangle %9.2f Mtriangles/s\n", vn_method_name((vn_method)m), ns, 1e3 / ns);
		fflush(stdout);
	}
	free(opt.workspace);
	free(times);
	free(normals);
	free(pos32);
	vn_io_mesh_free(&mesh);
	return 0;
}
