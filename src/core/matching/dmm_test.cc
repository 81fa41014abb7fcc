#include "core/matching/dmm.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <utility>

#include "core/error.h"
#include "core/sim/simulator.h"
#include "core/evaluation/tasks.h"
#include "core/testing/simulated_maps.h"
#include "core/testing/synthetic_maps.h"

namespace partslam {
namespace {

double angle_error(double a, double b) { return std::abs(wrap_angle(a - b)); }

// Small window so the exhaustive reference stays fast.
DmmConfig small_config() {
  DmmConfig config;
  config.linear_window = 2.5;
  config.angular_window = 2.0 * kDegree;
  return config;
}

TEST(Dmm, RefusesAMapSpreadOverKilometres) {
  Points2 points = {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}};
  EXPECT_NO_THROW(prepare_map(points, DmmConfig{}));
  points.emplace_back(3000.0, 5.0);  // one stray point 3 km away
  try {
    prepare_map(points, DmmConfig{});
    FAIL() << "a 3 km map was prepared";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("3000 x 5 m"), std::string::npos) << e.what();
  }
}

TEST(DmmConfig, ValidateNamesTheField) {
  const auto message = [](DmmConfig c) {
    try {
      validate(c);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  DmmConfig c;
  EXPECT_EQ(message(c), "");
  c.resolution = 0;
  EXPECT_NE(message(c).find("resolution"), std::string::npos);
  c = {};
  c.angular_window = 1.0;
  EXPECT_NE(message(c).find("angular_window"), std::string::npos);
  c = {};
  c.angular_step = -0.1;
  EXPECT_NE(message(c).find("angular_step"), std::string::npos);
  c = {};
  c.dilation = -1;
  EXPECT_NE(message(c).find("dilation"), std::string::npos);
  c = {};
  c.search_depth = 9;
  EXPECT_NE(message(c).find("search_depth"), std::string::npos);
  c = {};
  c.linear_window = std::nan("");
  EXPECT_NE(message(c).find("linear_window"), std::string::npos);
  c = {};
  c.extra_directions = {0.9};
  EXPECT_NE(message(c).find("extra_directions"), std::string::npos);
  c = {};
  c.extra_window = -0.1;
  EXPECT_NE(message(c).find("extra_window"), std::string::npos);
}

// A wing built 20 degrees off the building's axes: a query aligned to the wing's walls is out of reach of the
// canonical families (+- 3 degrees about each quarter turn) and found with the wing's direction searched too.
TEST(MatchDmm, AnExtraDirectionReachesAQueryTurnedOffTheAxes) {
  DmmConfig config;
  config.angular_window = 2.0 * kDegree;
  config.angular_step = 1.0 * kDegree;
  config.extra_directions = {-20.0 * kDegree};
  config.extra_window = 2.0 * kDegree;
  const PreparedQuery q = prepare_query({{1.0, 0.0}, {0.0, 2.0}}, config);
  ASSERT_EQ(q.rotations.size(), 4u * 5u + 4u * 5u);  // the families, then the wing's: four quarter turns each
  EXPECT_NEAR(q.rotations[20].angle, -22.0 * kDegree, 1e-12);
  EXPECT_NEAR(q.rotations[27].angle, 70.0 * kDegree, 1e-12);
  std::mt19937_64 rng(5);
  const testing::SyntheticWorld world = testing::random_world(rng, 14.0, 10);
  const Points2 map_points = testing::sample_world(world, {-6, 6, -6, 6}, rng);
  const Pose2 T_map_query{0.8, -0.4, -20.0 * kDegree};
  const Points2 query_points = transform(T_map_query.inverse(), map_points);
  DmmConfig axes = small_config();
  axes.angular_step = 0.5 * kDegree;
  DmmConfig wing = axes;
  wing.extra_directions = {-20.0 * kDegree};
  const DmmResult missed = match_dmm(prepare_query(query_points, axes), prepare_map(map_points, axes));
  const DmmResult found = match_dmm(prepare_query(query_points, wing), prepare_map(map_points, wing));
  EXPECT_LT(missed.inlier_fraction, 0.6);
  EXPECT_GE(found.inlier_fraction, 0.95);
  EXPECT_LT(angle_error(found.T_map_query.theta, T_map_query.theta), 0.5 * kDegree + 1e-9);
  EXPECT_NEAR(found.T_map_query.x, 0.8, 0.1 + 1e-9);
  EXPECT_NEAR(found.T_map_query.y, -0.4, 0.1 + 1e-9);
}

TEST(PrepareQuery, CanonicalRotationsAndAutoStep) {
  DmmConfig config;
  config.angular_window = 2.0 * kDegree;
  config.angular_step = 1.0 * kDegree;
  const PreparedQuery q = prepare_query({{1.0, 0.0}, {0.0, 2.0}}, config);
  ASSERT_EQ(q.rotations.size(), 4u * 5u);
  EXPECT_NEAR(q.rotations[0].angle, -2.0 * kDegree, 1e-12);
  EXPECT_NEAR(q.rotations[7].angle, 90.0 * kDegree, 1e-12);
  // (1, 0) -> (0, 1) and (0, 2) -> (-2, 0), sorted by row.
  EXPECT_EQ(q.rotations[7].x, (std::vector<int>{-20, 0}));
  EXPECT_EQ(q.rotations[7].y, (std::vector<int>{0, 10}));
  config.angular_step = 0.0;
  const PreparedQuery a = prepare_query({{10.0, 0.0}}, config);
  EXPECT_NEAR(a.angular_step, 0.01, 1e-4);  // one cell at 10 m
  config.canonical = false;
  config.angular_step = 10.0 * kDegree;
  EXPECT_EQ(prepare_query({{1.0, 0.0}}, config).rotations.size(), 36u);
}

TEST(MatchDmm, EmptyInputsScoreZero) {
  const DmmConfig config = small_config();
  const PreparedMap map = prepare_map({{0.0, 0.0}, {1.0, 0.0}}, config);
  const PreparedMap empty_map = prepare_map({}, config);
  const PreparedQuery query = prepare_query({{0.0, 0.0}}, config);
  const PreparedQuery empty_query = prepare_query({}, config);
  EXPECT_EQ(match_dmm(empty_query, map).inliers, 0);
  EXPECT_EQ(match_dmm(query, empty_map).inliers, 0);
  EXPECT_EQ(match_exhaustive(empty_query, map).inliers, 0);
  EXPECT_EQ(match_exhaustive(query, empty_map).inliers, 0);
  EXPECT_EQ(match_dmm(query, map).inliers, 1);
  EXPECT_DOUBLE_EQ(match_dmm(query, map).inlier_fraction, 1.0);
}

TEST(MatchDmm, ResolutionMismatchThrows) {
  DmmConfig config = small_config();
  const PreparedMap map = prepare_map({{0.0, 0.0}}, config);
  config.resolution = 0.05;
  const PreparedQuery query = prepare_query({{0.0, 0.0}}, config);
  EXPECT_THROW(match_dmm(query, map), InputError);
  EXPECT_THROW(match_exhaustive(query, map), InputError);
  EXPECT_THROW(match_dmm_many(query, std::span<const PreparedMap>(&map, 1)), InputError);
  config = small_config();
  config.canonical = false;
  EXPECT_THROW(match_dmm(prepare_query({{0.0, 0.0}}, config), map), InputError);
  EXPECT_THROW(prepare_query({{std::nan(""), 0.0}}, config), InputError);
}

// A query that is an exact copy of the map, shifted by whole cells: every point is an inlier.
TEST(MatchDmm, RecoversAnExactCellShift) {
  std::mt19937_64 rng(3);
  const testing::SyntheticWorld world = testing::random_world(rng, 14.0, 10);
  const Points2 map_points = testing::sample_world(world, {-6, 6, -6, 6}, rng);
  const Pose2 T_map_query{1.2, -0.7, std::numbers::pi / 2};
  const Points2 query_points = transform(T_map_query.inverse(), map_points);
  DmmConfig config = small_config();
  config.dilation = 0;
  config.angular_step = 1.0 * kDegree;
  const DmmResult r = match_dmm(prepare_query(query_points, config), prepare_map(map_points, config));
  EXPECT_GE(r.inlier_fraction, 0.97);  // cell-boundary rounding may lose a few points
  EXPECT_NEAR(r.T_map_query.x, 1.2, 0.1 + 1e-9);
  EXPECT_NEAR(r.T_map_query.y, -0.7, 0.1 + 1e-9);
  EXPECT_LT(angle_error(r.T_map_query.theta, std::numbers::pi / 2), 1e-9);
}

// The central guarantee: branch-and-bound returns exactly the exhaustive maximum on the same discretisation,
// for relevant (overlapping) and irrelevant pairs, canonical and full-circle windows, several depths.
TEST(MatchDmm, EqualsExhaustiveOnManyPairs) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> offset(-2.0, 2.0), residual(-1.5 * kDegree, 1.5 * kDegree);
  std::uniform_int_distribution<int> quarter(0, 3);
  int pairs = 0;
  for (int w = 0; w < 6; ++w) {
    const testing::SyntheticWorld world = testing::random_world(rng, 24.0, 25);
    const testing::SyntheticWorld other = testing::random_world(rng, 24.0, 25);
    for (int p = 0; p < 5; ++p) {
      const double theta = quarter(rng) * std::numbers::pi / 2 + residual(rng);
      testing::SyntheticPair pair = testing::make_pair(world, rng, {offset(rng), offset(rng)},
                                                       {offset(rng), offset(rng)}, theta, 8.0);
      if (p == 4) pair.map = testing::make_pair(other, rng, {0, 0}, {0, 0}, 0.0, 8.0).map;  // irrelevant
      DmmConfig config = small_config();
      config.dilation = p % 3;
      config.search_depth = (p % 2 == 0) ? 0 : 2 + w % 3;
      const PreparedQuery q = prepare_query(pair.query, config);
      const PreparedMap m = prepare_map(pair.map, config);
      const DmmResult bnb = match_dmm(q, m);
      const DmmResult ref = match_exhaustive(q, m);
      ASSERT_EQ(bnb.inliers, ref.inliers) << "world " << w << " pair " << p;
      EXPECT_LT(bnb.candidates_scored, ref.candidates_scored);
      // The reported pose really scores what is claimed (up to cell-boundary rounding of t + R x).
      EXPECT_NEAR(count_inliers(pair.query, m.grid, bnb.T_map_query), bnb.inliers, 0.02 * bnb.inliers + 1);
      ++pairs;
    }
  }
  EXPECT_EQ(pairs, 30);
}

TEST(MatchDmm, EqualsExhaustiveFullCircle) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi), shift(-0.8, 0.8);
  for (int p = 0; p < 3; ++p) {
    const testing::SyntheticWorld world = testing::random_world(rng, 16.0, 15);
    const Points2 map_points = testing::sample_world(world, {-3, 3, -3, 3}, rng);
    const Pose2 T_map_query{shift(rng), shift(rng), angle(rng)};
    const Points2 query_points = transform(T_map_query.inverse(), map_points);  // same points, unaligned
    DmmConfig config;
    config.canonical = false;
    config.linear_window = 1.0;
    const PreparedQuery q = prepare_query(query_points, config);
    const PreparedMap m = prepare_map(map_points, config);
    const DmmResult bnb = match_dmm(q, m);
    EXPECT_EQ(bnb.inliers, match_exhaustive(q, m).inliers);
    EXPECT_GT(bnb.inlier_fraction, 0.8);
    EXPECT_LE(angle_error(bnb.T_map_query.theta, T_map_query.theta), q.angular_step + 1e-9);
    EXPECT_LE(std::abs(bnb.T_map_query.x - T_map_query.x), config.resolution + 1e-9);
    EXPECT_LE(std::abs(bnb.T_map_query.y - T_map_query.y), config.resolution + 1e-9);
  }
}

