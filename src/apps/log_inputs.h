// The one wording of the logs every command reads (io/logs/scan_source.h loads them all), for the help texts: a
// command's help names every accepted input, the same way everywhere (README's usage block is generated from it).
#pragma once

#include <string>

namespace partslam::apps {

inline const std::string kLogInputs =
    "a CARMEN log (.clf/.log, plain or .gz), a ROS 1 bag (.bag), a ROS 2 bag (.mcap, .db3, or a rosbag2 folder with "
    "metadata.yaml), or sim[:SEED]";

}  // namespace partslam::apps
