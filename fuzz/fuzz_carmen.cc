// libFuzzer target: CARMEN logs (io/logs/carmen_log.h: FLASER, ROBOTLASER1, ODOM, comments, other messages), the
// input being the whole file (plain text; gzip is fuzz_gzip's).
#include "fuzz/fuzz_common.h"
#include "io/logs/carmen_log.h"

namespace partslam::fuzz {

void check_log(const io::CarmenLog& log, const io::LogReadOptions& options) {
  std::size_t points = 0;
  for (const Scan& s : log.scans) {
    check(std::isfinite(s.timestamp), "scan timestamp finite");
    check(plausible(s.T_world_laser) && plausible(s.T_world_odom), "scan poses plausible");
    check(s.num_beams >= 1 && s.points_laser.size() <= static_cast<std::size_t>(s.num_beams), "beam count");
    for (const Vec2& p : s.points_laser) check(finite(p) && p.norm() < options.max_usable_range, "scan point");
    points += s.points_laser.size();
  }
  check(points <= options.max_points, "max_points");
  check(points == log.stats.valid_beams, "valid beam count");
  for (const io::OdomReading& o : log.odometry) {
    check(std::isfinite(o.timestamp) && plausible(o.T_world_odom), "odometry plausible");
  }
}

}  // namespace partslam::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  const auto path = fuzz::write_file("log.clf", data, size);
  io::LogReadOptions options;
  options.max_points = 200000;  // the cap itself is what is checked, at a size a fuzzer reaches
  fuzz::expect_input_error([&] { fuzz::check_log(io::read_carmen_log(path, options), options); });
  return 0;
}
