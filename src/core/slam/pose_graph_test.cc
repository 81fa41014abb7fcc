#include "core/slam/pose_graph.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace partslam {
namespace {

// A square loop of 4 x 10 nodes, odometry with a heading bias, one loop closure back to the start.
struct SquareLoop {
  std::vector<Pose2> truth, drifted;
  std::vector<PoseGraphEdge> edges;
};

SquareLoop square_loop(double heading_bias) {
  SquareLoop l;
  Pose2 p;
  for (int side = 0; side < 4; ++side) {
    for (int k = 0; k < 10; ++k) {
      l.truth.push_back(p);
      p = p * Pose2{1.0, 0.0, k == 9 ? std::acos(-1.0) / 2 : 0.0};
    }
  }
  Pose2 d = l.truth[0];
  l.drifted.push_back(d);
  for (std::size_t i = 1; i < l.truth.size(); ++i) {
    const Pose2 step = l.truth[i - 1].inverse() * l.truth[i];
    const Pose2 odometry{step.x, step.y, step.theta + heading_bias};  // what the edge measures
    l.edges.push_back({i - 1, i, odometry, 100.0, 1000.0, false});
    d = d * odometry;
    l.drifted.push_back(d);
  }
  return l;
}

double max_error(const std::vector<Pose2>& a, const std::vector<Pose2>& b) {
  double e = 0;
  for (std::size_t i = 0; i < a.size(); ++i) e = std::max(e, (a[i].translation() - b[i].translation()).norm());
  return e;
}

TEST(PoseGraph, ALoopClosureUndoesTheDrift) {
  SquareLoop l = square_loop(0.01);
  const std::size_t last = l.truth.size() - 1;
  EXPECT_GT(max_error(l.drifted, l.truth), 1.0);
  // Without a closure the odometry edges are all satisfied as they are.
  EXPECT_LT(max_error(optimize_pose_graph(l.drifted, l.edges), l.drifted), 1e-6);
  l.edges.push_back({0, last, l.truth[0].inverse() * l.truth[last], 100.0, 1000.0, true});
  PoseGraphSummary s;
  const std::vector<Pose2> out = optimize_pose_graph(l.drifted, l.edges, {}, &s);
  EXPECT_LT(s.final_cost, s.initial_cost);
  EXPECT_LT(max_error(out, l.truth), max_error(l.drifted, l.truth) / 3);
  EXPECT_EQ(out[0].x, l.drifted[0].x);  // the first node is fixed
}

TEST(PoseGraph, TheRobustLossKeepsAWrongClosureFromBendingTheMap) {
  SquareLoop l = square_loop(0.0);
  l.edges.push_back({0, 20, Pose2{3.0, 3.0, 1.0}, 100.0, 1000.0, true});  // wildly wrong
  const std::vector<Pose2> robust = optimize_pose_graph(l.truth, l.edges, {0.1, 100});
  l.edges.back().robust = false;
  const std::vector<Pose2> plain = optimize_pose_graph(l.truth, l.edges);
  EXPECT_LT(max_error(robust, l.truth), max_error(plain, l.truth) / 2);
}

TEST(PoseGraph, RefusesBadGraphs) {
  const std::vector<Pose2> nodes(3);
  EXPECT_THROW(optimize_pose_graph(nodes, {{0, 3, {}, 1, 1, false}}), InputError);
  EXPECT_THROW(optimize_pose_graph(nodes, {{1, 1, {}, 1, 1, false}}), InputError);
  EXPECT_THROW(optimize_pose_graph(nodes, {{0, 1, {}, 0, 1, false}}), InputError);
  EXPECT_THROW(optimize_pose_graph({{std::nan(""), 0, 0}}, {}), InputError);
  EXPECT_EQ(optimize_pose_graph({}, {}).size(), 0u);
}

TEST(PoseGraph, ValidateNamesTheField) {
  EXPECT_NO_THROW(validate(PoseGraphConfig{}));
  PoseGraphConfig c;
  c.robust_scale = std::nan("");
  EXPECT_THAT([&] { validate(c); }, ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("robust_scale")));
  c = {};
  c.max_iterations = 0;
  EXPECT_THAT([&] { validate(c); }, ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("max_iterations")));
  EXPECT_THROW(optimize_pose_graph({Pose2{}}, {}, c), InputError);
}

}  // namespace
}  // namespace partslam
