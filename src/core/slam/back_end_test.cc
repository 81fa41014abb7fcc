#include "core/slam/back_end.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "core/testing/rectangle_laps.h"

namespace partslam {
namespace {

using testing::RectangleLaps;
using testing::rectangle_laps;

// The second lap's submaps closed on the first's, every 5th, with the true relative pose.
std::vector<LoopClosure> true_closures(const RectangleLaps& l) {
  std::vector<LoopClosure> out;
  for (std::size_t i = 0; i < l.lap; i += 5)
    out.push_back({l.lap + i, i, l.truth[i].inverse() * l.truth[l.lap + i], 0.9, 0.9, 0.9});
  return out;
}

double max_frame_error(const std::vector<Pose2>& frames, const std::vector<Pose2>& truth) {
  double e = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) e = std::max(e, (frames[i].translation() - truth[i].translation()).norm());
  return e;
}

TEST(BackEnd, ClosesTheLoopAndSetsAsideHalfAsManyWrongClosures) {
  const RectangleLaps l = rectangle_laps();
  std::vector<LoopClosure> closures = true_closures(l);
  const std::size_t good = closures.size();
  Rng rng(5);
  while (closures.size() < good + good / 2) {  // 50 % extra, between places at least 8 m apart
    const std::size_t q = l.lap + rng.index(l.lap), m = rng.index(l.lap);
    if ((l.truth[q].translation() - l.truth[m].translation()).norm() < 8) continue;
    closures.push_back({q, m, Pose2{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.3, 0.3)}, 1, 1, 1});
  }
  std::vector<LoopClosure> clean(closures.begin(), closures.begin() + static_cast<std::ptrdiff_t>(good));
  const BackEndResult without = solve_back_end(l.maps, clean);
  const BackEndResult with = solve_back_end(l.maps, closures);
  EXPECT_EQ(without.verdict, "closed") << without.reason;
  EXPECT_LT(max_frame_error(without.frames, l.truth), 0.5);
  EXPECT_LT(max_frame_error(with.frames, without.frames), 1e-6);  // the wrong closures changed nothing
  for (std::size_t k = 0; k < closures.size(); ++k) EXPECT_EQ(with.used[k], k < good) << k;
  EXPECT_EQ(with.rejected, closures.size() - good);
  // The front end's drift alone is far off: the test can fail.
  std::vector<Pose2> stored;
  for (const Submap& m : l.maps) stored.push_back(m.T_world_map);
  EXPECT_GT(max_frame_error(stored, l.truth), 5.0);
}

TEST(BackEnd, WithoutClosuresKeepsTheFrontEndAndSaysTheLoopIsOpen) {
  const RectangleLaps l = rectangle_laps();
  const BackEndResult r = solve_back_end(l.maps, {});
  EXPECT_EQ(r.verdict, "open");
  EXPECT_TRUE(r.trusted());
  for (std::size_t i = 0; i < l.maps.size(); ++i) EXPECT_NEAR(r.frames[i].x, l.maps[i].T_world_map.x, 1e-9);
}

TEST(BackEnd, ClosuresThatOutvoteTheTruthMakeTheVerdictDoubtful) {
  const RectangleLaps l = rectangle_laps();
  std::vector<LoopClosure> closures = true_closures(l);
  // As many again, all saying the second lap lies 3 m further along (a corridor alias): they agree with each
  // other, not with the true ones, and either side bends the chain.
  const std::size_t good = closures.size();
  for (std::size_t k = 0; k < good; ++k) {
    LoopClosure wrong = closures[k];
    wrong.T_match_query = Pose2{3.0, 0, 0} * wrong.T_match_query;
    closures.push_back(wrong);
  }
  const BackEndResult r = solve_back_end(l.maps, closures);
  EXPECT_FALSE(r.trusted()) << r.verdict;
  EXPECT_FALSE(r.reason.empty());
  // The closures are what is doubted: the front end's chain is the map written, untouched.
  EXPECT_TRUE(r.front_end_written);
  for (std::size_t i = 0; i < l.maps.size(); ++i) {
    EXPECT_EQ(r.frames[i].x, l.maps[i].T_world_map.x);
    EXPECT_EQ(r.frames[i].y, l.maps[i].T_world_map.y);
    EXPECT_EQ(r.frames[i].theta, l.maps[i].T_world_map.theta);
  }
  const BackEndResult right = solve_back_end(l.maps, true_closures(l));
  EXPECT_TRUE(right.trusted());
  EXPECT_FALSE(right.front_end_written);
}

TEST(BackEnd, RefusesSettingsOutOfRangeByName) {
  BackEndConfig c;
  c.max_rotation_residual = 0;
  try {
    solve_back_end({}, {}, c);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_rotation_residual"), std::string::npos);
  }
}

}  // namespace
}  // namespace partslam
