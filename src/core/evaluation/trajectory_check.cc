#include "core/evaluation/trajectory_check.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/maps/submap.h"
#include "core/slam/pose_graph.h"

namespace partslam {
namespace {

double quantile(std::vector<double>& v, double q) {
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

Consistency local_consistency(const Scans& estimate, const Scans& reference,
                              const std::vector<std::optional<std::size_t>>& reference_index,
                              const ConsistencyConfig& c) {
  if (reference_index.size() != estimate.size())
    throw InputError("local consistency: one reference index per estimated scan is needed");
  if (!(c.window_length > 0) || !(c.spacing > 0) || !(c.max_range > 0))
    throw InputError("local consistency: window_length, spacing and max_range must be positive");
  const std::vector<double> s = travel_distances(estimate);
  Consistency out;
  std::vector<double> d;
  double next_anchor = 0.0;
  for (std::size_t a = 0; a < estimate.size(); ++a) {
    if (s[a] < next_anchor) continue;
    next_anchor = s[a] + c.spacing;
    if (!reference_index[a]) continue;
    ++out.windows;
    const Pose2 est_anchor = estimate[a].T_world_laser.inverse();
    const Pose2 ref_anchor = reference.at(*reference_index[a]).T_world_laser.inverse();
    for (std::size_t j = a; j < estimate.size() && s[j] < s[a] + c.window_length; ++j) {
      if (!reference_index[j]) continue;
      const Pose2 est = est_anchor * estimate[j].T_world_laser;
      const Pose2 ref = ref_anchor * reference.at(*reference_index[j]).T_world_laser;
      for (const Vec2& p : estimate[j].points_laser)
        if (p.squaredNorm() <= c.max_range * c.max_range) d.push_back((est * p - ref * p).norm());
    }
  }
  out.points = d.size();
  if (!d.empty()) {
    out.max = *std::max_element(d.begin(), d.end());
    out.p90 = quantile(d, 0.9);
    out.median = quantile(d, 0.5);
  }
  return out;
}

std::vector<std::optional<Pose2>> reference_frames(const Submaps& maps, const Scans& estimate, const Scans& reference,
                                                   const std::vector<std::optional<std::size_t>>& reference_index,
                                                   const PoseTolerance& agree) {
  if (reference_index.size() != estimate.size())
    throw InputError("reference frames: one reference index per estimated scan is needed");
  std::vector<std::optional<Pose2>> frames(maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const Submap& m = maps[i];
    const auto first = static_cast<std::size_t>(std::max<std::int64_t>(m.anchor_scan, 0));
    const std::size_t end = std::min(estimate.size(), first + std::max<std::size_t>(m.scan_timestamps.size(), 1));
    // The frame each referenced scan of the submap implies, in scan order.
    std::vector<Pose2> implied;
    for (std::size_t j = first; j < end; ++j)
      if (reference_index[j])
        implied.push_back(reference.at(*reference_index[j]).T_world_laser *
                          (estimate[j].T_world_laser.inverse() * m.T_world_map));
    // The frame most of them agree with (the earliest among equals); none when no frame has more than half.
    std::size_t best = 0, best_votes = 0;
    for (std::size_t a = 0; a < implied.size(); ++a) {
      std::size_t votes = 0;
      for (const Pose2& b : implied) votes += agree.accepts(implied[a], b);
      if (votes > best_votes) best = a, best_votes = votes;
    }
    if (2 * best_votes > implied.size()) frames[i] = implied[best];
  }
  return frames;
}

Submaps with_reference_frames(const Submaps& maps, const std::vector<std::optional<Pose2>>& frames) {
  if (frames.size() != maps.size()) throw InputError("reference frames: one frame per submap is needed");
  Submaps kept;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    if (!frames[i]) continue;
    kept.push_back(maps[i]);
    kept.back().T_world_map = *frames[i];
  }
  return kept;
}

namespace {

// Finds a scan by timestamp (within 1 ms).
class ScanByTime {
 public:
  explicit ScanByTime(const Scans& scans) {
    for (std::size_t i = 0; i < scans.size(); ++i) by_time_.emplace_back(scans[i].timestamp, i);
    std::sort(by_time_.begin(), by_time_.end());
  }
  /// The scan whose timestamp is nearest t (the earlier on a tie), if within 1 ms: logs hold scans less than
  /// 1 ms apart (intel: 1479 pairs), so the first one in the window may be a neighbour of the named scan.
  std::optional<std::size_t> operator()(double t) const {
    auto it = std::lower_bound(by_time_.begin(), by_time_.end(), std::pair{t - 1e-3, std::size_t{0}});
    std::optional<std::size_t> best;
    double best_dt = 1e-3;
    for (; it != by_time_.end() && it->first <= t + 1e-3; ++it) {
      const double dt = std::abs(it->first - t);
      if (dt < best_dt || (!best && dt <= best_dt)) best = it->second, best_dt = dt;
    }
    return best;
  }

