#include "io/scan_source.h"

#include <charconv>
#include <filesystem>

#include "core/error.h"
#include "core/sim/simulator.h"
#include "io/ros2_bag.h"
#include "io/ros_bag.h"

namespace partslam::io {

bool is_simulator_spec(const std::string& spec) { return spec == "sim" || spec.rfind("sim:", 0) == 0; }

ScanSource load_scan_source(const std::string& spec, const LogReadOptions& options) {
  ScanSource out;
  out.source = spec;
  const bool bag = !is_simulator_spec(spec) && (is_ros_bag(spec) || is_ros2_bag(spec));
  if (!bag && (!options.scan_topic.empty() || !options.odom_topic.empty()))
    throw InputError(spec + ": --scan-topic and --odom-topic name a bag's topics; this is not a bag");
  if (is_simulator_spec(spec)) {
    SimulatorConfig config;
    if (spec.size() > 4) {
      const char* first = spec.data() + 4;
      const char* last = spec.data() + spec.size();
      const auto [ptr, ec] = std::from_chars(first, last, config.seed);
      if (ec != std::errc() || ptr != last) throw InputError("'" + spec + "': the simulator seed must be an integer");
    }
    out.name = "sim-" + std::to_string(config.seed);
    out.scans = simulate(config).scans;
    return out;
  }
  std::string name = std::filesystem::path(spec).filename().string();
  std::error_code ec;
  if (std::filesystem::is_directory(spec, ec) && !is_ros2_bag(spec))
    throw InputError(spec + ": a folder without metadata.yaml (a rosbag2 folder has one; a log is a file)");
  if (bag) {
    std::filesystem::path path = std::filesystem::path(spec).lexically_normal();
    if (!path.has_filename() || path.filename() == "metadata.yaml") path = path.parent_path();  // a rosbag2 folder
    out.name = path.stem().string();
    RosBagLog log = is_ros_bag(spec) ? read_ros_bag(spec, options) : read_ros2_bag(spec, options);
    out.scans = std::move(log.scans);
    out.warnings = std::move(log.warnings);
    return out;
  }
  for (const char* ext : {".gz", ".log", ".clf"}) {
    const std::string e(ext);
    if (name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0)
      name.resize(name.size() - e.size());
  }
  out.name = name;
  CarmenLog log = read_carmen_log(spec, options);
  out.scans = std::move(log.scans);
  out.warnings = std::move(log.warnings);
  if (out.scans.empty()) {
    std::string why;
    for (const std::string& w : out.warnings) why += "; " + w;
    throw InputError(spec + ": the log holds no laser scans" + why);
  }
  return out;
}

}  // namespace partslam::io
