/*
 * vn_io_batch_plan (vn_convert.h): which file goes where in a batch
 * (vnconvert --out-dir, vn.convert with out_dir, vn.dask), and the checks
 * made before any file is converted, so that every front end names its
 * outputs and refuses a batch alike.
 */
#define _DEFAULT_SOURCE /* scandir, alphasort's dirent fields */

#include "vn_convert.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct planner {
	vn_batch_plan* plan;
	size_t room;
	const char* out_dir;
	const vn_io_format* in_format;  /* options->input_format: for the files named */
	const vn_io_format* out_format; /* options->output_format, else each input's own */
	int recursive;
	vn_io_error* error;
} planner;

/* A copy of text[0 .. n) + tail (n (size_t)-1: all of text), or NULL. */
static char* joined(const char* text, size_t n, const char* tail)
{
	const size_t length = n == (size_t)-1 ? strlen(text) : n;
	char* s = (char*)malloc(length + strlen(tail) + 1);
	if (s) {
		memcpy(s, text, length);
		strcpy(s + length, tail);
	}
	return s;
}

static vn_io_result out_of_memory(vn_io_error* error)
{
	return vn_io_fail(error, vn_io_error_memory, "%s", "out of memory planning the batch");
}

/* Creates folder path and its missing parents. */
static vn_io_result make_folders(const char* path, vn_io_error* error)
{
	char* p = joined(path, (size_t)-1, "");
	if (!p)
		return out_of_memory(error);
	vn_io_result r = vn_io_success;
	for (char* c = p + 1; r == vn_io_success; ++c)
		if (*c == '/' || !*c) {
			const char end = *c;
			*c = '\0';
			struct stat st;
			if (mkdir(p, 0777) != 0 && errno != EEXIST)
				r = vn_io_fail(error, vn_io_error_write, "cannot create the folder '%s': %s", p, strerror(errno));
			else if (stat(p, &st) != 0 || !S_ISDIR(st.st_mode))
				r = vn_io_fail(error, vn_io_error_write, "'%s' is not a folder, so the outputs cannot go there", p);
			if (!(*c = end))
				break;
		}
	free(p);
	return r;
}

/* Adds file path, whose output is OUT_DIR/relative with the output's
 * extension; format NULL: path's extension names it. */
static vn_io_result add_file(planner* p, const char* path, const char* relative, const vn_io_format* format)
{
	vn_batch_plan* plan = p->plan;
	if (plan->count == p->room) {
		const size_t room = 2 * p->room + 16;
		vn_batch_file* files = (vn_batch_file*)realloc(plan->files, room * sizeof *files);
		if (!files)
			return out_of_memory(p->error);
		plan->files = files;
		p->room = room;
	}
	const char* name = strrchr(relative, '/') ? strrchr(relative, '/') + 1 : relative;
	const char* dot = strrchr(name, '.');
	const size_t stem = (size_t)(dot && dot != name ? dot - relative : (ptrdiff_t)strlen(relative));
	const vn_io_format* in_format = format ? format : vn_io_format_for_path(path);
	const vn_io_format* out_format = p->out_format ? p->out_format : in_format;
	/* The output's extension: --format's first, else the input's own as written. */
	char extension[64];
	if (p->out_format || !dot || dot == name)
		snprintf(extension, sizeof extension, "%.*s", (int)strcspn(out_format->extensions, " "), out_format->extensions);
	else
		snprintf(extension, sizeof extension, "%s", dot);
	char* under = joined(p->out_dir, (size_t)-1, p->out_dir[strlen(p->out_dir) - 1] == '/' ? "" : "/");
	char* relative_out = joined(relative, stem, extension);
	vn_batch_file* f = &plan->files[plan->count];
	memset(f, 0, sizeof *f);
	f->input = joined(path, (size_t)-1, "");
	f->output = under && relative_out ? joined(under, (size_t)-1, relative_out) : NULL;
	f->input_format = in_format->name;
	f->output_format = out_format->name;
	free(under);
	free(relative_out);
	plan->count++; /* also when a copy failed: vn_io_batch_plan_free frees it */
	return f->input && f->output ? vn_io_success : out_of_memory(p->error);
}

static int by_name(const struct dirent** x, const struct dirent** y)
{
	return strcmp((*x)->d_name, (*y)->d_name);
}

/* The files of folder path (relative: its place under OUT_DIR, "" or
 * ending with '/') that vn reads, by extension, in name order; its
 * subfolders too when recursive. Hidden entries are passed over. */
static vn_io_result add_folder(planner* p, const char* path, const char* relative)
{
	struct dirent** entries;
	const int n = scandir(path, &entries, NULL, by_name);
	if (n < 0)
		return vn_io_fail(p->error, vn_io_error_open, "cannot read the folder '%s': %s", path, strerror(errno));
	vn_io_result r = vn_io_success;
	for (int i = 0; i < n; ++i) {
		const char* name = entries[i]->d_name;
		struct stat st;
		char* base = joined(path, (size_t)-1, path[strlen(path) - 1] == '/' ? "" : "/");
		char* full = base ? joined(base, (size_t)-1, name) : NULL;
		char* under = joined(relative, (size_t)-1, name);
		char* sub = under ? joined(under, (size_t)-1, "/") : NULL;
		if (r != vn_io_success || name[0] == '.') {
			/* after a failure, or hidden */
		} else if (!full || !sub) {
			r = out_of_memory(p->error);
		} else if (stat(full, &st) != 0) {
			/* a dangling link */
		} else if (S_ISDIR(st.st_mode)) {
			if (p->recursive)
				r = add_folder(p, full, sub);
			else
				p->plan->unentered++;
		} else if (!vn_io_format_for_path(name)) {
			p->plan->skipped++;
		} else {
			r = add_file(p, full, under, NULL);
		}
		free(base);
		free(full);
		free(under);
		free(sub);
		free(entries[i]);
	}
	free(entries);
	return r;
}

