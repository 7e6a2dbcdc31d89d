/*
 * vn_io and the OFF format: reading every header variant, colours, polygons,
 * binary files, the exact error messages of malformed files, write/read
 * round trips and the atomic writer.
 *
 * Runs from tests/ (fixtures in data/off/); malformed inputs are written to a
 * temporary folder from the literals next to their expected message.
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, link, symlink, umask */

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "off.h"
#include "test_files.h"
#include "text.h"
#include "vn_io.h"

/* ------------------------------------------------------------------ helpers */

static char folder[64]; /* the temporary folder, made by main */

static void path_in_folder(char* out, size_t size, const char* name)
{
	snprintf(out, size, "%s/%s", folder, name);
}

static void write_bytes(const char* name, const void* data, size_t size)
{
	char path[256];
	path_in_folder(path, sizeof path, name);
	FILE* f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(data, 1, size, f), size);
	assert_int_equal(fclose(f), 0);
}

/* The whole file as a string; the caller frees it. */
static char* slurp(const char* path)
{
	char* data;
	size_t size;
	vn_io_error error;
	assert_int_equal(vn_io_read_all(path, &data, &size, &error), vn_io_success);
	return data;
}

/* Exact comparison that shows both values on failure. */
#define assert_exact(actual, expected)                                                                    \
	do {                                                                                                  \
		double actual_ = (actual), expected_ = (expected);                                                \
		if (!(actual_ == expected_))                                                                      \
			fail_msg("%s is %.17g, expected %.17g", #actual, actual_, expected_);                         \
	} while (0)

static void assert_doubles(const double* actual, const double* expected, size_t count)
{
	for (size_t i = 0; i < count; i++)
		if (!(actual[i] == expected[i]))
			fail_msg("element %zu is %.17g, expected %.17g", i, actual[i], expected[i]);
}

static void assert_floats(const float* actual, const float* expected, size_t count)
{
	for (size_t i = 0; i < count; i++)
		if (!(actual[i] == expected[i]))
			fail_msg("element %zu is %.9g, expected %.9g", i, actual[i], expected[i]);
}

static void assert_u32s(const uint32_t* actual, const uint32_t* expected, size_t count)
{
	for (size_t i = 0; i < count; i++)
		if (actual[i] != expected[i])
			fail_msg("element %zu is %u, expected %u", i, (unsigned)actual[i], (unsigned)expected[i]);
}

static void read_path_ok(const char* path, vn_io_mesh* mesh)
{
	vn_io_error error;
	vn_io_result r = vn_io_read_file(path, NULL, mesh, &error);
	if (r != vn_io_success)
		fail_msg("%s", error.message);
}

/* Writes size bytes to <folder>/name, reads it and requires success. */
static void read_bytes_ok(const char* name, const void* data, size_t size, vn_io_mesh* mesh)
{
	char path[256];
	write_bytes(name, data, size);
	path_in_folder(path, sizeof path, name);
	read_path_ok(path, mesh);
}

static void read_ok(const char* text, vn_io_mesh* mesh)
{
	read_bytes_ok("good.off", text, strlen(text), mesh);
}

/* Reads size bytes as <folder>/bad.off and requires `expected` with the
 * message "<folder>/" + message; the mesh must come back zeroed. */
static void expect_error_bytes(const void* data, size_t size, vn_io_result expected, const char* message)
{
	char path[256], full[600];
	vn_io_mesh mesh;
	vn_io_error error;
	write_bytes("bad.off", data, size);
	path_in_folder(path, sizeof path, "bad.off");
	memset(&mesh, 0xAB, sizeof mesh);
	vn_io_result r = vn_io_read_file(path, NULL, &mesh, &error);
	if (r != expected)
		fail_msg("result %d (%s), expected %d; message: %s", (int)r, vn_io_result_string(r), (int)expected,
		         r == vn_io_success ? "" : error.message);
	snprintf(full, sizeof full, "%s/%s", folder, message);
	assert_string_equal(error.message, full);
	assert_null(mesh.positions);
	assert_null(mesh.indices);
	assert_int_equal(mesh.vertex_count, 0);
}

static void expect_error(const char* text, vn_io_result expected, const char* message)
{
	expect_error_bytes(text, strlen(text), expected, message);
}

/* A binary OFF file under construction: big-endian words after a text header. */
typedef struct bytes {
	unsigned char data[512];
	size_t size;
} bytes;

static void add_text(bytes* b, const char* text)
{
	size_t n = strlen(text);
	assert_true(b->size + n <= sizeof b->data);
	memcpy(b->data + b->size, text, n);
	b->size += n;
}

static void add_word(bytes* b, uint32_t w)
{
	assert_true(b->size + 4 <= sizeof b->data);
	for (int k = 0; k < 4; k++)
		b->data[b->size++] = (unsigned char)(w >> (24 - 8 * k));
}

static void add_ints(bytes* b, size_t count, const int32_t* v)
{
	for (size_t i = 0; i < count; i++)
		add_word(b, (uint32_t)v[i]);
}

static void add_floats(bytes* b, size_t count, const float* v)
{
	for (size_t i = 0; i < count; i++) {
		uint32_t w;
		memcpy(&w, &v[i], sizeof w);
		add_word(b, w);
	}
}

#define ADD_INTS(b, ...) add_ints((b), sizeof((int32_t[]){__VA_ARGS__}) / sizeof(int32_t), (int32_t[]){__VA_ARGS__})
#define ADD_FLOATS(b, ...) add_floats((b), sizeof((float[]){__VA_ARGS__}) / sizeof(float), (float[]){__VA_ARGS__})

/* The triangle (0,0,0) (1,0,0) (0,1,0) that most tests read. */
static const double triangle_positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
static const uint32_t triangle_offsets[2] = {0, 3};
static const uint32_t triangle_indices[3] = {0, 1, 2};

static void assert_triangle(const vn_io_mesh* m)
{
	assert_int_equal(m->vertex_count, 3);
	assert_doubles(m->positions, triangle_positions, 9);
	assert_int_equal(m->face_count, 1);
	assert_u32s(m->face_offsets, triangle_offsets, 2);
	assert_u32s(m->indices, triangle_indices, 3);
}

/* ------------------------------------------------------------------ header variants */

static void test_off_counts_on_next_line(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", &m);
	assert_triangle(&m);
	assert_null(m.normals);
	assert_null(m.colors);
	assert_null(m.texcoords);
	assert_null(m.face_colors);
	assert_int_equal(m.colors_are_bytes, 0);
	assert_true(vn_io_mesh_is_triangles(&m));
	vn_io_mesh_free(&m);
}

static void test_off_counts_on_header_line(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", &m);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
}

/* Geomview: the keyword is "recommended but optional, as many existing
 * files lack this keyword". A leading 4 is a count then, not 4OFF. */
static void test_off_without_keyword(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("# no keyword\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", &m);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
	read_ok("4 1 0\n0 0 0\n1 0 0\n0 1 0\n5 5 5\n3 0 1 2\n", &m);
	assert_int_equal(m.vertex_count, 4);
	assert_doubles(m.positions + 9, (const double[]){5, 5, 5}, 3);
	assert_u32s(m.indices, triangle_indices, 3);
	vn_io_mesh_free(&m);
}

/* Princeton's ModelNet: the vertex count right after the keyword. */
static void test_off_count_run_into_keyword(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", &m);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
	read_ok("NOFF3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", &m);
	assert_triangle(&m);
	assert_non_null(m.normals);
	assert_doubles(m.normals + 6, (const double[]){0, 0, 1}, 3);
	vn_io_mesh_free(&m);
}

static void test_off_two_counts(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2", &m); /* and no final line break */
	assert_triangle(&m);
	vn_io_mesh_free(&m);
}

static void test_off_comments_and_blank_lines(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("# written by hand\n"
	        "\n"
	        "OFF # the keyword\n"
	        "# counts next\n"
	        "\t\n"
	        "3 1 0 # vertices faces edges\n"
	        "0 0 0 # first\n"
	        "\n"
	        "#1 1 1 (a commented-out vertex)\n"
	        "1 0 0\n"
	        "  0 1 0#glued comment\n"
	        "3 0 1 2 # the face\n"
	        "# trailing comment\n"
	        "\n",
	        &m);
	assert_triangle(&m);
	/* The header's whole-line comments, for the writers; not those after
	 * the counts, nor those after data on a line. */
	assert_string_equal(m.comments, " written by hand\n counts next");
	vn_io_mesh_free(&m);
}

static void test_off_crlf_and_byte_order_mark(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("\xEF\xBB\xBFOFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n", &m);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
	/* UTF-16 and UTF-32 text (Windows PowerShell's '>' writes UTF-16LE) is
	 * read as its UTF-8; it was refused. A binary OFF's header cannot be. */
	static const char triangle[] = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
	for (size_t unit = 2; unit <= 4; unit += 2)
		for (int big = 0; big < 2; big++) {
			unsigned char wide[4 * sizeof triangle];
			size_t n = 0;
			for (size_t i = 0; i < sizeof triangle; i++) /* the mark U+FEFF, then the text */
				for (size_t b = 0; b < unit; b++) {
					const unsigned c = i ? (unsigned char)triangle[i - 1] : 0xFEFF;
					wide[n++] = (unsigned char)(c >> 8 * (big ? unit - 1 - b : b));
				}
			read_bytes_ok("good.off", wide, n, &m);
			assert_triangle(&m);
			vn_io_mesh_free(&m);
		}
	static const char binary[] = "\xFF\xFEO\0F\0F\0 \0B\0I\0N\0A\0R\0Y\0\n\0";
	expect_error_bytes(binary, sizeof binary - 1, vn_io_error_parse,
	                   "bad.off:1: the header is UTF-16LE text (it starts with a byte order mark), but says BINARY: "
	                   "binary data cannot be read as text");
	static const char lone[] = "\xFF\xFEO\0F\0F\0\n\0\x00\xDC";
	expect_error_bytes(lone, sizeof lone - 1, vn_io_error_parse,
	                   "bad.off:2: the text is UTF-16LE (it starts with a byte order mark), but a low surrogate "
	                   "without its high one");
}

static void test_off_line_numbers_with_carriage_returns(void** state)
{
	(void)state;
	expect_error("OFF\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 5\r", vn_io_error_parse,
	             "bad.off:6: face 0 has index 5, but the file has 3 vertices");
	expect_error("OFF\r\n3 1 0\r\n0 0 0\r\n\r\n1 0 0\r\n0 1 0\r\n3 0 1 5\r\n", vn_io_error_parse,
	             "bad.off:7: face 0 has index 5, but the file has 3 vertices");
}

static void test_coff_float_colours_rgb_and_rgba(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("COFF\n3 1 0\n"
	        "0 0 0 1 0 0\n"
	        "1 0 0 0 0.5 0 0.25\n"
	        "0 1 0 0 0 1 1\n"
	        "3 0 1 2\n",
	        &m);
	assert_triangle(&m);
	const float colours[12] = {1, 0, 0, 1, 0, 0.5f, 0, 0.25f, 0, 0, 1, 1};
	assert_non_null(m.colors);
	assert_floats(m.colors, colours, 12);
	assert_int_equal(m.colors_are_bytes, 0);
	assert_null(m.normals);
	vn_io_mesh_free(&m);
}

static void test_coff_byte_colours(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("COFF\n3 1 0\n"
	        "0 0 0 255 0 0\n"
	        "1 0 0 0 51 0 102\n"
	        "0 1 0 1 0 0 255\n" /* 1 is a byte here, as the other colours are */
	        "3 0 1 2\n",
	        &m);
	const float colours[12] = {1, 0, 0, 1, 0, 0.2f, 0, 0.4f, 1 / 255.0f, 0, 0, 1};
	assert_floats(m.colors, colours, 12);
	assert_int_equal(m.colors_are_bytes, 1);
	assert_int_equal(m.face_colors_are_bytes, 0);
	vn_io_mesh_free(&m);
}

static void test_noff_normals(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0.6 0.8\n0 1 0 -1 0 0\n3 0 1 2\n", &m);
	assert_triangle(&m);
	const double normals[9] = {0, 0, 1, 0, 0.6, 0.8, -1, 0, 0};
	assert_non_null(m.normals);
	assert_doubles(m.normals, normals, 9);
	assert_null(m.colors);
	vn_io_mesh_free(&m);
}

static void test_cnoff_reads_position_normal_colour(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("CNOFF\n3 1 0\n"
	        "0 0 0  0 0 1  1 0 0\n"
	        "1 0 0  0 0 1  0 1 0 0.5\n"
	        "0 1 0  0 0 1  0 0 1\n"
	        "3 0 1 2\n",
	        &m);
	assert_triangle(&m);
	const double normals[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
	const float colours[12] = {1, 0, 0, 1, 0, 1, 0, 0.5f, 0, 0, 1, 1};
	assert_doubles(m.normals, normals, 9);
	assert_floats(m.colors, colours, 12);
	vn_io_mesh_free(&m);
}

static void test_stoff_texture_coordinates(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("STOFF\n3 1 0\n0 0 0 0.25 0.75\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n", &m);
	assert_triangle(&m);
	const float st[6] = {0.25f, 0.75f, 1, 0, 0, 1};
	assert_non_null(m.texcoords);
	assert_floats(m.texcoords, st, 6);
	assert_null(m.colors);
	assert_null(m.normals);
	vn_io_mesh_free(&m);
}

static void test_stcnoff_reads_every_field_in_order(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("STCNOFF\n3 1 0\n"
	        "0 0 0  1 0 0  0.5 0.5 0.5  0.125 0.25\n"
	        "1 0 0  0 1 0  1 1 1 0  0.5 1\n"
	        "0 1 0  0 0 1  0 0 0  1 0.5\n"
	        "3 0 1 2\n",
	        &m);
	assert_triangle(&m);
	const double normals[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
	const float colours[12] = {0.5f, 0.5f, 0.5f, 1, 1, 1, 1, 0, 0, 0, 0, 1};
	const float st[6] = {0.125f, 0.25f, 0.5f, 1, 1, 0.5f};
	assert_doubles(m.normals, normals, 9);
	assert_floats(m.colors, colours, 12);
	assert_floats(m.texcoords, st, 6);
	vn_io_mesh_free(&m);
}

static void test_4off_divides_by_w(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("4OFF\n3 1 0\n0 0 0 1\n2 0 0 2\n0 -0.5 0 -0.5\n3 0 1 2\n", &m);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
}

static void test_noff_dimension_3_on_own_line(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("nOFF\n3\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", &m);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
}

static void test_noff_dimension_and_counts_on_header_line(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("nOFF 3 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", &m);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
}

static void test_nan_and_inf_coordinates_are_read(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n2 0 0\nnan 1 -inf\n1e400 -0 2.5e-3\n", &m);
	assert_int_equal(m.vertex_count, 2);
	assert_true(isnan(m.positions[0]));
	assert_exact(m.positions[1], 1);
	assert_exact(m.positions[2], -INFINITY);
	assert_exact(m.positions[3], INFINITY);
	assert_true(m.positions[4] == 0 && signbit(m.positions[4]));
	assert_exact(m.positions[5], 0.0025);
	assert_int_equal(m.face_count, 0);
	assert_int_equal(m.face_offsets[0], 0);
	assert_false(vn_io_mesh_is_triangles(&m));
	vn_io_mesh_free(&m);
}

/* ------------------------------------------------------------------ polygons and face colours */

static void test_polygons_of_every_size(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n5 5 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0\n"
	        "3 0 1 2\n"
	        "4 0 1 2 3\n"
	        "5 0 1 2 4 3\n"
	        "2 3 4\n" /* fewer than 3 corners: kept, the core calls it degenerate */
	        "1 4\n",
	        &m);
	const uint32_t offsets[6] = {0, 3, 7, 12, 14, 15};
	const uint32_t indices[15] = {0, 1, 2, 0, 1, 2, 3, 0, 1, 2, 4, 3, 3, 4, 4};
	assert_int_equal(m.face_count, 5);
	assert_u32s(m.face_offsets, offsets, 6);
	assert_u32s(m.indices, indices, 15);
	assert_false(vn_io_mesh_is_triangles(&m));
	vn_io_mesh_free(&m);
}

static void test_face_colours_float_rgb_and_rgba(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 1 0.5 0\n3 2 1 0 0 0 1 0.75\n", &m);
	const float colours[8] = {1, 0.5f, 0, 1, 0, 0, 1, 0.75f};
	assert_non_null(m.face_colors);
	assert_floats(m.face_colors, colours, 8);
	assert_int_equal(m.face_colors_are_bytes, 0);
	assert_null(m.colors);
	vn_io_mesh_free(&m);
}

static void test_face_colours_bytes(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 51\n3 2 1 0 0 255 0 102\n", &m);
	const float colours[8] = {1, 0, 0.2f, 1, 0, 1, 0, 0.4f};
	assert_floats(m.face_colors, colours, 8);
	assert_int_equal(m.face_colors_are_bytes, 1);
	vn_io_mesh_free(&m);
}

static void test_face_colormap_index_is_ignored(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 17\n", &m);
	assert_triangle(&m);
	assert_null(m.face_colors);
	/* Not silently: the colour is not kept. */
	assert_string_equal(m.warnings, "face 0 gives its colour as an index into Geomview's colormap, which vn does not "
	                                "have: it is read as an uncoloured face");
	vn_io_mesh_free(&m);
}

static void test_uncoloured_faces_get_geomview_grey(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2 0 0 255\n3 0 1 2 4\n", &m);
	const float grey = 170 / 255.0f;
	const float colours[12] = {grey, grey, grey, 1, 0, 0, 1, 1, grey, grey, grey, 1};
	assert_floats(m.face_colors, colours, 12);
	assert_int_equal(m.face_colors_are_bytes, 1);
	assert_non_null(strstr(m.warnings, "face 2 gives its colour as an index into Geomview's colormap"));
	vn_io_mesh_free(&m);
}

/* ------------------------------------------------------------------ fixtures */

static void test_fixture_cube(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_path_ok("data/off/cube.off", &m);
	const double positions[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
	const uint32_t offsets[7] = {0, 4, 8, 12, 16, 20, 24};
	const uint32_t indices[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
	assert_int_equal(m.vertex_count, 8);
	assert_doubles(m.positions, positions, 24);
	assert_int_equal(m.face_count, 6);
	assert_u32s(m.face_offsets, offsets, 7);
	assert_u32s(m.indices, indices, 24);
	vn_io_mesh_free(&m);
}

static void test_fixture_colored(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_path_ok("data/off/colored.off", &m);
	const float grey = 170 / 255.0f;
	const float colours[16] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 128 / 255.0f, 1, 1, 1, 1};
	const float face_colours[16] = {1, 0, 0, 1, 0, 1, 0, 1, grey, grey, grey, 1, grey, grey, grey, 1};
	assert_int_equal(m.vertex_count, 4);
	assert_int_equal(m.face_count, 4);
	assert_floats(m.colors, colours, 16);
	assert_floats(m.face_colors, face_colours, 16);
	assert_int_equal(m.colors_are_bytes, 1);
	assert_int_equal(m.face_colors_are_bytes, 1);
	vn_io_mesh_free(&m);
}

static void test_fixture_binary(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_path_ok("data/off/tetra_binary.off", &m);
	const double positions[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
	const uint32_t indices[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
	const float grey = 170 / 255.0f;
	const float face_colours[16] = {1, 0, 0, 1, grey, grey, grey, 1, 0, 0.5f, 1, 1, grey, grey, grey, 1};
	assert_int_equal(m.vertex_count, 4);
	assert_doubles(m.positions, positions, 12);
	assert_int_equal(m.face_count, 4);
	assert_u32s(m.indices, indices, 12);
	assert_floats(m.face_colors, face_colours, 16);
	assert_int_equal(m.face_colors_are_bytes, 0);
	assert_true(vn_io_mesh_is_triangles(&m));
	vn_io_mesh_free(&m);
}

/* ------------------------------------------------------------------ binary */

static void test_binary_off(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n");
	ADD_INTS(&b, 3, 1, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0, 0, 0, 1, 0);
	ADD_INTS(&b, 3, 0, 1, 2, 0);
	vn_io_mesh m;
	read_bytes_ok("binary.off", b.data, b.size, &m);
	assert_triangle(&m);
	assert_null(m.face_colors);
	vn_io_mesh_free(&m);
}

/* pmp-library writes binary OFF in little-endian words, without the colour
 * count after a face's indices: read so (with a warning) when only that
 * reading's counts fit the file. */
static void test_binary_off_as_pmp_library_writes_it(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n");
	const size_t header = b.size;
	ADD_INTS(&b, 4, 2, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0);
	ADD_INTS(&b, 3, 0, 1, 2, 3, 1, 3, 2);
	for (size_t i = header; i < b.size; i += 4) { /* each word little-endian */
		unsigned char t = b.data[i];
		b.data[i] = b.data[i + 3], b.data[i + 3] = t;
		t = b.data[i + 1], b.data[i + 1] = b.data[i + 2], b.data[i + 2] = t;
	}
	vn_io_mesh m;
	read_bytes_ok("pmp.off", b.data, b.size, &m);
	const double positions[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
	const uint32_t offsets[3] = {0, 3, 6}, indices[6] = {0, 1, 2, 1, 3, 2};
	assert_int_equal(m.vertex_count, 4);
	assert_int_equal(m.face_count, 2);
	assert_doubles(m.positions, positions, 12);
	assert_u32s(m.face_offsets, offsets, 3);
	assert_u32s(m.indices, indices, 6);
	assert_non_null(m.warnings);
	assert_non_null(strstr(m.warnings, "binary OFF as pmp-library writes it"));
	vn_io_mesh_free(&m);
}

static void test_binary_noff_with_comment_before_header(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "# binary with normals\nNOFF BINARY\n");
	ADD_INTS(&b, 3, 1, 0);
	ADD_FLOATS(&b, 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0.6f, 0.8f, 0, 1, 0, -1, 0, 0);
	ADD_INTS(&b, 3, 0, 1, 2, 0);
	vn_io_mesh m;
	read_bytes_ok("binary.off", b.data, b.size, &m);
	assert_triangle(&m);
	const double normals[9] = {0, 0, 1, 0, 0.6f, 0.8f, -1, 0, 0};
	assert_doubles(m.normals, normals, 9);
	vn_io_mesh_free(&m);
}

static void test_binary_coff_and_face_colours(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "COFF BINARY\n");
	ADD_INTS(&b, 3, 2, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0.5f, 0, 1, 0, 0, 0, 1, 0.25f);
	ADD_INTS(&b, 3, 0, 1, 2, 3);
	ADD_FLOATS(&b, 0, 0, 1);
	ADD_INTS(&b, 3, 2, 1, 0, 4);
	ADD_FLOATS(&b, 1, 1, 0, 0.5f);
	vn_io_mesh m;
	read_bytes_ok("binary.off", b.data, b.size, &m);
	assert_int_equal(m.vertex_count, 3);
	assert_doubles(m.positions, triangle_positions, 9);
	const float colours[12] = {1, 0, 0, 1, 0, 1, 0, 0.5f, 0, 0, 1, 0.25f};
	const float face_colours[8] = {0, 0, 1, 1, 1, 1, 0, 0.5f};
	const uint32_t indices[6] = {0, 1, 2, 2, 1, 0};
	assert_floats(m.colors, colours, 12);
	assert_floats(m.face_colors, face_colours, 8);
	assert_u32s(m.indices, indices, 6);
	vn_io_mesh_free(&m);
}

static void test_binary_stoff_and_ndim(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "STnOFF BINARY\n");
	ADD_INTS(&b, 3, 3, 1, 0); /* dimension 3, then the counts */
	ADD_FLOATS(&b, 0, 0, 0, 0.25f, 0.5f, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1);
	ADD_INTS(&b, 3, 0, 1, 2, 1);
	ADD_FLOATS(&b, 9); /* colormap index: ignored */
	vn_io_mesh m;
	read_bytes_ok("binary.off", b.data, b.size, &m);
	assert_triangle(&m);
	const float st[6] = {0.25f, 0.5f, 1, 0, 0, 1};
	assert_floats(m.texcoords, st, 6);
	assert_null(m.face_colors);
	assert_non_null(strstr(m.warnings, "face 0 gives its colour as an index into Geomview's colormap"));
	vn_io_mesh_free(&m);
}

static void test_binary_4off(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "4OFF BINARY\n");
	ADD_INTS(&b, 3, 1, 0);
	ADD_FLOATS(&b, 0, 0, 0, 4, 2, 0, 0, 2, 0, 3, 0, 3);
	ADD_INTS(&b, 3, 0, 1, 2, 0);
	vn_io_mesh m;
	read_bytes_ok("binary.off", b.data, b.size, &m);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
}

static void test_binary_truncated_vertex(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n"); /* 11 bytes, then the counts */
	ADD_INTS(&b, 2, 0, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0);
	expect_error_bytes(b.data, b.size, vn_io_error_parse,
	                   "bad.off: byte 11: the header announces 2 vertices and 0 faces, more than the 20 bytes that "
	                   "follow can hold");
}

static void test_binary_truncated_face(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n");
	ADD_INTS(&b, 3, 1, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0, 0, 0, 1, 0);
	ADD_INTS(&b, 3, 0, 1); /* the face starts at byte 59 */
	expect_error_bytes(b.data, b.size, vn_io_error_parse,
	                   "bad.off: byte 63: face 0 has 3 corners, more than the rest of the file holds");
}

static void test_binary_index_out_of_range(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n");
	ADD_INTS(&b, 3, 1, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0, 0, 0, 1, 0);
	ADD_INTS(&b, 3, 0, 3, 2, 0);
	expect_error_bytes(b.data, b.size, vn_io_error_parse,
	                   "bad.off: byte 63: face 0 has index 3, but the file has 3 vertices");
}

static void test_binary_negative_count(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n");
	ADD_INTS(&b, 3, -1, 0);
	expect_error_bytes(b.data, b.size, vn_io_error_parse, "bad.off: byte 15: the face count -1 is negative");
}

static void test_binary_counts_beyond_file_size(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n");
	ADD_INTS(&b, 2000000000, 0, 0);
	ADD_FLOATS(&b, 0, 0, 0);
	expect_error_bytes(b.data, b.size, vn_io_error_parse,
	                   "bad.off: byte 11: the header announces 2000000000 vertices and 0 faces, more than the 12 "
	                   "bytes that follow can hold");
}

static void test_binary_trailing_bytes(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n");
	ADD_INTS(&b, 3, 1, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0, 0, 0, 1, 0);
	ADD_INTS(&b, 3, 0, 1, 2, 0);
	add_text(&b, "xy");
	expect_error_bytes(b.data, b.size, vn_io_error_parse, "bad.off: byte 79: 2 unexpected bytes after the last face");
}

static void test_binary_bad_face_colour_count(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "OFF BINARY\n");
	ADD_INTS(&b, 3, 1, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0, 0, 0, 1, 0);
	ADD_INTS(&b, 3, 0, 1, 2, 2);
	ADD_FLOATS(&b, 0, 0);
	expect_error_bytes(b.data, b.size, vn_io_error_parse,
	                   "bad.off: byte 63: face 0 has 2 colour components; a face colour is 0, 1 (colormap index), "
	                   "3 or 4 numbers");
}

static void test_binary_text_after_keyword(void** state)
{
	(void)state;
	expect_error("OFF BINARY 3 1 0\n", vn_io_error_parse, "bad.off:1: unexpected '3' after BINARY");
}

/* ------------------------------------------------------------------ malformed ASCII */

static void test_error_unknown_keyword(void** state)
{
	(void)state;
	expect_error("# ply?\nNCOFF 3 1 0\n", vn_io_error_parse,
	             "bad.off:2: expected an OFF header keyword ([ST][C][N][4][n]OFF) or the counts, found 'NCOFF'");
	/* Digits run into the keyword only as ModelNet's counts do. */
	expect_error("OFFx 3 1 0\n", vn_io_error_parse,
	             "bad.off:1: expected an OFF header keyword ([ST][C][N][4][n]OFF) or the counts, found 'OFFx'");
	expect_error("nOFF3 3 1 0\n", vn_io_error_parse,
	             "bad.off:1: expected an OFF header keyword ([ST][C][N][4][n]OFF) or the counts, found 'nOFF3'");
}

static void test_error_empty_file(void** state)
{
	(void)state;
	expect_error("", vn_io_error_parse, "bad.off: expected an OFF header keyword, but the file is empty");
}

static void test_error_only_comments(void** state)
{
	(void)state;
	expect_error("# nothing\n\n", vn_io_error_parse,
	             "bad.off: expected an OFF header keyword, but the file is only blanks and comments");
}

static void test_error_ndim_other_than_3(void** state)
{
	(void)state;
	expect_error("nOFF\n4\n3 1 0\n", vn_io_error_unsupported,
	             "bad.off:2: nOFF dimension 4 is not supported: vn reads 3-dimensional vertices only");
}

static void test_error_missing_counts(void** state)
{
	(void)state;
	expect_error("OFF\n# no counts\n", vn_io_error_parse, "bad.off:2: the file ends before the vertex and face counts");
}

static void test_error_one_count(void** state)
{
	(void)state;
	expect_error("OFF\n3\n", vn_io_error_parse, "bad.off:2: expected the counts 'vertices faces [edges]', found 1 value");
}

static void test_error_four_counts(void** state)
{
	(void)state;
	expect_error("OFF 3 1 0 0\n", vn_io_error_parse,
	             "bad.off:1: expected the counts 'vertices faces [edges]', found 4 values");
}

static void test_error_count_not_integer(void** state)
{
	(void)state;
	expect_error("OFF\n3 1.5 0\n", vn_io_error_parse, "bad.off:2: the face count '1.5' is not a non-negative integer");
	expect_error("OFF\n-3 1 0\n", vn_io_error_parse,
	             "bad.off:2: the vertex count '-3' is not a non-negative integer");
	expect_error("OFF\n3 1 x\n", vn_io_error_parse, "bad.off:2: the edge count 'x' is not a non-negative integer");
}

static void test_error_counts_beyond_file_size(void** state)
{
	(void)state;
	expect_error("OFF\n1000000000000000 1 0\n0 0 0\n", vn_io_error_parse,
	             "bad.off:2: the header announces 1000000000000000 vertices and 1 faces, more than the 6 bytes "
	             "that follow can hold");
	expect_error("OFF\n1 99999999999999999999999 0\n0 0 0\n", vn_io_error_parse,
	             "bad.off:2: the face count '99999999999999999999999' is too large");
}

static void test_error_vertex_too_few_numbers(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", vn_io_error_parse,
	             "bad.off:4: vertex 1 has 2 numbers, but OFF vertices have 3 (x y z)");
}