// Known offsets: the pose is within one grid cell and one rotation step of the truth.
TEST(MatchDmm, PoseWithinOneCellAndOneStepOfTruth) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> offset(-1.5, 1.5), residual(-2.5 * kDegree, 2.5 * kDegree);
  std::uniform_int_distribution<int> quarter(0, 3);
  const DmmConfig config;  // the defaults
  for (int p = 0; p < 12; ++p) {
    const testing::SyntheticWorld world = testing::random_world(rng, 30.0, 40);
    const double theta = quarter(rng) * std::numbers::pi / 2 + residual(rng);
    const testing::SyntheticPair pair =
        testing::make_pair(world, rng, {offset(rng), offset(rng)}, {offset(rng), offset(rng)}, theta);
    const PreparedQuery q = prepare_query(pair.query, config);
    const DmmResult r = match_dmm(q, prepare_map(pair.map, config));
    EXPECT_GT(r.inlier_fraction, 0.5) << "pair " << p;
    EXPECT_LE(angle_error(r.T_map_query.theta, pair.T_map_query.theta), q.angular_step + 1e-9) << "pair " << p;
    EXPECT_LE(std::abs(r.T_map_query.x - pair.T_map_query.x), config.resolution + 1e-9) << "pair " << p;
    EXPECT_LE(std::abs(r.T_map_query.y - pair.T_map_query.y), config.resolution + 1e-9) << "pair " << p;
  }
}