 private:
  std::vector<std::pair<double, std::size_t>> by_time_;
};

}  // namespace

Scans reference_from_relations(const Scans& estimate, const Relations& relations,
                               std::vector<std::optional<std::size_t>>& reference_index) {
  const ScanByTime find(estimate);
  std::vector<std::pair<std::size_t, std::size_t>> linked;  // scan indices of each usable relation
  std::vector<const Relation*> used;
  std::vector<bool> is_node(estimate.size(), false);
  for (const Relation& r : relations) {
    const auto a = find(r.t1), b = find(r.t2);
    if (!a || !b || *a == *b) continue;
    linked.emplace_back(*a, *b);
    used.push_back(&r);
    is_node[*a] = is_node[*b] = true;
  }
  if (linked.empty()) throw InputError("relations: no relation names two scans of the log");
  reference_index.assign(estimate.size(), std::nullopt);
  Scans nodes;
  std::vector<Pose2> initial;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    if (!is_node[i]) continue;
    reference_index[i] = nodes.size();
    nodes.push_back(estimate[i]);
    initial.push_back(estimate[i].T_world_laser);
  }
  std::vector<PoseGraphEdge> edges;
  for (std::size_t k = 0; k < linked.size(); ++k)
    edges.push_back({*reference_index[linked[k].first], *reference_index[linked[k].second], used[k]->T_1_2, 1e4, 1e4,
                     false});
  for (std::size_t n = 1; n < nodes.size(); ++n)
    edges.push_back({n - 1, n, initial[n - 1].inverse() * initial[n], 1.0, 1.0, false});
  const std::vector<Pose2> solved = optimize_pose_graph(initial, edges, {1.0, 200});
  for (std::size_t n = 0; n < nodes.size(); ++n) nodes[n].T_world_laser = solved[n];
  return nodes;
}

RelationsError relations_error(const Scans& scans, const Relations& relations, const Pose2& T_base_laser) {
  const ScanByTime find(scans);
  const Pose2 T_laser_base = T_base_laser.inverse();
  RelationsError e;
  std::vector<double> dt, dr;
  for (const Relation& r : relations) {
    const auto a = find(r.t1), b = find(r.t2);
    if (!a || !b) {
      ++e.missing;
      continue;
    }
    const Pose2 T_world_1 = scans[*a].T_world_laser * T_laser_base, T_world_2 = scans[*b].T_world_laser * T_laser_base;
    const Pose2 E = r.T_1_2.inverse() * (T_world_1.inverse() * T_world_2);
    dt.push_back(E.translation().norm());
    dr.push_back(std::abs(E.theta));
  }
  const auto mean_std = [](const std::vector<double>& v, double& mean, double& sd) {
    if (v.empty()) return;
    double sum = 0, sq = 0;
    for (double x : v) sum += x;
    mean = sum / static_cast<double>(v.size());
    for (double x : v) sq += (x - mean) * (x - mean);
    sd = std::sqrt(sq / static_cast<double>(v.size()));
  };
  mean_std(dt, e.translation_mean, e.translation_std);
  mean_std(dr, e.rotation_mean, e.rotation_std);
  e.relations = dt.size();
  return e;
}

}  // namespace partslam
