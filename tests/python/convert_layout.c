/* The layout of vn_convert.h's structs as the C compiler makes it, for
 * tests/python/test_convert.py to check the ctypes copies in
 * python/vn/_convert.py against: "STRUCT FIELD OFFSET" lines, then
 * "STRUCT sizeof SIZE". */
#include <stddef.h>
#include <stdio.h>

#include "vn_convert.h"

#define FIELD(s, f) printf("%s %s %zu\n", #s, #f, offsetof(s, f))
#define SIZE(s) printf("%s sizeof %zu\n", #s, sizeof(s))

int main(void)
{
	FIELD(vn_convert_options, input_format);
	FIELD(vn_convert_options, output_format);
	FIELD(vn_convert_options, method);
	FIELD(vn_convert_options, threads);
	FIELD(vn_convert_options, in_place);
	FIELD(vn_convert_options, no_weld);
	FIELD(vn_convert_options, weld_epsilon);
	FIELD(vn_convert_options, crease);
	FIELD(vn_convert_options, crease_angle);
	FIELD(vn_convert_options, weld_scope);
	FIELD(vn_convert_options, tangents);
	FIELD(vn_convert_options, draco);
	FIELD(vn_convert_options, meshopt);
	FIELD(vn_convert_options, draco_qp);
	FIELD(vn_convert_options, draco_qn);
	FIELD(vn_convert_options, draco_qt);
	FIELD(vn_convert_options, draco_qc);
	FIELD(vn_convert_options, draco_cl_set);
	FIELD(vn_convert_options, draco_cl);
	FIELD(vn_convert_options, apply_transforms);
	FIELD(vn_convert_options, stats);
	FIELD(vn_convert_options, ignore_misfits);
	FIELD(vn_convert_options, image_names_from_output);
	FIELD(vn_convert_options, input_is_copy);
	FIELD(vn_convert_options, progress);
	FIELD(vn_convert_options, progress_context);
	SIZE(vn_convert_options);
	FIELD(vn_convert_report, warnings);
	FIELD(vn_convert_report, stats);
	FIELD(vn_convert_report, input_format);
	FIELD(vn_convert_report, output_format);
	FIELD(vn_convert_report, method);
	FIELD(vn_convert_report, threads);
	FIELD(vn_convert_report, vertices);
	FIELD(vn_convert_report, faces);
	FIELD(vn_convert_report, triangles);
	FIELD(vn_convert_report, welded_vertices);
	FIELD(vn_convert_report, hard_edges);
	FIELD(vn_convert_report, split_vertices);
	FIELD(vn_convert_report, zero_normals);
	FIELD(vn_convert_report, degenerate_faces);
	FIELD(vn_convert_report, read_seconds);
	FIELD(vn_convert_report, normals_seconds);
	FIELD(vn_convert_report, write_seconds);
	FIELD(vn_convert_report, seconds);
	FIELD(vn_convert_report, draco_normals_compared);
	FIELD(vn_convert_report, draco_normal_bits);
	FIELD(vn_convert_report, draco_normal_median_degrees);
	FIELD(vn_convert_report, draco_normal_max_degrees);
	SIZE(vn_convert_report);
	FIELD(vn_batch_file, input);
	FIELD(vn_batch_file, output);
	FIELD(vn_batch_file, input_format);
	FIELD(vn_batch_file, output_format);
	SIZE(vn_batch_file);
	FIELD(vn_batch_plan, files);
	FIELD(vn_batch_plan, count);
	FIELD(vn_batch_plan, skipped);
	FIELD(vn_batch_plan, unentered);
	SIZE(vn_batch_plan);
	return 0;
}