// CPD (Eq. 2): a small crop found on a large dictionary map with the whole map as the translation window.
TEST(MatchDmm, SmallCropOnLargeDictionary) {
  std::mt19937_64 rng(8);
  const testing::SyntheticWorld world = testing::random_world(rng, 40.0, 80);
  const Points2 dictionary = testing::sample_world(world, {-20, 20, -14, 14}, rng);
  DmmConfig config = dmm_config_for_dictionary();
  const PreparedMap m = prepare_map(dictionary, config);
  EXPECT_GE(m.packed.size(), 4u);
  for (const Vec2& centre : {Vec2(-12.0, 5.0), Vec2(8.0, -6.0), Vec2(15.0, 9.0)}) {
    // The crop is cut from the dictionary's own points: random walls are too self-similar for a resampled
    // crop to have a unique best fit, and crops under ~6 m x 5 m often fit equally well elsewhere.
    const Box2 box{centre.x() - 3.0, centre.x() + 3.0, centre.y() - 2.5, centre.y() + 2.5};
    Points2 crop_world;
    for (const Vec2& x : dictionary) {
      if (box.contains(x)) crop_world.push_back(x);
    }
    const Vec2 c = centroid(crop_world);
    const Pose2 T_dict_crop{c.x(), c.y(), std::numbers::pi};  // crop frame: centred, upside down
    const Points2 crop = transform(T_dict_crop.inverse(), crop_world);
    const PreparedQuery q = prepare_query(crop, config);
    const DmmResult bnb = match_dmm(q, m);
    const DmmResult ref = match_exhaustive(q, m);
    EXPECT_EQ(bnb.inliers, ref.inliers);
    EXPECT_GT(bnb.inlier_fraction, 0.9);
    EXPECT_LE(std::abs(bnb.T_map_query.x - T_dict_crop.x), 0.1 + 1e-9);
    EXPECT_LE(std::abs(bnb.T_map_query.y - T_dict_crop.y), 0.1 + 1e-9);
    EXPECT_LT(bnb.candidates_scored * 50, ref.candidates_scored);
  }
}

