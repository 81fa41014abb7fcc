#include "core/slam/wall_direction.h"

#include <algorithm>
#include <cmath>

namespace partslam {

double wall_direction(const Scans& scans, std::size_t first) {
  double c = 0, s = 0;
  for (std::size_t k = 0; k < std::min(scans.size(), first); ++k) {
    const Points2& p = scans[k].points_laser;
    for (std::size_t i = 1; i + 1 < p.size(); ++i) {
      if ((p[i + 1] - p[i]).norm() > 0.5 || (p[i] - p[i - 1]).norm() > 0.5) continue;
      const Vec2 d = p[i + 1] - p[i - 1];
      if (d.norm() < 1e-6) continue;
      const double normal = scans[k].T_world_laser.theta + std::atan2(d.x(), -d.y());
      c += std::cos(4 * normal), s += std::sin(4 * normal);
    }
  }
  if (std::hypot(c, s) < 1e-9) return 0.0;
  return std::atan2(s, c) / 4;
}

}  // namespace partslam
