// rotation_residuals CORRECTED_LOG: how far each stored map's own canonical frame lies from the rotations the
// localizer searches (docs/NOTES.md, "Small local maps off the building's axes"). Builds the building map and
// the stored maps of the log as `locate` and `submaps` do; for each stored map, the rotation that takes its
// canonical frame into the building map's canonical frame is the truth, and its residual is the distance to
// the nearest family searched (multiples of 45 degrees and the building's wing directions). Prints how many
// residuals exceed 3, 6 and 10 degrees, and, for those more than 6 degrees off the quarter turns, where the
// building's direction falls among the stored map's own Manhattan entropy minima (a search over its secondary
// minima would find the rank-1 to 3 ones).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <utility>
#include <vector>

#include "core/maps/grid_map.h"
#include "core/maps/manhattan.h"
#include "core/maps/submap.h"
#include "core/matching/localizer.h"
#include "io/logs/scan_source.h"

using namespace partslam;

namespace {

constexpr double kDeg = std::numbers::pi / 180;

// The rank (1 = lowest) of the local minimum of the points' axis entropy (1-degree steps over a quarter turn)
// within 3 degrees of `want` [rad], 0 when none is.
int entropy_minimum_rank(const Points2& points, double want) {
  std::vector<double> h(90);
  for (int k = 0; k < 90; ++k) h[k] = axis_entropy(points, k * kDeg, kMapResolution);
  std::vector<std::pair<double, int>> minima;
  for (int k = 0; k < 90; ++k)
    if (h[k] <= h[(k + 89) % 90] && h[k] <= h[(k + 1) % 90]) minima.push_back({h[k], k});
  std::sort(minima.begin(), minima.end());
  for (std::size_t i = 0; i < minima.size(); ++i)
    if (std::abs(std::remainder(minima[i].second * kDeg - want, std::numbers::pi / 2)) <= 3 * kDeg)
      return static_cast<int>(i) + 1;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: rotation_residuals CORRECTED_LOG\n");
    return 2;
  }
  try {
    const Scans scans = io::load_scan_source(argv[1]).scans;
    const Localizer localizer(build_grid_map(scans));
    std::vector<double> families;
    const int turns = localizer.config().dmm.canonical_turns;  // the localizer's own families
    for (int k = 0; k < turns; ++k) families.push_back(k * 2 * std::numbers::pi / turns);
    for (const double w : localizer.wing_directions())
      for (int k = 0; k < 4; ++k) families.push_back(w + k * std::numbers::pi / 2);
    int maps = 0, over3 = 0, over6 = 0, over10 = 0, off_quarter = 0;
    int ranks[4] = {0, 0, 0, 0};  // rank 1, 2, 3, other
    for (const Submap& m : build_submaps(scans)) {
      // The stored map's points in the building's canonical frame are turned by this much from its own.
      const double truth = m.T_world_map.theta + localizer.alignment_angle();
      double residual = std::numbers::pi;
      for (const double f : families)
        residual = std::min(residual, std::abs(std::remainder(truth - f, 2 * std::numbers::pi)));
      ++maps, over3 += residual > 3 * kDeg, over6 += residual > 6 * kDeg, over10 += residual > 10 * kDeg;
      const double quarter = std::remainder(truth, std::numbers::pi / 2);
      if (std::abs(quarter) <= 6 * kDeg) continue;
      ++off_quarter;
      const int rank = entropy_minimum_rank(m.points, quarter);
      ++ranks[rank >= 1 && rank <= 3 ? rank - 1 : 3];
    }
    std::printf(
        "%s: %d stored maps, residual > 3 / 6 / 10 deg: %d / %d / %d; more than 6 deg off the quarter turns: "
        "%d, the building's direction their entropy minimum of rank 1 / 2 / 3 / none of these: %d / %d / %d "
        "/ %d\n",
        argv[1], maps, over3, over6, over10, off_quarter, ranks[0], ranks[1], ranks[2], ranks[3]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rotation_residuals: %s\n", e.what());
    return 1;
  }
}
