/* vneval: the paper's accuracy and speed comparison (Jin, Lewis, West 2005,
 * section 3.2), on the test ensemble that libvnpaper (src/paper/) generates.
 *
 *   vneval [--csv FILE] [--svg-dir DIR] [--table FILE] [--model M,..] ...
 *
 * For every model x resolution x method: theta = acos(N_exact . N_scheme) in
 * degrees over the non-boundary vertices (eq. 11, dot product clamped to
 * [-1, 1]), summarized as median, 90th percentile, max, mean and RMS, and
 * drawn as cumulative histograms (the paper's Figures 1-4). Speed: time per
 * vertex per method over the high-resolution models (Figure 5).
 *
 * Everything but the timings is deterministic: two runs write identical
 * CSV, tables and accuracy charts. */
#include "common.h"
#include "svgplot.h"
#include "vn_paper.h"

#include <ctype.h>
#include <math.h>
#include <sys/stat.h>

static const char* prog = "vneval";

static void usage(FILE* out)
{
	fprintf(out,
	        "usage: vneval [options]\n"
	        "Measures every vertex-normal scheme against the exact normals of the paper's test ensemble.\n"
	        "\n"
	        "outputs (any combination; with none, a summary is printed):\n"
	        "      --csv FILE         one row per model, resolution and method:\n"
	        "                         model,resolution,method,vertices,median_deg,p90_deg,max_deg,mean_deg,rms_deg\n"
	        "      --svg-dir DIR      cumulative histograms (hist_MODEL_RES.svg; Figures 1-3), the turbulence\n"
	        "                         aliasing figure (fig4_turbulence_aliasing.svg) and the speed chart\n"
	        "                         (fig5_speed.svg, with its numbers in speed.csv)\n"
	        "      --table FILE       Markdown: Table 4 by the rule in docs/REPRODUCTION.md, medians, RMS\n"
	        "      --export-off DIR   every selected model as NOFF with its exact normals (MODEL_RES.off)\n"
	        "\n"
	        "filters (comma-separated lists, any case; default all):\n"
	        "      --model M          sphere_tp torus_tp perlin_hf fractal09_hf fractal05_hf fractal01_hf\n"
	        "                         sphere_mt cosine_mt perlin_mt turbulence_mt\n"
	        "      --resolution R     low medium high\n"
	        "      --method M         mwe mwa mwselr mwaat mwelr mwrelr mewcsa\n"
	        "\n"
	        "  -r, --repeat K         timed repetitions for the speed chart (default 15)\n"
	        "  -q, --quiet            no summary or progress\n"
	        "  -h, --help             this text\n"
	        "      --version          print the version\n");
}

#define die(status, fmt, arg) tool_die(prog, status, fmt, arg)

static void* xmalloc(size_t n)
{
	void* p = malloc(n ? n : 1);
	if (!p)
		die(1, "%s", "out of memory");
	return p;
}

/* True when s[0..len) is `name`, ignoring case (names are lower case). */
static int same_name(const char* s, size_t len, const char* name)
{
	if (strlen(name) != len)
		return 0;
	for (size_t i = 0; i < len; ++i)
		if (tolower((unsigned char)s[i]) != name[i])
			return 0;
	return 1;
}

/* Parses a comma-separated list of names (any case) into a selection mask;
 * `name` gives the name of value i, or NULL past the last. */
static unsigned parse_list(const char* arg, const char* (*name)(int), const char* what)
{
	if (!strcmp(arg, "all"))
		return ~0u;
	unsigned mask = 0;
	const char* s = arg;
	while (*s) {
		const char* e = strchr(s, ',');
		const size_t len = e ? (size_t)(e - s) : strlen(s);
		int found = 0;
		for (int i = 0; name(i); ++i)
			if (same_name(s, len, name(i))) {
				mask |= 1u << i, found = 1;
				break;
			}
		if (!found) {
			char msg[160];
			snprintf(msg, sizeof(msg), "unknown %s in '%%s' (see --help)", what);
			die(2, msg, arg);
		}
		s = e ? e + 1 : s + len;
	}
	return mask;
}

