// libFuzzer target: ROS 2 bags (io/ros2_bag.h) stored as SQLite .db3 files (and io/sqlite_salvage.h, for the cut-short ones), the input being the whole file;
// read once as it is and once with skip_damaged.
#include "fuzz/fuzz_common.h"
#include "io/ros2_bag.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  const auto path = fuzz::write_file("bag.db3", data, size);
  for (const bool skip : {false, true}) {
    io::LogReadOptions options;
    options.max_points = 200000;
    options.skip_damaged = skip;
    fuzz::expect_input_error([&] {
      const io::RosBagLog log = io::read_ros2_bag(path, options);
      fuzz::check(!log.scans.empty(), "scans not empty");
      for (const Scan& s : log.scans) {
        fuzz::check(std::isfinite(s.timestamp), "scan timestamp finite");
        fuzz::check(fuzz::plausible(s.T_world_laser) && fuzz::plausible(s.T_world_odom), "scan poses plausible");
        fuzz::check(s.points_laser.size() <= static_cast<std::size_t>(s.num_beams), "beam count");
        for (const Vec2& p : s.points_laser) fuzz::check(fuzz::finite(p), "scan point finite");
      }
    });
  }
  return 0;
}
