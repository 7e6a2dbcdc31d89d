/* vnconvert: recompute a mesh's vertex normals and write it out.
 *
 *   vnconvert IN OUT [--method M] ...
 *
 * Exit status: 0 on success, 1 when the work failed (unreadable or
 * malformed input, unwritable output), 2 on a usage error. Every failure
 * prints exactly one line on stderr and leaves OUT as it was. */
/* MAP_ANONYMOUS (glibc: not in POSIX 2008). */
#define _DEFAULT_SOURCE
#include "common.h"

#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <sys/mman.h>
#include <sys/wait.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "vn_convert.h"

static const char* prog = "vnconvert";

static void usage(FILE* out)
{
	fprintf(out,
	        "usage: vnconvert IN OUT [options]\n"
	        "       vnconvert --out-dir DIR [--format F] [options] IN...\n"
	        "Recomputes the vertex normals of the mesh IN and writes the mesh with them to OUT.\n"
	        "IN or OUT '-' is standard input or output, for formats that are one file (not .gltf);\n"
	        "then --input-format or --format names the format. A failure writes nothing there.\n"
	        "\n"
	        "options:\n"
	        "  -m, --method M         weighting scheme (default mwa, the paper's overall choice);\n"
	        "                         one of");
	for (unsigned m = 0; m < vn_method_count; ++m)
		fprintf(out, " %s", vn_method_name((vn_method)m));
	fprintf(out,
	        "\n"
	        "      --list-methods     list the schemes with a description and reference\n"
	        "      --list-conversions what each pair of formats keeps (a Markdown table)\n"
	        "  -f, --format F         output format, overriding OUT's extension\n"
	        "      --input-format F   input format, overriding IN's extension\n"
	        "  -j, --threads N        workers (default: all %u cores; results do not depend on it): the\n"
	        "                         threads of a conversion; in a batch, the files converted at once\n"
	        "                         (one thread each, the cores left over going to the last files)\n"
	        "      --apply-transforms glTF written as another format, which has no scene graph:\n"
	        "                         the default scene as drawn, each mesh once per node using it,\n"
	        "                         with the node transforms applied; without it, every mesh once,\n"
	        "                         in its own (mesh-local) coordinates, with a warning where the\n"
	        "                         scene draws a mesh transformed, twice or not at all\n"
	        "      --in-place         allow OUT to be IN (otherwise refused)\n"
	        "      --stats            print counts, degenerate input and timings\n"
	        "  -q, --quiet            no warnings or progress\n"
	        "  -h, --help             this text\n"
	        "      --version          print the version\n"
	        "\n"
	        "batch mode: every IN (a file, or a folder's files of a format vn reads) to DIR:\n"
	        "  -o, --out-dir DIR      write DIR/STEM.EXT for each input (EXT: --format's, else the\n"
	        "                         input's own); DIR and its subfolders are created\n"
	        "  -r, --recursive        enter the subfolders of folder inputs, keeping their layout\n"
	        "                         under DIR (without it, subfolders are counted, not entered)\n"
	        "  A status line per file on stderr (-q: only failures) and a summary; exit status 1\n"
	        "  when a file failed (the others are still converted), 2 before any work when two\n"
	        "  inputs would have one output, an output is its input, or an option applies to no\n"
	        "  file (one that applies to some files applies to those). --input-format applies to\n"
	        "  the files named; a folder's files go by their extensions (others, and hidden ones,\n"
	        "  are passed over). Images a .gltf output refers to are copied as STEM_NAME, so that\n"
	        "  models converted into one folder keep theirs apart.\n"
	        "\n",
	        tool_cpu_count());
	fprintf(out,
	        "Every conversion welds vertices at one position (glTF to glTF: within a primitive),\n"
	        "so the copies a file splits along seams get one normal; copies whose input normals\n"
	        "differ keep the hard edge between them, and opposed ones (the two sides of a\n"
	        "double-sided surface) are not welded; a face and its reverse on the same vertices\n"
	        "(both sides sharing them) are computed apart and those vertices split:\n"
	        "      --no-weld          compute on the vertices as the file splits them (seams show)\n"
	        "      --weld-epsilon E   weld vertices whose coordinates all differ by at most E\n"
	        "                         (default 0: exactly equal positions only)\n"
	        "      --crease-angle DEG hard edges where faces meet at more than DEG degrees (0 to 180):\n"
	        "                         per-corner normals, vertices split where they differ\n"
	        "\n"
	        "glTF output (.gltf/.glb):\n"
	        "      --draco D          KHR_draco_mesh_compression: keep (default: compressed primitives\n"
	        "                         are re-encoded with their own attributes and bits), off\n"
	        "                         (written uncompressed) or on (every triangle primitive\n"
	        "                         compressed, with the bits below); from other formats, on\n"
	        "                         compresses and keep and off do not\n"
	        "\n"
	        "glTF to glTF only (.gltf/.glb in and out):\n"
	        "      --weld-scope S     primitive (default) or mesh: weld across a mesh's primitives\n"
	        "      --tangents T       keep (default: left as they are, with a warning) or drop\n"
	        "                         (TANGENT removed from primitives and morph targets, and\n"
	        "                         its data with them)\n"
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
	        "formats:\n");
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
	        "transforms are not applied unless --apply-transforms). OFF to glTF writes one mesh\n"
	        "with POSITION, NORMAL and indices (polygons fan-triangulated).\n");
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
	/* The conversion: every flag vn_io_convert_option takes, and --stats. */
	vn_convert_options o;
	const vn_io_format* in_format;  /* o's formats, or IN's and OUT's extensions' */
	const vn_io_format* out_format;
	unsigned threads; /* -j, else every core: a conversion's threads; in batch mode the files converted at once */
	int quiet;
	/* Batch mode (out_dir not NULL): every IN into out_dir. */
	const char* out_dir;
	int recursive;
	const char** inputs;
	size_t input_count;
} args;

