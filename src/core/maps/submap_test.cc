#include "core/maps/submap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "core/error.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

// Scans driving along +x at the given spacing, each seeing 30 points of a wall 2 m to the left.
Scans straight_drive(int n, double spacing) {
  Scans scans(n);
  for (int i = 0; i < n; ++i) {
    scans[i].timestamp = i;
    scans[i].T_world_laser = scans[i].T_world_odom = {i * spacing, 0.0, 0.0};
    for (int k = 0; k < 30; ++k) scans[i].points_laser.emplace_back(-1.5 + 0.1 * k, 2.0);
  }
  return scans;
}

double distance_to_walls(const Vec2& p, const Segments2& walls) {
  double best = 1e300;
  for (const Segment2& w : walls) {
    const Vec2 e = w.b - w.a;
    const double t = std::clamp((p - w.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (w.a + t * e - p).norm());
  }
  return best;
}

std::vector<std::int64_t> anchors(const Submaps& maps) {
  std::vector<std::int64_t> a;
  for (const Submap& m : maps) a.push_back(m.anchor_scan);
  return a;
}

// Known answer: anchors fall on the first scan at or past each multiple of the spacing (0.5 m), also when
// the scan spacing divides it (rounding of the summed travel must not push an anchor one scan late).
TEST(BuildSubmaps, AnchorsEveryHalfMetreOfTravel) {
  EXPECT_EQ(anchors(build_submaps(straight_drive(31, 0.1))),
            (std::vector<std::int64_t>{0, 5, 10, 15, 20, 25, 30}));
  // 0.3 m spacing: travel 0, 0.3, 0.6, 0.9, 1.2, 1.5, 1.8, 2.1 -> anchors at 0, 0.6, 1.2, 1.5, 2.1.
  EXPECT_EQ(anchors(build_submaps(straight_drive(8, 0.3))), (std::vector<std::int64_t>{0, 2, 4, 5, 7}));
  const Submaps maps = build_submaps(straight_drive(31, 0.1));
  EXPECT_EQ(maps[1].scan_timestamps.size(), 20u);  // window [0.5, 2.5): scans 5 .. 24
  EXPECT_DOUBLE_EQ(maps[1].scan_timestamps.front(), 5.0);
}

TEST(BuildSubmaps, RejectsBadConfig) {
  SubmapConfig config;
  config.spacing = 0.0;
  EXPECT_THROW(build_submaps({}, config), InputError);
  config = {};
  config.max_range = 0.0;
  EXPECT_THROW(build_submaps({}, config), InputError);
  config = {};
  config.window_length = 1e9;  // `locate --window 1e9` labelled a stretch past the log's end
  EXPECT_THROW(validate(config), InputError);
  config.window_length = 10000.0;
  EXPECT_NO_THROW(validate(config));
}

// The usable-range cap: endpoints farther than max_range from the laser are dropped before the submap is
// built, so they cannot drag its centroid.
TEST(BuildSubmaps, DropsEndpointsBeyondTheUsableRange) {
  Scans scans = straight_drive(31, 0.1);
  for (Scan& s : scans) s.points_laser.emplace_back(25.0, 0.0);  // one far return per scan
  SubmapConfig near, far;
  near.max_range = 8.0;
  far.max_range = 30.0;
  far.crop_size = 100.0;
  const Submaps capped = build_submaps(scans, near), full = build_submaps(scans, far);
  ASSERT_FALSE(capped.empty());
  ASSERT_FALSE(full.empty());
  // The wall is 2 m to the left of the path: with the cap, the centroid sits on it.
  EXPECT_NEAR(capped[0].T_world_map.y, 2.0, 1e-6);
  EXPECT_GT((full[0].T_world_map.translation() - capped[0].T_world_map.translation()).norm(), 1.0);
  EXPECT_EQ(points_world(scans[0], 8.0).size(), 30u);
  EXPECT_EQ(points_world(scans[0], 30.0).size(), 31u);
}

class SimulatedSubmaps : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    log_ = new SimulatedLog(simulate());
    maps_ = new Submaps(build_submaps(log_->scans));
  }
  static void TearDownTestSuite() {
    delete maps_;
    delete log_;
  }
  static SimulatedLog* log_;
  static Submaps* maps_;
};
SimulatedLog* SimulatedSubmaps::log_ = nullptr;
Submaps* SimulatedSubmaps::maps_ = nullptr;

TEST_F(SimulatedSubmaps, OneSubmapPerHalfMetreOfTravel) {
  const double travel = travel_distances(log_->scans).back();
  EXPECT_NEAR(static_cast<double>(maps_->size()), travel / 0.5, 2.0);
  for (std::size_t k = 1; k < maps_->size(); ++k) {
    EXPECT_GE((*maps_)[k].travel - (*maps_)[k - 1].travel, 0.5 - 0.1 - 1e-9);
    EXPECT_LE((*maps_)[k].travel - (*maps_)[k - 1].travel, 0.5 + 0.1 + 1e-9);
  }
}

