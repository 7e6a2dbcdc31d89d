/*
 * vn_io_convert (vn_convert.h), called directly: a zeroed options struct is
 * the defaults, its output is vnconvert's byte for byte, errors come back
 * as vnconvert's one-line messages with nothing written, options are set
 * and checked as vnconvert's flags are, warnings and --stats come back in
 * the report; vn_io_batch_plan names a batch's outputs and refuses what
 * vnconvert --out-dir refuses, before anything is written.
 *
 *   test_convert VNCONVERT    (run from tests/)
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, sysconf */

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test_files.h"
#include "vn_convert.h"

static char folder[64]; /* the temporary folder, made by main */
static const char* vnconvert;

/* folder/name, in a static buffer of one of 4 slots (several per call). */
static const char* in_folder(const char* name)
{
	static char paths[4][256];
	static int next;
	char* p = paths[next++ % 4];
	snprintf(p, sizeof paths[0], "%s/%s", folder, name);
	return p;
}

static void write_text(const char* path, const char* text)
{
	FILE* f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fputs(text, f) >= 0, 1);
	assert_int_equal(fclose(f), 0);
}

/* The whole file; the caller frees it. */
static char* slurp(const char* path, size_t* size)
{
	char* data;
	vn_io_error error;
	assert_int_equal(vn_io_read_all(path, &data, size, &error), vn_io_success);
	return data;
}

static void assert_same_bytes(const char* a, const char* b)
{
	size_t na, nb;
	char *x = slurp(a, &na), *y = slurp(b, &nb);
	assert_int_equal(na, nb);
	assert_memory_equal(x, y, na);
	free(x);
	free(y);
}

static int exists(const char* path)
{
	return access(path, F_OK) == 0;
}

/* ------------------------------------------------------------------ defaults */

static void test_zeroed_options_are_the_defaults(void** state)
{
	(void)state;
	vn_convert_options zero, given;
	memset(&zero, 0, sizeof zero);
	memset(&given, 0, sizeof given);
	vn_convert_report r;
	vn_io_error error;
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("zero.off"), &zero, &r, &error), vn_io_success);
	assert_string_equal(r.input_format, "off");
	assert_string_equal(r.output_format, "off");
	assert_string_equal(r.method, "mwa");
	assert_int_equal(r.threads, (unsigned)sysconf(_SC_NPROCESSORS_ONLN));
	assert_int_equal(r.vertices, 8);
	assert_int_equal(r.faces, 6);
	assert_int_equal(r.triangles, 12);
	assert_int_equal(r.welded_vertices + r.hard_edges + r.split_vertices + r.zero_normals, 0);
	assert_null(r.warnings);
	assert_null(r.stats);
	vn_io_convert_report_free(&r);
	/* The defaults spelt out, and no options at all: the same bytes. */
	given.method = "mwa";
	given.threads = 1;
	given.output_format = "off";
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("given.off"), &given, NULL, &error), vn_io_success);
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("null.off"), NULL, NULL, NULL), vn_io_success);
	assert_same_bytes(in_folder("zero.off"), in_folder("given.off"));
	assert_same_bytes(in_folder("zero.off"), in_folder("null.off"));
}

/* OFF to GLB, and with crease angle and Draco bits to .drc: vnconvert's bytes. */
static void test_output_is_vnconvert_s(void** state)
{
	(void)state;
	char command[1024];
	snprintf(command, sizeof command, "'%s' ../samples/torus.off '%s' -q && '%s' ../samples/torus.off '%s' -q "
	         "--crease-angle 40 --draco-qn 12 --draco-cl 0 --method mwselr",
	         vnconvert, in_folder("cli.glb"), vnconvert, in_folder("cli.drc"));
	assert_int_equal(system(command), 0);
	vn_io_error error;
	assert_int_equal(vn_io_convert("../samples/torus.off", in_folder("lib.glb"), NULL, NULL, &error), vn_io_success);
	assert_same_bytes(in_folder("cli.glb"), in_folder("lib.glb"));
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	o.crease = 1;
	o.crease_angle = 40;
	o.draco_qn = 12;
	o.draco_cl_set = 1; /* level 0 */
	o.method = "mwselr";
	vn_convert_report r;
	assert_int_equal(vn_io_convert("../samples/torus.off", in_folder("lib.drc"), &o, &r, &error), vn_io_success);
	assert_same_bytes(in_folder("cli.drc"), in_folder("lib.drc"));
	assert_string_equal(r.method, "mwselr");
	assert_int_equal(r.draco_normal_bits, 0); /* measured with stats only */
	vn_io_convert_report_free(&r);
}

