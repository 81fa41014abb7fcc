#include "core/matching/localizer.h"

#include <cmath>

#include "core/error.h"
#include "core/maps/manhattan.h"
#include "core/maps/scan.h"
#include "core/timing.h"

namespace partslam {

void validate(const LocalizerConfig& c) {
  validate(c.dmm);
  if (!(c.elsewhere_distance >= 0.0 && c.elsewhere_distance <= 100.0))
    throw InputError("localizer: elsewhere_distance must be in [0, 100] m");
  if (!(c.elsewhere_angle >= 0.0 && c.elsewhere_angle <= std::numbers::pi))
    throw InputError("localizer: elsewhere_angle must be in [0, pi] rad");
}

Localizer::Localizer(const Points2& map_points, const LocalizerConfig& config) : config_(config) {
  validate(config_);
  if (map_points.empty()) throw InputError("localizer: the building map has no occupied cell");
  const auto t0 = Clock::now();
  for (const Vec2& p : map_points) {
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw InputError("localizer: building map points must be finite and within " + std::to_string(kMaxCoordinate) + " m");
  }
  if (config_.dmm.canonical) T_canonical_map_ = {0.0, 0.0, manhattan_angle(map_points)};
  map_ = prepare_map(transform(T_canonical_map_, map_points), config_.dmm);
  prepare_ms_ = ms_since(t0);
}

Localization Localizer::locate(const Points2& query_points) const {
  if (query_points.empty()) throw InputError("localizer: the local map has no point");
  const auto t0 = Clock::now();
  const PreparedQuery query = prepare_query(query_points, config_.dmm);
  const DmmResult best = match_dmm(query, map_);
  const DmmResult other =
      match_dmm_elsewhere(query, map_, best.T_map_query, config_.elsewhere_distance, config_.elsewhere_angle);
  Localization out;
  const Pose2 T_map_canonical = T_canonical_map_.inverse();
  out.T_map_query = T_map_canonical * best.T_map_query;
  out.T_map_elsewhere = T_map_canonical * other.T_map_query;
  out.inliers = best.inliers;
  out.inlier_fraction = best.inlier_fraction;
  out.elsewhere_fraction = other.inlier_fraction;
  out.confidence = std::max(0.0, best.inlier_fraction - other.inlier_fraction);
  out.time_ms = ms_since(t0);
  return out;
}

}  // namespace partslam