TEST_F(SimulatedSubmaps, PointsAreCroppedAlignedAndOnePerCell) {
  for (const Submap& m : *maps_) {
    ASSERT_GE(m.points.size(), 20u);
    ASSERT_GE(m.alignment_angle, 0.0);
    ASSERT_LT(m.alignment_angle, std::numbers::pi / 2);
    // The crop is a 12.8 m square around the centroid, taken in the canonical frame.
    for (const Vec2& p : m.points) {
      ASSERT_LT(std::abs(p.x()), 6.4);
      ASSERT_LT(std::abs(p.y()), 6.4);
    }
    // Back in the world, one point per occupied 0.1 m cell, and every point near a wall (a cell mean of
    // wall points lies on the wall up to the range noise, or within half a cell diagonal of it in a corner).
    std::set<std::pair<std::int64_t, std::int64_t>> cells;
    for (const Vec2& p : transform(m.T_world_map, m.points)) {
      // A point within rounding of a cell edge may have crossed it on the way back (e.g. an axis-aligned
      // beam from a robot on the grid keeps one coordinate exact): it counts for no cell.
      const Vec2 f = p / 0.1;
      const Vec2 frac = f - f.array().round().matrix();
      if (frac.cwiseAbs().minCoeff() > 1e-9) {
        ASSERT_TRUE(cells.emplace(std::floor(f.x()), std::floor(f.y())).second) << "submap " << m.id;
      }
      ASSERT_LT(distance_to_walls(p, log_->plan.walls), 0.071 + 0.04) << "submap " << m.id;
    }
  }
}

// The map pose is the centroid of the window's points, one per 0.1 m cell, recomputed here independently.
TEST_F(SimulatedSubmaps, PoseIsTheCentroidOfTheWindowPoints) {
  const std::vector<double> s = travel_distances(log_->scans);
  for (std::size_t k = 0; k < maps_->size(); k += 10) {
    const Submap& m = (*maps_)[k];
    std::map<std::pair<std::int64_t, std::int64_t>, std::pair<Vec2, int>> cells;
    std::size_t window = 0;
    for (std::size_t j = m.anchor_scan; j < log_->scans.size() && s[j] < m.travel + 2.0; ++j, ++window) {
      for (const Vec2& p : points_world(log_->scans[j], SubmapConfig{}.max_range)) {
        auto& cell = cells
                         .try_emplace({static_cast<std::int64_t>(std::floor(p.x() / 0.1)),
                                       static_cast<std::int64_t>(std::floor(p.y() / 0.1))},
                                      Vec2::Zero(), 0)
                         .first->second;
        cell.first += p;
        ++cell.second;
      }
    }
    EXPECT_EQ(m.scan_timestamps.size(), window);
    Vec2 c = Vec2::Zero();
    for (const auto& [key, cell] : cells) c += cell.first / cell.second;
    c /= static_cast<double>(cells.size());
    EXPECT_NEAR((m.T_world_map.translation() - c).norm(), 0.0, 1e-6) << "submap " << k;
    EXPECT_NEAR(wrap_angle(m.T_world_map.theta + m.alignment_angle), 0.0, 1e-12);
    // The anchor scan's pose lies inside the crop (the laser sees what is around it).
    const Vec2 anchor = m.T_world_map.inverse() * log_->scans[m.anchor_scan].T_world_laser.translation();
    EXPECT_LT(anchor.norm(), 6.4 * std::sqrt(2.0));
  }
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

TEST(BuildLocalMap, IsTheStoredSubmapOverTheSameScans) {
  const Scans scans = simulate().scans;
  const Submaps stored = build_submaps(scans);
  const Submap& m = stored.at(20);
  const std::vector<double> s = travel_distances(scans);
  const Submap local = build_local_map(scans, s[static_cast<std::size_t>(m.anchor_scan)], m.travel + 2.0);
  EXPECT_EQ(local.anchor_scan, m.anchor_scan);
  EXPECT_EQ(local.scan_timestamps, m.scan_timestamps);
  EXPECT_EQ(local.points, m.points);
  EXPECT_EQ(local.T_world_map.x, m.T_world_map.x);
  EXPECT_THROW(build_local_map(scans, 5.0, 4.0), InputError);
  EXPECT_THROW(build_local_map(scans, 1e6, 1e6 + 2), InputError);  // beyond the log
  SubmapConfig c;
  c.min_points = 100000;
  EXPECT_THROW(build_local_map(scans, 0.0, 2.0, c), InputError);
}

// A local map from bare points (a point file) is the submap of the scans those points came from.
TEST(LocalMapFromPoints, IsTheSubmapOfTheSamePoints) {
  const Scans scans = simulate().scans;
  const Submaps stored = build_submaps(scans);
  const Submap& m = stored.at(20);
  Points2 world;
  for (std::size_t j = 0; j < m.scan_timestamps.size(); ++j) {
    const Points2 p = points_world(scans[static_cast<std::size_t>(m.anchor_scan) + j], kDefaultMaxRange);
    world.insert(world.end(), p.begin(), p.end());
  }
  const Submap local = local_map_from_points(world);
  EXPECT_EQ(local.points, m.points);
  EXPECT_DOUBLE_EQ(local.T_world_map.x, m.T_world_map.x);
  EXPECT_DOUBLE_EQ(local.T_world_map.theta, m.T_world_map.theta);
  // Laser origins given in the points' frame end up in the map frame, as the submap's own.
  ASSERT_FALSE(m.origins.empty());
  const Submap with_origins = local_map_from_points(world, {}, transform(m.T_world_map, m.origins));
  ASSERT_EQ(with_origins.origins.size(), m.origins.size());
  for (std::size_t i = 0; i < m.origins.size(); ++i)
    EXPECT_LT((with_origins.origins[i] - m.origins[i]).norm(), 1e-9);
  EXPECT_THROW(local_map_from_points(world, {}, Points2{{0.0, NAN}}), InputError);
  EXPECT_THROW(local_map_from_points(Points2{}), InputError);
  EXPECT_THROW(local_map_from_points(Points2{{0.0, 0.0}, {NAN, 1.0}}), InputError);
  EXPECT_THROW(local_map_from_points(Points2(5, Vec2(1.0, 1.0))), InputError);  // one cell
}

}  // namespace
}  // namespace partslam
