// Loads each glTF/GLB given with Debian's tinygltf 2.7, an independent
// reader (vn's own glTF code does not use its loader): exit 1 naming every
// file it refuses. Images are not decoded.
//   tinygltf_load FILE...
#include <cstdio>
#include <string>
#include <tiny_gltf.h>

static bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                       void*)
{
	return true;
}

int main(int argc, char** argv)
{
	int failed = 0;
	for (int i = 1; i < argc; ++i) {
		tinygltf::TinyGLTF loader;
		loader.SetImageLoader(skip_image, nullptr);
		tinygltf::Model model;
		std::string err, warn, path = argv[i];
		const bool glb = path.size() > 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
		const bool ok = glb ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
		                    : loader.LoadASCIIFromFile(&model, &err, &warn, path);
		if (!ok) {
			std::fprintf(stderr, "%s: tinygltf: %s\n", argv[i], err.c_str());
			failed = 1;
		}
	}
	return failed;
}
