// libFuzzer target: map_server YAML (io/formats/map_server.h, read_map_yaml), the input being map.yaml. Three small
// fixed images lie beside it (P5 8-bit map.pgm, P5 16-bit map16.pgm, P2 map2.pgm) for its 'image:' field to name;
// fuzz_map_server_pgm fuzzes the images.
#include "fuzz/fuzz_map_server.h"
#include "io/formats/map_server.h"

namespace {

void write_images() {
  using partslam::fuzz::write_file;
  using namespace std::string_view_literals;
  // 4 x 3, occupied / free / unknown / in-between pixels.
  write_file("map.pgm", "P5\n# fixed\n4 3\n255\n\x00\xfe\xcd\x80\xfe\xfe\x00\x10\xcd\xcd\xfe\xff"sv);
  write_file("map16.pgm", "P5 2 2 65535\n\x00\x00\xff\xfe\x80\x00\xcd\xcd"sv);
  write_file("map2.pgm", "P2\n3 2\n100\n0 50 100\n100 99 1\n");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  static const bool images = (write_images(), true);
  (void)images;
  const auto path = fuzz::write_file("map.yaml", data, size);
  fuzz::expect_input_error([&] { fuzz::check_grid_map(io::read_map_yaml(path)); });
  return 0;
}
