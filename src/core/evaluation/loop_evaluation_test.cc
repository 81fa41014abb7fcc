#include "core/evaluation/loop_evaluation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace partslam {
namespace {

std::vector<std::optional<Pose2>> exact_frames(const Submaps& maps) {
  std::vector<std::optional<Pose2>> frames;
  for (const Submap& m : maps) frames.emplace_back(m.T_world_map);
  return frames;
}

TEST(LoopEvaluation, JudgesPosesAgainstTheTruth) {
  Submaps maps(3);
  for (std::size_t i = 0; i < 3; ++i) maps[i].travel = 30.0 * static_cast<double>(i);
  maps[0].T_world_map = {0, 0, 0};
  maps[1].T_world_map = {50, 0, 0};
  maps[2].T_world_map = {1, 0, 0};  // the place of map 0, revisited
  std::vector<LoopClosure> closures = {{2, 0, Pose2{1.0, 0.0, 0.0}, 0.9, 0.0, 0.5},   // right
                                       {2, 1, Pose2{0.0, 0.0, 0.0}, 0.8, 0.0, 0.6},   // another place, more confident
                                       {1, 0, Pose2{50.0, 0.0, 0.0}, 0.3, 0.0, 0.3}};  // right pose, not the same place
  const LoopEvaluation e = evaluate_loop_closures(closures, maps, exact_frames(maps));
  EXPECT_EQ(e.relevant_pairs, 1u);
  EXPECT_EQ(e.hypotheses, 3u);
  EXPECT_EQ(e.correct, 2u);
  EXPECT_EQ(e.recall_at_full_precision, 0.0);  // the most confident one is wrong
  EXPECT_EQ(e.relevant_queries, 1u);
  EXPECT_EQ(e.query_recall_at_full_precision, 0.0);
  EXPECT_EQ(e.verdicts, (std::vector<int>{1, 0, 1}));
  ASSERT_EQ(e.curve.size(), 3u);
  EXPECT_DOUBLE_EQ(e.curve[1].precision, 0.5);
  EXPECT_DOUBLE_EQ(e.curve[1].recall, 1.0);
  EXPECT_NEAR(e.max_f1, 0.8, 1e-12);  // all three: precision 2/3, recall 1
  // Unknown frames leave their hypotheses out.
  std::vector<std::optional<Pose2>> partial = exact_frames(maps);
  partial[1].reset();
  EXPECT_EQ(evaluate_loop_closures(closures, maps, partial).hypotheses, 1u);
  EXPECT_EQ(evaluate_loop_closures(closures, maps, partial).recall_at_full_precision, 1.0);
  EXPECT_EQ(evaluate_loop_closures(closures, maps, partial).query_recall_at_full_precision, 1.0);
  EXPECT_EQ(evaluate_loop_closures(closures, maps, partial).verdicts, (std::vector<int>{1, -1, -1}));
  EXPECT_THROW(evaluate_loop_closures(closures, maps, {}), InputError);
}

TEST(LoopEvaluation, ValidateNamesTheField) {
  EXPECT_NO_THROW(validate(LoopTruthConfig{}));
  LoopTruthConfig c;
  c.radius = 0;
  EXPECT_THAT([&] { validate(c); }, ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("radius")));
  c = {};
  c.min_travel_gap = -1;
  EXPECT_THAT([&] { validate(c); }, ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("min_travel_gap")));
  c = {};
  c.max_rotation_error = std::nan("");
  EXPECT_THAT([&] { validate(c); }, ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("max_rotation_error")));
}

}  // namespace
}  // namespace partslam