static const char* model_name_i(int i)
{
	return vn_model_name((vn_model)i);
}

static const char* resolution_name_i(int i)
{
	return vn_resolution_name((vn_resolution)i);
}

static const char* method_name_i(int i)
{
	return vn_method_name((vn_method)i);
}

/* ---------------------------------------------------------------- accuracy */

typedef struct result {
	size_t n;      /* non-boundary vertices */
	double* theta; /* sorted, degrees */
	double median, p90, max, mean, rms;
} result;

static int cmp_double(const void* a, const void* b)
{
	const double x = *(const double*)a, y = *(const double*)b;
	return (x > y) - (x < y);
}

/* Quantile by the nearest-rank rule on sorted values. */
static double quantile(const double* s, size_t n, double q)
{
	size_t k = (size_t)ceil(q * (double)n);
	return s[k ? k - 1 : 0];
}

static void evaluate(const vn_model_mesh* mesh, vn_method method, double* normals, result* r)
{
	const vn_positions pos = {mesh->positions, mesh->vertex_count, 0, vn_scalar_float64};
	const vn_vectors out = {normals, 0, vn_scalar_float64};
	const vn_result res =
	    vn_triangle_normals(&out, &pos, mesh->indices, 3 * mesh->triangle_count, method, NULL, NULL);
	if (res != vn_result_success)
		die(1, "computing normals: %s", vn_result_string(res));
	r->theta = (double*)xmalloc(sizeof(double) * mesh->vertex_count);
	r->n = 0;
	double sum = 0, sum2 = 0;
	for (size_t v = 0; v < mesh->vertex_count; ++v) {
		if (mesh->boundary[v])
			continue;
		const double* a = mesh->normals + 3 * v;
		const double* b = normals + 3 * v;
		double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
		d = d > 1 ? 1 : d < -1 ? -1 : d;
		const double t = acos(d) * (180.0 / 3.14159265358979323846);
		r->theta[r->n++] = t;
		sum += t, sum2 += t * t;
	}
	qsort(r->theta, r->n, sizeof(double), cmp_double);
	if (r->n) {
		r->median = quantile(r->theta, r->n, 0.5);
		r->p90 = quantile(r->theta, r->n, 0.9);
		r->max = r->theta[r->n - 1];
		r->mean = sum / (double)r->n;
		r->rms = sqrt(sum2 / (double)r->n);
	}
}

/* ---------------------------------------------------------------- charts */

#define NM vn_model_count
#define NR vn_resolution_count
#define NK vn_method_count

typedef struct run {
	unsigned models, resolutions, methods;
	vn_model_mesh mesh[NM][NR];
	result res[NM][NR][NK];
} run;

static int selected(unsigned mask, int i)
{
	return (mask >> i) & 1;
}

/* The x range of a chart: from the decade below the smallest first
 * percentile (at least 1e-6 degrees) to 180 degrees. */
static double chart_x0(const run* R, int m, int r)
{
	double lo = 180;
	for (int k = 0; k < NK; ++k) {
		const result* x = &R->res[m][r][k];
		if (selected(R->methods, k) && x->n) {
			const double q = quantile(x->theta, x->n, 0.01);
			lo = q < lo ? q : lo;
		}
	}
	lo = lo < 1e-6 ? 1e-6 : lo;
	return pow(10, floor(log10(lo)));
}

static void chart_panel(FILE* f, const run* R, int m, int r, const svg_panel* p, const char* title)
{
	svg_axes(f, p, "angular discrepancy (degrees, log scale)", "fraction of vertices", title);
	for (int k = 0; k < NK; ++k)
		if (selected(R->methods, k))
			svg_cumulative(f, p, R->res[m][r][k].theta, R->res[m][r][k].n, k);
}

/* Each method keeps its colour whatever the selection. */
static void legend(FILE* f, const run* R, double x, double y)
{
	const char* names[NK];
	int series[NK], n = 0;
	for (int k = 0; k < NK; ++k)
		if (selected(R->methods, k))
			names[n] = vn_method_name((vn_method)k), series[n++] = k;
	svg_legend(f, x, y, names, series, n);
}

