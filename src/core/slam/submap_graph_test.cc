#include "core/slam/submap_graph.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"

namespace partslam {
namespace {

// A square walked once, a submap every metre, stored with a heading drift of 0.005 rad per submap; the last
// submap is where the first is (its true pose relative to the first: the identity).
struct Square {
  Submaps maps;
  std::vector<Pose2> truth;
};

Square drifting_square() {
  Square s;
  Pose2 truth, stored;
  for (int i = 0; i <= 16; ++i) {
    s.truth.push_back(truth);
    Submap m;
    m.T_world_map = stored;
    m.travel = i;
    s.maps.push_back(m);
    const Pose2 step = (i % 4 == 3) ? Pose2{1, 0, std::acos(-1.0) / 2} : Pose2{1, 0, 0};
    truth = truth * step;
    stored = stored * (step * Pose2{0, 0, 0.005});
  }
  return s;
}

TEST(SubmapGraph, WithoutClosuresKeepsTheStoredFrames) {
  const Square s = drifting_square();
  const std::vector<Pose2> frames = optimize_submap_graph(s.maps, {});
  ASSERT_EQ(frames.size(), s.maps.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_NEAR(frames[i].x, s.maps[i].T_world_map.x, 1e-6);
    EXPECT_NEAR(frames[i].y, s.maps[i].T_world_map.y, 1e-6);
  }
}

TEST(SubmapGraph, AClosureBringsTheLastSubmapBackToTheFirst) {
  const Square s = drifting_square();
  const std::size_t last = s.maps.size() - 1;
  const double drift = (s.maps[last].T_world_map.translation() - s.maps[0].T_world_map.translation()).norm();
  ASSERT_GT(drift, 0.15);
  const std::vector<LoopClosure> closures = {{last, 0, Pose2{}, 0.9, 0.9, 0.9}};
  PoseGraphSummary summary;
  const std::vector<Pose2> frames = optimize_submap_graph(s.maps, closures, {}, {}, &summary);
  EXPECT_LT((frames[last].translation() - frames[0].translation()).norm(), 0.25 * drift);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_EQ(frames[0].x, s.maps[0].T_world_map.x);  // the first is held fixed
}

TEST(SubmapGraph, ValidateNamesTheWeight) {
  EXPECT_NO_THROW(validate(SubmapGraphWeights{}));
  SubmapGraphWeights w;
  w.chain_rotation = 0;
  EXPECT_THAT([&] { validate(w); }, ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("chain_rotation")));
  w = {};
  w.loop_translation = std::numeric_limits<double>::infinity();
  EXPECT_THAT([&] { validate(w); }, ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("loop_translation")));
}

}  // namespace
}  // namespace partslam
