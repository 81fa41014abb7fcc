// Where scans come from on the command line: a CARMEN log (plain or gzip), a ROS 1 bag (*.bag, io/ros_bag.h), a
// ROS 2 bag (*.mcap, *.db3 or a rosbag2 folder, io/ros2_bag.h), or
// "sim[:SEED]" for the built-in simulated building (docs/DESIGN.md, "Embedded default"), so every command also
// runs without ../shared/data.
#pragma once

#include <string>
#include <vector>

#include "core/maps/scan.h"
#include "io/carmen_log.h"

namespace partslam::io {

struct ScanSource {
  std::string name;    ///< dataset name: the log's file name without .gz/.log/.clf, or "sim-SEED"
  std::string source;  ///< the spec it was loaded from
  Scans scans;
  /// The reader's warnings (a recording cut short, damage skipped), "<file>: ..." each; the apps print them.
  std::vector<std::string> warnings;
};

/// True for "sim" and "sim:SEED".
bool is_simulator_spec(const std::string& spec);

/// Loads a log or runs the simulator. Throws InputError for an unreadable log or a bad seed.
ScanSource load_scan_source(const std::string& spec, const LogReadOptions& options = {});

}  // namespace partslam::io
