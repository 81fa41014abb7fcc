// libFuzzer target: the map database's file structure (io/store/map_database.h), the input being the whole SQLite
// file (seeds: small databases with 512-byte pages). It is opened read-only and every table is read
// (fuzz_map_database.h, read_everything).
#include "fuzz/fuzz_map_database.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = partslam::fuzz::write_database(data, size);
  partslam::fuzz::read_everything(path);
  return 0;
}