static const char* need_value(int argc, char** argv, int* i)
{
	if (*i + 1 >= argc)
		die(2, "option %s needs a value", argv[*i]);
	return argv[++*i];
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
	a.inputs = (const char**)calloc((size_t)argc, sizeof *a.inputs);
	if (!a.inputs)
		die(1, "%s", "out of memory");
	vn_io_error err;
	for (int i = 1; i < argc; ++i) {
		const char* s = argv[i];
		const int arity = vn_io_convert_option_arity(s);
		if (arity >= 0) {
			const char* v = arity ? need_value(argc, argv, &i) : NULL;
			if (vn_io_convert_option(&a.o, s, v, &err) != vn_io_success)
				die(2, "%s", err.message);
		} else if (!strcmp(s, "-h") || !strcmp(s, "--help")) {
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
		} else if (!strcmp(s, "--stats")) {
			a.o.stats = 1;
		} else if (!strcmp(s, "-q") || !strcmp(s, "--quiet")) {
			a.quiet = 1;
		} else if (!strcmp(s, "-o") || !strcmp(s, "--out-dir")) {
			a.out_dir = need_value(argc, argv, &i);
		} else if (!strcmp(s, "-r") || !strcmp(s, "--recursive")) {
			a.recursive = 1;
		} else if (s[0] == '-' && s[1]) {
			die(2, "unknown option '%s' (see --help)", s);
		} else {
			a.inputs[a.input_count++] = s;
		}
	}
	a.threads = a.o.threads ? a.o.threads : tool_cpu_count();
	a.in_format = a.o.input_format ? vn_io_format_by_name(a.o.input_format) : NULL;
	a.out_format = a.o.output_format ? vn_io_format_by_name(a.o.output_format) : NULL;
	if (a.out_dir) {
		if (!a.input_count)
			die(2, "%s", "usage: vnconvert --out-dir DIR IN... (see --help)");
		if (a.o.stats)
			die(2, "%s", "--stats is for one file: a batch ends with a summary instead");
		return a;
	}
	if (a.recursive)
		die(2, "%s", "--recursive walks the folders of a batch: give --out-dir DIR too");
	if (a.input_count > 2)
		die(2, "unexpected argument '%s': give one input and one output (or --out-dir DIR for many inputs)",
		    a.inputs[2]);
	if (a.input_count < 2)
		die(2, "%s", "usage: vnconvert IN OUT [--method M] (see --help)");
	a.in = a.inputs[0];
	a.out = a.inputs[1];
	if (!strcmp(a.in, "-") || !strcmp(a.out, "-")) {
		if (!strcmp(a.in, "-") && !a.in_format)
			die(2, "%s", "IN '-' (standard input) needs --input-format: there is no extension to tell the format");
		if (!strcmp(a.out, "-") && !a.out_format)
			die(2, "%s", "OUT '-' (standard output) needs --format: there is no extension to tell the format");
		if (a.o.stats)
			die(2, "%s", "--stats needs IN and OUT to be files, not '-'");
		const vn_io_format* f = !strcmp(a.in, "-") && a.in_format->companions ? a.in_format : a.out_format;
		if ((!strcmp(a.in, "-") && a.in_format->companions) || (!strcmp(a.out, "-") && a.out_format->companions))
			die(2, "'-' is for formats that are one file, and %s (%s) may come with other files (%s): use a file name",
			    f->title, f->extensions, f->companions);
	}
	if (!a.in_format && !(a.in_format = vn_io_format_for_path(a.in)))
		unknown_extension(a.in, 1);
	if (!a.out_format && !(a.out_format = vn_io_format_for_path(a.out)))
		unknown_extension(a.out, 0);
	/* Before '-' reads standard input. */
	if (vn_io_convert_check(&a.o, a.in_format, a.out_format, &err) != vn_io_success)
		die(2, "%s", err.message);
	return a;
}