static void test_error_vertex_too_many_numbers(void** state)
{
	(void)state;
	expect_error("NOFF\n3 1 0\n0 0 0 0 0 1 7\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", vn_io_error_parse,
	             "bad.off:3: vertex 0 has 7 numbers, but NOFF vertices have 6 (x y z nx ny nz)");
}

static void test_error_colour_vertex_count(void** state)
{
	(void)state;
	expect_error("STCOFF\n1 0 0\n0 0 0 1 1 0 0\n# padding: the header check wants 16 bytes\n", vn_io_error_parse,
	             "bad.off:3: vertex 0 has 7 numbers, but STCOFF vertices have 8 or 9 (x y z r g b [a] s t)");
}

static void test_error_not_a_number(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1.0abc 0 0\n0 1 0\n3 0 1 2\n", vn_io_error_parse,
	             "bad.off:4: vertex 1: '1.0abc' is not a number");
	expect_error("OFF\n1 0 0\n0 0 0,5\n", vn_io_error_parse, "bad.off:3: vertex 0: '0,5' is not a number");
}

static void test_error_binary_garbage_is_quoted_safely(void** state)
{
	(void)state;
	expect_error("OFF\n1 0 0\n0 \x01\x02z 0\n", vn_io_error_parse, "bad.off:3: vertex 0: '??z' is not a number");
	expect_error("OFF\n1 0 0\n0 0 1234567890123456789012345678901234567890x\n", vn_io_error_parse,
	             "bad.off:3: vertex 0: '123456789012345678901234...' is not a number");
}