// The best match elsewhere equals a brute-force maximum over the candidates outside the excluded disc (at
// the rotations near the avoided one), and never lies inside it.
TEST(MatchDmm, ElsewhereEqualsBruteForceOutsideTheExcludedDisc) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> offset(-1.5, 1.5);
  for (int p = 0; p < 6; ++p) {
    const testing::SyntheticWorld world = testing::random_world(rng, 20.0, 20);
    const testing::SyntheticPair pair = testing::make_pair(world, rng, {offset(rng), offset(rng)},
                                                           {offset(rng), offset(rng)}, (p % 4) * std::numbers::pi / 2);
    DmmConfig config = small_config();
    config.search_depth = p % 2 == 0 ? 0 : 2;
    const PreparedQuery q = prepare_query(pair.query, config);
    const PreparedMap m = prepare_map(pair.map, config);
    const DmmResult best = match_dmm(q, m);
    const double min_distance = 0.25 + 0.25 * p, min_angle = 10 * kDegree;
    const DmmResult other = match_dmm_elsewhere(q, m, best.T_map_query, min_distance, min_angle);
    const double r = config.resolution;
    const auto outside = [&](double angle, int i, int j) {
      return std::hypot(i * r - best.T_map_query.x, j * r - best.T_map_query.y) >= min_distance - 1e-9 ||
             angle_error(angle, best.T_map_query.theta) > min_angle;
    };
    int brute = 0;
    const int w = static_cast<int>(std::floor(config.linear_window / r + 1e-9));
    for (const RotatedQuery& rq : q.rotations) {
      for (int j = -w; j <= w; ++j) {
        for (int i = -w; i <= w; ++i) {
          if (!outside(rq.angle, i, j)) continue;
          int score = 0;
          for (std::size_t k = 0; k < rq.x.size(); ++k) score += m.grid.at(rq.x[k] + i, rq.y[k] + j);
          brute = std::max(brute, score);
        }
      }
    }
    EXPECT_EQ(other.inliers, brute) << "pair " << p;
    EXPECT_LE(other.inliers, best.inliers);
    EXPECT_TRUE(outside(other.T_map_query.theta, static_cast<int>(std::lround(other.T_map_query.x / r)),
                        static_cast<int>(std::lround(other.T_map_query.y / r))));
  }
  const PreparedQuery q = prepare_query({{0.0, 0.0}}, small_config());
  EXPECT_THROW(match_dmm_elsewhere(q, prepare_map({{0.0, 0.0}}, small_config()), Pose2{}, -1.0, 0.1), InputError);
}

