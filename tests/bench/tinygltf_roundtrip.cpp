// The baseline of docs/PERFORMANCE.md's glTF row: what tinygltf alone takes
// to load a GLB and save it again (no normal computation).
//   tinygltf_roundtrip IN.glb OUT.glb
#include <cstdio>
#include <string>
#include <tiny_gltf.h>

int main(int argc, char** argv)
{
	if (argc != 3) {
		std::fprintf(stderr, "usage: tinygltf_roundtrip IN.glb OUT.glb\n");
		return 2;
	}
	tinygltf::TinyGLTF io;
	tinygltf::Model model;
	std::string err, warn;
	if (!io.LoadBinaryFromFile(&model, &err, &warn, argv[1])) {
		std::fprintf(stderr, "%s: %s\n", argv[1], err.c_str());
		return 1;
	}
	if (!io.WriteGltfSceneToFile(&model, argv[2], true, true, false, true)) {
		std::fprintf(stderr, "%s: cannot write\n", argv[2]);
		return 1;
	}
	return 0;
}