static void test_error_homogeneous_w_zero(void** state)
{
	(void)state;
	expect_error("4OFF\n3 1 0\n0 0 0 1\n1 0 0 0\n0 1 0 1\n3 0 1 2\n", vn_io_error_parse,
	             "bad.off:4: vertex 1 has w = 0; 4OFF coordinates are divided by w");
}

static void test_error_truncated_vertices(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n# the third vertex went missing\n", vn_io_error_parse,
	             "bad.off:5: the file ends after 2 of the 3 vertices the header announces");
}

static void test_error_truncated_faces(void** state)
{
	(void)state;
	expect_error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n# end\n", vn_io_error_parse,
	             "bad.off:7: the file ends after 1 of the 2 faces the header announces");
}

static void test_error_index_out_of_range(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", vn_io_error_parse,
	             "bad.off:6: face 0 has index 3, but the file has 3 vertices");
}

static void test_error_negative_index(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", vn_io_error_parse,
	             "bad.off:6: face 0 has a negative index -1");
}

static void test_error_index_not_an_integer(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.0 2\n", vn_io_error_parse,
	             "bad.off:6: face 0: '1.0' is not a vertex index");
}

static void test_error_face_more_corners_than_indices(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", vn_io_error_parse,
	             "bad.off:6: the file ends in face 0, after 3 of its 4 indices");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n", vn_io_error_parse,
	             "bad.off:6: face 0 has 4000000000 corners, more than the rest of the file holds");
	/* A short face takes the next line's first word as its last index. */
	expect_error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n3 0 1 2\n", vn_io_error_parse,
	             "bad.off:7: face 0 has index 3, but the file has 3 vertices");
}

