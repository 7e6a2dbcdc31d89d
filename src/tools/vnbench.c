/* vnbench: times the normal computation alone (no file I/O).
 *
 *   vnbench MESH [--method M|all] [--threads N] [--repeat K] [--csv]
 *   vnbench MESH --corners [--sharp-every K] [--crease DEG] [...]
 *   vnbench MESH --plan [--float32] [...]
 *   vnbench MESH --shuffle SEED [...]
 *
 * Positions are handed to the library as packed float32, as the peer
 * benchmark in shared/bench/peers does, so rows compare like for like. Each
 * method runs once to warm up, then K timed times; the median is reported.
 * --corners times vn_polygon_corner_normals and, in the same run on the same
 * mesh, vn_polygon_normals, per face, and prints their ratio. --plan times
 * vn_plan_create once and vn_plan_normals per frame, and in the same run the
 * entry point without a plan, and prints after how many frames the plan has
 * paid for itself. --shuffle times a randomly ordered copy of the mesh
 * (faces and vertices permuted), as files without locality come. */
#include "common.h"

#include <math.h>

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
	        "      --float64          pass positions as float64 (the default with --plan)\n"
	        "      --float32          pass positions as float32 (the default without --plan)\n"
	        "      --alloc            let every call allocate its work memory (default: one\n"
	        "                         workspace reused by all calls, as an application would)\n"
	        "      --csv              print CSV: method,threads,triangles,median_ns_per_tri,mtri_per_s\n"
	        "                         (--corners: method,threads,faces,polygon_ns_per_face,\n"
	        "                         corner_ns_per_face,ratio)\n"
	        "      --corners          time per-corner normals (vn_polygon_corner_normals) next to\n"
	        "                         vertex normals (vn_polygon_normals), both per face, and on\n"
	        "                         triangle meshes vn_corner_normals too\n"
	        "      --sharp-every K    with --corners: flag every K-th corner's edge sharp (default 0: none)\n"
	        "      --crease DEG       with --corners: crease angle in degrees (default 180: none)\n"
	        "      --plan             time a per-frame plan: vn_plan_create once, vn_plan_normals\n"
	        "                         per frame, next to the call without a plan (CSV: method,\n"
	        "                         threads,triangles,positions,create_ms,plan_ns_per_tri,\n"
	        "                         today_ns_per_tri,speedup,frames_to_pay_off)\n"
	        "      --shuffle SEED     permute the faces and the vertices at random first (the same\n"
	        "                         order for the same SEED): a mesh without locality\n"
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

/* The next number of a splitmix64 sequence. */
static uint64_t splitmix(uint64_t* state)
{
	uint64_t z = (*state += 0x9e3779b97f4a7c15u);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
	return z ^ (z >> 31);
}

/* A random permutation of 0 .. n - 1 (Fisher-Yates), or NULL. */
static uint32_t* permutation(size_t n, uint64_t* state)
{
	uint32_t* p = (uint32_t*)malloc(sizeof(uint32_t) * (n ? n : 1));
	for (size_t i = 0; p && i < n; ++i)
		p[i] = (uint32_t)i;
	for (size_t i = n; p && i > 1; --i) {
		const size_t j = (size_t)(splitmix(state) % i);
		const uint32_t t = p[i - 1];
		p[i - 1] = p[j], p[j] = t;
	}
	return p;
}

/* --shuffle: the mesh's faces and vertices in a random order drawn from
 * seed; each face keeps its corners' cyclic order. Only positions and faces
 * are kept (vnbench reads nothing else). */