class MatchDmmMany : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::QueryAndMaps data = testing::query_and_sixteen_maps();
    query = std::move(data.query);
    for (const Points2& m : data.maps) maps.push_back(prepare_map(m));
  }
  Points2 query;
  std::vector<PreparedMap> maps;
};

TEST_F(MatchDmmMany, ExactScoresParallelEqualsSerial) {
  const PreparedQuery q = prepare_query(query);
  const std::vector<DmmResult> serial = match_dmm_many(q, maps);
  const std::vector<DmmResult> parallel = match_dmm_many(q, maps, 0, 2);
  ASSERT_EQ(serial.size(), maps.size());
  for (std::size_t m = 0; m < maps.size(); ++m) {
    EXPECT_TRUE(serial[m].exact);
    EXPECT_EQ(serial[m].inliers, match_dmm(q, maps[m]).inliers);
    EXPECT_EQ(parallel[m].inliers, serial[m].inliers);
    EXPECT_EQ(parallel[m].T_map_query.x, serial[m].T_map_query.x);
  }
}

TEST_F(MatchDmmMany, TopKKeepsTheKBestExactAndPrunesOnlyLosers) {
  const PreparedQuery q = prepare_query(query);
  const std::vector<DmmResult> all = match_dmm_many(q, maps);
  for (const int k : {1, 3}) {
    const std::vector<DmmResult> top = match_dmm_many(q, maps, k);
    std::vector<int> scores;
    for (const DmmResult& r : all) scores.push_back(r.inliers);
    std::sort(scores.rbegin(), scores.rend());
    const int kth = scores[static_cast<std::size_t>(k - 1)];
    int pruned = 0, exact_at_least_kth = 0;
    std::int64_t work_top = 0, work_all = 0;
    for (std::size_t m = 0; m < maps.size(); ++m) {
      work_top += top[m].candidates_scored;
      work_all += all[m].candidates_scored;
      if (top[m].exact) {
        EXPECT_EQ(top[m].inliers, all[m].inliers);
        exact_at_least_kth += all[m].inliers >= kth;
      } else {
        ++pruned;
        EXPECT_EQ(top[m].inliers, 0);
        EXPECT_LE(all[m].inliers, kth);  // only maps that cannot beat the k-th best are dropped
      }
    }
    EXPECT_GE(exact_at_least_kth, k);
    EXPECT_GT(pruned, 0);
    EXPECT_LT(work_top, work_all);
  }
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

// Eq. 1 of the discretised candidate nearest to a pose: the rotation of the prepared query closest to
// T.theta and the translation rounded to the lattice.
int score_nearest_candidate(const PreparedQuery& q, const OccupancyGrid& grid, const Pose2& T) {
  std::size_t best = 0;
  for (std::size_t k = 1; k < q.rotations.size(); ++k) {
    if (angle_error(q.rotations[k].angle, T.theta) < angle_error(q.rotations[best].angle, T.theta)) best = k;
  }
  const RotatedQuery& r = q.rotations[best];
  const int i = static_cast<int>(std::lround(T.x / q.resolution)), j = static_cast<int>(std::lround(T.y / q.resolution));
  int score = 0;
  for (std::size_t k = 0; k < r.x.size(); ++k) score += grid.at(r.x[k] + i, r.y[k] + j);
  return score;
}

// Submaps of the built-in simulator, with exact ground truth (T_world_map of every submap).
class SimulatedPairs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    SubmapConfig config;
    config.spacing = 2.0;  // fewer submaps: faster, and enough loop closures
    // The full 30 m range: these tests measure dMM on the simulated building's geometry; with the 8 m default
    // cap its submaps hold fewer walls and more places alias (29 of 40 poses within a cell instead of 35).
    config.max_range = 30.0;
    maps_ = new Submaps(build_submaps(simulate().scans, config));
    pairs_ = new std::vector<RelevantPair>(relevant_pairs(*maps_, TaskConfig{}));
  }
  static void TearDownTestSuite() {
    delete maps_;
    delete pairs_;
  }
  static Pose2 truth(const RelevantPair& p) {
    return (*maps_)[p.global].T_world_map.inverse() * (*maps_)[p.query].T_world_map;
  }
  static Submaps* maps_;
  static std::vector<RelevantPair>* pairs_;
};
Submaps* SimulatedPairs::maps_ = nullptr;
std::vector<RelevantPair>* SimulatedPairs::pairs_ = nullptr;