static void progress(void* context, const char* what, const char* path)
{
	if (!((const args*)context)->quiet && isatty(STDERR_FILENO))
		fprintf(stderr, "%s: %s %s\n", prog, what, path);
}

/* The exit status of a failure: 2 for a usage error (the command line
 * asks for what cannot be done), else 1. */
static int exit_status(vn_io_result r)
{
	return r == vn_io_error_option || r == vn_io_error_same_file || r == vn_io_error_format ? 2 : 1;
}

/* Converts a.in to a.out: exit status 0, 1 (*triangles: how many it wrote
 * on success) or 2, with every message on stderr (warnings; an error in
 * one line) and the --stats text on stdout. */
static int convert_one(args a, size_t* triangles)
{
	a.o.input_format = a.in_format->name;
	a.o.output_format = a.out_format->name;
	a.o.threads = a.threads;
	a.o.progress = progress;
	a.o.progress_context = &a;
	vn_convert_report report;
	vn_io_error err;
	const vn_io_result res = vn_io_convert(a.in, a.out, &a.o, &report, &err);
	for (const char* line = report.warnings; line && *line && !a.quiet; line += strcspn(line, "\n") + 1)
		fprintf(stderr, "%s: warning: %.*s\n", prog, (int)strcspn(line, "\n"), line);
	if (report.stats)
		fputs(report.stats, stdout);
	*triangles = report.triangles;
	vn_io_convert_report_free(&report);
	if (res == vn_io_success)
		return 0;
	fprintf(stderr, "%s: error: %s\n", prog, err.message);
	return exit_status(res);
}
/* ------------------------------------------------------------------ many files, and '-'
 *
 * Each file is converted in a child process (fork, then convert_one): a
 * crash or an exit in one file's conversion is that file's failure alone,
 * and its messages are collected whole and printed together. */

typedef struct job {
	const char *in, *out;           /* as converted */
	const char *in_name, *out_name; /* as messages name them (temporaries of '-': "<stdin>") */
	const vn_io_format *in_format, *out_format;
	pid_t pid;
	int fd;      /* the child's stderr, read end */
	char* text;  /* what it wrote there */
	size_t length, capacity;
	double start;
} job;

/* Written by each child before it exits: shared memory, one per job. */
typedef struct outcome {
	size_t triangles;
} outcome;

/* Copies line (length n) to out with every in/out path of j replaced by
 * the name messages give it. */
static void put_named(FILE* out, const job* j, const char* line, size_t n)
{
	const char* from[2] = {j->in, j->out};
	const char* to[2] = {j->in_name, j->out_name};
	size_t i = 0;
	while (i < n) {
		int hit = -1;
		for (int k = 0; k < 2 && hit < 0; ++k)
			if (from[k] != to[k] && strlen(from[k]) <= n - i && !strncmp(line + i, from[k], strlen(from[k])))
				hit = k;
		if (hit < 0) {
			fputc(line[i++], out);
			continue;
		}
		fputs(to[hit], out);
		i += strlen(from[hit]);
	}
}