static void shuffle_mesh(vn_io_mesh* mesh, unsigned long seed)
{
	const size_t nv = mesh->vertex_count, nf = mesh->face_count, ni = mesh->face_offsets[nf];
	uint64_t state = seed;
	uint32_t* vperm = permutation(nv, &state); /* old vertex -> new */
	uint32_t* fperm = permutation(nf, &state); /* new face -> old */
	double* pos = (double*)malloc(sizeof(double) * 3 * (nv ? nv : 1));
	uint32_t* idx = (uint32_t*)malloc(sizeof(uint32_t) * (ni ? ni : 1));
	uint32_t* off = (uint32_t*)malloc(sizeof(uint32_t) * (nf + 1));
	if (!vperm || !fperm || !pos || !idx || !off)
		die(1, "%s", "out of memory");
	for (size_t v = 0; v < nv; ++v)
		memcpy(pos + 3 * (size_t)vperm[v], mesh->positions + 3 * v, 3 * sizeof(double));
	off[0] = 0;
	for (size_t g = 0; g < nf; ++g) {
		const uint32_t a = mesh->face_offsets[fperm[g]], b = mesh->face_offsets[fperm[g] + 1];
		for (uint32_t c = a; c < b; ++c)
			idx[off[g] + c - a] = vperm[mesh->indices[c]];
		off[g + 1] = off[g] + (b - a);
	}
	free(mesh->positions), free(mesh->indices), free(mesh->face_offsets);
	mesh->positions = pos, mesh->indices = idx, mesh->face_offsets = off;
	free(fperm);
	free(vperm);
}

/* What one timed call computes. */
typedef struct bench {
	const vn_io_mesh* mesh;
	const vn_positions* pos;
	const vn_options* opt;
	const vn_vectors* out;         /* per vertex */
	const vn_vectors* corner_out;  /* per corner */
	const uint8_t* sharp;
	double crease;
	int tri;
	vn_plan* plan;
} bench;

enum { run_vertex, run_polygon, run_corner, run_triangle_corner, run_plan };

static vn_result run_once(const bench* b, int kind, vn_method m)
{
	const vn_io_mesh* mesh = b->mesh;
	const size_t nf = mesh->face_count;
	switch (kind) {
	case run_vertex:
		if (b->tri)
			return vn_triangle_normals(b->out, b->pos, mesh->indices, 3 * nf, m, b->opt, NULL);
		/* fall through */
	case run_polygon:
		return vn_polygon_normals(b->out, b->pos, mesh->indices, mesh->face_offsets, nf, m, b->opt, NULL);
	case run_plan:
		return vn_plan_normals(b->plan, b->pos, m, b->out, NULL);
	case run_triangle_corner:
		return vn_corner_normals(b->corner_out, b->pos, mesh->indices, 3 * nf, m, b->crease, b->sharp, b->opt, NULL);
	default:
		return vn_polygon_corner_normals(b->corner_out, b->pos, mesh->indices, mesh->face_offsets, nf, m, b->crease,
		                                 b->sharp, b->opt, NULL);
	}
}

/* The median time of `repeat` calls after one warm-up, in seconds. */
static double median_time(const bench* b, int kind, vn_method m, unsigned long repeat, double* times)
{
	for (unsigned long k = 0; k <= repeat; ++k) {
		const double t0 = tool_now();
		const vn_result r = run_once(b, kind, m);
		const double t = tool_now() - t0;
		if (r != vn_result_success)
			die(1, "%s", vn_result_string(r));
		if (k)
			times[k - 1] = t; /* k == 0 is the warm-up */
	}
	qsort(times, repeat, sizeof(double), cmp_double);
	return repeat & 1 ? times[repeat / 2] : 0.5 * (times[repeat / 2 - 1] + times[repeat / 2]);
}

