#include "core/parts/descriptor_database.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/error.h"
#include "core/testing/parts.h"

namespace partslam {
namespace {

constexpr Matcher kMatchers[] = {Matcher::kMaxMax, Matcher::kSumMax, Matcher::kSumMaxWeighted};

using testing::part;

// A box on the 0.1 m grid, sides 0.1..12.8 m, somewhere on a 60 m x 40 m dictionary.
Box2 random_box(std::mt19937& rng, double cx, double cy, double spread) {
  std::uniform_int_distribution<int> side(1, 128),
      jitter(-static_cast<int>(spread * 10), static_cast<int>(spread * 10));
  const int w = side(rng), h = side(rng);
  const int x0 = static_cast<int>(cx * 10) + jitter(rng) - w / 2,
            y0 = static_cast<int>(cy * 10) + jitter(rng) - h / 2;
  return {0.1 * x0, 0.1 * (x0 + w), 0.1 * y0, 0.1 * (y0 + h)};
}

MapDescriptor random_map(std::mt19937& rng, int parts) {
  std::uniform_real_distribution<double> x(0, 60), y(0, 40), as(0, 1);
  const double cx = x(rng), cy = y(rng);
  MapDescriptor d;
  for (int k = 0; k < parts; ++k) d.parts.push_back(part(random_box(rng, cx, cy, 3.0), as(rng)));
  return d;
}

std::vector<MapDescriptor> random_database(std::mt19937& rng, int n, int k) {
  std::vector<MapDescriptor> maps;
  for (int i = 0; i < n; ++i) maps.push_back(random_map(rng, i % 11 == 5 ? static_cast<int>(rng() % k) : k));
  return maps;
}

void expect_matches_reference(const MapDescriptor& query, const std::vector<MapDescriptor>& maps,
                              const DescriptorDatabase& db, double origin_gate = 0.0) {
  for (Matcher m : kMatchers) {
    const std::vector<float> scores = db.score_all(query, m, {.origin_gate = origin_gate});
    ASSERT_EQ(scores.size(), maps.size());
    int nonzero = 0;
    for (std::size_t i = 0; i < maps.size(); ++i) {
      const double expected = match_score(query, maps[i], m, origin_gate);
      ASSERT_NEAR(scores[i], expected, 2e-6 * std::max(1.0, expected)) << to_string(m) << " map " << i;
      nonzero += scores[i] > 0;
    }
    EXPECT_GT(nonzero, static_cast<int>(maps.size() / 50)) << "test data should overlap now and then";
  }
}

TEST(DescriptorDatabase, HandMadeKnownAnswers) {
  const MapDescriptor query{{part({0, 2, 0, 2}, 0.5), part({10, 12, 0, 2}, 0.8), part({20, 21, 0, 1}, 1.0)}};
  const MapDescriptor stored{
      {part({1, 3, 0, 2}), part({10, 12, 0, 2}), part({20, 22, 0, 2}), part({0, 2, 0, 1})}};
  const MapDescriptor far{{part({100, 102, 0, 2})}};
  DescriptorDatabase db({far, stored, MapDescriptor{}}, {.parts_per_map = 4});
  const double r = 1.0 / std::sqrt(2.0);
  EXPECT_EQ(db.size(), 3u);
  const std::vector<float> mm = db.score_all(query, Matcher::kMaxMax);
  const std::vector<float> sm = db.score_all(query, Matcher::kSumMax);
  const std::vector<float> smw = db.score_all(query, Matcher::kSumMaxWeighted);
  EXPECT_NEAR(mm[1], 1.0, 1e-6);
  EXPECT_NEAR(sm[1], r + 1.5, 1e-6);
  EXPECT_NEAR(smw[1], 0.5 * r + 1.3, 1e-6);
  for (const auto* s : {&mm, &sm, &smw}) {
    EXPECT_EQ((*s)[0], 0.0f);
    EXPECT_EQ((*s)[2], 0.0f);
  }
  EXPECT_EQ(db.score_all(MapDescriptor{}, Matcher::kSumMax), std::vector<float>(3, 0.0f));
}

TEST(DescriptorDatabase, EqualsNaiveFormulaOnRandomDescriptors) {
  std::mt19937 rng(42);
  for (int k : {1, 3, 5}) {
    const std::vector<MapDescriptor> maps = random_database(rng, 1500, k);
    for (bool spatial : {false, true}) {
      const DescriptorDatabase db(maps, {.parts_per_map = k, .spatial_order = spatial});
      expect_matches_reference(random_map(rng, 3), maps, db);  // iMM-sized query
    }
  }
  // hMM-sized query: 100 parts spread over the whole dictionary.
  const std::vector<MapDescriptor> maps = random_database(rng, 800, 3);
  MapDescriptor query;
  for (int i = 0; i < 100; ++i) query.parts.push_back(random_map(rng, 1).parts[0]);
  expect_matches_reference(query, maps, DescriptorDatabase(maps));
}

// Parts with keypoint boxes anywhere in the crop and any quarter turn, so their dictionary origins spread.
MapDescriptor with_random_keypoints(std::mt19937& rng, MapDescriptor d) {
  std::uniform_int_distribution<int> cell(-64, 40);
  for (Part& p : d.parts) {
    p.rotation = static_cast<int>(rng() % 4);
    const bool swap = p.rotation & 1;
    const double w = swap ? p.descriptor_box.height() : p.descriptor_box.width();
    const double h = swap ? p.descriptor_box.width() : p.descriptor_box.height();
    const double x0 = 0.1 * cell(rng), y0 = 0.1 * cell(rng);
    p.keypoint_box = {x0, x0 + w, y0, y0 + h};
  }
  return d;
}

TEST(DescriptorDatabase, OriginGateEqualsReference) {
  std::mt19937 rng(7);
  std::vector<MapDescriptor> maps = random_database(rng, 1200, 3);
  for (MapDescriptor& m : maps) m = with_random_keypoints(rng, m);
  MapDescriptor query;
  for (int i = 0; i < 100; ++i) query.parts.push_back(random_map(rng, 1).parts[0]);
  query = with_random_keypoints(rng, query);
  const DescriptorDatabase db(maps);
  // Origins lie on the 0.05 m half-cell grid, so a gate of 6.025 m is 6.0 m for both, away from any tie.
  expect_matches_reference(query, maps, db, 6.025);
  // The gate only ever removes part pairs: every gated score is at most the ungated one, some are lower.
  const std::vector<float> open = db.score_all(query, Matcher::kSumMax);
  const std::vector<float> gated = db.score_all(query, Matcher::kSumMax, {.origin_gate = 6.025});
  int lower = 0;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    EXPECT_LE(gated[i], open[i]);
    lower += gated[i] < open[i];
  }
  EXPECT_GT(lower, 0);
  EXPECT_THROW(db.score_all(query, Matcher::kSumMax, {.origin_gate = -1.0}), InputError);
}

TEST(DescriptorDatabase, LayoutAndThreadsDoNotChangeResults) {
  std::mt19937 rng(3);
  const std::vector<MapDescriptor> maps = random_database(rng, 5000, 3);
  MapDescriptor query;
  for (int i = 0; i < 40; ++i) query.parts.push_back(random_map(rng, 1).parts[0]);
  const DescriptorDatabase sorted(maps), unsorted(maps, {.spatial_order = false});
  DescriptorDatabase incremental;
  for (const MapDescriptor& m : maps) incremental.add(m);
  for (Matcher m : kMatchers) {
    const std::vector<float> serial = sorted.score_all(query, m);
    EXPECT_EQ(sorted.score_all(query, m, {.num_threads = 2}), serial) << to_string(m);
    EXPECT_EQ(sorted.score_all(query, m, {.num_threads = 0}), serial);
    EXPECT_EQ(sorted.score_all(query, m, {.num_threads = 7}), serial);
    EXPECT_EQ(unsorted.score_all(query, m), serial);  // pruning and storage order are exact
    EXPECT_EQ(incremental.score_all(query, m), serial);
  }
}

// With the origin gate on, blocks are also skipped by the range of their parts' origins: bit for bit the same
// scores whatever the blocks hold (Morton order, input order, one map at a time) and the threads.
TEST(DescriptorDatabase, OriginPruningIsExact) {
  constexpr double kGate = 2.025;  // 2.0 m on the half-cell grid of origins, away from ties (see above)
  std::mt19937 rng(9);
  std::vector<MapDescriptor> maps = random_database(rng, 5000, 3);
  for (MapDescriptor& m : maps) m = with_random_keypoints(rng, m);
  const DescriptorDatabase sorted(maps), unsorted(maps, {.spatial_order = false});
  DescriptorDatabase incremental;
  for (const MapDescriptor& m : maps) incremental.add(m);
  for (int q = 0; q < 5; ++q) {
    MapDescriptor query = with_random_keypoints(rng, random_map(rng, q == 0 ? 40 : 3));
    for (Matcher m : kMatchers) {
      const std::vector<float> serial = sorted.score_all(query, m, {.origin_gate = kGate});
      EXPECT_EQ(unsorted.score_all(query, m, {.origin_gate = kGate}), serial) << to_string(m);
      EXPECT_EQ(incremental.score_all(query, m, {.origin_gate = kGate}), serial) << to_string(m);
      EXPECT_EQ(sorted.score_all(query, m, {.num_threads = 2, .origin_gate = kGate}), serial) << to_string(m);
      for (std::size_t i = 0; i < maps.size(); i += 97)  // and the reference, map by map
        EXPECT_NEAR(serial[i], match_score(query, maps[i], m, kGate), 1e-5 * (1 + serial[i])) << i;
    }
  }
}

TEST(DescriptorDatabase, QueryBoxesBeyondTheGridKeepTheirArea) {
  const MapDescriptor stored{{part({0, 2, 0, 2})}};
  const MapDescriptor query{{part({-5000, 5000, -1, 3})}};  // wider than the 16-bit grid
  DescriptorDatabase db({stored});
  EXPECT_NEAR(db.score_all(query, Matcher::kSumMax)[0], match_score(query, stored, Matcher::kSumMax), 1e-9);
  EXPECT_GT(db.score_all(query, Matcher::kSumMax)[0], 0.0f);
}

TEST(DescriptorDatabase, RejectsBadInput) {
  DescriptorDatabase db(DescriptorDatabaseConfig{.parts_per_map = 2});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(db.add({{part({0, 1, 0, 1}), part({0, 1, 0, 1}), part({0, 1, 0, 1})}}), InputError);  // > K
  EXPECT_THROW(db.add({{part({0, 25.6, 0, 1})}}), InputError);     // 256 cells wide
  EXPECT_THROW(db.add({{part({4000, 4001, 0, 1})}}), InputError);  // off the grid
  EXPECT_THROW(db.add({{part({nan, 1, 0, 1})}}), InputError);
  EXPECT_EQ(db.size(), 0u);
  EXPECT_EQ(db.add({{part({0, 25.5, 0, 1})}}), 0u);  // 255 cells is fine
  EXPECT_THROW(db.score_all({{part({0, 1, 0, 1}, -0.5)}}, Matcher::kSumMaxWeighted), InputError);
  EXPECT_THROW(db.score_all({{part({0, nan, 0, 1})}}, Matcher::kSumMax), InputError);
  EXPECT_THROW(db.score_all({}, Matcher::kSumMax, {.num_threads = -1}), InputError);
  EXPECT_THROW(DescriptorDatabase(DescriptorDatabaseConfig{.parts_per_map = 0}), InputError);
  EXPECT_THROW(DescriptorDatabase(DescriptorDatabaseConfig{.resolution = 0}), InputError);
}

}  // namespace
}  // namespace partslam