// A lazy DmmSearch's first pose (the verified ranking's first step) costs about what the depth-first search
// costs: a subtree popped before the answer is known is searched only for a leaf that reaches the best one found
// so far in that call. Without that bar a subtree popped early spent a whole search on a leaf far below the answer.
// Counted in bounds evaluated over relevant and random pairs, so the test does not depend on the machine.
TEST_F(SimulatedPairs, SearchFirstPoseBoundsAboutAsManyNodesAsTheDepthFirstSearch) {
  std::mt19937_64 rng(4);
  std::int64_t best_first = 0, depth_first = 0;
  for (int t = 0; t < 12; ++t) {
    const RelevantPair p = t % 2 == 0 ? (*pairs_)[rng() % pairs_->size()]
                                      : RelevantPair{rng() % maps_->size(), rng() % maps_->size()};
    const PreparedQuery q = prepare_query((*maps_)[p.query].points);
    const PreparedMap m = prepare_map((*maps_)[p.global].points);
    const DmmResult reference = match_dmm(q, m);
    DmmSearch search(q, m, 1.0, 0.3, /*lazy=*/true);
    const DmmResult first = search.next();
    ASSERT_EQ(first.inliers, reference.inliers) << "pair " << t;
    best_first += first.candidates_scored, depth_first += reference.candidates_scored;
  }
  ASSERT_GT(depth_first, 0);
  EXPECT_LE(best_first, 2 * depth_first) << "best-first " << best_first << " bounds, depth-first " << depth_first;
}

