// What libdraco alone needs (tests/bench/draco_memory.sh measures its peak
// memory): each .drc decoded with Draco's own decoder, one after the other,
// and with "encode" each decoded mesh encoded again as vnconvert does by
// default (its bits, 14 for positions, 10 for normals, 12 for texture
// coordinates, 8 for colours; compression level 7: speed 3).
//   draco_floor decode|encode FILE.drc...
#include <draco/compression/decode.h>
#include <draco/compression/expert_encode.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

int main(int argc, char** argv)
{
	if (argc < 3 || (strcmp(argv[1], "decode") && strcmp(argv[1], "encode"))) {
		fprintf(stderr, "usage: draco_floor decode|encode FILE.drc...\n");
		return 2;
	}
	const bool encode = !strcmp(argv[1], "encode");
	for (int i = 2; i < argc; ++i) {
		std::ifstream in(argv[i], std::ios::binary);
		const std::vector<char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
		draco::DecoderBuffer buffer;
		buffer.Init(data.data(), data.size());
		auto mesh = draco::Decoder().DecodeMeshFromBuffer(&buffer);
		if (!mesh.ok()) {
			fprintf(stderr, "%s: %s\n", argv[i], mesh.status().error_msg());
			return 1;
		}
		if (!encode)
			continue;
		draco::ExpertEncoder encoder(*mesh.value());
		for (int a = 0; a < mesh.value()->num_attributes(); ++a) {
			const draco::PointAttribute& attribute = *mesh.value()->attribute(a);
			const int bits[] = {14, 10, 8, 12};
			if (attribute.data_type() == draco::DT_FLOAT32 && attribute.attribute_type() <= draco::GeometryAttribute::TEX_COORD)
				encoder.SetAttributeQuantization(a, bits[attribute.attribute_type()]);
		}
		encoder.SetSpeedOptions(3, 3);
		draco::EncoderBuffer out;
		if (!encoder.EncodeToBuffer(&out).ok()) {
			fprintf(stderr, "%s: cannot encode\n", argv[i]);
			return 1;
		}
	}
	return 0;
}
