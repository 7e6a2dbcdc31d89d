/*
 * libFuzzer entry point for the OBJ reader and writer (seed corpus:
 * tests/data/obj). Debian's libdraco is not instrumented, so coverage guides
 * only through vn's side (the scan that checks a file before Draco reads
 * it); a crash or out-of-bounds read inside libdraco still shows.
 *
 * Every accepted input must give a consistent mesh (indices within the
 * vertices, faces of 3 or more corners, names within their lists), and
 * writing it and reading that back must give the same counts and corners,
 * and every face the same group and smoothing group.
 * The input is also read as the mesh's material library (mtl.c): every
 * colour, emission, roughness and metallic factor within [0, 1].
 */
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "mtl.h"
#include "obj.h"

static void check_library(vn_io_mesh& m, const uint8_t* data, size_t size)
{
	FILE* warnings = fopen("/dev/null", "w");
	if (!warnings)
		return;
	if (!vn_io_mtl_parse(reinterpret_cast<const char*>(data), size, "fuzz.mtl", nullptr, &m, warnings))
		abort();
	fclose(warnings);
	for (size_t i = 0; i < m.materials.count; i++) {
		const vn_io_material& d = m.material_defs[i];
		for (double c : d.color)
			if (!(c >= 0 && c <= 1))
				abort();
		for (double c : d.emissive)
			if (!(c >= 0 && c <= 1))
				abort();
		if (!(d.roughness == -1 || (d.roughness >= 0 && d.roughness <= 1)) || !(d.metallic >= 0 && d.metallic <= 1))
			abort();
	}
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

static void check_names(const vn_io_face_names& n, size_t faces)
{
	for (size_t f = 0; n.of_face && f < faces; f++)
		if (n.of_face[f] != VN_IO_NO_NAME && n.of_face[f] >= n.count)
			abort();
	for (size_t i = 0; i < n.count; i++)
		if (!n.names[i])
			abort();
}

static void check_mesh(const vn_io_mesh& m)
{
	if (!m.positions || !m.face_offsets || !m.indices || m.face_offsets[0] != 0)
		abort();
	for (size_t f = 0; f < m.face_count; f++)
		if (m.face_offsets[f + 1] < m.face_offsets[f] + 3)
			abort();
	for (uint32_t i = 0; i < m.face_offsets[m.face_count]; i++)
		if (m.indices[i] >= m.vertex_count)
			abort();
	check_names(m.materials, m.face_count);
	check_names(m.objects, m.face_count);
	check_names(m.groups, m.face_count);
	check_names(m.smoothing, m.face_count);
	/* Lines: of 2 points or more, each a vertex. */
	if (m.line_count && (!m.line_offsets || !m.line_indices || m.line_offsets[0] != 0))
		abort();
	for (size_t l = 0; l < m.line_count; l++)
		if (m.line_offsets[l + 1] < m.line_offsets[l] + 2)
			abort();
	for (uint32_t i = 0; m.line_count && i < m.line_offsets[m.line_count]; i++)
		if (m.line_indices[i] >= m.vertex_count)
			abort();
}

/* Whether every face has the same name (or none) in a and b. */
static bool same_names(const vn_io_face_names& a, const vn_io_face_names& b, size_t faces)
{
	if (!a.of_face || !b.of_face)
		return !a.of_face == !b.of_face;
	for (size_t f = 0; f < faces; f++) {
		const uint32_t i = a.of_face[f], k = b.of_face[f];
		if ((i == VN_IO_NO_NAME) != (k == VN_IO_NO_NAME) || (i != VN_IO_NO_NAME && strcmp(a.names[i], b.names[k])))
			return false;
	}
	return true;
}

/* The writer keeps a double in full, but a double that is exactly a float
 * (read from a glTF, or a float printed in 17 digits) as the float's
 * shortest text, which reads back as another double of the same float. */
static bool same_coordinates(const double* back, const double* in)
{
	for (int k = 0; k < 3; k++) {
		const bool is_float = std::fabs(in[k]) <= FLT_MAX && double(float(in[k])) == in[k];
		if (is_float ? float(back[k]) != float(in[k]) : memcmp(&back[k], &in[k], sizeof(double)) != 0)
			return false;
	}
	return true;
}

static void check_round_trip(const vn_io_mesh& m)
{
	char* text = nullptr;
	size_t size = 0;
	FILE* out = open_memstream(&text, &size);
	if (!out)
		return;
	vn_io_error error;
	const vn_io_result written = vn_io_obj_write(out, "fuzz.obj", &m, nullptr, &error);
	fclose(out);
	if (written != vn_io_success)
		abort();
	vn_io_mesh back;
	if (vn_io_obj_read_memory(text, size, "written.obj", &back, &error) != vn_io_success) {
		fprintf(stderr, "%s\n", error.message);
		abort();
	}
	const uint32_t corners = m.face_offsets[m.face_count];
	if (back.face_count != m.face_count || back.vertex_count > m.vertex_count ||
	    memcmp(back.face_offsets, m.face_offsets, (m.face_count + 1) * sizeof(uint32_t)) != 0 ||
	    !back.normals != !m.normals || !back.texcoords != !m.texcoords ||
	    !back.materials.of_face != !m.materials.of_face || !back.objects.of_face != !m.objects.of_face ||
	    !same_names(back.groups, m.groups, m.face_count) || !same_names(back.smoothing, m.smoothing, m.face_count))
		abort();
	for (uint32_t c = 0; c < corners; c++)
		if (!same_coordinates(back.positions + 3 * back.indices[c], m.positions + 3 * m.indices[c]))
			abort();
	/* Every line back, its points where they were. */
	if (back.line_count != m.line_count ||
	    (m.line_count && memcmp(back.line_offsets, m.line_offsets, (m.line_count + 1) * sizeof(uint32_t)) != 0))
		abort();
	for (uint32_t c = 0; m.line_count && c < m.line_offsets[m.line_count]; c++)
		if (!same_coordinates(back.positions + 3 * back.line_indices[c], m.positions + 3 * m.line_indices[c]))
			abort();
	/* A point cloud: every vertex back, in order. */
	if (!m.face_count && back.vertex_count != m.vertex_count)
		abort();
	for (size_t i = 0; !m.face_count && i < m.vertex_count; i++)
		if (!same_coordinates(back.positions + 3 * i, m.positions + 3 * i))
			abort();
	vn_io_mesh_free(&back);
	free(text);
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	vn_io_mesh mesh;
	vn_io_error error;
	error.message[0] = '\0';
	if (vn_io_obj_read_memory(reinterpret_cast<const char*>(data), size, "fuzz.obj", &mesh, &error) == vn_io_success) {
		check_mesh(mesh);
		check_round_trip(mesh);
		check_library(mesh, data, size);
	} else if (strncmp(error.message, "fuzz.obj", 8) != 0 || mesh.positions || mesh.indices) {
		abort();
	}
	vn_io_mesh_free(&mesh);
	return 0;
}