TEST_F(SimulatedPairs, BranchAndBoundEqualsExhaustiveAndBeatsTheTruth) {
  ASSERT_GE(pairs_->size(), 50u);
  const DmmConfig config;  // the defaults
  std::mt19937_64 rng(2);
  for (int t = 0; t < 16; ++t) {
    const bool relevant = t < 10;
    const RelevantPair p = relevant ? (*pairs_)[rng() % pairs_->size()]
                                    : RelevantPair{rng() % maps_->size(), rng() % maps_->size()};
    const PreparedQuery q = prepare_query((*maps_)[p.query].points, config);
    const PreparedMap m = prepare_map((*maps_)[p.global].points, config);
    const DmmResult bnb = match_dmm(q, m);
    ASSERT_EQ(bnb.inliers, match_exhaustive(q, m).inliers) << "pair " << p.query << " " << p.global;
    if (relevant) {
      EXPECT_GE(bnb.inliers, score_nearest_candidate(q, m.grid, truth(p)));
    }
  }
}

// Known offsets on realistic data: most relevant pairs come out within one cell and one rotation step of the
// exact relative pose, almost all within two (the rest are aliased places of the simulated building).
TEST_F(SimulatedPairs, PoseOfRelevantPairsIsWithinACellAndAStep) {
  const DmmConfig config;
  std::mt19937_64 rng(3);
  int within_one = 0, within_two = 0;
  const int n = 40;
  for (int t = 0; t < n; ++t) {
    const RelevantPair p = (*pairs_)[rng() % pairs_->size()];
    const PreparedQuery q = prepare_query((*maps_)[p.query].points, config);
    const DmmResult r = match_dmm(q, prepare_map((*maps_)[p.global].points, config));
    const Pose2 T = truth(p);
    const double e = std::max(std::abs(r.T_map_query.x - T.x), std::abs(r.T_map_query.y - T.y)) / config.resolution;
    const double a = angle_error(r.T_map_query.theta, T.theta) / q.angular_step;
    within_one += e <= 1 + 1e-9 && a <= 1 + 1e-9;
    within_two += e <= 2 + 1e-9 && a <= 2 + 1e-9;
  }
  EXPECT_GE(within_one, n * 8 / 10) << within_one << " of " << n;
  EXPECT_GE(within_two, n * 9 / 10) << within_two << " of " << n;
}

// A query (not only a stored map) spread over more than kMaxMapExtent is refused at once, naming the extent: a
// stored map edited to two points 131 km apart, used as the query, took 2.6 GB and 18 minutes.
TEST(Dmm, RefusesAQueryWiderThanTheMapExtentLimit) {
  Points2 wide{{-65500.0, 0.0}, {0.0, 0.0}, {65500.0, 0.0}};
  try {
    prepare_query(wide, DmmConfig{});
    FAIL() << "a 131 km wide query was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("query's points span 131000"), std::string::npos) << e.what();
  }
  EXPECT_THROW(prepare_map(wide, DmmConfig{}), InputError);
  EXPECT_NO_THROW(prepare_query({{-400.0, 0.0}, {400.0, 1.0}}, DmmConfig{}));
}

}  // namespace
}  // namespace partslam
