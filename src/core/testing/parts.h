// Test helper: a part whose descriptor box is given, its keypoint box as large at the origin, and its
// appearance score, for the descriptor matcher's and the descriptor database's tests.
#pragma once

#include "core/parts/part.h"

namespace partslam::testing {

inline Part part(const Box2& descriptor_box, double as = 1.0) {
  Part p;
  p.descriptor_box = descriptor_box;
  p.keypoint_box = {0, descriptor_box.width(), 0, descriptor_box.height()};
  p.appearance_score = as;
  return p;
}

}  // namespace partslam::testing