/* Indices on the lines after their count (libigl writes long faces so;
 * Geomview reads them as words): the colour is the rest of the last one. */
static void test_face_indices_across_lines(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n4 0\n1\n# a comment\n\n3 2 255 0 0\n3 1 3 2\n", &m);
	const uint32_t offsets[] = {0, 4, 7}, indices[] = {0, 1, 3, 2, 1, 3, 2};
	assert_int_equal(m.face_count, 2);
	assert_u32s(m.face_offsets, offsets, 3);
	assert_u32s(m.indices, indices, 7);
	const float red[] = {1, 0, 0, 1};
	assert_non_null(m.face_colors);
	assert_floats(m.face_colors, red, 4);
	vn_io_mesh_free(&m);
}

static void test_error_face_without_corners(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n0 # nothing\n", vn_io_error_parse, "bad.off:6: face 0 has 0 corners");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\nthree 0 1 2\n", vn_io_error_parse,
	             "bad.off:6: face 0: expected the number of corners, found 'three'");
}

static void test_error_face_colour_lengths(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5 0.5\n", vn_io_error_parse,
	             "bad.off:6: face 0 has 2 numbers after its 3 indices; a face colour is 1 colormap index, 3 (RGB) "
	             "or 4 (RGBA) numbers");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 1 1 1 1 1\n", vn_io_error_parse,
	             "bad.off:6: face 0 has 5 numbers after its 3 indices; a face colour is 1 colormap index, 3 (RGB) "
	             "or 4 (RGBA) numbers");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5\n", vn_io_error_parse,
	             "bad.off:6: face 0: '0.5' after the indices is not a colormap index");
}

static void test_error_colour_out_of_range(void** state)
{
	(void)state;
	expect_error("COFF\n1 0 0\n0 0 0 300 0 0\n", vn_io_error_parse,
	             "bad.off:3: vertex 0 has colour component 300; components are fractions in [0, 1] or integers "
	             "0..255");
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 1.5 0 0\n", vn_io_error_parse,
	             "bad.off:6: face 0 has colour component 1.5; components are fractions in [0, 1] or integers "
	             "0..255");
	expect_error("COFF\n1 0 0\n0 0 0 -0.5 0 0\n", vn_io_error_parse,
	             "bad.off:3: vertex 0 has colour component -0.5; components are fractions in [0, 1] or integers "
	             "0..255");
	expect_error("COFF\n1 0 0\n0 0 0 nan 0 0\n", vn_io_error_parse,
	             "bad.off:3: vertex 0 has colour component nan; components are fractions in [0, 1] or integers "
	             "0..255");
}

static void test_error_colour_styles_mixed(void** state)
{
	(void)state;
	expect_error("COFF\n2 0 0\n0 0 0 200 0 0\n1 0 0 0.5 0 0\n", vn_io_error_parse,
	             "bad.off:4: vertex 1 has colour component 0.5, but vertex 0 has 200: colours must be all "
	             "fractions in [0, 1] or all integers 0..255");
}

static void test_error_trailing_content(void** state)
{
	(void)state;
	expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n# fine\n3 0 1 2\n", vn_io_error_parse,
	             "bad.off:8: unexpected '3' after the last of the 1 faces the header announces");
	expect_error("OFF\n1 0 0\n0 0 0\nEND\n", vn_io_error_parse,
	             "bad.off:4: unexpected 'END' after the last of the 0 faces the header announces");
}

/* ------------------------------------------------------------------ writing */

static vn_io_result write_to_folder(const char* name, const vn_io_mesh* m, vn_io_error* error)
{
	char path[256];
	path_in_folder(path, sizeof path, name);
	return vn_io_write_file(path, NULL, m, NULL, error);
}

static void test_write_exact_text(void** state)
{
	(void)state;
	double positions[9] = {0, 0.1, -2.5, 1.0 / 3.0, 1e-300, 123456789, 0.1f, 0, -0.0};
	double normals[9] = {0, 0, 1, 0.6, 0.8, 0, 1.0 / 3.0, 0, 0};
	uint32_t offsets[3] = {0, 3, 4};
	uint32_t indices[4] = {0, 1, 2, 2};
	vn_io_mesh m = {0};
	m.vertex_count = 3;
	m.positions = positions;
	m.normals = normals;
	m.face_count = 2;
	m.face_offsets = offsets;
	m.indices = indices;
	vn_io_error error;
	assert_int_equal(write_to_folder("exact.off", &m, &error), vn_io_success);
	char path[256];
	path_in_folder(path, sizeof path, "exact.off");
	char* text = slurp(path);
	assert_string_equal(text, "NOFF\n"
	                          "3 2 0\n"
	                          "0 0.1 -2.5 0 0 1\n"
	                          "0.3333333333333333 1e-300 123456789 0.6 0.8 0\n"
	                          "0.10000000149011612 0 -0 0.333333333 0 0\n"
	                          "3 0 1 2\n"
	                          "1 2\n");
	free(text);
}

/* The text output's integers (0 and 2^64 - 1 at the ends) and its buffer:
 * pieces of every length from 1 to 97 bytes, 40,000 in all, cross its
 * 16 KB many times and at every offset, and come out in order. */
static void test_text_out_integers_and_buffer(void** state)
{
	(void)state;
	char path[256];
	path_in_folder(path, sizeof path, "text_out.txt");
	FILE* out = fopen(path, "wb");
	assert_non_null(out);
	vn_io_text_out w = {out, 0, 0, 0, {0}};
	vn_io_put_uint(&w, "", 0);
	vn_io_put_uint(&w, " ", UINT64_MAX);
	vn_io_put_uint(&w, "//", 4294967295u);
	vn_io_put_uint(&w, "/", 10);
	vn_io_put(&w, "\n");
	static char expected[50000];
	size_t n = (size_t)snprintf(expected, sizeof expected, "0 18446744073709551615//4294967295/10\n");
	for (int length = 1; n + (size_t)length < 40000; length = length % 97 + 1) {
		char piece[98];
		for (int k = 0; k < length; k++)
			piece[k] = (char)('a' + (n + (size_t)k) % 26);
		piece[length] = '\0';
		vn_io_put(&w, piece);
		memcpy(expected + n, piece, (size_t)length + 1);
		n += (size_t)length;
	}
	assert_true(vn_io_flush(&w));
	assert_int_equal(fclose(out), 0);
	char* text = slurp(path);
	assert_int_equal(strlen(text), n);
	assert_string_equal(text, expected);
	free(text);
}

