// Where scans come from on the command line: a table of the formats read (scan_source_formats), each with how it
// recognises a spec and the reader of its own file: a CARMEN log, plain or gzip (io/logs/carmen_log.h), a ROS 1 bag
// (*.bag, io/logs/ros_bag.h), a ROS 2 bag (*.mcap, *.db3, a rosbag2 folder or its metadata.yaml, io/logs/ros2_bag.h),
// or "sim[:SEED]" for the built-in simulated building (core/sim/simulator.h; docs/DESIGN.md, "Embedded default"), so
// every command also runs without ../shared/data. load_scan_source picks the first format that recognises the spec
// and refuses, for every format, an input that gave no scan.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/maps/scan.h"
#include "io/logs/log_read_options.h"

namespace partslam::io {

struct ScanSource {
  std::string name;    ///< dataset name: the log's file name without .gz/.log/.clf, or "sim-SEED"
  std::string source;  ///< the spec it was loaded from
  Scans scans;
  /// The laser's mount on the robot, where the log says it (a bag's base_link -> laser transforms, a CARMEN log's
  /// fixed offset between its laser and robot poses); the scans are posed at the laser either way. The robot's poses
  /// (what `slam --relations` judges by default) are T_world_laser * T_base_laser^-1.
  std::optional<Pose2> T_base_laser;
  /// The reader's warnings (a recording cut short, damage skipped), "<file>: ..." each; the apps print them.
  std::vector<std::string> warnings;
};

/// One format load_scan_source reads.
struct SourceFormat {
  const char* name;         ///< e.g. "ROS 1 bag"
  const char* scan_records; ///< what holds its scans, for the empty-input error: "sensor_msgs/LaserScan messages"
  bool bag;                 ///< it has topics (--scan-topic, --odom-topic apply)
  bool (*recognises)(const std::string& spec);
  /// Reads the scans (possibly none) with the name and the warnings; the caller sets `source` and checks.
  ScanSource (*read)(const std::string& spec, const LogReadOptions& options);
};

/// Every format, in the order they are tried (the first that recognises a spec reads it; CARMEN, last, takes any
/// file).
std::span<const SourceFormat> scan_source_formats();

/// The format that reads `spec`. Throws InputError for a folder that is not a rosbag2 folder.
const SourceFormat& scan_source_format(const std::string& spec);

/// True for "sim" and "sim:SEED".
bool is_simulator_spec(const std::string& spec);

/// Loads a log or runs the simulator. Throws InputError for an unreadable log, one without a laser scan
/// ("<spec>: no laser scans: ..."), a bad seed, or bag topics asked of an input without topics.
ScanSource load_scan_source(const std::string& spec, const LogReadOptions& options = {});

}  // namespace partslam::io