static FILE* open_out(const char* dir, const char* name)
{
	char path[4096];
	snprintf(path, sizeof(path), "%s/%s", dir, name);
	FILE* f = fopen(path, "w");
	if (!f)
		die(1, "cannot write %s", path);
	return f;
}

static void close_out(FILE* f, const char* what)
{
	if (ferror(f) | fclose(f))
		die(1, "writing %s failed", what);
}

static void write_histograms(const run* R, const char* dir)
{
	for (int m = 0; m < NM; ++m)
		for (int r = 0; r < NR; ++r) {
			if (!selected(R->models, m) || !selected(R->resolutions, r))
				continue;
			char name[128], title[256];
			snprintf(name, sizeof(name), "hist_%s_%s.svg", vn_model_name((vn_model)m), vn_resolution_name((vn_resolution)r));
			snprintf(title, sizeof(title), "%s, %s resolution: %zu triangles, %zu interior vertices",
			         vn_model_name((vn_model)m), vn_resolution_name((vn_resolution)r), R->mesh[m][r].triangle_count,
			         R->res[m][r][0].n);
			FILE* f = open_out(dir, name);
			svg_begin(f, 720, 440, title);
			const svg_panel p = {70, 40, 500, 340, chart_x0(R, m, r), 180, 0, 1, 1, 0};
			chart_panel(f, R, m, r, &p, "");
			legend(f, R, 596, 40);
			svg_end(f);
			close_out(f, name);
		}
}

/* Figure 4: turbulence at low, medium and high resolution side by side. */
static void write_aliasing(const run* R, const char* dir)
{
	const int m = vn_model_turbulence_mt;
	if (!selected(R->models, m) || (R->resolutions & 7) != 7)
		return;
	FILE* f = open_out(dir, "fig4_turbulence_aliasing.svg");
	svg_begin(f, 1260, 440, "Turbulence (marching tetrahedra): aliasing, low to high resolution");
	double x0 = 180;
	for (int r = 0; r < NR; ++r) {
		const double v = chart_x0(R, m, r);
		x0 = v < x0 ? v : x0;
	}
	for (int r = 0; r < NR; ++r) {
		char title[160];
		snprintf(title, sizeof(title), "%s: %zu triangles", vn_resolution_name((vn_resolution)r),
		         R->mesh[m][r].triangle_count);
		const svg_panel p = {70 + 380.0 * r, 56, 320, 320, x0, 180, 0, 1, 1, 0};
		chart_panel(f, R, m, r, &p, title);
	}
	legend(f, R, 1150, 56);
	svg_end(f);
	close_out(f, "fig4_turbulence_aliasing.svg");
}

/* Figure 5 and speed.csv: ns per vertex per method over the selected models
 * at high resolution (or the highest selected), median of K repeats. */
