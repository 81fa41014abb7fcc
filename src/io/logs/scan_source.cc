#include "io/logs/scan_source.h"

#include <array>
#include <charconv>
#include <filesystem>

#include "core/error.h"
#include "core/sim/simulator.h"
#include "io/logs/carmen_log.h"
#include "io/logs/ros2_bag.h"
#include "io/logs/ros_bag.h"

namespace partslam::io {
namespace {

ScanSource read_simulator(const std::string& spec, const LogReadOptions&) {
  SimulatorConfig config;
  if (spec.size() > 4) {
    const char* first = spec.data() + 4;
    const char* last = spec.data() + spec.size();
    const auto [ptr, ec] = std::from_chars(first, last, config.seed);
    if (ec != std::errc() || ptr != last) throw InputError("'" + spec + "': the simulator seed must be an integer");
  }
  ScanSource out;
  out.name = "sim-" + std::to_string(config.seed);
  out.scans = simulate(config).scans;
  return out;
}

// A bag's name: its file's stem, or a rosbag2 folder's name.
std::string bag_name(const std::string& spec) {
  std::filesystem::path path = std::filesystem::path(spec).lexically_normal();
  if (!path.has_filename() || path.filename() == "metadata.yaml") path = path.parent_path();  // a rosbag2 folder
  return path.stem().string();
}

ScanSource from_bag(const std::string& spec, RosBagLog log) {
  ScanSource out;
  out.name = bag_name(spec);
  out.scans = std::move(log.scans);
  if (!log.laser_frame.empty()) out.T_base_laser = log.T_base_laser;
  out.warnings = std::move(log.warnings);
  return out;
}

bool is_ros1_spec(const std::string& spec) { return !is_simulator_spec(spec) && is_ros_bag(spec); }
bool is_ros2_spec(const std::string& spec) { return !is_simulator_spec(spec) && is_ros2_bag(spec); }
ScanSource read_ros1(const std::string& spec, const LogReadOptions& o) { return from_bag(spec, read_ros_bag(spec, o)); }
ScanSource read_ros2(const std::string& spec, const LogReadOptions& o) { return from_bag(spec, read_ros2_bag(spec, o)); }

bool is_carmen_spec(const std::string& spec) {
  std::error_code ec;
  return !is_simulator_spec(spec) && !std::filesystem::is_directory(spec, ec);
}

ScanSource read_carmen(const std::string& spec, const LogReadOptions& options) {
  ScanSource out;
  out.name = std::filesystem::path(spec).filename().string();
  for (const std::string e : {".gz", ".log", ".clf"})
    if (out.name.size() > e.size() && out.name.compare(out.name.size() - e.size(), e.size(), e) == 0)
      out.name.resize(out.name.size() - e.size());
  CarmenLog log = read_carmen_log(spec, options);
  out.scans = std::move(log.scans);
  out.T_base_laser = log.T_base_laser;
  out.warnings = std::move(log.warnings);
  return out;
}

constexpr std::array<SourceFormat, 4> kFormats{{
    {"simulator", "simulated scans", false, is_simulator_spec, read_simulator},
    {"ROS 1 bag", "sensor_msgs/LaserScan messages", true, is_ros1_spec, read_ros1},
    {"ROS 2 bag", "sensor_msgs/LaserScan messages", true, is_ros2_spec, read_ros2},
    {"CARMEN log", "FLASER or ROBOTLASER1 messages", false, is_carmen_spec, read_carmen},
}};

}  // namespace

bool is_simulator_spec(const std::string& spec) { return spec == "sim" || spec.rfind("sim:", 0) == 0; }

std::span<const SourceFormat> scan_source_formats() { return kFormats; }

const SourceFormat& scan_source_format(const std::string& spec) {
  std::error_code ec;
  const bool folder = !is_simulator_spec(spec) && std::filesystem::is_directory(spec, ec);
  for (const SourceFormat& f : kFormats)
    if (f.recognises(spec) && (!folder || f.read == read_ros2)) return f;
  throw InputError(spec + ": a folder without metadata.yaml (a rosbag2 folder has one; a log is a file)");
}

ScanSource load_scan_source(const std::string& spec, const LogReadOptions& options) {
  const SourceFormat& format = scan_source_format(spec);
  if (!format.bag && (!options.scan_topic.empty() || !options.odom_topic.empty()))
    throw InputError(spec + ": --scan-topic and --odom-topic name a bag's topics; this is not a bag");
  ScanSource out = format.read(spec, options);
  out.source = spec;
  if (out.scans.empty()) {  // one check for every format
    std::string why;
    for (const std::string& w : out.warnings) why += "; " + w;
    throw InputError(spec + ": no laser scans: the " + format.name + " holds no " + format.scan_records + why);
  }
  return out;
}

}  // namespace partslam::io
