// libFuzzer target: map_server PGM images (io/formats/map_server.h, read_map_yaml), the input being map.pgm. The
// first input byte chooses the fixed map.yaml beside it (mode trinary, scale or raw; negate 0 or 1).
#include "fuzz/fuzz_map_server.h"
#include "io/formats/map_server.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  if (size < 1) return 0;
  static const char* const kModes[] = {"trinary", "scale", "raw"};
  const std::string yaml = std::string("image: map.pgm\nresolution: 0.05\norigin: [-1.5, 2.0, 0.1]\nnegate: ") +
                           ((data[0] & 1) != 0 ? "1" : "0") + "\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmode: " +
                           kModes[(data[0] >> 1) % 3] + "\n";
  const auto path = fuzz::write_file("map.yaml", yaml);
  fuzz::write_file("map.pgm", data + 1, size - 1);
  fuzz::expect_input_error([&] { fuzz::check_grid_map(io::read_map_yaml(path)); });
  return 0;
}