/* "12,345" */
static const char* grouped(size_t n, char text[32])
{
	char digits[32];
	const int len = snprintf(digits, sizeof digits, "%zu", n);
	int o = 0;
	for (int i = 0; i < len; ++i) {
		if (i && (len - i) % 3 == 0)
			text[o++] = ',';
		text[o++] = digits[i];
	}
	text[o] = '\0';
	return text;
}

typedef struct batch {
	args* a;
	job* jobs;
	size_t count;
	int stdio;                          /* one job for '-': its messages as they are, no status lines */
	size_t ok, failed, triangles;
	double start;
	int bar;                            /* a progress bar is on the terminal's last line */
	vn_batch_plan plan;                 /* the files of a batch (not '-') */
} batch;

static void clear_bar(batch* b)
{
	if (b->bar)
		fputs("\r\033[K", stderr);
	b->bar = 0;
}

static void draw_bar(batch* b, size_t done)
{
	if (b->stdio || b->a->quiet || !isatty(STDERR_FILENO) || tool_now() - b->start < 1)
		return;
	const int width = 30, filled = (int)(width * done / b->count);
	fprintf(stderr, "\r[%.*s%*s] %zu/%zu files", filled, "==============================", width - filled, "", done,
	        b->count);
	b->bar = 1;
}

/* The child's messages, then its status line; counts it. */
static void report(batch* b, job* j, int status, const outcome* o)
{
	clear_bar(b);
	const char* error = NULL;
	size_t error_length = 0;
	static const char prefix[] = "vnconvert: error: ";
	for (size_t i = 0; i < j->length;) {
		const char* line = j->text + i;
		const size_t n = strcspn(line, "\n");
		i += n + (i + n < j->length);
		/* The error goes into the status line (the last one, if several). */
		if (!b->stdio && n >= sizeof prefix - 1 && !strncmp(line, prefix, sizeof prefix - 1)) {
			error = line + sizeof prefix - 1;
			error_length = n - (sizeof prefix - 1);
			continue;
		}
		put_named(stderr, j, line, n);
		fputc('\n', stderr);
	}
	const int crashed = WIFSIGNALED(status), code = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
	if (b->stdio) {
		if (crashed)
			fprintf(stderr, "%s: error: %s: crashed converting it (%s)\n", prog, j->in_name, strsignal(WTERMSIG(status)));
		b->failed = crashed || code;
		b->ok = !b->failed;
		return;
	}
	if (!crashed && code == 0) {
		b->ok++;
		b->triangles += o->triangles;
		char n[32];
		if (!b->a->quiet)
			fprintf(stderr, "ok   %s -> %s  (%s %s, %.1f ms)\n", j->in_name, j->out_name, grouped(o->triangles, n),
			        noun(o->triangles, "triangle", "triangles"), 1e3 * (tool_now() - j->start));
		return;
	}
	b->failed++;
	if (crashed)
		fprintf(stderr, "FAIL %s: crashed (%s)\n", j->in_name, strsignal(WTERMSIG(status)));
	else if (error)
		fprintf(stderr, "FAIL %s: %.*s\n", j->in_name, (int)error_length, error);
	else
		fprintf(stderr, "FAIL %s: exit status %d\n", j->in_name, code);
}

static void start(batch* b, size_t i, unsigned threads, outcome* o)
{
	job* j = &b->jobs[i];
	int p[2];
	if (pipe(p) != 0)
		die(1, "cannot start a conversion: %s", strerror(errno));
	fflush(stdout);
	fflush(stderr);
	j->start = tool_now();
	j->pid = fork();
	if (j->pid < 0)
		die(1, "cannot start a conversion: %s", strerror(errno));
	if (j->pid == 0) {
		close(p[0]);
		if (dup2(p[1], STDERR_FILENO) < 0)
			_exit(1);
		close(p[1]);
		args a = *b->a;
		a.in = j->in;
		a.out = j->out;
		a.in_format = j->in_format;
		a.out_format = j->out_format;
		a.threads = threads;
		a.o.image_names_from_output = !b->stdio;
		a.o.input_is_copy = b->stdio;
		/* An option refused only when it applies to no file of the batch (plan). */
		a.o.ignore_misfits = 1;
		const int status = convert_one(a, &o->triangles);
		exit(status);
	}
	close(p[1]);
	j->fd = p[0];
}