/* vn_io_format_g against literal printf texts: ties to even on the exact
 * value, carries to a new power of 10, both styles, and values past the
 * integer path (printf's text there). */
static void test_format_g_literals(void** state)
{
	(void)state;
	static const struct {
		double v;
		int digits;
		const char* text;
	} cases[] = {
	    {0.1, 17, "0.10000000000000001"},   {0.125, 2, "0.12"},        {0.375, 2, "0.38"},
	    {2.5, 1, "2"},                      {3.5, 1, "4"},             {999.6, 3, "1e+03"},
	    {9.9999, 3, "10"},                  {123456.0, 9, "123456"},   {1200.0, 4, "1200"},
	    {1200.0, 2, "1.2e+03"},             {0.0001, 6, "0.0001"},     {0.00001, 6, "1e-05"},
	    {1.5e-7, 9, "1.5e-07"},             {-0.0, 9, "-0"},           {0.0, 17, "0"},
	    {-2.75, 2, "-2.8"},                 {1e300, 9, "1e+300"},      {5e-324, 17, "4.9406564584124654e-324"},
	    {9999999999.9999962, 16, "9999999999.999996"},                 {9999999999.9999962, 17, "9999999999.9999962"},
	    {0.30000000000000004, 16, "0.3"}, {1.0 / 3.0, 9, "0.333333333"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
		char text[VN_IO_NUMBER_SIZE];
		const size_t n = vn_io_format_g(text, cases[i].v, cases[i].digits);
		assert_string_equal(text, cases[i].text);
		assert_int_equal(n, strlen(cases[i].text));
	}
	char text[VN_IO_NUMBER_SIZE];
	vn_io_format_g(text, NAN, 9);
	assert_string_equal(text, "nan");
	vn_io_format_g(text, -INFINITY, 9);
	assert_string_equal(text, "-inf");
}

/* A reproducible stream of doubles: every bit pattern, values near 1,
 * short decimals (as text files hold them), floats, dyadic fractions (exact
 * ties at some digit count) and the neighbours of powers of 10. */
static double test_value(uint64_t* state, unsigned kind)
{
	uint64_t x = *state;
	x ^= x << 13, x ^= x >> 7, x ^= x << 17;
	*state = x;
	double v;
	switch (kind % 6) {
	case 0:
		memcpy(&v, &x, sizeof v);
		return isfinite(v) ? v : 1.0;
	case 1: return ldexp(1.0 + (double)(x >> 11) * 0x1p-53, (int)(x % 90) - 40) * (x & 1 ? -1 : 1);
	case 2: return (double)(x % 1000000000) / pow(10.0, (double)(x >> 40 & 15));
	case 3: return (double)(float)((double)(x % 1000000) / pow(10.0, (double)(x >> 40 & 7)));
	case 4: return (double)(x % 100000) / (double)(1u << (x >> 40 & 15));
	default: v = pow(10.0, (double)((int)(x % 36) - 14));
		for (int k = (int)(x >> 40 & 7) - 3; k != 0; k += k < 0 ? 1 : -1)
			v = nextafter(v, k < 0 ? 0.0 : INFINITY);
		return v;
	}
}

static void test_format_g_matches_printf(void** state)
{
	(void)state;
	uint64_t seed = 88172645463325252ull;
	for (unsigned i = 0; i < 120000; ++i) {
		const double v = test_value(&seed, i);
		const int digits = 1 + (int)(i / 6 % 17);
		char ours[VN_IO_NUMBER_SIZE], theirs[64];
		vn_io_format_g(ours, v, digits);
		snprintf(theirs, sizeof theirs, "%.*g", digits, v);
		if (strcmp(ours, theirs) != 0)
			fail_msg("%a at %d digits: '%s', printf '%s'", v, digits, ours, theirs);
	}
}

/* vn_io_parse_real's fast path (plain decimals of up to 15 significant
 * digits) against strtod, bit for bit: literals at its edges, then the
 * stream printed at every precision and with up to 9 zeros in front. */
static void test_parse_real_matches_strtod(void** state)
{
	(void)state;
	static const char* const cases[] = {"0", "-0", "+1", "1.", ".5", "-.5", "0.1", "0.000000000000000000001",
	                                    "123456789012345", "1234567890123456", "0.1234567890123456",
	                                    "4123456.11", "637012.24", "9007199254740993", "1e5", "1E-5", "1.5e300",
	                                    "0x10", "inf", "-nan", "00000000000000000001.5", "1.0000000000000000000000",
	                                    /* 16 to 19 digits: 2^60 + 128 and + 384, halfway between
	                                     * doubles (ties to even, down then up); 2^53 - 1 and 2^64 - 1;
	                                     * floats as vn writes them; 19 digits, 22 after the point */
	                                    "1152921504606847104", "1152921504606847360", "9007199254740991",
	                                    "18446744073709551615", "0.10000000149011612", "-0.30000001192092896",
	                                    "0.0009999999999999999", "9999999999999999999", "0.0000000000000000000001"};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		double ours = 1.0;
		char* end;
		const double theirs = strtod(cases[i], &end);
		assert_true(vn_io_parse_real((const unsigned char*)cases[i], strlen(cases[i]), &ours));
		if (memcmp(&ours, &theirs, sizeof ours) != 0 && !(isnan(ours) && isnan(theirs)))
			fail_msg("'%s': %a, strtod %a", cases[i], ours, theirs);
	}
	static const char* const refused[] = {"", "-", ".", "1..2", "1.2.3", "1,5", "--1", "1 "};
	for (size_t i = 0; i < sizeof refused / sizeof refused[0]; i++) {
		double v;
		if (vn_io_parse_real((const unsigned char*)refused[i], strlen(refused[i]), &v))
			fail_msg("'%s' read as %g", refused[i], v);
	}
	uint64_t seed = 88172645463325252ull;
	for (unsigned i = 0; i < 120000; ++i) {
		const double v = test_value(&seed, i);
		char text[80];
		snprintf(text, sizeof text, "%0*.*f", (int)(i % 10) + (v < 0), (int)(i / 10 % 18), v);
		if (strlen(text) > VN_IO_TOKEN_MAX)
			continue;
		double ours;
		const double theirs = strtod(text, NULL);
		assert_true(vn_io_parse_real((const unsigned char*)text, strlen(text), &ours));
		if (memcmp(&ours, &theirs, sizeof ours) != 0)
			fail_msg("'%s': %a, strtod %a", text, ours, theirs);
	}
	/* 16 to 19 significant digits (the 128-bit division), the point
	 * anywhere from none to 22 digits from the end. */
	for (unsigned i = 0; i < 300000; ++i) {
		seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
		const int digits = 16 + (int)(i % 4), fraction = (int)(i / 4 % 23);
		uint64_t m = seed % 9000000000000000000ull + 1000000000000000000ull; /* 19 digits */
		for (int k = digits; k < 19; k++)
			m /= 10;
		char whole[24], text[64];
		const int n = snprintf(whole, sizeof whole, "%llu", (unsigned long long)m);
		if (fraction >= n) /* 0.000ddd */
			snprintf(text, sizeof text, "%s0.%.*s%s", i & 1 ? "-" : "", fraction - n, "0000000", whole);
		else /* ddd.ddd, or ddd. */
			snprintf(text, sizeof text, "%s%.*s.%s", i & 1 ? "-" : "", n - fraction, whole, whole + n - fraction);
		double ours;
		const double theirs = strtod(text, NULL);
		assert_true(vn_io_parse_real((const unsigned char*)text, strlen(text), &ours));
		if (memcmp(&ours, &theirs, sizeof ours) != 0)
			fail_msg("'%s': %a, strtod %a", text, ours, theirs);
	}
}

/* The shortest of 15 to 17 digits that strtod reads back: literals, then
 * the stream against that definition. */