int main(int argc, char** argv)
{
	tool_check_version(prog);
	const char* path = NULL;
	int all = 1, csv = 0, f64 = -1, alloc = 0, corners = 0, plan = 0;
	unsigned long sharp_every = 0, shuffle_seed = 0;
	int shuffle = 0;
	double crease_deg = 180.0;
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
			if (!vn_io_parse_uint(argv[++i], 1, 256, &threads))
				die(2, "--threads needs a whole number from 1 to 256, not '%s'", argv[i]);
		} else if ((!strcmp(s, "-r") || !strcmp(s, "--repeat")) && has_value) {
			if (!vn_io_parse_uint(argv[++i], 1, 100000, &repeat))
				die(2, "--repeat needs a whole number from 1 to 100000, not '%s'", argv[i]);
		} else if (!strcmp(s, "--corners")) {
			corners = 1;
		} else if (!strcmp(s, "--sharp-every") && has_value) {
			if (!vn_io_parse_uint(argv[++i], 0, 1000000000, &sharp_every))
				die(2, "--sharp-every needs a whole number, not '%s'", argv[i]);
		} else if (!strcmp(s, "--crease") && has_value) {
			char* end;
			crease_deg = strtod(argv[++i], &end);
			if (*end || !(crease_deg >= 0.0))
				die(2, "--crease needs a number of degrees >= 0, not '%s'", argv[i]);
		} else if (!strcmp(s, "--csv")) {
			csv = 1;
		} else if (!strcmp(s, "--float64")) {
			f64 = 1;
		} else if (!strcmp(s, "--float32")) {
			f64 = 0;
		} else if (!strcmp(s, "--plan")) {
			plan = 1;
		} else if (!strcmp(s, "--shuffle") && has_value) {
			if (!vn_io_parse_uint(argv[++i], 0, 4294967295ul, &shuffle_seed))
				die(2, "--shuffle needs a whole number seed, not '%s'", argv[i]);
			shuffle = 1;
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
	if (plan && corners)
		die(2, "%s", "--plan and --corners time different things: give one");
	if (f64 < 0)
		f64 = plan;

	vn_io_mesh mesh;
	vn_io_error err;
	memset(&mesh, 0, sizeof(mesh));
	if (vn_io_read_file(path, NULL, &mesh, &err) != vn_io_success)
		die(1, "%s", err.message);
	if (!mesh.face_count)
		die(1, "%s: the mesh has no faces to time", path);
	if (shuffle)
		shuffle_mesh(&mesh, shuffle_seed);

	const size_t nv = mesh.vertex_count, nf = mesh.face_count;
	const int tri = vn_io_mesh_is_triangles(&mesh);
	const size_t triangles = (size_t)vn_io_mesh_triangle_count(&mesh);
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
		/* vn.h's bound for the corner normals' work memory */
		const size_t corner_bytes = 36 * mesh.face_offsets[nf] + 24 * nf + 4 * nv + 64 * threads + 64;
		if (corners && corner_bytes > opt.workspace_size)
			opt.workspace_size = corner_bytes;
		if (!(opt.workspace = malloc(opt.workspace_size)))
			die(1, "%s", "out of memory");
	}

	const size_t ni = mesh.face_offsets[nf];
	float* corner_normals = NULL;
	uint8_t* sharp = NULL;
	if (corners) {
		corner_normals = (float*)malloc(3 * sizeof(float) * (ni ? ni : 1));
		sharp = sharp_every ? (uint8_t*)calloc(ni ? ni : 1, 1) : NULL;
		if (!corner_normals || (sharp_every && !sharp))
			die(1, "%s", "out of memory");
		for (size_t c = 0; sharp && c < ni; c += sharp_every)
			sharp[c] = 1;
	}
	const vn_vectors corner_out = {corner_normals, 0, vn_scalar_float32};
	bench b = {&mesh, &pos, &opt, &out, &corner_out, sharp, crease_deg * (3.141592653589793 / 180.0), tri, NULL};
	double create_ms = 0.0;
	if (plan) {
		/* The plan takes the options' threads and simd; it holds its own work memory. */
		vn_options popt = opt;
		popt.workspace = NULL, popt.workspace_size = 0;
		const double t0 = tool_now();
		const vn_result r = vn_plan_create(mesh.indices, tri ? NULL : mesh.face_offsets, nf, nv, &popt, &b.plan);
		create_ms = 1e3 * (tool_now() - t0);
		if (r != vn_result_success)
			die(1, "vn_plan_create: %s", vn_result_string(r));
	}

	if (corners) {
		if (csv)
			printf("method,threads,faces,polygon_ns_per_face,corner_ns_per_face,ratio,triangle_corner_ns_per_face\n");
		else
			printf("%s: %zu vertices, %zu faces, %zu corners, %lu thread(s), median of %lu after 1 warm-up;\n"
			       "corner normals with every %lu-th edge flagged (0: none), crease %g degrees\n",
			       path, nv, nf, ni, threads, repeat, sharp_every, crease_deg);
	} else if (plan) {
		if (csv)
			printf("method,threads,triangles,positions,create_ms,plan_ns_per_tri,today_ns_per_tri,speedup,"
			       "frames_to_pay_off\n");
		else
			printf("%s: %zu vertices, %zu %s, %lu thread(s), float%d positions, median of %lu after 1 warm-up;\n"
			       "vn_plan_create %.2f ms\n",
			       path, nv, nf, tri ? "triangles" : "polygons", threads, f64 ? 64 : 32, repeat, create_ms);
	} else if (csv)
		printf("method,threads,triangles,median_ns_per_tri,mtri_per_s\n");
	else
		printf("%s: %zu vertices, %zu %s, %lu thread(s), median of %lu after 1 warm-up\n", path, nv, nf,
		       tri ? "triangles" : "polygons", threads, repeat);

	for (unsigned m = 0; m < vn_method_count; ++m) {
		if (!all && m != (unsigned)method)
			continue;
		if (corners) {
			const double tp = 1e9 * median_time(&b, run_polygon, (vn_method)m, repeat, times) / (double)nf;
			const double tc = 1e9 * median_time(&b, run_corner, (vn_method)m, repeat, times) / (double)nf;
			/* Triangle meshes: vn_corner_normals too (the triangle kernels' arithmetic). */
			const double tt = tri ? 1e9 * median_time(&b, run_triangle_corner, (vn_method)m, repeat, times) / (double)nf
			                      : 0.0;
			if (csv) {
				printf("%s,%lu,%zu,%.3f,%.3f,%.3f,", vn_method_name((vn_method)m), threads, nf, tp, tc, tc / tp);
				if (tri)
					printf("%.3f", tt);
				printf("\n");
			} else {
				printf("%-7s polygon %8.2f ns/face  corner %8.2f ns/face  ratio %5.2f", vn_method_name((vn_method)m),
				       tp, tc, tc / tp);
				if (tri)
					printf("  (vn_corner_normals %8.2f ns/face)", tt);
				printf("\n");
			}
			fflush(stdout);
			continue;
		}
		if (plan) {
			const double tp = median_time(&b, run_plan, (vn_method)m, repeat, times);
			const double tt = median_time(&b, run_vertex, (vn_method)m, repeat, times);
			const double pns = 1e9 * tp / (double)triangles, tns = 1e9 * tt / (double)triangles;
			/* frames after which create + k plan frames cost less than k frames without */
			const double pay = tt > tp ? ceil(1e-3 * create_ms / (tt - tp)) : INFINITY;
			if (csv)
				printf("%s,%lu,%zu,float%d,%.3f,%.3f,%.3f,%.3f,%.0f\n", vn_method_name((vn_method)m), threads, triangles,
				       f64 ? 64 : 32, create_ms, pns, tns, tns / pns, pay);
			else
				printf("%-7s plan %8.2f ns/triangle  without %8.2f ns/triangle  x%5.2f  pays off after %.0f frames\n",
				       vn_method_name((vn_method)m), pns, tns, tns / pns, pay);
			fflush(stdout);
			continue;
		}
		const double med = median_time(&b, run_vertex, (vn_method)m, repeat, times);
		const double ns = 1e9 * med / (double)triangles;
		if (csv)
			printf("%s,%lu,%zu,%.3f,%.2f\n", vn_method_name((vn_method)m), threads, triangles, ns, 1e3 / ns);
		else
			printf("%-7s %8.2f ns/triangle %9.2f Mtriangles/s\n", vn_method_name((vn_method)m), ns, 1e3 / ns);
		fflush(stdout);
	}
	vn_plan_destroy(b.plan);
	free(sharp);
	free(corner_normals);
	free(opt.workspace);
	free(times);
	free(normals);
	free(pos32);
	vn_io_mesh_free(&mesh);
	return 0;
}