/* ------------------------------------------------------------------ errors */

static void test_missing_input(void** state)
{
	(void)state;
	vn_convert_report r;
	vn_io_error error;
	assert_int_equal(vn_io_convert("data/off/missing.off", in_folder("missing.glb"), NULL, &r, &error),
	                 vn_io_error_open);
	assert_string_equal(error.message, "data/off/missing.off: cannot open: No such file or directory");
	assert_false(exists(in_folder("missing.glb")));
	assert_null(r.warnings);
}

/* A malformed input leaves an existing output as it was, and a new one unmade. */
static void test_failure_writes_nothing(void** state)
{
	(void)state;
	char bad[256];
	snprintf(bad, sizeof bad, "%s", in_folder("bad.off"));
	write_text(bad, "OFF\n3 1 0\n0 0 0\n1 0 0\n");
	write_text(in_folder("kept.off"), "old\n");
	vn_io_error error;
	assert_int_equal(vn_io_convert(bad, in_folder("kept.off"), NULL, NULL, &error), vn_io_error_parse);
	char expected[512];
	snprintf(expected, sizeof expected,
	         "%s:2: the header announces 3 vertices and 1 faces, more than the 12 bytes that follow can hold", bad);
	assert_string_equal(error.message, expected);
	size_t n;
	char* kept = slurp(in_folder("kept.off"), &n);
	assert_string_equal(kept, "old\n");
	free(kept);
	assert_int_equal(vn_io_convert(bad, in_folder("new.drc"), NULL, NULL, &error), vn_io_error_parse);
	assert_false(exists(in_folder("new.drc")));
}

static void test_option_that_does_not_apply(void** state)
{
	(void)state;
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	o.draco_qp = 12;
	vn_io_error error;
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("misfit.off"), &o, NULL, &error),
	                 vn_io_error_option);
	assert_string_equal(error.message, "--draco-qp applies to Draco (.drc) output, to glTF to glTF conversions and "
	                                   "to glTF output with --draco on, and this one is off to off: leave it out");
	memset(&o, 0, sizeof o);
	o.tangents = "drop";
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("misfit.glb"), &o, NULL, &error),
	                 vn_io_error_option);
	assert_string_equal(error.message, "--tangents applies only to glTF to glTF conversions (.gltf or .glb in and "
	                                   "out), and this one is off to glb: leave it out");
	assert_false(exists(in_folder("misfit.off")));
	assert_false(exists(in_folder("misfit.glb")));
	/* A batch's file that the option is not for: converted without it. */
	o.ignore_misfits = 1;
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("misfit.glb"), &o, NULL, &error), vn_io_success);
}

static void test_output_is_input(void** state)
{
	(void)state;
	char path[256];
	snprintf(path, sizeof path, "%s", in_folder("self.off"));
	write_text(path, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
	vn_io_error error;
	assert_int_equal(vn_io_convert(path, path, NULL, NULL, &error), vn_io_error_same_file);
	char expected[512];
	snprintf(expected, sizeof expected, "output '%s' is the input; pass --in-place to overwrite it", path);
	assert_string_equal(error.message, expected);
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	o.in_place = 1;
	assert_int_equal(vn_io_convert(path, path, &o, NULL, &error), vn_io_success);
}

static void test_unknown_format(void** state)
{
	(void)state;
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	o.output_format = "stp";
	vn_io_error error;
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("x.stp"), &o, NULL, &error), vn_io_error_option);
	assert_string_equal(error.message, "--format is one of off, obj, ply, stl, gltf, glb, drc, not 'stp'");
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("x.stp"), NULL, NULL, &error), vn_io_error_format);
	assert_non_null(strstr(error.message, "cannot tell the format of '"));
}