static void write_speed(const run* R, const char* dir, unsigned long repeat)
{
	int r = NR - 1;
	while (r > 0 && !selected(R->resolutions, r))
		--r;
	size_t total = 0, most = 0;
	for (int m = 0; m < NM; ++m)
		if (selected(R->models, m)) {
			total += R->mesh[m][r].vertex_count;
			most = R->mesh[m][r].vertex_count > most ? R->mesh[m][r].vertex_count : most;
		}
	double* normals = (double*)xmalloc(3 * sizeof(double) * most);
	double* t = (double*)xmalloc(sizeof(double) * repeat);
	double ns[NK] = {0};
	for (int k = 0; k < NK; ++k) {
		if (!selected(R->methods, k))
			continue;
		for (unsigned long i = 0; i <= repeat; ++i) {
			const double t0 = tool_now();
			for (int m = 0; m < NM; ++m) {
				if (!selected(R->models, m))
					continue;
				const vn_model_mesh* mesh = &R->mesh[m][r];
				const vn_positions pos = {mesh->positions, mesh->vertex_count, 0, vn_scalar_float64};
				const vn_vectors out = {normals, 0, vn_scalar_float64};
				vn_triangle_normals(&out, &pos, mesh->indices, 3 * mesh->triangle_count, (vn_method)k, NULL, NULL);
			}
			if (i) /* i == 0 warms up */
				t[i - 1] = tool_now() - t0;
		}
		qsort(t, repeat, sizeof(double), cmp_double);
		ns[k] = 1e9 * t[repeat / 2] / (double)total;
	}
	FILE* c = open_out(dir, "speed.csv");
	fprintf(c, "method,resolution,vertices,median_ns_per_vertex\n");
	double top = 0;
	for (int k = 0; k < NK; ++k)
		if (selected(R->methods, k)) {
			fprintf(c, "%s,%s,%zu,%.2f\n", vn_method_name((vn_method)k), vn_resolution_name((vn_resolution)r), total,
			        ns[k]);
			top = ns[k] > top ? ns[k] : top;
		}
	close_out(c, "speed.csv");

	char title[200];
	snprintf(title, sizeof(title), "Time per vertex, %s-resolution models (%zu vertices), median of %lu runs",
	         vn_resolution_name((vn_resolution)r), total, repeat);
	FILE* f = open_out(dir, "fig5_speed.svg");
	svg_begin(f, 720, 420, title);
	int n = 0;
	for (int k = 0; k < NK; ++k)
		n += selected(R->methods, k);
	const svg_panel p = {80, 50, 600, 300, 0, 1, 0, svg_nice_max(top * 1.1), 0, 1};
	svg_axes(f, &p, "", "ns per vertex (one thread)", "");
	for (int k = 0, i = 0; k < NK; ++k)
		if (selected(R->methods, k))
			svg_bar(f, &p, i++, n, ns[k], vn_method_name((vn_method)k), k);
	svg_end(f);
	close_out(f, "fig5_speed.svg");
	free(t);
	free(normals);
}

/* ---------------------------------------------------------------- Table 4 */

/* The paper's figures show each class at one resolution: TP and HF low, MT high. */
static vn_resolution paper_resolution(int m)
{
	return m >= vn_model_sphere_mt ? vn_resolution_high : vn_resolution_low;
}

/* The rule that turns medians into marks (docs/REPRODUCTION.md). A row's
 * reference is the typical face-weighted scheme: the median of the six
 * face-weighted schemes' median discrepancies. A scheme is
 *   ok (good) when its median is at most 0.9 times the reference,
 *   x  (bad)  when it is at least 1.25 times the reference,
 * and unmarked otherwise, so a row where no scheme stands out has no mark. */
#define TABLE4_GOOD 0.9
#define TABLE4_BAD 1.25

static void table4_marks(const run* R, int m, const char* marks[NK])
{
	const vn_resolution r = paper_resolution(m);
	double face[vn_method_mewcsa];
	for (int k = 0; k < vn_method_mewcsa; ++k)
		face[k] = R->res[m][r][k].median;
	qsort(face, vn_method_mewcsa, sizeof(double), cmp_double);
	const double ref = 0.5 * (face[2] + face[3]);
	for (int k = 0; k < NK; ++k) {
		const double v = R->res[m][r][k].median;
		marks[k] = v >= TABLE4_BAD * ref ? "×" : v <= TABLE4_GOOD * ref ? "✓" : "";
	}
}

