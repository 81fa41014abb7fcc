#include "core/evaluation/drifted_twin.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/maps/submap.h"
#include "core/random.h"

namespace partslam {

OdometryNoise odometry_noise(const std::string& level) {
  if (level == "mild") return {0.01, 0.3 * kDegree, 0.01, 0.2 * kDegree, 2.0, 0.1, 2.0 * kDegree};
  if (level == "harsh") return {0.05, 2.0 * kDegree, 0.03, 1.0 * kDegree, 20.0, 0.3, 11.0 * kDegree};
  throw InputError("odometry noise: unknown level '" + level + "' (mild or harsh)");
}

void validate(const OdometryNoise& n) {
  const std::pair<double, const char*> fields[] = {
      {n.scale_error, "scale_error"},       {n.heading_bias, "heading_bias"},
      {n.translation_noise, "translation_noise"}, {n.rotation_noise, "rotation_noise"},
      {n.slips_per_km, "slips_per_km"},     {n.slip_translation, "slip_translation"},
      {n.slip_rotation, "slip_rotation"}};
  for (const auto& [v, name] : fields)
    if (!(v >= 0.0) || !std::isfinite(v))
      throw InputError(std::string("odometry noise: ") + name + " must be a finite number >= 0");
  if (n.scale_error >= 0.5) throw InputError("odometry noise: scale_error must be below 0.5");
}

Scans drifted_twin(const Scans& truth, const OdometryNoise& n, std::uint64_t seed) {
  validate(n);
  Rng per_run(seed, 1), increments(seed, 2), slips(seed, 3);
  const double scale = 1.0 + per_run.uniform(-n.scale_error, n.scale_error);
  const double bias = per_run.uniform(-n.heading_bias, n.heading_bias);
  Scans out = truth;
  if (out.empty()) return out;
  Pose2 odometry = truth.front().T_world_laser;
  out.front().T_world_odom = odometry;
  for (std::size_t i = 1; i < truth.size(); ++i) {
    const Pose2 d = truth[i - 1].T_world_laser.inverse() * truth[i].T_world_laser;
    const double length = d.translation().norm();
    const double root = std::sqrt(length);
    Pose2 noisy{scale * d.x + n.translation_noise * root * increments.normal(),
                scale * d.y + n.translation_noise * root * increments.normal(),
                d.theta + bias * length + n.rotation_noise * root * increments.normal()};
    if (slips.uniform() < n.slips_per_km * 1e-3 * length) {
      const double angle = slips.uniform(-std::acos(-1.0), std::acos(-1.0));
      const double jump = slips.uniform(0.0, n.slip_translation);
      noisy.x += jump * std::cos(angle);
      noisy.y += jump * std::sin(angle);
      noisy.theta += slips.uniform(-n.slip_rotation, n.slip_rotation);
    }
    noisy.theta = wrap_angle(noisy.theta);
    odometry = odometry * noisy;
    out[i].T_world_laser = out[i].T_world_odom = odometry;
  }
  return out;
}

Relations bench_relations(const Scans& truth, const BenchRelationsConfig& c) {
  if (!(c.spacing > 0) || !(c.revisit_radius > 0) || !(c.revisit_gap >= 0) || c.max_revisits == 0)
    throw InputError("bench relations: spacing, revisit_radius and max_revisits must be positive, revisit_gap >= 0");
  for (const double o : c.travel_offsets)
    if (!(o > 0) || !std::isfinite(o)) throw InputError("bench relations: travel offsets must be positive");
  // A scan can be named when no other scan's timestamp is within 1 ms of its own.
  std::vector<double> times;
  for (const Scan& s : truth) times.push_back(s.timestamp);
  std::sort(times.begin(), times.end());
  const auto nameable = [&times](double t) {
    const auto it = std::lower_bound(times.begin(), times.end(), t - 1e-3);
    return it != times.end() && (it + 1 == times.end() || *(it + 1) > t + 1e-3);
  };
  const std::vector<double> s = travel_distances(truth);
  std::vector<std::size_t> starts;
  double last = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (s[i] - last < c.spacing || !nameable(truth[i].timestamp)) continue;
    starts.push_back(i);
    last = s[i];
  }
  Relations out;
  const auto relate = [&](std::size_t a, std::size_t b) {
    out.push_back({truth[a].timestamp, truth[b].timestamp, truth[a].T_world_laser.inverse() * truth[b].T_world_laser});
  };
  for (const std::size_t a : starts) {
    for (const double offset : c.travel_offsets) {
      const auto it = std::lower_bound(s.begin(), s.end(), s[a] + offset);
      if (it == s.end()) continue;
      const auto b = static_cast<std::size_t>(it - s.begin());
      if (nameable(truth[b].timestamp)) relate(a, b);
    }
  }
  std::vector<std::pair<std::size_t, std::size_t>> revisits;
  for (std::size_t i = 0; i < starts.size(); ++i)
    for (std::size_t j = i + 1; j < starts.size(); ++j) {
      const std::size_t a = starts[i], b = starts[j];
      if (s[b] - s[a] >= c.revisit_gap &&
          (truth[a].T_world_laser.translation() - truth[b].T_world_laser.translation()).norm() <= c.revisit_radius)
        revisits.emplace_back(a, b);
    }
  const std::size_t step = (revisits.size() + c.max_revisits - 1) / c.max_revisits;
  for (std::size_t k = 0; k < revisits.size(); k += std::max<std::size_t>(step, 1)) relate(revisits[k].first, revisits[k].second);
  if (out.empty()) throw InputError("bench relations: the log is too short for any relation");
  return out;
}

}  // namespace partslam