/* Runs every job, a->threads at once; returns the exit status: 0, or 1
 * when a file failed. */
static int run(batch* b)
{
	outcome* outcomes = (outcome*)mmap(NULL, b->count * sizeof *outcomes, PROT_READ | PROT_WRITE,
	                                   MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	struct pollfd* fds = (struct pollfd*)calloc(b->a->threads, sizeof *fds);
	size_t* slot = (size_t*)calloc(b->a->threads, sizeof *slot); /* job of each fds entry */
	if (outcomes == MAP_FAILED || !fds || !slot)
		die(1, "%s", "out of memory");
	size_t next = 0, running = 0, done = 0;
	while (done < b->count) {
		for (; running < b->a->threads && next < b->count; ++next) {
			/* Single-threaded conversions side by side; the cores no file
			 * is left for go to the last ones. */
			const unsigned free = b->a->threads - (unsigned)running;
			const size_t left = b->count - next;
			start(b, next, left < free ? (unsigned)(free / left) : 1, &outcomes[next]);
			fds[running] = (struct pollfd){b->jobs[next].fd, POLLIN, 0};
			slot[running++] = next;
		}
		if (poll(fds, running, 200) < 0 && errno != EINTR)
			die(1, "cannot wait for the conversions: %s", strerror(errno));
		for (size_t r = 0; r < running;) {
			job* j = &b->jobs[slot[r]];
			if (!fds[r].revents) {
				r++;
				continue;
			}
			if (j->capacity - j->length < 4096) {
				j->capacity = 2 * j->capacity + 4096;
				if (!(j->text = (char*)realloc(j->text, j->capacity)))
					die(1, "%s", "out of memory");
			}
			const ssize_t got = read(j->fd, j->text + j->length, j->capacity - j->length);
			if (got > 0 || (got < 0 && errno == EINTR)) {
				j->length += got > 0 ? (size_t)got : 0;
				r++;
				continue;
			}
			/* End of its stderr: the child has exited (or is about to). */
			close(j->fd);
			int status;
			while (waitpid(j->pid, &status, 0) < 0 && errno == EINTR) {
			}
			report(b, j, status, &outcomes[slot[r]]);
			free(j->text);
			j->text = NULL;
			++done;
			--running;
			fds[r] = fds[running];
			slot[r] = slot[running];
		}
		draw_bar(b, done);
	}
	clear_bar(b);
	munmap(outcomes, b->count * sizeof *outcomes);
	free(fds);
	free(slot);
	return b->failed ? 1 : 0;
}

/* A copy of text[0 .. n) + tail, or of text when n is -1 (dies when out of memory). */
static char* joined(const char* text, size_t n, const char* tail)
{
	const size_t length = n == (size_t)-1 ? strlen(text) : n;
	char* s = (char*)malloc(length + strlen(tail) + 1);
	if (!s)
		die(1, "%s", "out of memory");
	memcpy(s, text, length);
	strcpy(s + length, tail);
	return s;
}

/* The jobs of a batch, each checked before any is run (vn_io_batch_plan). */
static void plan(batch* b)
{
	args* a = b->a;
	vn_io_error err;
	const vn_io_result r =
	    vn_io_batch_plan(a->inputs, a->input_count, a->out_dir, a->recursive, &a->o, &b->plan, &err);
	if (r != vn_io_success)
		die(exit_status(r), "%s", err.message);
	b->count = b->plan.count;
	b->jobs = (job*)calloc(b->count ? b->count : 1, sizeof *b->jobs);
	if (!b->jobs)
		die(1, "%s", "out of memory");
	for (size_t i = 0; i < b->count; ++i) {
		const vn_batch_file* f = &b->plan.files[i];
		job* j = &b->jobs[i];
		j->in = j->in_name = f->input;
		j->out = j->out_name = f->output;
		j->in_format = vn_io_format_by_name(f->input_format);
		j->out_format = vn_io_format_by_name(f->output_format);
	}
}

static int convert_batch(args* a)
{
	batch b;
	memset(&b, 0, sizeof b);
	b.a = a;
	b.start = tool_now();
	plan(&b);
	const int status = b.count ? run(&b) : 0;
	if (!a->quiet) {
		char n[32];
		fprintf(stderr, "%s: %zu %s converted", prog, b.ok, noun(b.ok, "file", "files"));
		if (b.failed)
			fprintf(stderr, ", %zu failed", b.failed);
		if (b.plan.skipped)
			fprintf(stderr, ", %zu skipped (not a format vn reads)", b.plan.skipped);
		if (b.plan.unentered)
			fprintf(stderr, ", %zu %s not entered (--recursive)", b.plan.unentered,
			        noun(b.plan.unentered, "folder", "folders"));
		fprintf(stderr, "; %s %s in %.2f s\n", grouped(b.triangles, n), noun(b.triangles, "triangle", "triangles"),
		        tool_now() - b.start);
	}
	vn_io_batch_plan_free(&b.plan);
	free(b.jobs);
	return status;
}

/* IN or OUT '-': standard input is copied into a temporary folder first,
 * and the output goes there whole before it is copied to standard output,
 * so that a failure writes nothing there. */
static int convert_stdio(args* a)
{
	const char* tmp = getenv("TMPDIR");
	char* folder = joined(tmp && *tmp ? tmp : "/tmp", (size_t)-1, "/vnconvert.XXXXXX");
	if (!mkdtemp(folder))
		die(1, "cannot create a temporary folder in %s: %s", tmp && *tmp ? tmp : "/tmp", strerror(errno));
	job j;
	memset(&j, 0, sizeof j);
	j.in_format = a->in_format;
	j.out_format = a->out_format;
	char extension[64];
	snprintf(extension, sizeof extension, "/stdin%.*s", (int)strcspn(a->in_format->extensions, " "),
	         a->in_format->extensions);
	char* in = joined(folder, (size_t)-1, extension);
	snprintf(extension, sizeof extension, "/stdout%.*s", (int)strcspn(a->out_format->extensions, " "),
	         a->out_format->extensions);
	char* out = joined(folder, (size_t)-1, extension);
	const int from_stdin = !strcmp(a->in, "-"), to_stdout = !strcmp(a->out, "-");
	j.in = from_stdin ? in : a->in;
	j.out = to_stdout ? out : a->out;
	j.in_name = from_stdin ? "<stdin>" : a->in;
	j.out_name = to_stdout ? "<stdout>" : a->out;
	int status = 1;
	char buffer[1 << 16];
	size_t n;
	FILE* f = from_stdin ? fopen(in, "wb") : NULL;
	if (from_stdin) {
		while (f && (n = fread(buffer, 1, sizeof buffer, stdin)) > 0)
			if (fwrite(buffer, 1, n, f) != n)
				break;
		if (!f || ferror(stdin) || ferror(f) | (fclose(f) != 0)) {
			fprintf(stderr, "%s: error: <stdin>: cannot copy it into %s: %s\n", prog, folder, strerror(errno));
			goto done;
		}
	}
	batch b;
	memset(&b, 0, sizeof b);
	b.a = a;
	b.jobs = &j;
	b.count = 1;
	b.stdio = 1;
	b.start = tool_now();
	a->threads = a->threads ? a->threads : 1;
	status = run(&b);
	if (status == 0 && to_stdout) {
		signal(SIGPIPE, SIG_IGN); /* a closed pipe is an error, told */
		f = fopen(out, "rb");
		while (f && (n = fread(buffer, 1, sizeof buffer, f)) > 0)
			if (fwrite(buffer, 1, n, stdout) != n)
				break;
		if (!f || ferror(f) || fflush(stdout) != 0 || ferror(stdout)) {
			fprintf(stderr, "%s: error: <stdout>: cannot write: %s\n", prog, strerror(errno));
			status = 1;
		}
		if (f)
			fclose(f);
	}
done:
	unlink(in);
	unlink(out);
	rmdir(folder);
	free(in);
	free(out);
	free(folder);
	return status;
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
	int status;
	if (a.out_dir)
		status = convert_batch(&a);
	else if (!strcmp(a.in, "-") || !strcmp(a.out, "-"))
		status = convert_stdio(&a);
	else {
		size_t triangles;
		status = convert_one(a, &triangles);
	}
	free(a.inputs);
	return status;
}
