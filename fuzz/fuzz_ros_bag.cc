// libFuzzer target: ROS 1 bags (io/logs/ros_bag.h, read with Debian's librosbag), the input being the whole file.
#include <console_bridge/console.h>

#include "fuzz/fuzz_common.h"
#include "io/logs/ros_bag.h"
#include "io/logs/scan_source.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  // librosbag's own complaints about bad headers go to the console: keep the fuzzer's output (and speed) to itself.
  static const bool quiet = (console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE), true);
  (void)quiet;
  const auto path = fuzz::write_file("log.bag", data, size);
  io::LogReadOptions options;
  options.max_points = 200000;
  fuzz::expect_input_error([&] {
    // through load_scan_source, which refuses a bag without scans
    fuzz::check_bag_scans(io::load_scan_source(path.string(), options).scans);
  });
  return 0;
}