static void write_table(const run* R, const char* path)
{
	FILE* f = fopen(path, "w");
	if (!f)
		die(1, "cannot write %s", path);
	fprintf(f, "<!-- generated by vneval --table; do not edit -->\n");
	if (R->models == (1u << NM) - 1 && R->methods == (1u << NK) - 1 && R->resolutions == (1u << NR) - 1) {
		fprintf(f, "### Table 4 (vn)\n\n| model | resolution |");
		for (int k = 0; k < NK; ++k)
			fprintf(f, " %s |", vn_method_name((vn_method)k));
		fprintf(f, "\n|---|---|");
		for (int k = 0; k < NK; ++k)
			fprintf(f, ":-:|");
		fprintf(f, "\n");
		for (int m = 0; m < NM; ++m) {
			const char* marks[NK];
			table4_marks(R, m, marks);
			fprintf(f, "| %s | %s |", vn_model_name((vn_model)m), vn_resolution_name(paper_resolution(m)));
			for (int k = 0; k < NK; ++k)
				fprintf(f, " %s |", marks[k]);
			fprintf(f, "\n");
		}
	}
	static const char* const stats[] = {"median", "RMS"};
	for (int s = 0; s < 2; ++s) {
		fprintf(f, "\n### %s angular discrepancy (degrees)\n\n| model | resolution |", stats[s]);
		for (int k = 0; k < NK; ++k)
			if (selected(R->methods, k))
				fprintf(f, " %s |", vn_method_name((vn_method)k));
		fprintf(f, "\n|---|---|");
		for (int k = 0; k < NK; ++k)
			if (selected(R->methods, k))
				fprintf(f, "--:|");
		fprintf(f, "\n");
		for (int m = 0; m < NM; ++m)
			for (int r = 0; r < NR; ++r) {
				if (!selected(R->models, m) || !selected(R->resolutions, r))
					continue;
				fprintf(f, "| %s | %s |", vn_model_name((vn_model)m), vn_resolution_name((vn_resolution)r));
				for (int k = 0; k < NK; ++k)
					if (selected(R->methods, k))
						fprintf(f, " %.3g |", s ? R->res[m][r][k].rms : R->res[m][r][k].median);
				fprintf(f, "\n");
			}
	}
	close_out(f, path);
}

/* ---------------------------------------------------------------- export */

static void export_off(const vn_model_mesh* mesh, const char* dir, const char* name)
{
	char path[4096];
	snprintf(path, sizeof(path), "%s/%s.off", dir, name);
	uint32_t* offsets = (uint32_t*)xmalloc(sizeof(uint32_t) * (mesh->triangle_count + 1));
	for (size_t f = 0; f <= mesh->triangle_count; ++f)
		offsets[f] = (uint32_t)(3 * f);
	vn_io_mesh m;
	memset(&m, 0, sizeof(m));
	m.vertex_count = mesh->vertex_count;
	m.positions = mesh->positions;
	m.normals = mesh->normals;
	m.face_count = mesh->triangle_count;
	m.face_offsets = offsets;
	m.indices = mesh->indices;
	vn_io_error err;
	if (vn_io_write_file(path, vn_io_format_by_name("off"), &m, NULL, &err) != vn_io_success)
		die(1, "%s", err.message);
	free(offsets);
}

