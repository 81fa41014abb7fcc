#include "core/matching/dmm_ransac.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "core/testing/synthetic_maps.h"

namespace partslam {
namespace {

struct Fixture {
  Points2 map_points, query_points;
  Pose2 T_map_query{0.8, -0.5, 90.0 * kDegree + 1.0 * kDegree};
};

// A small map (so random minimal samples hit the truth often) and the same points in a rotated query frame.
Fixture small_copy() {
  std::mt19937_64 rng(4);
  const testing::SyntheticWorld world = testing::random_world(rng, 10.0, 6);
  Fixture f;
  f.map_points = testing::sample_world(world, {-2.5, 2.5, -2.5, 2.5}, rng);
  f.query_points = transform(f.T_map_query.inverse(), f.map_points);
  return f;
}

TEST(DmmRansac, FindsTheTruePoseOfACopy) {
  const Fixture f = small_copy();
  ASSERT_GT(f.map_points.size(), 40u);
  DmmRansacConfig config;
  config.iterations = 3000;
  const DmmResult r = match_dmm_ransac(f.query_points, prepare_ransac_map(f.map_points, config), config);
  EXPECT_GT(r.inlier_fraction, 0.8);
  EXPECT_NEAR(r.T_map_query.x, f.T_map_query.x, 0.15);
  EXPECT_NEAR(r.T_map_query.y, f.T_map_query.y, 0.15);
  EXPECT_NEAR(wrap_angle(r.T_map_query.theta - f.T_map_query.theta), 0.0, 2.0 * kDegree);
  EXPECT_LE(r.candidates_scored, 3000);  // stops early once every point is an inlier
}

TEST(DmmRansac, SeededAndScoreMatchesThePose) {
  const Fixture f = small_copy();
  DmmRansacConfig config;
  config.iterations = 200;
  const PreparedRansacMap map = prepare_ransac_map(f.map_points, config);
  const DmmResult a = match_dmm_ransac(f.query_points, map, config);
  const DmmResult b = match_dmm_ransac(f.query_points, map, config);
  EXPECT_EQ(a.inliers, b.inliers);
  EXPECT_EQ(a.T_map_query.x, b.T_map_query.x);
  EXPECT_EQ(a.T_map_query.theta, b.T_map_query.theta);
  EXPECT_EQ(count_inliers(f.query_points, map.inlier_grid, a.T_map_query), a.inliers);
  // Canonical: every hypothesis is within the window of a multiple of 90 degrees.
  const double residual =
      a.T_map_query.theta - std::round(a.T_map_query.theta / (90 * kDegree)) * 90 * kDegree;
  EXPECT_LE(std::abs(residual), config.angular_window + 1e-12);
}

TEST(DmmRansac, MoreIterationsNeverScoreLessWithTheSameSeed) {
  const Fixture f = small_copy();
  DmmRansacConfig config;
  const PreparedRansacMap map = prepare_ransac_map(f.map_points, config);
  int previous = 0;
  for (const int iterations : {10, 100, 1000}) {
    config.iterations = iterations;
    const int inliers = match_dmm_ransac(f.query_points, map, config).inliers;
    EXPECT_GE(inliers, previous);  // the same random stream, extended
    previous = inliers;
  }
}

TEST(DmmRansac, InlierDistanceSetsTheGridDilation) {
  DmmRansacConfig config;
  config.inlier_distance = 0.3;
  EXPECT_EQ(prepare_ransac_map({{0.05, 0.05}}, config).inlier_grid.num_occupied(), 29u);  // disc of radius 3
  config.inlier_distance = 0.0;
  EXPECT_EQ(prepare_ransac_map({{0.05, 0.05}}, config).inlier_grid.num_occupied(), 1u);
}

TEST(DmmRansac, EmptyInputsAndBadConfig) {
  const DmmRansacConfig config;
  const PreparedRansacMap map = prepare_ransac_map({{0, 0}, {2, 0}}, config);
  EXPECT_EQ(match_dmm_ransac({}, map, config).inliers, 0);
  EXPECT_EQ(match_dmm_ransac({{0, 0}}, prepare_ransac_map({}, config), config).inliers, 0);
  EXPECT_EQ(match_dmm_ransac({{0, 0}, {0.1, 0}}, map, config).inliers, 0);  // no sample >= min_sample_distance
  DmmRansacConfig bad;
  bad.iterations = -1;
  EXPECT_THROW(validate(bad), InputError);
  bad = {};
  bad.resolution = 0;
  EXPECT_THROW(prepare_ransac_map({}, bad), InputError);
  bad = {};
  bad.max_draws = 0;
  EXPECT_THROW(match_dmm_ransac({}, map, bad), InputError);
  bad = {};
  bad.resolution = 0.05;
  EXPECT_THROW(match_dmm_ransac({{0, 0}}, map, bad), InputError);
}

}  // namespace
}  // namespace partslam
