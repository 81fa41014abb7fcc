#include "core/evaluation/tasks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <set>

#include "core/error.h"

namespace partslam {
namespace {

// A robot drives a 40 m square loop twice; one submap per metre of travel.
Submaps loop_maps() {
  Submaps maps;
  double travel = 0;
  for (int lap = 0; lap < 2; ++lap) {
    for (int i = 0; i < 40; ++i, travel += 1.0) {
      Submap m;
      const double s = i % 40;
      const Vec2 p = s < 10 ? Vec2(s, 0) : s < 20 ? Vec2(10, s - 10) : s < 30 ? Vec2(30 - s, 10) : Vec2(0, 40 - s);
      m.T_world_map = Pose2{p.x(), p.y(), 0};
      m.travel = travel;
      m.id = static_cast<std::int64_t>(maps.size());
      maps.push_back(m);
    }
  }
  return maps;
}

TEST(Tasks, RelevantPairsAreLoopClosuresOnly) {
  const Submaps maps = loop_maps();
  TaskConfig config;
  config.radius = 0.5;  // only the exact revisit (same corner of the square) qualifies
  const auto pairs = relevant_pairs(maps, config);
  // Each of the 40 places is visited twice, 40 m apart in travel: 2 ordered pairs per place.
  EXPECT_EQ(pairs.size(), 80u);
  for (const auto& p : pairs) {
    EXPECT_GT(std::abs(maps[p.query].travel - maps[p.global].travel), config.min_travel_gap);
    EXPECT_LE((maps[p.query].T_world_map.translation() - maps[p.global].T_world_map.translation()).norm(), 0.5);
  }
}

TEST(Tasks, DatabaseHoldsRelevantPlusIrrelevantFarMaps) {
  const Submaps maps = loop_maps();
  TaskConfig config;
  config.db_size = 10;
  config.num_tasks = 25;
  const auto tasks = make_tasks(maps, config);
  ASSERT_EQ(tasks.size(), 25u);
  for (const Task& t : tasks) {
    ASSERT_EQ(t.database.size(), 10u);
    EXPECT_EQ(std::count(t.database.begin(), t.database.end(), t.relevant), 1);
    EXPECT_EQ(std::set<std::size_t>(t.database.begin(), t.database.end()).size(), 10u);
    for (std::size_t i : t.database) {
      if (i == t.relevant) continue;
      EXPECT_GT((maps[t.query].T_world_map.translation() - maps[i].T_world_map.translation()).norm(),
                2 * config.radius);
    }
  }
}

TEST(Tasks, DeterministicGivenSeedAndDifferentAcrossSeeds) {
  const Submaps maps = loop_maps();
  TaskConfig config;
  config.db_size = 10;
  config.num_tasks = 20;
  const auto a = make_tasks(maps, config), b = make_tasks(maps, config);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].query, b[i].query);
    EXPECT_EQ(a[i].database, b[i].database);
  }
  config.seed = 2;
  const auto c = make_tasks(maps, config);
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) differs |= a[i].database != c[i].database;
  EXPECT_TRUE(differs);
}

TEST(Tasks, TrueOverlapPlacesTheQueryByTheGroundTruthPoses) {
  Submap a, b;
  for (double x = -3; x < 3; x += 0.1) a.points.push_back({x, 1.0});
  a.T_world_map = Pose2{5.0, 5.0, 0.3};
  // b holds the same wall seen from a frame 1 m along x and turned by 90 deg.
  b.T_world_map = Pose2{6.0, 5.0, 0.3 + std::numbers::pi / 2};
  for (const Vec2& p : a.points) b.points.push_back(b.T_world_map.inverse() * (a.T_world_map * p));
  EXPECT_NEAR(true_overlap(a, b), 1.0, 1e-12);
  b.T_world_map.x += 3.0;  // wrong pose: the wall misses most of b's cells
  EXPECT_LT(true_overlap(a, b), 0.3);
  Submap empty;
  EXPECT_EQ(true_overlap(empty, a), 0.0);
  const Submaps maps = {a, b};
  EXPECT_DOUBLE_EQ(low_overlap_share(maps, {{0, 1}, {1, 0}}, 0.3, 2), 1.0);
  EXPECT_DOUBLE_EQ(low_overlap_share(maps, {}, 0.3), 0.0);
}

TEST(Tasks, RejectsAbsurdParameters) {
  TaskConfig config;
  config.db_size = 1;
  EXPECT_THROW(validate(config), InputError);
  config = {};
  config.radius = -1;
  EXPECT_THROW(validate(config), InputError);
  config = {};
  config.num_tasks = 0;
  EXPECT_THROW(validate(config), InputError);
}

}  // namespace
}  // namespace partslam
