#include "core/parts/cpd.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"

namespace partslam {
namespace {

// A wall along x and one along y meeting at (1, 2), points every 0.1 m.
Points2 l_shape() {
  Points2 p;
  for (int i = 0; i <= 40; ++i) p.emplace_back(1.0 + 0.1 * i, 2.0);
  for (int i = 1; i <= 40; ++i) p.emplace_back(1.0, 2.0 + 0.1 * i);
  return p;
}

// Points scattered without any symmetry, so a crop fits the dictionary at exactly one place.
Points2 scatter(std::uint32_t seed, int n, double half) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> cell(static_cast<int>(-half * 10), static_cast<int>(half * 10));
  Points2 p;
  for (int i = 0; i < n; ++i) p.emplace_back(0.1 * cell(rng) + 0.05, 0.1 * cell(rng) + 0.05);
  return p;
}

// Outlines of `n` random rectangles (walls every 0.1 m) within +-half: a Manhattan scene with many corners.
Points2 rooms(std::uint32_t seed, int n, double half) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> corner(static_cast<int>(-half * 10), static_cast<int>(half * 10) - 60),
      side(20, 60);
  Points2 p;
  for (int r = 0; r < n; ++r) {
    const int x0 = corner(rng), y0 = corner(rng), w = side(rng), h = side(rng);
    for (int i = 0; i < w; ++i) p.emplace_back(0.1 * (x0 + i), 0.1 * y0), p.emplace_back(0.1 * (x0 + i), 0.1 * (y0 + h));
    for (int i = 0; i <= h; ++i) p.emplace_back(0.1 * x0, 0.1 * (y0 + i)), p.emplace_back(0.1 * (x0 + w), 0.1 * (y0 + i));
  }
  return p;
}

// Every box of the given kind a candidate, MC on the inlier share.
CpdConfig every_candidate(CandidateMode mode) {
  CpdConfig c;
  c.candidates = mode;
  c.maximality = MaximalityMode::kInlierShare;
  c.t_size = 0.0;
  return c;
}

TEST(FindCorners, TheCornerOfAnLShapeComesFirst) {
  CpdConfig c;
  const Points2 corners = find_corners(l_shape(), c);
  ASSERT_FALSE(corners.empty());
  // The response peaks on a wall next to the corner, within half the neighbourhood radius of it.
  EXPECT_LT((corners.front() - Vec2(1.0, 2.0)).norm(), c.corner_radius / 2);
  // Kept corners respect the spacing and the count.
  for (std::size_t i = 0; i < corners.size(); ++i)
    for (std::size_t j = i + 1; j < corners.size(); ++j)
      EXPECT_GE((corners[i] - corners[j]).norm(), c.corner_spacing - 1e-9);
  c.corners = 1;
  EXPECT_EQ(find_corners(l_shape(), c).size(), 1u);
  // A straight wall has no corner stronger than its ends; the input order does not matter.
  Points2 reversed = l_shape();
  std::reverse(reversed.begin(), reversed.end());
  c.corners = 24;
  EXPECT_EQ(find_corners(reversed, c), find_corners(l_shape(), c));
}

TEST(Cpd, PartsOfAMapCutFromTheDictionaryPointBackToWhereItWasCut) {
  // The dictionary holds the map shifted by (7.3, -4.1), among other points far away.
  Points2 map = rooms(1, 3, 5.0);
  for (const Vec2& p : scatter(1, 300, 5.0)) map.push_back(p);
  Points2 dictionary;
  for (const Vec2& p : map) dictionary.push_back(p + Vec2(7.3, -4.1));
  for (const Vec2& p : scatter(2, 400, 5.0)) dictionary.push_back(p + Vec2(30, 30));
  for (CandidateMode mode : {CandidateMode::kCorners, CandidateMode::kPartitions}) {
    CpdConfig c = every_candidate(mode);
    c.max_parts = 12;
    const PreparedDictionary prepared = prepare_dictionary(dictionary, c);
    const CpdResult r = discover_parts(map, prepared, c, 5);
    ASSERT_GE(r.parts.size(), 3u);
    for (const Part& p : r.parts) {
      EXPECT_DOUBLE_EQ(p.appearance_score, 1.0);
      EXPECT_EQ(p.rotation, 0);
      // Within the dilation (one cell) and the residual rotation's reach of the truth.
      EXPECT_LT((dictionary_origin(p) - Vec2(7.3, -4.1)).norm(), 0.2);
      EXPECT_NEAR(p.descriptor_box.width(), p.keypoint_box.width(), 1e-9);
    }
  }
}

TEST(Cpd, DeterministicAndParallelEqualsSerial) {
  Points2 dictionary = rooms(3, 12, 15.0);
  std::vector<Points2> maps;
  for (std::uint32_t s = 10; s < 16; ++s) maps.push_back(rooms(s, 3, 6.0));
  std::vector<const Points2*> ptrs;
  std::vector<std::uint64_t> keys;
  for (std::size_t i = 0; i < maps.size(); ++i) ptrs.push_back(&maps[i]), keys.push_back(100 + i);
  for (CandidateMode mode : {CandidateMode::kCorners, CandidateMode::kPartitions}) {
    const CpdConfig c = every_candidate(mode);
    const PreparedDictionary prepared = prepare_dictionary(dictionary, c);
    const auto serial = discover_parts_many(ptrs, keys, prepared, c, 1);
    const auto parallel = discover_parts_many(ptrs, keys, prepared, c, 2);
    ASSERT_EQ(serial.size(), parallel.size());
    for (std::size_t i = 0; i < serial.size(); ++i) {
      ASSERT_GT(serial[i].parts.size(), 0u);
      ASSERT_EQ(serial[i].parts.size(), parallel[i].parts.size());
      for (std::size_t k = 0; k < serial[i].parts.size(); ++k) {
        EXPECT_EQ(serial[i].parts[k].descriptor_box.x_min, parallel[i].parts[k].descriptor_box.x_min);
        EXPECT_EQ(serial[i].parts[k].descriptor_box.y_min, parallel[i].parts[k].descriptor_box.y_min);
        EXPECT_EQ(serial[i].parts[k].appearance_score, parallel[i].parts[k].appearance_score);
      }
    }
  }
}

TEST(Cpd, RejectsAbsurdParameters) {
  CpdConfig c;
  c.box_sizes = {};
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.box_sizes = {-1.0};
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.corners = 0;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.corner_radius = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(validate(c), InputError);
  EXPECT_THROW(prepare_dictionary({}, CpdConfig{}), InputError);
}

}  // namespace
}  // namespace partslam
