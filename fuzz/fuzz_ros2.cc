// libFuzzer target: ROS 2 bags (io/logs/ros2_bag.h). Byte 0 even: the rest is an MCAP file (io/logs/mcap_file.h:
// chunks, lz4, zstd); odd: a rosbag2 .db3 file (SQLite; io/files/sqlite_salvage.h for the cut-short ones). Each is
// read once as it is and once with skip_damaged.
#include "fuzz/fuzz_common.h"
#include "io/logs/ros2_bag.h"
#include "io/logs/scan_source.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  if (size == 0) return 0;
  const auto path = fuzz::write_file(data[0] % 2 == 0 ? "bag.mcap" : "bag.db3", data + 1, size - 1);
  for (const bool skip : {false, true}) {
    io::LogReadOptions options;
    options.max_points = 200000;
    options.skip_damaged = skip;
    fuzz::expect_input_error([&] { fuzz::check_bag_scans(io::load_scan_source(path.string(), options).scans); });
  }
  return 0;
}
