#include "core/matching/scan_matcher.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace partslam {
namespace {

// Walls of an L-shaped room with a pillar, sampled every 2 cm: structure in x, y and rotation.
Points2 room() {
  Points2 p;
  for (double t = 0; t <= 6.0; t += 0.02) p.emplace_back(t, 0.0), p.emplace_back(0.0, t * 0.8);
  for (double t = 0; t <= 3.0; t += 0.02) p.emplace_back(6.0, t), p.emplace_back(3.0 + t, 3.0);
  for (double t = 0; t <= 0.5; t += 0.02) p.emplace_back(2.0 + t, 2.0), p.emplace_back(2.0, 2.0 + t);
  return p;
}

TEST(LikelihoodField, IsOneOnPointsAndFallsOffWithDistance) {
  const LikelihoodField field({{1.0, 1.0}}, 0.05, 0.1);
  EXPECT_NEAR(field.interpolate({1.0, 1.0}, nullptr), 1.0, 1e-6);
  EXPECT_NEAR(field.at({1.1, 1.0}), std::exp(-0.5), 1e-3);
  EXPECT_EQ(field.at({5.0, 5.0}), 0.0f);  // outside the grid
  Vec2 gradient;
  field.interpolate({1.07, 1.0}, &gradient);
  EXPECT_LT(gradient.x(), 0.0);  // uphill is towards the point
  EXPECT_GT(std::abs(gradient.x()), 2 * std::abs(gradient.y()));
  EXPECT_TRUE(LikelihoodField({}, 0.05, 0.1).empty());
  EXPECT_THROW(LikelihoodField({{0, 0}, {1e6, 1e6}}, 0.05, 0.1), InputError);  // 2^26-cell cap
}

TEST(LikelihoodField, ShiftedSumsAreTheCellsSumsInsideAndAcrossTheEdge) {
  const LikelihoodField field(room(), 0.05, 0.1);  // the points grown by 3 sigma: 6 cells of margin
  std::vector<Eigen::Vector2i> cells;
  for (const Vec2& p : room()) cells.push_back(field.cell_of(p));
  // Windows of shifts about the cells as they are (inside the grid), about cells moved 9 and 40 cells (across
  // the edge) and 4000 (wholly off it), by steps of 1 and 2 cells: each sum the same additions in the same
  // order as cell by cell.
  std::vector<double> sums;
  for (const int d : {0, 9, -40, 4000}) {
    std::vector<Eigen::Vector2i> moved = cells;
    for (Eigen::Vector2i& q : moved) q += Eigen::Vector2i(d, -d);
    for (const int step : {1, 2}) {
      const int shifts = 3;
      field.shifted_sums(moved, step, shifts, sums);
      ASSERT_EQ(sums.size(), 49u);
      for (int sy = -shifts; sy <= shifts; ++sy) {
        for (int sx = -shifts; sx <= shifts; ++sx) {
          double expected = 0.0;
          for (const Eigen::Vector2i& q : moved) expected += field.cell_value(q.x() + sx * step, q.y() + sy * step);
          EXPECT_EQ(sums[static_cast<std::size_t>((sy + shifts) * 7 + sx + shifts)], expected)
              << d << " " << step << " " << sx << " " << sy;
          if (d == 4000) {
            EXPECT_EQ(expected, 0.0);
          }
        }
      }
    }
  }
  field.shifted_sums(cells, 1, 0, sums);
  EXPECT_GT(sums.at(0), 0.8 * static_cast<double>(cells.size()));
  field.shifted_sums({}, 1, 2, sums);
  EXPECT_EQ(sums, std::vector<double>(25, 0.0));
  EXPECT_THROW(field.shifted_sums(cells, 0, 2, sums), std::invalid_argument);
}

TEST(ScanMatcher, RecoversAnOffsetInsideTheWindow) {
  const Points2 map = room();
  const LikelihoodField field(map, 0.05, 0.1);
  for (const Pose2 truth : {Pose2{0.17, -0.12, 0.08}, Pose2{-0.25, 0.2, -0.15}, Pose2{0.0, 0.0, 0.0}}) {
    // The scan sees the room from `truth`: its points are the map's points in the scan frame.
    const Points2 scan = transform(truth.inverse(), map);
    const ScanMatch m = match_scan(field, scan, Pose2{}, ScanMatcherConfig{});
    EXPECT_NEAR(m.pose.x, truth.x, 0.01);
    EXPECT_NEAR(m.pose.y, truth.y, 0.01);
    EXPECT_NEAR(m.pose.theta, truth.theta, 0.003);
    EXPECT_GT(m.score, 0.95);
  }
}

TEST(ScanMatcher, GivesTheSamePoseOnAnyNumberOfThreads) {
  const LikelihoodField field(room(), 0.05, 0.1);
  // A symmetric-ish scan (a square's corner) whose search has near ties across rotations.
  Points2 scan;
  for (double t = 0; t <= 2.0; t += 0.05) scan.emplace_back(t - 1.0, -1.0), scan.emplace_back(-1.0, t - 1.0);
  for (const Pose2 prediction : {Pose2{1.0, 1.0, 0.1}, Pose2{2.5, 0.7, -0.2}, Pose2{4.0, 2.0, 1.0}}) {
    ScanMatcherConfig one, three;
    three.num_threads = 3;
    const ScanMatch a = match_scan(field, scan, prediction, one), b = match_scan(field, scan, prediction, three);
    EXPECT_EQ(a.pose.x, b.pose.x);
    EXPECT_EQ(a.pose.y, b.pose.y);
    EXPECT_EQ(a.pose.theta, b.pose.theta);
    EXPECT_EQ(a.score, b.score);
  }
}

TEST(ScanMatcher, EmptyInputKeepsThePrediction) {
  const Pose2 prediction{1.0, 2.0, 0.3};
  const ScanMatch none = match_scan(LikelihoodField(room(), 0.05, 0.1), {}, prediction);
  EXPECT_EQ(none.pose.x, 1.0);
  EXPECT_EQ(none.score, 0.0);
  EXPECT_EQ(match_scan(LikelihoodField(), room(), prediction).pose.theta, 0.3);
}

TEST(ScanMatcher, RefusesAbsurdConfigs) {
  ScanMatcherConfig c;
  c.resolution = 0;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.sigma = std::nan("");
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.linear_window = 50;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.angular_window = -1;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.max_iterations = -1;
  EXPECT_THROW(validate(c), InputError);
}

}  // namespace
}  // namespace partslam