/* ------------------------------------------------------------------ options by flag */

static void test_options_set_as_vnconvert_parses_them(void** state)
{
	(void)state;
	assert_int_equal(vn_io_convert_option_arity("--draco-qp"), 1);
	assert_int_equal(vn_io_convert_option_arity("-m"), 1);
	assert_int_equal(vn_io_convert_option_arity("--no-weld"), 0);
	assert_int_equal(vn_io_convert_option_arity("--stats"), -1);
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	vn_io_error error;
	assert_int_equal(vn_io_convert_option(&o, "-m", "MWAAT", &error), vn_io_success);
	assert_string_equal(o.method, "mwaat");
	assert_int_equal(vn_io_convert_option(&o, "--draco-cl", "0", &error), vn_io_success);
	assert_int_equal(o.draco_cl_set, 1);
	assert_int_equal(o.draco_cl, 0);
	assert_int_equal(vn_io_convert_option(&o, "--crease-angle", "30", &error), vn_io_success);
	assert_int_equal(o.crease, 1);
	assert_true(o.crease_angle == 30);
	assert_int_equal(vn_io_convert_option(&o, "--weld-scope", "mesh", &error), vn_io_success);
	assert_string_equal(o.weld_scope, "mesh");
	assert_int_equal(vn_io_convert_option(&o, "--no-weld", NULL, &error), vn_io_success);
	assert_int_equal(o.no_weld, 1);
	assert_int_equal(vn_io_convert_option(&o, "--draco-qp", "31", &error), vn_io_error_option);
	assert_string_equal(error.message, "--draco-qp needs a whole number of bits from 1 to 30, not '31'");
	assert_int_equal(vn_io_convert_option(&o, "--tangents", "strip", &error), vn_io_error_option);
	assert_string_equal(error.message, "--tangents is keep or drop, not 'strip'");
	assert_int_equal(vn_io_convert_option(&o, "--threads", NULL, &error), vn_io_error_option);
	assert_string_equal(error.message, "option --threads needs a value");
	assert_int_equal(vn_io_convert_option(&o, "--stats", NULL, &error), vn_io_error_option);
	assert_string_equal(error.message, "unknown option '--stats' (see --help)");
}

/* Fields set directly are checked as if given as flags. */
static void test_fields_out_of_range(void** state)
{
	(void)state;
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	o.draco_qn = 1;
	vn_io_error error;
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("range.drc"), &o, NULL, &error),
	                 vn_io_error_option);
	assert_string_equal(error.message, "--draco-qn needs a whole number of bits from 2 to 30, not '1'");
	memset(&o, 0, sizeof o);
	o.method = "mwz";
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("range.drc"), &o, NULL, &error),
	                 vn_io_error_option);
	assert_string_equal(error.message, "--method is one of mwe, mwa, mwselr, mwaat, mwelr, mwrelr, mewcsa, smewcsa, quadric, jet, adaptive, not 'mwz' "
	                                   "(see --list-methods)");
	memset(&o, 0, sizeof o);
	o.crease = 1;
	o.crease_angle = 181;
	assert_int_equal(vn_io_convert("data/off/cube.off", in_folder("range.drc"), &o, NULL, &error),
	                 vn_io_error_option);
	assert_string_equal(error.message, "--crease-angle needs a number of degrees from 0 to 180, not '181'");
	assert_false(exists(in_folder("range.drc")));
}

/* ------------------------------------------------------------------ the report */

