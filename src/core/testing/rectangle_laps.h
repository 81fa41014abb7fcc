// Test helper: twice round a 20 m x 10 m rectangle, a submap every 0.5 m of travel: the true frames, and the
// stored frames of a front end whose heading drifts 0.002 rad per submap (the back end's and the closure
// checks' tests).
#pragma once

#include <cmath>
#include <vector>

#include "core/maps/submap.h"
#include "core/types.h"

namespace partslam::testing {

struct RectangleLaps {
  std::vector<Pose2> truth;
  Submaps maps;         ///< stored frames and travel; no points
  std::size_t lap = 0;  ///< submaps per lap
};

inline RectangleLaps rectangle_laps() {
  RectangleLaps l;
  Pose2 pose;
  for (int lap = 0; lap < 2; ++lap)
    for (const double side : {20.0, 10.0, 20.0, 10.0}) {
      for (int k = 0; k < static_cast<int>(side / 0.5); ++k) {
        l.truth.push_back(pose);
        pose = pose * Pose2{0.5, 0, 0};
      }
      pose = pose * Pose2{0, 0, std::acos(-1.0) / 2};
    }
  l.lap = l.truth.size() / 2;
  Pose2 stored = l.truth[0];
  for (std::size_t i = 0; i < l.truth.size(); ++i) {
    if (i > 0) stored = stored * ((l.truth[i - 1].inverse() * l.truth[i]) * Pose2{0, 0, 0.002});
    Submap m;
    m.travel = 0.5 * static_cast<double>(i);
    m.T_world_map = stored;
    l.maps.push_back(m);
  }
  return l;
}

}  // namespace partslam::testing
