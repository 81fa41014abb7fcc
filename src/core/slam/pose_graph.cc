#include "core/slam/pose_graph.h"

#include <ceres/ceres.h>

#include <cmath>
#include <string>

#include "core/error.h"

namespace partslam {
namespace {

// Residual of one edge: (T_from^-1 T_to) against the measurement, in the frame of `from`, weighted.
struct EdgeResidual {
  Pose2 measured;
  double sqrt_wt, sqrt_wr;

  template <typename T>
  bool operator()(const T* from, const T* to, T* r) const {
    using std::cos, std::sin;
    const T c = cos(from[2]), s = sin(from[2]);
    const T dx = to[0] - from[0], dy = to[1] - from[1];
    const T local_x = c * dx + s * dy, local_y = -s * dx + c * dy;
    T dtheta = to[2] - from[2] - T(measured.theta);
    dtheta = atan2(sin(dtheta), cos(dtheta));  // wrapped
    r[0] = T(sqrt_wt) * (local_x - T(measured.x));
    r[1] = T(sqrt_wt) * (local_y - T(measured.y));
    r[2] = T(sqrt_wr) * dtheta;
    return true;
  }
};

void check(const std::vector<Pose2>& initial, const std::vector<PoseGraphEdge>& edges) {
  for (std::size_t i = 0; i < initial.size(); ++i)
    if (!std::isfinite(initial[i].x) || !std::isfinite(initial[i].y) || !std::isfinite(initial[i].theta))
      throw InputError("pose graph: node " + std::to_string(i) + " has a non-finite pose");
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    const std::string name = "pose graph: edge " + std::to_string(k);
    if (e.from >= initial.size() || e.to >= initial.size() || e.from == e.to)
      throw InputError(name + " joins nodes " + std::to_string(e.from) + " and " + std::to_string(e.to) + " of " +
                       std::to_string(initial.size()));
    if (!(e.translation_weight > 0) || !(e.rotation_weight > 0) || !std::isfinite(e.translation_weight) ||
        !std::isfinite(e.rotation_weight))
      throw InputError(name + ": weights must be positive and finite");
    if (!std::isfinite(e.T_from_to.x) || !std::isfinite(e.T_from_to.y) || !std::isfinite(e.T_from_to.theta))
      throw InputError(name + ": non-finite measurement");
  }
}

}  // namespace

void validate(const PoseGraphConfig& c) {
  if (!(c.robust_scale > 0) || !std::isfinite(c.robust_scale))
    throw InputError("pose graph config: robust_scale must be finite and > 0, got " + std::to_string(c.robust_scale));
  if (c.max_iterations < 1 || c.max_iterations > 100000)
    throw InputError("pose graph config: max_iterations must be in [1, 100000], got " +
                     std::to_string(c.max_iterations));
}

std::vector<Pose2> optimize_pose_graph(const std::vector<Pose2>& initial, const std::vector<PoseGraphEdge>& edges,
                                       const PoseGraphConfig& config, PoseGraphSummary* summary) {
  check(initial, edges);
  validate(config);
  std::vector<std::array<double, 3>> x(initial.size());
  for (std::size_t i = 0; i < initial.size(); ++i) x[i] = {initial[i].x, initial[i].y, initial[i].theta};
  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges) {
    auto* cost = new ceres::AutoDiffCostFunction<EdgeResidual, 3, 3, 3>(
        new EdgeResidual{e.T_from_to, std::sqrt(e.translation_weight), std::sqrt(e.rotation_weight)});
    problem.AddResidualBlock(cost, e.robust ? new ceres::CauchyLoss(config.robust_scale) : nullptr, x[e.from].data(),
                             x[e.to].data());
  }
  if (!x.empty() && problem.HasParameterBlock(x[0].data())) problem.SetParameterBlockConstant(x[0].data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = config.max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary s;
  ceres::Solve(options, &problem, &s);
  if (summary) *summary = {s.initial_cost, s.final_cost, static_cast<int>(s.iterations.size()),
                           s.termination_type == ceres::CONVERGENCE};
  std::vector<Pose2> out(initial.size());
  for (std::size_t i = 0; i < initial.size(); ++i) out[i] = {x[i][0], x[i][1], wrap_angle(x[i][2])};
  return out;
}

}  // namespace partslam