static void test_warnings_and_stats_in_the_report(void** state)
{
	(void)state;
	char in[256];
	snprintf(in, sizeof in, "%s", in_folder("isolated.off"));
	write_text(in, "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n5 5 5\n3 0 1 2\n");
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	o.stats = 1;
	o.threads = 1;
	vn_convert_report r;
	vn_io_error error;
	assert_int_equal(vn_io_convert(in, in_folder("isolated.drc"), &o, &r, &error), vn_io_success);
	assert_string_equal(r.warnings,
	                    "1 of 4 vertices has no normal (isolated, only degenerate faces, or faces whose normals cancel); "
	                    "written as the zero vector (Draco's octahedral coding decodes it as (1, 0, 0))\n"
	                    "4 vertices and 1 triangle: only the vertices faces use are written, as Draco cannot store "
	                    "more than 3 points per triangle\n");
	assert_int_equal(r.zero_normals, 1);
	assert_int_equal(r.triangles, 1);
	char head[512];
	snprintf(head, sizeof head,
	         "input:              %s (off)\noutput:             %s (drc)\nmethod:             mwa\n"
	         "vertices:           4\nfaces:              1 (triangles)\n",
	         in, in_folder("isolated.drc"));
	assert_non_null(r.stats);
	assert_memory_equal(r.stats, head, strlen(head));
	assert_non_null(strstr(r.stats, "\nzero normals:       1\nthreads:            1\n"));
	assert_non_null(strstr(r.stats, "\ndraco settings:     qp=14 qn=10 qt=12 qc=8 cl=7\n"));
	assert_int_equal(r.draco_normal_bits, 10);
	assert_int_equal(r.draco_normals_compared, 3);
	vn_io_convert_report_free(&r);
	assert_null(r.warnings);
	assert_null(r.stats);
}

/* ------------------------------------------------------------------ batch plans */

/* A folder of three models, a file of no format vn reads, a hidden file
 * and a subfolder, with and without recursion; a file named with
 * --input-format. */
static void test_batch_plan_names_outputs(void** state)
{
	(void)state;
	char in[128], path[256]; /* in_folder's slots are reused */
	snprintf(in, sizeof in, "%.100s", in_folder("plan_in"));
	assert_int_equal(mkdir(in, 0777), 0);
	snprintf(path, sizeof path, "%s/sub", in);
	assert_int_equal(mkdir(path, 0777), 0);
	const char* names[] = {"b.off", "a.Glb", "notes.txt", ".hidden.off", "sub/c.drc"};
	for (size_t i = 0; i < sizeof names / sizeof *names; ++i) {
		snprintf(path, sizeof path, "%s/%s", in, names[i]);
		write_text(path, "x");
	}
	char out[256];
	snprintf(out, sizeof out, "%s", in_folder("plan_out/"));
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	vn_batch_plan plan;
	vn_io_error error;
	const char* inputs[] = {in, "data/off/cube.off"};
	assert_int_equal(vn_io_batch_plan(inputs, 2, out, 0, &o, &plan, &error), vn_io_success);
	assert_int_equal(plan.count, 3);
	assert_int_equal(plan.skipped, 1);
	assert_int_equal(plan.unentered, 1);
	snprintf(path, sizeof path, "%s/a.Glb", in);
	assert_string_equal(plan.files[0].input, path);
	assert_string_equal(plan.files[0].output, in_folder("plan_out/a.Glb"));
	assert_string_equal(plan.files[0].input_format, "glb");
	assert_string_equal(plan.files[0].output_format, "glb");
	assert_string_equal(plan.files[1].output, in_folder("plan_out/b.off"));
	assert_string_equal(plan.files[2].input, "data/off/cube.off");
	assert_string_equal(plan.files[2].output, in_folder("plan_out/cube.off"));
	assert_true(exists(out));
	vn_io_batch_plan_free(&plan);
	assert_null(plan.files);
	assert_int_equal(plan.count, 0);
	/* Recursive, to one format: the subfolder's layout, made under out. */
	o.output_format = "drc";
	assert_int_equal(vn_io_batch_plan(inputs, 1, out, 1, &o, &plan, &error), vn_io_success);
	assert_int_equal(plan.count, 3);
	assert_int_equal(plan.unentered, 0);
	assert_string_equal(plan.files[0].output, in_folder("plan_out/a.drc"));
	assert_string_equal(plan.files[2].output, in_folder("plan_out/sub/c.drc"));
	assert_string_equal(plan.files[2].input_format, "drc");
	assert_true(exists(in_folder("plan_out/sub")));
	vn_io_batch_plan_free(&plan);
	/* --input-format names the format of a file named, whatever its name. */
	o.output_format = NULL;
	o.input_format = "off";
	snprintf(path, sizeof path, "%s/notes.txt", in);
	const char* named[] = {path};
	assert_int_equal(vn_io_batch_plan(named, 1, out, 0, &o, &plan, &error), vn_io_success);
	assert_int_equal(plan.count, 1);
	assert_string_equal(plan.files[0].output, in_folder("plan_out/notes.txt")); /* the input's own extension */
	assert_string_equal(plan.files[0].output_format, "off");
	vn_io_batch_plan_free(&plan);
	vn_io_batch_plan_free(NULL);
}