static void test_format_exact(void** state)
{
	(void)state;
	static const struct {
		double v;
		const char* text;
	} cases[] = {
	    {0.1, "0.1"},
	    {0.30000000000000004, "0.30000000000000004"},
	    {1.0 / 3.0, "0.3333333333333333"},
	    {(double)0.1f, "0.10000000149011612"},
	    {9999999999.9999962, "9999999999.999996"},
	    {1e-300, "1e-300"},
	    {-0.0, "-0"},
	    {123456789.0, "123456789"},
	    /* 16 digits, 5.960464477539062e-08, lie below 2^-24 within half an
	     * ulp but past the quarter that is half the gap to the double below */
	    {0x1p-24, "5.9604644775390625e-08"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
		char text[VN_IO_NUMBER_SIZE];
		vn_io_format_exact(text, cases[i].v);
		assert_string_equal(text, cases[i].text);
	}
	uint64_t seed = 2463534242ull;
	for (unsigned i = 0; i < 60000; ++i) {
		const double v = test_value(&seed, i);
		char ours[VN_IO_NUMBER_SIZE], theirs[64];
		vn_io_format_exact(ours, v);
		for (int digits = 15;; ++digits) {
			snprintf(theirs, sizeof theirs, "%.*g", digits, v);
			if (digits == 17 || strtod(theirs, NULL) == v)
				break;
		}
		if (strcmp(ours, theirs) != 0)
			fail_msg("%a: '%s', the shortest that reads back '%s'", v, ours, theirs);
	}
}

/* A float's text at a digit count where strtof reads it back, else 0:
 * ties to even (33554450 is halfway between 33554448, whose significand
 * is even, and 33554452), a float Draco's arithmetic reads from a shorter
 * text than strtof does (237666192), 2^-20 below its power of 2, the
 * subnormals and zero; then every float kind at 1 to 9 digits against
 * printf and strtof. */
static void test_format_float(void** state)
{
	(void)state;
	static const struct {
		float v;
		int digits;
		const char* text; /* NULL: not read back */
	} cases[] = {
	    {33554448.0f, 7, "3.355445e+07"}, {33554452.0f, 7, NULL}, {33554452.0f, 8, "33554452"},
	    {0.2f, 6, "0.2"}, {0.1f, 1, "0.1"}, {237666192.0f, 7, NULL}, {237666192.0f, 8, "2.3766619e+08"},
	    {0x1p-20f, 6, NULL}, {0x1p-20f, 7, "9.536743e-07"}, {0x1p-149f, 1, "1e-45"}, {-0.0f, 6, "-0"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
		char text[VN_IO_NUMBER_SIZE];
		const size_t n = vn_io_format_float(text, cases[i].v, cases[i].digits);
		if (!cases[i].text && n)
			fail_msg("%a at %d digits: '%s', which strtof reads as %a", (double)cases[i].v, cases[i].digits, text,
			         (double)strtof(text, NULL));
		if (cases[i].text)
			assert_string_equal(n ? text : "(none)", cases[i].text);
	}
	uint64_t seed = 1181783497276652981ull;
	for (unsigned i = 0; i < 60000; ++i) {
		uint32_t bits = (uint32_t)(seed >> 32);
		seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
		float v;
		if (i % 2) {
			memcpy(&v, &bits, sizeof v);
		} else {
			v = (float)test_value(&seed, i / 2);
		}
		if (!isfinite(v))
			continue;
		for (int digits = 1; digits <= 9; ++digits) {
			char ours[VN_IO_NUMBER_SIZE], theirs[64];
			const size_t n = vn_io_format_float(ours, v, digits);
			snprintf(theirs, sizeof theirs, "%.*g", digits, (double)v);
			const int back = strtof(theirs, NULL) == v;
			if (back != (n != 0) || (n && strcmp(ours, theirs) != 0))
				fail_msg("%a at %d digits: '%s' (%zu), printf '%s', which strtof reads %s", (double)v, digits,
				         n ? ours : "", n, theirs, back ? "back" : "as another float");
		}
	}
}

static void test_write_colours_in_source_style(void** state)
{
	(void)state;
	double positions[6] = {0, 0, 0, 1, 0, 0};
	float colors[8] = {1, 0, 0.2f, 1, 0, 1, 0, 0.4f};
	float texcoords[4] = {0.5f, 0.25f, 1, 0};
	uint32_t offsets[2] = {0, 2};
	uint32_t indices[2] = {0, 1};
	float face_colors[4] = {0.5f, 0.25f, 1, 1};
	vn_io_mesh m = {0};
	m.vertex_count = 2;
	m.positions = positions;
	m.colors = colors;
	m.colors_are_bytes = 1;
	m.texcoords = texcoords;
	m.face_count = 1;
	m.face_offsets = offsets;
	m.indices = indices;
	m.face_colors = face_colors;
	vn_io_error error;
	assert_int_equal(write_to_folder("style.off", &m, &error), vn_io_success);
	char path[256];
	path_in_folder(path, sizeof path, "style.off");
	char* text = slurp(path);
	assert_string_equal(text, "STCOFF\n"
	                          "2 1 0\n"
	                          "0 0 0 255 0 51 255 0.5 0.25\n"
	                          "1 0 0 0 255 0 102 1 0\n"
	                          "2 0 1 0.5 0.25 1 1\n");
	free(text);
}

static void test_round_trip_is_exact(void** state)
{
	(void)state;
	double positions[12] = {0.1, -1.0 / 3.0, 1e-310, 6.02214076e23, 0.1f, -0.0, 1 + 0x1p-52, 3, 4, 5, 6, 7};
	double normals[12] = {0, 0, 1, 0.6, 0.8, 0, -0.5, 0.25, 0.125, 1, 0, 0};
	float colors[16] = {0.1f, 0.2f, 0.3f, 1, 1.0f / 3.0f, 0, 1, 0.5f, 0, 0, 0, 0, 1, 1, 1, 1};
	float texcoords[8] = {0.1f, 0.9f, 1e-7f, 1, 0, 0, 0.5f, 0.5f};
	uint32_t offsets[3] = {0, 3, 7};
	uint32_t indices[7] = {0, 1, 2, 3, 2, 1, 0};
	float face_colors[8] = {0.7f, 0.1f, 0.2f, 1, 0, 0, 0, 1};
	vn_io_mesh m = {0};
	m.vertex_count = 4;
	m.positions = positions;
	m.normals = normals;
	m.colors = colors;
	m.texcoords = texcoords;
	m.face_count = 2;
	m.face_offsets = offsets;
	m.indices = indices;
	m.face_colors = face_colors;
	vn_io_error error;
	assert_int_equal(write_to_folder("trip.off", &m, &error), vn_io_success);

	vn_io_mesh back;
	char path[256];
	path_in_folder(path, sizeof path, "trip.off");
	read_path_ok(path, &back);
	assert_int_equal(back.vertex_count, 4);
	assert_doubles(back.positions, positions, 12);
	assert_doubles(back.normals, normals, 12);
	assert_floats(back.colors, colors, 16);
	assert_floats(back.texcoords, texcoords, 8);
	assert_int_equal(back.face_count, 2);
	assert_u32s(back.face_offsets, offsets, 3);
	assert_u32s(back.indices, indices, 7);
	assert_floats(back.face_colors, face_colors, 8);
	assert_int_equal(back.colors_are_bytes, 0);
	assert_int_equal(back.face_colors_are_bytes, 0);
	vn_io_mesh_free(&back);
}

static void test_round_trip_keeps_byte_colours(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_path_ok("data/off/colored.off", &m);
	vn_io_error error;
	assert_int_equal(write_to_folder("colored.off", &m, &error), vn_io_success);
	char path[256];
	path_in_folder(path, sizeof path, "colored.off");
	char* text = slurp(path);
	assert_string_equal(text, "COFF\n"
	                          "# A tetrahedron with colours as integers 0..255 (as MeshLab writes them).\n"
	                          "4 4 0\n"
	                          "0 0 0 255 0 0 255\n"
	                          "1 0 0 0 255 0 255\n"
	                          "0 1 0 0 0 255 128\n"
	                          "0 0 1 255 255 255 255\n"
	                          "3 0 2 1 255 0 0 255\n"
	                          "3 0 1 3 0 255 0 255\n"
	                          "3 1 2 3 170 170 170 255\n"
	                          "3 0 3 2 170 170 170 255\n");
	free(text);
	vn_io_mesh back;
	read_path_ok(path, &back);
	assert_floats(back.colors, m.colors, 16);
	assert_floats(back.face_colors, m.face_colors, 16);
	assert_int_equal(back.colors_are_bytes, 1);
	assert_int_equal(back.face_colors_are_bytes, 1);
	vn_io_mesh_free(&back);
	vn_io_mesh_free(&m);
}

/* Reads text as OFF, writes it and requires exactly `expected` back. */
static void rewrite_exactly(const char* name, const char* text, const char* expected)
{
	vn_io_mesh m;
	char path[256];
	vn_io_error error;
	read_bytes_ok(name, text, strlen(text), &m);
	assert_int_equal(write_to_folder(name, &m, &error), vn_io_success);
	vn_io_mesh_free(&m);
	path_in_folder(path, sizeof path, name);
	char* written = slurp(path);
	assert_string_equal(written, expected);
	free(written);
}

/* OFF -> OFF keeps every colour's alpha, also when all are opaque (255 or
 * 1), and writes RGB as Geomview's RGBA. */
static void test_write_keeps_alpha(void** state)
{
	(void)state;
	rewrite_exactly("opaque_bytes.off",
	                "COFF\n2 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n2 0 1 0 0 255 255\n",
	                "COFF\n2 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n2 0 1 0 0 255 255\n");
	rewrite_exactly("opaque_fractions.off",
	                "COFF\n2 1 0\n0 0 0 1 0 0.5 1\n1 0 0 0 1 0 1\n2 0 1 0 0 1 1\n",
	                "COFF\n2 1 0\n0 0 0 1 0 0.5 1\n1 0 0 0 1 0 1\n2 0 1 0 0 1 1\n");
	rewrite_exactly("translucent.off",
	                "COFF\n2 1 0\n0 0 0 255 0 0 128\n1 0 0 0 255 0 0\n2 0 1 0 0 255 1\n",
	                "COFF\n2 1 0\n0 0 0 255 0 0 128\n1 0 0 0 255 0 0\n2 0 1 0 0 255 1\n");
	/* RGB only: Geomview would read the next line's first number as alpha. */
	rewrite_exactly("rgb.off", "COFF\n2 1 0\n0 0 0 255 0 0\n1 0 0 0 255 0\n2 0 1 0 0 255\n",
	                "COFF\n2 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n2 0 1 0 0 255 255\n");
	/* Float colours and texture coordinates are written as the shortest text
	 * that reads back as the same float. */
	rewrite_exactly("st.off", "STCOFF\n1 0 0\n0 0 0 0.2 0.3 0.4 0.9 0.1 0.7\n",
	                "STCOFF\n1 0 0\n0 0 0 0.2 0.3 0.4 0.9 0.1 0.7\n");
}

/* Binary OFF colours (always RGBA floats) come out as ASCII with the same alphas. */
static void test_write_keeps_binary_alpha(void** state)
{
	(void)state;
	bytes b = {{0}, 0};
	add_text(&b, "COFF BINARY\n");
	ADD_INTS(&b, 2, 1, 0);
	ADD_FLOATS(&b, 0, 0, 0, 1, 0, 0, 1);
	ADD_FLOATS(&b, 1, 0, 0, 0, 1, 0, 0.25f);
	ADD_INTS(&b, 2, 0, 1, 4);
	ADD_FLOATS(&b, 0, 0, 1, 1);
	vn_io_mesh m;
	read_bytes_ok("alpha_binary.off", b.data, b.size, &m);
	vn_io_error error;
	assert_int_equal(write_to_folder("alpha_binary_out.off", &m, &error), vn_io_success);
	vn_io_mesh_free(&m);
	char path[256];
	path_in_folder(path, sizeof path, "alpha_binary_out.off");
	char* text = slurp(path);
	assert_string_equal(text, "COFF\n2 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 0.25\n2 0 1 0 0 1 1\n");
	free(text);
}

static void test_writer_reports_stream_errors(void** state)
{
	(void)state;
	char path[256];
	path_in_folder(path, sizeof path, "readonly.off");
	write_bytes("readonly.off", "x", 1);
	FILE* in = fopen(path, "rb"); /* writing to a read-only stream fails */
	assert_non_null(in);
	vn_io_mesh m = {0};
	double positions[3] = {1, 2, 3};
	uint32_t offsets[1] = {0};
	m.vertex_count = 1;
	m.positions = positions;
	m.face_offsets = offsets;
	vn_io_error error;
	assert_int_equal(vn_io_off_write(in, "out.off", &m, NULL, &error), vn_io_error_write);
	assert_string_equal(error.message, "out.off: cannot write: Bad file descriptor");
	fclose(in);
}

/* A format whose writer writes a little, then fails like a full disk. */
static vn_io_result failing_write(FILE* out, const char* path, const vn_io_mesh* mesh, const void* settings,
                                  vn_io_error* error)
{
	(void)mesh, (void)settings;
	fputs("partial output\n", out);
	return vn_io_fail(error, vn_io_error_write, "%s: disk full", path);
}

static const vn_io_format failing_format = {
    .name = "failing", .extensions = ".fail", .description = "fails after writing a line", .write = failing_write};

/* The names in folder/sub, sorted, joined by spaces. */
static void list_folder(const char* sub, char* out, size_t size)
{
	char path[256];
	path_in_folder(path, sizeof path, sub);
	assert_int_equal(list_names(path, out, size), 0);
}

static void test_failed_write_leaves_destination_untouched(void** state)
{
	(void)state;
	char sub[256], path[256], names[256];
	path_in_folder(sub, sizeof sub, "atomic");
	assert_int_equal(mkdir(sub, 0755), 0);
	write_bytes("atomic/out.off", "original\n", 9);
	path_in_folder(path, sizeof path, "atomic/out.off");

	vn_io_mesh m = {0};
	vn_io_error error;
	assert_int_equal(vn_io_write_file(path, &failing_format, &m, NULL, &error), vn_io_error_write);
	char expected[300];
	snprintf(expected, sizeof expected, "%s: disk full", path);
	assert_string_equal(error.message, expected);
	char* text = slurp(path);
	assert_string_equal(text, "original\n");
	free(text);
	list_folder("atomic", names, sizeof names);
	assert_string_equal(names, "out.off");

	/* Without a previous file, nothing at all is left. */
	path_in_folder(path, sizeof path, "atomic/new.off");
	assert_int_equal(vn_io_write_file(path, &failing_format, &m, NULL, &error), vn_io_error_write);
	list_folder("atomic", names, sizeof names);
	assert_string_equal(names, "out.off");
}

static void test_write_replaces_existing_file(void** state)
{
	(void)state;
	char sub[256], path[256], names[256];
	path_in_folder(sub, sizeof sub, "replace");
	assert_int_equal(mkdir(sub, 0755), 0);
	write_bytes("replace/out.off", "original\n", 9);
	path_in_folder(path, sizeof path, "replace/out.off");
	double positions[3] = {1, 2, 3};
	uint32_t offsets[1] = {0};
	vn_io_mesh m = {0};
	m.vertex_count = 1;
	m.positions = positions;
	m.face_offsets = offsets;
	vn_io_error error;
	assert_int_equal(vn_io_write_file(path, NULL, &m, NULL, &error), vn_io_success);
	char* text = slurp(path);
	assert_string_equal(text, "OFF\n1 0 0\n1 2 3\n");
	free(text);
	list_folder("replace", names, sizeof names);
	assert_string_equal(names, "out.off");
}

static void test_written_file_mode_follows_umask(void** state)
{
	(void)state;
	char path[256];
	struct stat st;
	vn_io_mesh m = {0};
	uint32_t offsets[1] = {0};
	m.face_offsets = offsets;
	vn_io_error error;
	mode_t saved = umask(022);
	assert_int_equal(write_to_folder("mode644.off", &m, &error), vn_io_success);
	umask(077);
	assert_int_equal(write_to_folder("mode600.off", &m, &error), vn_io_success);
	umask(saved);
	path_in_folder(path, sizeof path, "mode644.off");
	assert_int_equal(stat(path, &st), 0);
	assert_int_equal(st.st_mode & 0777, 0644);
	path_in_folder(path, sizeof path, "mode600.off");
	assert_int_equal(stat(path, &st), 0);
	assert_int_equal(st.st_mode & 0777, 0600);
}

static void test_write_into_missing_folder(void** state)
{
	(void)state;
	char path[256], expected[400];
	path_in_folder(path, sizeof path, "no/such/folder/out.off");
	vn_io_mesh m = {0};
	vn_io_error error;
	assert_int_equal(vn_io_write_file(path, NULL, &m, NULL, &error), vn_io_error_write);
	snprintf(expected, sizeof expected, "%s: the folder '%s/no/such/folder' does not exist: create it first", path,
	         folder);
	assert_string_equal(error.message, expected);
}

static void test_write_unknown_extension(void** state)
{
	(void)state;
	vn_io_mesh m = {0};
	vn_io_error error;
	assert_int_equal(vn_io_write_file("out.xyz", NULL, &m, NULL, &error), vn_io_error_format);
	assert_string_equal(error.message, "out.xyz: unknown file extension (vn knows .off .obj .ply .stl .gltf .glb .drc)");
}

/* ------------------------------------------------------------------ files and formats */

static void test_read_missing_file(void** state)
{
	(void)state;
	vn_io_mesh m;
	vn_io_error error;
	assert_int_equal(vn_io_read_file("data/off/missing.off", NULL, &m, &error), vn_io_error_open);
	assert_string_equal(error.message, "data/off/missing.off: cannot open: No such file or directory");
	assert_null(m.positions);
}

static void test_read_unknown_extension(void** state)
{
	(void)state;
	vn_io_mesh m;
	vn_io_error error;
	assert_int_equal(vn_io_read_file("data/off/cube.fbx", NULL, &m, &error), vn_io_error_format);
	assert_string_equal(error.message, "data/off/cube.fbx: unknown file extension (vn knows .off .obj .ply .stl .gltf .glb .drc)");
}

static void test_read_with_explicit_format(void** state)
{
	(void)state;
	const char text[] = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
	char path[256];
	write_bytes("mesh.txt", text, sizeof text - 1);
	path_in_folder(path, sizeof path, "mesh.txt");
	vn_io_mesh m;
	vn_io_error error;
	assert_int_equal(vn_io_read_file(path, vn_io_format_by_name("off"), &m, &error), vn_io_success);
	assert_triangle(&m);
	vn_io_mesh_free(&m);
}

static void test_read_all(void** state)
{
	(void)state;
	char path[256];
	write_bytes("all.bin", "ab\0cd", 5);
	path_in_folder(path, sizeof path, "all.bin");
	char* data;
	size_t size;
	vn_io_error error;
	assert_int_equal(vn_io_read_all(path, &data, &size, &error), vn_io_success);
	assert_int_equal(size, 5);
	assert_memory_equal(data, "ab\0cd", 6); /* and NUL-terminated */
	free(data);
	assert_int_equal(vn_io_read_all(folder, &data, &size, &error), vn_io_error_open);
	assert_null(data);
	char expected[200];
	snprintf(expected, sizeof expected, "%s: cannot read: Is a directory", folder);
	assert_string_equal(error.message, expected);
}

static void test_read_memory_names_the_source(void** state)
{
	(void)state;
	vn_io_mesh m;
	vn_io_error error;
	const char text[] = "OFF\n1 0 0\n0 0 0\n";
	/* Not NUL-terminated after `size` bytes: the trailing "junk" must not be read. */
	const char buffer[] = "OFF\n1 0 0\n0 0 0\njunk";
	assert_int_equal(vn_io_off_read_memory(buffer, sizeof text - 1, "memory", &m, &error), vn_io_success);
	assert_int_equal(m.vertex_count, 1);
	vn_io_mesh_free(&m);
	assert_int_equal(vn_io_off_read_memory(buffer, sizeof buffer - 1, "memory", &m, &error), vn_io_error_parse);
	assert_string_equal(error.message, "memory:4: unexpected 'junk' after the last of the 0 faces the header announces");
}

static void test_same_file(void** state)
{
	(void)state;
	char a[256], b[256], c[256], d[256], missing[256];
	write_bytes("same_a.off", "x", 1);
	write_bytes("same_d.off", "x", 1);
	path_in_folder(a, sizeof a, "same_a.off");
	path_in_folder(b, sizeof b, "same_b.off");
	path_in_folder(c, sizeof c, "same_c.off");
	path_in_folder(d, sizeof d, "same_d.off");
	path_in_folder(missing, sizeof missing, "same_missing.off");
	assert_int_equal(link(a, b), 0);
	assert_int_equal(symlink(a, c), 0);
	assert_true(vn_io_same_file(a, a));
	assert_true(vn_io_same_file(a, b));
	assert_true(vn_io_same_file(c, a));
	assert_false(vn_io_same_file(a, d));
	assert_false(vn_io_same_file(a, missing));
	assert_false(vn_io_same_file(missing, missing));
}

static void test_format_lookup(void** state)
{
	(void)state;
	const vn_io_format* off = vn_io_format_at(0);
	assert_non_null(off);
	assert_string_equal(off->name, "off");
	assert_string_equal(off->extensions, ".off");
	assert_string_equal(vn_io_format_at(1)->name, "obj");
	assert_string_equal(vn_io_format_at(2)->name, "ply");
	assert_string_equal(vn_io_format_at(3)->name, "stl");
	assert_string_equal(vn_io_format_at(4)->name, "gltf");
	assert_string_equal(vn_io_format_at(5)->name, "glb");
	assert_string_equal(vn_io_format_at(6)->name, "drc");
	assert_null(vn_io_format_at(7));
	assert_ptr_equal(vn_io_format_for_path("scene.GLB"), vn_io_format_at(5));
	assert_ptr_equal(vn_io_format_for_path("scene.gltf"), vn_io_format_at(4));
	assert_ptr_equal(vn_io_format_for_path("Mesh.OBJ"), vn_io_format_at(1));
	assert_ptr_equal(vn_io_format_for_path("scan.PLY"), vn_io_format_at(2));
	assert_ptr_equal(vn_io_format_for_path("dir.d/mesh.OFF"), off);
	assert_ptr_equal(vn_io_format_for_path("mesh.off"), off);
	assert_null(vn_io_format_for_path("mesh.off.gz"));
	assert_null(vn_io_format_for_path("off"));
	assert_null(vn_io_format_for_path(NULL));
	assert_ptr_equal(vn_io_format_by_name("Off"), off);
	assert_null(vn_io_format_by_name("of"));
	assert_null(vn_io_format_by_name(NULL));
}

/* OBJ's `v x y z r g b` has no alpha: vnconvert warns only when an alpha
 * is not 1, and only once where the colours are lost anyway (STL). */
static void test_losses_name_colour_alpha(void** state)
{
	(void)state;
	const vn_io_format* obj = vn_io_format_by_name("obj");
	const vn_io_format* ply = vn_io_format_by_name("ply");
	const vn_io_format* stl = vn_io_format_by_name("stl");
	char text[128];
	vn_io_mesh m;
	read_ok("COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 0.5\n0 1 0 0 0 1 1\n3 0 1 2\n", &m);
	assert_int_equal(vn_io_mesh_losses(&m, obj, text, sizeof text), 1);
	assert_string_equal(text, "vertex colour alpha");
	assert_int_equal(vn_io_mesh_losses(&m, ply, text, sizeof text), 0);
	assert_string_equal(text, "");
	assert_int_equal(vn_io_mesh_losses(&m, stl, text, sizeof text), 1);
	assert_string_equal(text, "vertex colours");
	vn_io_mesh_free(&m);

	read_ok("COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1\n3 0 1 2\n", &m);
	assert_int_equal(vn_io_mesh_losses(&m, obj, text, sizeof text), 0);
	assert_string_equal(text, "");
	vn_io_mesh_free(&m);
}

static void test_result_strings(void** state)
{
	(void)state;
	assert_string_equal(vn_io_result_string(vn_io_success), "success");
	assert_string_equal(vn_io_result_string(vn_io_error_parse), "malformed file");
	assert_string_equal(vn_io_result_string(vn_io_error_same_file), "the output is the input file");
	assert_string_equal(vn_io_result_string(vn_io_result_count_), "unknown vn_io result");
	for (int r = 0; r < vn_io_result_count_; r++)
		for (int s = r + 1; s < vn_io_result_count_; s++)
			assert_string_not_equal(vn_io_result_string((vn_io_result)r), vn_io_result_string((vn_io_result)s));
}

static void test_fail_formats_and_returns(void** state)
{
	(void)state;
	vn_io_error error;
	assert_int_equal(vn_io_fail(&error, vn_io_error_memory, "%s:%d: %s", "a.off", 7, "why"), vn_io_error_memory);
	assert_string_equal(error.message, "a.off:7: why");
	assert_int_equal(vn_io_fail(NULL, vn_io_error_parse, "ignored"), vn_io_error_parse);
}

static void test_mesh_free_and_is_triangles(void** state)
{
	(void)state;
	vn_io_mesh m;
	read_ok("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 2 1 3\n", &m);
	assert_true(vn_io_mesh_is_triangles(&m));
	m.face_offsets[1] = 2; /* a 2-gon and a 4-gon */
	assert_false(vn_io_mesh_is_triangles(&m));
	vn_io_mesh_free(&m);
	assert_null(m.positions);
	assert_null(m.face_offsets);
	assert_int_equal(m.face_count, 0);
	vn_io_mesh_free(&m); /* a zeroed mesh is fine */
	vn_io_mesh_free(NULL);
	assert_false(vn_io_mesh_is_triangles(NULL));
}

/* ------------------------------------------------------------------ runner */

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test(test_off_counts_on_next_line),
	    cmocka_unit_test(test_off_counts_on_header_line),
	    cmocka_unit_test(test_off_without_keyword),
	    cmocka_unit_test(test_off_count_run_into_keyword),
	    cmocka_unit_test(test_off_two_counts),
	    cmocka_unit_test(test_off_comments_and_blank_lines),
	    cmocka_unit_test(test_off_crlf_and_byte_order_mark),
	    cmocka_unit_test(test_off_line_numbers_with_carriage_returns),
	    cmocka_unit_test(test_coff_float_colours_rgb_and_rgba),
	    cmocka_unit_test(test_coff_byte_colours),
	    cmocka_unit_test(test_noff_normals),
	    cmocka_unit_test(test_cnoff_reads_position_normal_colour),
	    cmocka_unit_test(test_stoff_texture_coordinates),
	    cmocka_unit_test(test_stcnoff_reads_every_field_in_order),
	    cmocka_unit_test(test_4off_divides_by_w),
	    cmocka_unit_test(test_noff_dimension_3_on_own_line),
	    cmocka_unit_test(test_noff_dimension_and_counts_on_header_line),
	    cmocka_unit_test(test_nan_and_inf_coordinates_are_read),
	    cmocka_unit_test(test_polygons_of_every_size),
	    cmocka_unit_test(test_face_colours_float_rgb_and_rgba),
	    cmocka_unit_test(test_face_colours_bytes),
	    cmocka_unit_test(test_face_colormap_index_is_ignored),
	    cmocka_unit_test(test_uncoloured_faces_get_geomview_grey),
	    cmocka_unit_test(test_fixture_cube),
	    cmocka_unit_test(test_fixture_colored),
	    cmocka_unit_test(test_fixture_binary),
	    cmocka_unit_test(test_binary_off),
	    cmocka_unit_test(test_binary_off_as_pmp_library_writes_it),
	    cmocka_unit_test(test_binary_noff_with_comment_before_header),
	    cmocka_unit_test(test_binary_coff_and_face_colours),
	    cmocka_unit_test(test_binary_stoff_and_ndim),
	    cmocka_unit_test(test_binary_4off),
	    cmocka_unit_test(test_binary_truncated_vertex),
	    cmocka_unit_test(test_binary_truncated_face),
	    cmocka_unit_test(test_binary_index_out_of_range),
	    cmocka_unit_test(test_binary_negative_count),
	    cmocka_unit_test(test_binary_counts_beyond_file_size),
	    cmocka_unit_test(test_binary_trailing_bytes),
	    cmocka_unit_test(test_binary_bad_face_colour_count),
	    cmocka_unit_test(test_binary_text_after_keyword),
	    cmocka_unit_test(test_error_unknown_keyword),
	    cmocka_unit_test(test_error_empty_file),
	    cmocka_unit_test(test_error_only_comments),
	    cmocka_unit_test(test_error_ndim_other_than_3),
	    cmocka_unit_test(test_error_missing_counts),
	    cmocka_unit_test(test_error_one_count),
	    cmocka_unit_test(test_error_four_counts),
	    cmocka_unit_test(test_error_count_not_integer),
	    cmocka_unit_test(test_error_counts_beyond_file_size),
	    cmocka_unit_test(test_error_vertex_too_few_numbers),
	    cmocka_unit_test(test_error_vertex_too_many_numbers),
	    cmocka_unit_test(test_error_colour_vertex_count),
	    cmocka_unit_test(test_error_not_a_number),
	    cmocka_unit_test(test_error_binary_garbage_is_quoted_safely),
	    cmocka_unit_test(test_error_homogeneous_w_zero),
	    cmocka_unit_test(test_error_truncated_vertices),
	    cmocka_unit_test(test_error_truncated_faces),
	    cmocka_unit_test(test_error_index_out_of_range),
	    cmocka_unit_test(test_error_negative_index),
	    cmocka_unit_test(test_error_index_not_an_integer),
	    cmocka_unit_test(test_error_face_more_corners_than_indices),
	    cmocka_unit_test(test_face_indices_across_lines),
	    cmocka_unit_test(test_error_face_without_corners),
	    cmocka_unit_test(test_error_face_colour_lengths),
	    cmocka_unit_test(test_error_colour_out_of_range),
	    cmocka_unit_test(test_error_colour_styles_mixed),
	    cmocka_unit_test(test_error_trailing_content),
	    cmocka_unit_test(test_write_exact_text),
	    cmocka_unit_test(test_text_out_integers_and_buffer),
	    cmocka_unit_test(test_format_g_literals),
	    cmocka_unit_test(test_format_g_matches_printf),
	    cmocka_unit_test(test_parse_real_matches_strtod),
	    cmocka_unit_test(test_format_exact),
	    cmocka_unit_test(test_format_float),
	    cmocka_unit_test(test_write_colours_in_source_style),
	    cmocka_unit_test(test_round_trip_is_exact),
	    cmocka_unit_test(test_round_trip_keeps_byte_colours),
	    cmocka_unit_test(test_write_keeps_alpha),
	    cmocka_unit_test(test_write_keeps_binary_alpha),
	    cmocka_unit_test(test_writer_reports_stream_errors),
	    cmocka_unit_test(test_failed_write_leaves_destination_untouched),
	    cmocka_unit_test(test_write_replaces_existing_file),
	    cmocka_unit_test(test_written_file_mode_follows_umask),
	    cmocka_unit_test(test_write_into_missing_folder),
	    cmocka_unit_test(test_write_unknown_extension),
	    cmocka_unit_test(test_read_missing_file),
	    cmocka_unit_test(test_read_unknown_extension),
	    cmocka_unit_test(test_read_with_explicit_format),
	    cmocka_unit_test(test_read_all),
	    cmocka_unit_test(test_read_memory_names_the_source),
	    cmocka_unit_test(test_same_file),
	    cmocka_unit_test(test_format_lookup),
	    cmocka_unit_test(test_losses_name_colour_alpha),
	    cmocka_unit_test(test_result_strings),
	    cmocka_unit_test(test_fail_formats_and_returns),
	    cmocka_unit_test(test_mesh_free_and_is_triangles),
	};
	snprintf(folder, sizeof folder, "/tmp/vn_test_off.XXXXXX");
	if (!mkdtemp(folder)) {
		perror("mkdtemp");
		return 1;
	}
	int failures = cmocka_run_group_tests(tests, NULL, NULL);
	remove_tree(folder);
	return failures;
}
