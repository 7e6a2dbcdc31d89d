/* Computes one triangle's normals through the installed library. */
#include <stdio.h>
#include <vn.h>

int main(void)
{
	if (vn_version() >> 8 != VN_VERSION >> 8)
		return 1;
	const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
	const uint32_t idx[] = {0, 1, 2};
	float n[9];
	const vn_positions p = {pos, 3, 0, vn_scalar_float32};
	const vn_vectors o = {n, 0, vn_scalar_float32};
	vn_result r = vn_triangle_normals(&o, &p, idx, 3, vn_method_mwselr, NULL, NULL);
	printf("%s %g %g %g\n", vn_result_string(r), n[0], n[1], n[2]);
	return r != vn_result_success || n[2] != 1.0f;
}