static int by_output(const void* x, const void* y)
{
	const vn_batch_file *p = *(const vn_batch_file* const*)x, *q = *(const vn_batch_file* const*)y;
	const int c = strcmp(p->output, q->output);
	return c ? c : (p < q ? -1 : p > q);
}

/* The checks over the whole plan: an option that applies to no file, two
 * inputs for one output, an output that is its input. */
static vn_io_result check(const vn_batch_plan* plan, const vn_convert_options* o, vn_io_error* error)
{
	char misfit[512];
	size_t fits = 0;
	for (size_t i = 0; i < plan->count; ++i)
		fits += !vn_io_convert_misfit(o, vn_io_format_by_name(plan->files[i].input_format),
		                              vn_io_format_by_name(plan->files[i].output_format), misfit, sizeof misfit);
	if (plan->count && !fits)
		return vn_io_fail(error, vn_io_error_option, "%s, and no file of this batch is converted so: leave it out",
		                  misfit);
	const vn_batch_file** sorted = (const vn_batch_file**)malloc((plan->count ? plan->count : 1) * sizeof *sorted);
	if (!sorted)
		return out_of_memory(error);
	for (size_t i = 0; i < plan->count; ++i)
		sorted[i] = &plan->files[i];
	qsort(sorted, plan->count, sizeof *sorted, by_output);
	vn_io_result r = vn_io_success;
	for (size_t i = 1; i < plan->count && r == vn_io_success; ++i)
		if (!strcmp(sorted[i - 1]->output, sorted[i]->output))
			r = vn_io_fail(error, vn_io_error_option,
			               "'%s' and '%s' would both be written to '%s': convert them into different folders",
			               sorted[i - 1]->input, sorted[i]->input, sorted[i]->output);
	free(sorted);
	for (size_t i = 0; i < plan->count && r == vn_io_success; ++i)
		if (!o->in_place && vn_io_same_file(plan->files[i].input, plan->files[i].output))
			r = vn_io_fail(error, vn_io_error_same_file, "output '%s' is the input; pass --in-place to overwrite it",
			               plan->files[i].output);
	return r;
}

vn_io_result vn_io_batch_plan(const char* const* inputs, size_t count, const char* out_dir, int recursive,
                              const vn_convert_options* options, vn_batch_plan* plan, vn_io_error* error)
{
	static const vn_convert_options defaults;
	const vn_convert_options* o = options ? options : &defaults;
	memset(plan, 0, sizeof *plan);
	if (!out_dir || !*out_dir)
		return vn_io_fail(error, vn_io_error_option, "%s", "a batch needs an output folder (--out-dir DIR)");
	planner p = {plan, 0, out_dir, NULL, NULL, recursive, error};
	/* vn_io_convert_option set these to format names it checked. */
	if ((o->input_format && !(p.in_format = vn_io_format_by_name(o->input_format))) ||
	    (o->output_format && !(p.out_format = vn_io_format_by_name(o->output_format))))
		return vn_io_fail(error, vn_io_error_format, "no format is called '%s'",
		                  p.in_format || !o->input_format ? o->output_format : o->input_format);
	vn_io_result r = vn_io_success;
	for (size_t i = 0; i < count && r == vn_io_success; ++i) {
		const char* in = inputs[i];
		struct stat st;
		if (!strcmp(in, "-"))
			r = vn_io_fail(error, vn_io_error_option, "%s",
			               "'-' (standard input) is for one file: give IN OUT without --out-dir");
		else if (stat(in, &st) == 0 && S_ISDIR(st.st_mode))
			r = add_folder(&p, in, "");
		else if (!p.in_format && !vn_io_format_for_path(in)) {
			char text[sizeof error->message];
			vn_io_unknown_format(in, 1, text, sizeof text);
			r = vn_io_fail(error, vn_io_error_format, "%s", text);
		} else
			r = add_file(&p, in, strrchr(in, '/') ? strrchr(in, '/') + 1 : in, p.in_format);
	}
	if (r == vn_io_success)
		r = check(plan, o, error);
	if (r == vn_io_success)
		r = make_folders(out_dir, error);
	for (size_t i = 0; i < plan->count && r == vn_io_success; ++i) {
		const char* output = plan->files[i].output;
		char* folder = joined(output, (size_t)(strrchr(output, '/') - output), "");
		r = folder ? make_folders(folder, error) : out_of_memory(error);
		free(folder);
	}
	if (r != vn_io_success)
		vn_io_batch_plan_free(plan);
	return r;
}

void vn_io_batch_plan_free(vn_batch_plan* plan)
{
	if (!plan)
		return;
	for (size_t i = 0; i < plan->count; ++i) {
		free(plan->files[i].input);
		free(plan->files[i].output);
	}
	free(plan->files);
	memset(plan, 0, sizeof *plan);
}
