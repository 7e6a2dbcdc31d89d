// How often Draco's OBJ number parser and a correctly rounding one
// (strtof) disagree on the fewest digits that read back as a float
// (docs/PERFORMANCE.md, "Writing text formats"; why vn's OBJ writer asks
// both): random float bit patterns, each written "%.*g" with 6 to 12
// digits, the fewest each reader gets back exactly. Prints how many floats
// have a shorter text for Draco than for strtof (texts only Draco reads
// right), and one example.
//   g++ -O2 tests/bench/draco_float_text.cpp -ldraco -o draco_float_text && ./draco_float_text [COUNT [MIN MAX]]
// COUNT random patterns (default 20000000), of which those with MIN <= |v| <= MAX
// (default 1e-30 and 1e30) are counted.
#include <draco/core/decoder_buffer.h>
#include <draco/io/parser_utils.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

static float draco_reads(const char* text)
{
	draco::DecoderBuffer buffer;
	buffer.Init(text, std::strlen(text));
	float v = NAN;
	draco::parser::ParseFloat(&buffer, &v);
	return v;
}

int main(int argc, char** argv)
{
	const long count = argc > 1 ? std::atol(argv[1]) : 20000000;
	const float lo = argc > 3 ? std::strtof(argv[2], nullptr) : 1e-30f, hi = argc > 3 ? std::strtof(argv[3], nullptr) : 1e30f;
	uint64_t s = 88172645463325252ull;
	long n = 0, draco_shorter = 0, strtof_shorter = 0;
	for (long i = 0; i < count; i++) {
		s ^= s << 13, s ^= s >> 7, s ^= s << 17;
		const uint32_t bits = uint32_t(s);
		float v;
		std::memcpy(&v, &bits, sizeof v);
		if (!std::isfinite(v) || std::fabs(v) < lo || std::fabs(v) > hi)
			continue;
		n++;
		int by_draco = 0, by_strtof = 0;
		char text[320]; /* %g of a float has at most 50 characters; the compiler counts 310 */
		for (int p = 6; p <= 12 && !(by_draco && by_strtof); p++) {
			std::snprintf(text, sizeof text, "%.*g", p, double(v));
			if (!by_draco && draco_reads(text) == v)
				by_draco = p;
			if (!by_strtof && std::strtof(text, nullptr) == v)
				by_strtof = p;
		}
		if (by_draco && by_draco < by_strtof && !draco_shorter++) {
			std::snprintf(text, sizeof text, "%.*g", by_draco, double(v));
			std::printf("for example %.9g: Draco reads '%s' back, strtof as %.9g\n", double(v), text,
			            double(std::strtof(text, nullptr)));
		}
		strtof_shorter += by_strtof && by_strtof < by_draco;
	}
	std::printf("%ld floats: the fewest digits Draco reads back are fewer than strtof's for %ld (%.3f%%), more for %ld\n", n,
	            draco_shorter, 100.0 * double(draco_shorter) / double(n), strtof_shorter);
}
