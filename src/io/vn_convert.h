/*
 * vn_convert: one file conversion, as vnconvert does it (read, recompute the
 * normals, write), behind one entry point that vnconvert and the Python
 * package (through libvnio.so) both call, so that the conversion, its
 * checks and its messages exist once.
 *
 * Options follow cgltf's and meshoptimizer's style: an all-zero
 * vn_convert_options is the defaults (mwa, every core, welding, Draco bits
 * from the input or vn_drc_default_options). Each vnconvert flag that
 * shapes a conversion has a field, and vn_io_convert_option sets a field
 * from the flag's name and value as vnconvert's command line gives them,
 * with vnconvert's messages.
 *
 * Nothing is printed: warnings and what `vnconvert --stats` shows come back
 * in a vn_convert_report, an error as one line in a vn_io_error.
 */
#ifndef VN_CONVERT_H
#define VN_CONVERT_H

#include "vn_io.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vn_convert_options {
	const char* input_format;  /* a format name ("off", "glb": --input-format); NULL: IN's extension */
	const char* output_format; /* --format; NULL: OUT's extension */
	const char* method;        /* a vn_method_name ("mwa"); NULL: mwa */
	unsigned threads;          /* 1 to 256; 0: every core. Results do not depend on it */
	int in_place;              /* OUT may be IN (otherwise refused) */
	int no_weld;               /* compute on the vertices as the file splits them */
	double weld_epsilon;       /* weld vertices whose coordinates all differ by at most this */
	int crease;                /* hard edges where faces meet at more than crease_angle */
	double crease_angle;       /* degrees, 0 to 180 */
	/* glTF to glTF only; NULL: the default (the first value named). */
	const char* weld_scope; /* "primitive" or "mesh" */
	const char* tangents;   /* "keep" or "drop" */
	const char* draco;      /* "keep", "off" or "on" */
	const char* meshopt;    /* "keep" or "off" */
	/* Draco output: quantization bits (0: a .drc input's, else the default)
	 * and, when draco_cl_set, the compression level (0 to 10). */
	int draco_qp, draco_qn, draco_qt, draco_qc;
	int draco_cl_set, draco_cl;
	int apply_transforms; /* glTF written as a format without a scene graph: the scene as drawn */

	/* Not vnconvert flags. */
	int stats; /* fill vn_convert_report.stats (Draco output: one more encoding, for the normal error) */
	/* Options that do not apply to this pair of formats are ignored rather
	 * than refused: a batch, where they apply to some other files. */
	int ignore_misfits;
	/* Images a .gltf output copies are named OUTSTEM_NAME (vnconvert --out-dir). */
	int image_names_from_output;
	/* IN is a temporary copy (vnconvert's '-'): an OBJ's material library
	 * names are written as read, not made relative to IN's folder. */
	int input_is_copy;
	/* Called before reading and writing (what: "reading", "writing",
	 * "converting"); NULL: not called. */
	void (*progress)(void* context, const char* what, const char* path);
	void* progress_context;
} vn_convert_options;

typedef struct vn_convert_report {
	/* NULL or lines, each ending with '\n': what the conversion warns about
	 * ("out.stl cannot hold vertex normals: not written"). */
	char* warnings;
	/* With options.stats: what vnconvert --stats prints ("vertices: 8"
	 * lines); else NULL. */
	char* stats;
	const char* input_format; /* format names, as resolved */
	const char* output_format;
	const char* method;
	unsigned threads;
	size_t vertices;  /* input vertices (glTF to glTF: of the primitives processed) */
	size_t faces;     /* input faces */
	size_t triangles; /* triangles written (polygons fan-triangulated) */
	size_t welded_vertices, hard_edges, split_vertices, zero_normals, degenerate_faces;
	double read_seconds, normals_seconds, write_seconds; /* 0 on the glTF to glTF path */
	double seconds;                                     /* the whole conversion */
	/* Draco output with options.stats: the angle normal quantization adds
	 * (glTF to glTF: of the primitives at the finest normal bits). */
	size_t draco_normals_compared;
	int draco_normal_bits;
	double draco_normal_median_degrees, draco_normal_max_degrees;
} vn_convert_report;