int main(int argc, char** argv)
{
	tool_check_version(prog);
	const char *csv = NULL, *svg = NULL, *table = NULL, *export_dir = NULL;
	unsigned long repeat = 15;
	int quiet = 0;
	static run R;
	R.models = R.resolutions = R.methods = ~0u;

	for (int i = 1; i < argc; ++i) {
		const char* s = argv[i];
		const int has = i + 1 < argc;
		if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
			usage(stdout);
			return 0;
		} else if (!strcmp(s, "--version")) {
			printf("vneval %s (libvn %s)\n", VN_VERSION_STRING, vn_version_string());
			return 0;
		} else if (!strcmp(s, "--csv") && has) {
			csv = argv[++i];
		} else if (!strcmp(s, "--svg-dir") && has) {
			svg = argv[++i];
		} else if (!strcmp(s, "--table") && has) {
			table = argv[++i];
		} else if (!strcmp(s, "--export-off") && has) {
			export_dir = argv[++i];
		} else if (!strcmp(s, "--model") && has) {
			R.models = parse_list(argv[++i], model_name_i, "model");
		} else if (!strcmp(s, "--resolution") && has) {
			R.resolutions = parse_list(argv[++i], resolution_name_i, "resolution");
		} else if (!strcmp(s, "--method") && has) {
			R.methods = parse_list(argv[++i], method_name_i, "method");
		} else if ((!strcmp(s, "-r") || !strcmp(s, "--repeat")) && has) {
			if (!vn_io_parse_uint(argv[++i], 1, 10000, &repeat))
				die(2, "--repeat needs a whole number from 1 to 10000, not '%s'", argv[i]);
		} else if (!strcmp(s, "-q") || !strcmp(s, "--quiet")) {
			quiet = 1;
		} else {
			die(2, "unknown option or missing value: '%s' (see --help)", s);
		}
	}
	R.models &= (1u << NM) - 1, R.resolutions &= (1u << NR) - 1, R.methods &= (1u << NK) - 1;
	if (svg && mkdir(svg, 0777) != 0 && errno != EEXIST)
		die(1, "cannot create folder %s", svg);
	if (export_dir && mkdir(export_dir, 0777) != 0 && errno != EEXIST)
		die(1, "cannot create folder %s", export_dir);

	const int progress = !quiet && isatty(STDERR_FILENO);
	for (int m = 0; m < NM; ++m)
		for (int r = 0; r < NR; ++r) {
			if (!selected(R.models, m) || !selected(R.resolutions, r))
				continue;
			if (progress)
				fprintf(stderr, "\r%s: %-14s %-6s", prog, vn_model_name((vn_model)m),
				        vn_resolution_name((vn_resolution)r));
			vn_model_mesh* mesh = &R.mesh[m][r];
			const vn_result g = vn_model_generate((vn_model)m, (vn_resolution)r, NULL, mesh);
			if (g != vn_result_success)
				die(1, "generating the models: %s", vn_result_string(g));
			if (export_dir) {
				char name[128];
				snprintf(name, sizeof(name), "%s_%s", vn_model_name((vn_model)m),
				         vn_resolution_name((vn_resolution)r));
				export_off(mesh, export_dir, name);
			}
			double* normals = (double*)xmalloc(3 * sizeof(double) * mesh->vertex_count);
			for (int k = 0; k < NK; ++k)
				if (selected(R.methods, k))
					evaluate(mesh, (vn_method)k, normals, &R.res[m][r][k]);
			free(normals);
		}
	if (progress)
		fprintf(stderr, "\r%40s\r", "");

	if (csv) {
		FILE* f = fopen(csv, "w");
		if (!f)
			die(1, "cannot write %s", csv);
		fprintf(f, "model,resolution,method,vertices,median_deg,p90_deg,max_deg,mean_deg,rms_deg\n");
		for (int m = 0; m < NM; ++m)
			for (int r = 0; r < NR; ++r)
				for (int k = 0; k < NK; ++k) {
					if (!selected(R.models, m) || !selected(R.resolutions, r) || !selected(R.methods, k))
						continue;
					const result* x = &R.res[m][r][k];
					fprintf(f, "%s,%s,%s,%zu,%.6g,%.6g,%.6g,%.6g,%.6g\n", vn_model_name((vn_model)m),
					        vn_resolution_name((vn_resolution)r), vn_method_name((vn_method)k), x->n, x->median,
					        x->p90, x->max, x->mean, x->rms);
				}
		close_out(f, csv);
	}
	if (svg) {
		write_histograms(&R, svg);
		write_aliasing(&R, svg);
		write_speed(&R, svg, repeat);
	}
	if (table)
		write_table(&R, table);
	if (!quiet) {
		printf("median angular discrepancy (degrees) over interior vertices\n%-14s %-6s", "model", "res");
		for (int k = 0; k < NK; ++k)
			if (selected(R.methods, k))
				printf(" %9s", vn_method_name((vn_method)k));
		printf("\n");
		for (int m = 0; m < NM; ++m)
			for (int r = 0; r < NR; ++r) {
				if (!selected(R.models, m) || !selected(R.resolutions, r))
					continue;
				printf("%-14s %-6s", vn_model_name((vn_model)m), vn_resolution_name((vn_resolution)r));
				for (int k = 0; k < NK; ++k)
					if (selected(R.methods, k))
						printf(" %9.3g", R.res[m][r][k].median);
				printf("\n");
			}
	}
	for (int m = 0; m < NM; ++m)
		for (int r = 0; r < NR; ++r) {
			for (int k = 0; k < NK; ++k)
				free(R.res[m][r][k].theta);
			vn_model_free(&R.mesh[m][r], NULL);
		}
	return 0;
}