static void test_batch_plan_refusals(void** state)
{
	(void)state;
	vn_batch_plan plan;
	vn_io_error error;
	char text[512];
	const char* twice[] = {"data/off/cube.off", "../samples/torus.off", "data/off/cube.off"};
	assert_int_equal(vn_io_batch_plan(twice, 3, in_folder("refused"), 0, NULL, &plan, &error), vn_io_error_option);
	snprintf(text, sizeof text,
	         "'data/off/cube.off' and 'data/off/cube.off' would both be written to '%s': convert them into "
	         "different folders",
	         in_folder("refused/cube.off"));
	assert_string_equal(error.message, text);
	assert_null(plan.files);
	assert_false(exists(in_folder("refused"))); /* nothing made before the checks */
	const char* self[] = {"data/off/cube.off"};
	assert_int_equal(vn_io_batch_plan(self, 1, "data/off", 0, NULL, &plan, &error), vn_io_error_same_file);
	assert_string_equal(error.message, "output 'data/off/cube.off' is the input; pass --in-place to overwrite it");
	vn_convert_options o;
	memset(&o, 0, sizeof o);
	o.in_place = 1;
	assert_int_equal(vn_io_batch_plan(self, 1, "data/off", 0, &o, &plan, &error), vn_io_success);
	vn_io_batch_plan_free(&plan);
	/* --tangents applies to glTF to glTF only: refused for OFF files alone. */
	o.in_place = 0;
	o.tangents = "drop";
	assert_int_equal(vn_io_batch_plan(self, 1, in_folder("refused"), 0, &o, &plan, &error), vn_io_error_option);
	assert_string_equal(error.message, "--tangents applies only to glTF to glTF conversions (.gltf or .glb in and "
	                                   "out), and no file of this batch is converted so: leave it out");
	const char* dash[] = {"-"};
	assert_int_equal(vn_io_batch_plan(dash, 1, in_folder("refused"), 0, NULL, &plan, &error), vn_io_error_option);
	const char* unknown[] = {"data/model.xyz"};
	assert_int_equal(vn_io_batch_plan(unknown, 1, in_folder("refused"), 0, NULL, &plan, &error), vn_io_error_format);
	assert_int_equal(vn_io_batch_plan(self, 1, "", 0, NULL, &plan, &error), vn_io_error_option);
	const char* none[] = {in_folder("no_such_folder/")};
	assert_int_equal(vn_io_batch_plan(none, 1, in_folder("refused"), 0, NULL, &plan, &error), vn_io_error_format);
	assert_false(exists(in_folder("refused")));
}

int main(int argc, char** argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: test_convert VNCONVERT\n");
		return 2;
	}
	vnconvert = argv[1];
	snprintf(folder, sizeof folder, "%s", "/tmp/vn_test_convert.XXXXXX");
	if (!mkdtemp(folder))
		return 1;
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_zeroed_options_are_the_defaults),
	    cmocka_unit_test(test_output_is_vnconvert_s),
	    cmocka_unit_test(test_missing_input),
	    cmocka_unit_test(test_failure_writes_nothing),
	    cmocka_unit_test(test_option_that_does_not_apply),
	    cmocka_unit_test(test_output_is_input),
	    cmocka_unit_test(test_unknown_format),
	    cmocka_unit_test(test_options_set_as_vnconvert_parses_them),
	    cmocka_unit_test(test_fields_out_of_range),
	    cmocka_unit_test(test_warnings_and_stats_in_the_report),
	    cmocka_unit_test(test_batch_plan_names_outputs),
	    cmocka_unit_test(test_batch_plan_refusals),
	};
	const int failed = cmocka_run_group_tests(tests, NULL, NULL);
	remove_tree(folder);
	return failed;
}