/* Converts the file `in` to `out` (written atomically: on failure it is as
 * it was). options NULL: the defaults. report (may be NULL) is zeroed, then
 * filled, also on failure (the warnings until then); free it with
 * vn_io_convert_report_free. Returns vn_io_error_option for an option
 * value out of range or not applying to this pair of formats,
 * vn_io_error_format for a format not known, vn_io_error_same_file, or
 * what reading, computing or writing failed with. */
VN_IO_API vn_io_result vn_io_convert(const char* in, const char* out, const vn_convert_options* options,
                                     vn_convert_report* report, vn_io_error* error);

/* Frees what the report holds and zeroes it; NULL is fine. */
VN_IO_API void vn_io_convert_report_free(vn_convert_report* report);

/* Whether vnconvert flag `name` ("--draco-qp", "-m") sets an option: 1
 * when it takes a value, 0 when it is a switch, -1 when it is no option
 * of a conversion. */
VN_IO_API int vn_io_convert_option_arity(const char* name);

/* Sets the field of flag `name` from `value` (ignored for a switch) as
 * vnconvert parses it, or fails with vnconvert's message and
 * vn_io_error_option ("--draco-qp needs a whole number of bits from 1 to
 * 30, not '31'"). String fields are set to static text. */
VN_IO_API vn_io_result vn_io_convert_option(vn_convert_options* options, const char* name, const char* value,
                                            vn_io_error* error);

/* ------------------------------------------------------------------ batches
 *
 * A batch (vnconvert --out-dir, the Python package's convert with out_dir,
 * vn.dask) converts many files into one folder. vn_io_batch_plan says which
 * file goes where and makes every check before the first conversion; each
 * file is then one vn_io_convert(input, output) with input_format and
 * output_format set from its vn_batch_file, ignore_misfits and
 * image_names_from_output set, as vnconvert's batch does (same bytes). */

typedef struct vn_batch_file {
	char* input;               /* as named, or FOLDER/NAME for a folder's file */
	char* output;              /* OUT_DIR/PATH/STEM.EXT */
	const char* input_format;  /* format names (static text) */
	const char* output_format;
} vn_batch_file;

typedef struct vn_batch_plan {
	vn_batch_file* files; /* count of them, in the order of the inputs, a folder's files in name order */
	size_t count;
	size_t skipped;   /* folder entries of no format vn reads (passed over) */
	size_t unentered; /* subfolders not entered (recursive 0) */
} vn_batch_plan;

/* Plans converting inputs[0 .. count) into the folder out_dir. An input is
 * a file, or a folder whose files of a format vn reads (by extension;
 * hidden entries passed over) are taken in name order; with recursive its
 * subfolders too, their layout kept under out_dir. A file goes to
 * out_dir/STEM.EXT, EXT being options->output_format's first extension,
 * else the input's own. options->input_format applies to the files named,
 * not to a folder's. Refuses, before anything is written, with
 * vn_io_error_option: '-', two inputs that would have one output, an option
 * given in `options` that applies to no file (one that applies to some
 * applies to those); vn_io_error_same_file: an output that is its input
 * (unless options->in_place); vn_io_error_format: a file named whose
 * extension names no format. Then creates out_dir and the folders of the
 * outputs (vn_io_error_write when it cannot). options NULL: the defaults.
 * *plan is zeroed, then filled on success; free it with
 * vn_io_batch_plan_free. */
VN_IO_API vn_io_result vn_io_batch_plan(const char* const* inputs, size_t count, const char* out_dir, int recursive,
                                        const vn_convert_options* options, vn_batch_plan* plan, vn_io_error* error);

/* Frees what the plan holds and zeroes it; NULL is fine. */
VN_IO_API void vn_io_batch_plan_free(vn_batch_plan* plan);

/* What an option given in `options` that does not apply to converting `in`
 * to `out` applies to ("--tangents applies only to glTF to glTF
 * conversions (.gltf or .glb in and out)"), into text; 0 when every option
 * applies, else 1. */
int vn_io_convert_misfit(const vn_convert_options* options, const vn_io_format* in, const vn_io_format* out,
                         char* text, size_t size);

/* vn_io_error_option with "MISFIT, and this one is off to glb: leave it
 * out" when an option does not apply (the check vn_io_convert starts with,
 * unless options->ignore_misfits). */
vn_io_result vn_io_convert_check(const vn_convert_options* options, const vn_io_format* in, const vn_io_format* out,
                                 vn_io_error* error);

#ifdef __cplusplus
}
#endif

#endif /* VN_CONVERT_H */
