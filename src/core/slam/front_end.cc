#include "core/slam/front_end.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <numbers>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/maps/local_shape.h"
#include "core/maps/submap.h"
#include "core/timing.h"

namespace partslam {

Points2 matching_points(const Scan& scan, const FrontEndConfig& c) {
  Points2 near;
  near.reserve(scan.points_laser.size());
  for (const Vec2& p : scan.points_laser)
    if (p.squaredNorm() <= c.max_range * c.max_range) near.push_back(p);
  return voxel_downsample(near, c.point_resolution);
}

namespace {

// How the scan's surfaces fix a translation: sum n n^T over the normals of consecutive beam endpoints (each within
// 0.5 m of its neighbours, within max_range). unconstrained_direction(it, ratio) is the direction (unit, laser
// frame) they do not fix, if any: a bare corridor's walls all have normals across it, so its axis.
Eigen::Matrix2d normal_scatter(const Scan& scan, const FrontEndConfig& c) {
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  for_each_surface_tangent(scan.points_laser, c.max_range, [&](const Vec2& d) {
    const Vec2 n(-d.y() / d.norm(), d.x() / d.norm());
    A += n * n.transpose();
  });
  return A;
}

// The pose the front end's last step, continued at the same velocity, predicts for a scan `dt` after the previous
// one: T_prev * (T_before^-1 T_prev)^(dt / dt_prev), the power taken on (x, y, theta) (a step is small). The
// ratio is clamped to [0, 3] (stamps that stall or bunch); no step yet: the previous pose.
Pose2 constant_velocity(const Scans& done, double timestamp) {
  const Scan& prev = done.back();
  if (done.size() < 2) return prev.T_world_laser;
  const Scan& before = done[done.size() - 2];
  const Pose2 step = before.T_world_laser.inverse() * prev.T_world_laser;
  const double dt_prev = prev.timestamp - before.timestamp, dt = timestamp - prev.timestamp;
  const double r = dt_prev > 0 && dt >= 0 ? std::clamp(dt / dt_prev, 0.0, 3.0) : 1.0;
  return prev.T_world_laser * Pose2{r * step.x, r * step.y, r * step.theta};
}

bool moved(const Pose2& from, const Pose2& to, double translation, double rotation) {
  return (to.translation() - from.translation()).norm() >= translation ||
         std::abs(wrap_angle(to.theta - from.theta)) >= rotation;
}

// The local map: world points of the last key scans and the likelihood field over them.
class LocalMap {
 public:
  explicit LocalMap(const FrontEndConfig& c) : config_(c) {}

  void add(Points2 world_points) {
    scans_.push_back(std::move(world_points));
    if (static_cast<int>(scans_.size()) > config_.local_map_scans) scans_.pop_front();
    Points2 all;
    for (const Points2& s : scans_) all.insert(all.end(), s.begin(), s.end());
    all = voxel_downsample(all, config_.point_resolution);
    field_ = LikelihoodField(all, config_.matcher.resolution, config_.matcher.sigma);
    if (config_.fine_sigma > 0) fine_field_ = LikelihoodField(all, config_.matcher.resolution, config_.fine_sigma);
  }
  const LikelihoodField& field() const { return field_; }
  const LikelihoodField& fine_field() const { return fine_field_; }

 private:
  const FrontEndConfig& config_;
  std::deque<Points2> scans_;
  LikelihoodField field_, fine_field_;
};

// A scan's match on the local map from `prediction` (the odometry's, from the previous scan's pose). Where the
// front end's constant velocity predicts far from it, that prediction is matched too, and kept (in `prediction`
// too) when it scores more than second_margin better.
ScanMatch match_predicted(const LocalMap& local, const Points2& points, const Scans& done, const Scan& scan,
                          const FrontEndConfig& config, FrontEndStats& stats, Pose2& prediction) {
  ScanMatch m = match_scan(local.field(), points, prediction, config.matcher);
  if (config.second_prediction > 0) {
    const Pose2 velocity = constant_velocity(done, scan.timestamp);
    const Pose2 d = prediction.inverse() * velocity;
    if (d.translation().norm() > config.second_prediction * config.matcher.linear_window ||
        std::abs(d.theta) > config.second_prediction * config.matcher.angular_window) {
      ++stats.second_predictions;
      const ScanMatch v = match_scan(local.field(), points, velocity, config.matcher);
      if (v.score > m.score + config.second_margin) {
        m = v, prediction = velocity;
        ++stats.velocity_kept;
      }
    }
  }
  if (config.wide_score > 0 && m.score < config.wide_score) {
    // Every heading: four windows of a quarter turn each (the matcher's window is at most 1 rad).
    ++stats.wide_searches;
    ScanMatcherConfig wide = config.matcher;
    wide.linear_window = config.wide_window;
    wide.angular_window = std::numbers::pi / 4 + 0.01;
    ScanMatch best = m;
    for (int k = 0; k < 4; ++k) {
      const Pose2 turned{prediction.x, prediction.y, wrap_angle(prediction.theta + k * std::numbers::pi / 2)};
      const ScanMatch w = match_scan(local.field(), points, turned, wide);
      if (w.score > best.score) best = w;
    }
    if (best.score > m.score + config.wide_margin) m = best, ++stats.wide_kept;
  }
  return m;
}

// The odometry's recent error, as the front end measures it: an exponential mean of the squared moves from the
// odometry's prediction to the accepted match on scans that fix both directions of translation.
struct OdometryError {
  double mean_square = -1;  ///< none yet
  void add(double square) { mean_square = mean_square < 0 ? square : mean_square + (square - mean_square) / 50; }
};

// The odometry's scale as the front end measures it (FrontEndConfig::scale_memory): over stretches of at least
// kScaleStretch of odometry travel on consecutive scans that fix both directions, the least-squares ratio of the
// match's motion to the odometry's (stretches, not single steps: a step's own noise would bias the ratio towards
// 0), each stretch's weight decaying with the odometry travel after it.
struct OdometryScale {
  double products = 0, squares = 0, travel = 0;
  Pose2 matched, odometry;  // the open stretch's motion so far
  bool open = false;
  // A scan that does not fix both directions, or whose step is not the odometry's: the open stretch is dropped.
  void drop() { open = false; }
  // A scan that fixes both directions: the match's step and the odometry's, both in the previous scan's frame.
  void step(const Pose2& matched_step, const Pose2& odometry_step, double memory) {
    if (!open) matched = odometry = Pose2{}, open = true;
    matched = matched * matched_step, odometry = odometry * odometry_step;
    const double length = odometry.translation().norm();
    if (length < kScaleStretch) return;
    open = false;
    // A stretch the match moved further from the odometry than any scale would (a slip, a bump) says nothing of it.
    if ((matched.translation() - odometry.translation()).norm() > kScaleOutlier + (kMaxOdometryScale - 1.0) * length)
      return;
    const double keep = std::exp(-length / memory);
    products = products * keep + matched.translation().dot(odometry.translation());
    squares = squares * keep + length * length;
    travel += length;
  }
  double value() const {
    if (travel < kMinScaleTravel || !(squares > 0)) return 1.0;
    return std::clamp(products / squares, 1.0 / kMaxOdometryScale, kMaxOdometryScale);
  }
};

// Where a scan was predicted from: the previous scan's pose and the odometry's step since (`prediction` is the
// pose matched from; it is from * step when `odometry_step`, the odometry's own step: not a stall, the step after
// one, or another prediction kept).
struct Predicted {
  Pose2 prediction, from, step;
  bool odometry_step = false;
};

// The pose of an accepted match: refined on the fine field (fine_sigma > 0), and where the odometry moves, its
// translation along the scan's weak direction (a bare corridor's axis) taken from the prediction (the odometry's
// step times its learned scale, where the prediction is that step); along a half-constrained direction, kept
// within half_constrained_slack times the odometry's recent error of the prediction (only on the odometry's own
// steps).
Pose2 accepted_pose(const LocalMap& local, const Points2& points, const Scan& scan, const Pose2& matched,
                    const Predicted& p, bool odometry_moves, const FrontEndConfig& config,
                    OdometryError& odometry_error, OdometryScale& odometry_scale, FrontEndStats& stats) {
  Pose2 pose = matched;
  if (config.fine_sigma > 0) {
    ScanMatcherConfig fine = config.matcher;
    fine.sigma = config.fine_sigma, fine.linear_window = 0, fine.angular_window = 0;
    pose = match_scan(local.fine_field(), points, matched, fine).pose;
  }
  if (!odometry_moves) return pose;
  const bool bound_half = config.half_constrained_ratio > 0 && p.odometry_step;
  const bool learn_scale = config.scale_memory > 0 && p.odometry_step;
  if (!learn_scale) odometry_scale.drop();
  if (config.degenerate_ratio <= 0 && !bound_half && !learn_scale) return pose;
  const Eigen::Matrix2d scatter = normal_scatter(scan, config);  // once for every ratio
  if (const std::optional<Vec2> weak = unconstrained_direction(scatter, config.degenerate_ratio)) {
    ++stats.degenerate;
    const double scale = odometry_scale.value();
    odometry_scale.drop();
    if (!learn_scale || scale == 1.0) return keep_along(pose, p.prediction, *weak, 0.0);
    ++stats.scaled;
    const Pose2 scaled = p.from * Pose2{scale * p.step.x, scale * p.step.y, p.step.theta};
    return keep_along(pose, scaled, *weak, 0.0);
  }
  if (learn_scale && !unconstrained_direction(scatter, config.scale_ratio))
    odometry_scale.step(p.from.inverse() * pose, p.step, config.scale_memory);
  else
    odometry_scale.drop();
  if (!bound_half) return pose;
  if (const std::optional<Vec2> half = unconstrained_direction(scatter, config.half_constrained_ratio)) {
    if (odometry_error.mean_square < 0) return pose;
    const double slack = config.half_constrained_slack * std::sqrt(odometry_error.mean_square);
    const Vec2 along = Eigen::Rotation2Dd(pose.theta) * *half;
    if (std::abs(along.dot(pose.translation() - p.prediction.translation())) <= slack) return pose;
    ++stats.half_constrained;
    return keep_along(pose, p.prediction, *half, slack);
  }
  odometry_error.add((pose.translation() - p.prediction.translation()).squaredNorm());
  return pose;
}

// Counts a heading jump: the scan (kept as scan `index`, at T_world_laser) turned from the previous one by more
// than jump_turn away from the odometry's turn.
void count_heading_jump(const Scan& prev, const Scan& scan, const Pose2& T_world_laser, std::size_t index,
                        const FrontEndConfig& config, FrontEndStats& stats) {
  const double turn = wrap_angle(T_world_laser.theta - prev.T_world_laser.theta);
  const double odometry_turn = wrap_angle(scan.T_world_odom.theta - prev.T_world_odom.theta);
  if (std::abs(wrap_angle(turn - odometry_turn)) > config.jump_turn) {
    if (stats.jump_scans.size() < 100) stats.jump_scans.push_back(index);
    ++stats.heading_jumps;
  }
  if (std::abs(odometry_turn) >= kTurningStep) {
    ++stats.turning_steps;
    stats.turn_products += turn * odometry_turn;
    stats.odometry_turn_squares += odometry_turn * odometry_turn;
  }
}

}  // namespace

void validate(const FrontEndConfig& c) {
  validate_nested("front end config", "matcher", [&] { validate(c.matcher); });
  auto positive = [](double v, const char* field, double max) {
    if (!(v > 0.0) || !(v <= max))
      throw InputError(std::string("front end config: ") + field + " must be in (0, " + std::to_string(max) + "]");
  };
  positive(c.max_range, "max_range", 1000.0);
  positive(c.point_resolution, "point_resolution", 1.0);
  positive(c.key_translation, "key_translation", 100.0);
  positive(c.key_rotation, "key_rotation", 2 * std::acos(-1.0));
  if (c.local_map_scans < 1 || c.local_map_scans > 10000)
    throw InputError("front end config: local_map_scans must be in [1, 10000]");
  if (!(c.min_score >= 0.0 && c.min_score <= 1.0))
    throw InputError("front end config: min_score must be in [0, 1]");
  if (!(c.fine_sigma >= 0.0 && c.fine_sigma <= 10.0))
    throw InputError("front end config: fine_sigma must be in [0, 10] m");
  if (!(c.jump_turn > 0.0 && c.jump_turn <= 7.0)) throw InputError("front end config: jump_turn must be in (0, 7] rad");
  if (!(c.degenerate_ratio >= 0.0 && c.degenerate_ratio < 1.0))
    throw InputError("front end config: degenerate_ratio must be in [0, 1)");
  if (!(c.scale_memory >= 0.0 && c.scale_memory <= 1e6))
    throw InputError("front end config: scale_memory must be in [0, 1e6]");
  if (!(c.scale_ratio >= 0.0 && c.scale_ratio < 1.0))
    throw InputError("front end config: scale_ratio must be in [0, 1)");
  if (!(c.half_constrained_ratio >= 0.0 && c.half_constrained_ratio < 1.0))
    throw InputError("front end config: half_constrained_ratio must be in [0, 1)");
  if (!(c.half_constrained_slack >= 0.0 && c.half_constrained_slack <= 100.0))
    throw InputError("front end config: half_constrained_slack must be in [0, 100]");
  if (!(c.second_prediction >= 0.0 && c.second_prediction <= 10.0))
    throw InputError("front end config: second_prediction must be in [0, 10]");
  if (!(c.second_margin >= 0.0 && c.second_margin <= 1.0))
    throw InputError("front end config: second_margin must be in [0, 1]");
  if (!(c.wide_score >= 0.0 && c.wide_score <= 1.0)) throw InputError("front end config: wide_score must be in [0, 1]");
  if (!(c.wide_window >= 0.0 && c.wide_window <= 5.0))
    throw InputError("front end config: wide_window must be in [0, 5] m");
  if (!(c.wide_margin >= 0.0 && c.wide_margin <= 1.0))
    throw InputError("front end config: wide_margin must be in [0, 1]");
}

namespace {

// The log's scans with every point mirrored (y -> -y): what an upside-down laser's scans look like upright.
Scans mirrored(const Scans& raw) {
  Scans out = raw;
  for (Scan& s : out)
    for (Vec2& p : s.points_laser) p.y() = -p.y();
  return out;
}

FrontEndResult match_log(const Scans& raw, const FrontEndConfig& config, const Progress& progress) {
  const auto t0 = Clock::now();
  FrontEndResult result;
  FrontEndStats& stats = result.stats;
  LocalMap local(config);
  // Without odometry the prediction is a standing robot: nothing to keep along a corridor.
  bool odometry_moves = false;
  for (std::size_t i = 1; i < raw.size() && !odometry_moves; ++i)
    odometry_moves = moved(raw[i - 1].T_world_odom, raw[i].T_world_odom, 1e-9, 1e-9);
  Pose2 last_key;
  OdometryError odometry_error;
  OdometryScale odometry_scale;
  bool after_stall = false;  // the step before repeated the odometry's pose
  double score_sum = 0.0;
  std::size_t matched = 0;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const Scan& scan = raw[i];
    if (!result.scans.empty()) {
      const Scan& prev = result.scans.back();
      if (scan.timestamp < prev.timestamp) {
        ++stats.time_reversals;
        continue;
      }
      if (moved(prev.T_world_odom, scan.T_world_odom, 1e-9, 1e-9)) stats.odometry_moves = true;
    }
    Scan out = scan;
    const Points2 points = matching_points(scan, config);
    if (!result.scans.empty()) {
      const Scan& prev = result.scans.back();
      Predicted p;
      p.from = prev.T_world_laser, p.step = prev.T_world_odom.inverse() * scan.T_world_odom;
      Pose2& prediction = p.prediction = p.from * p.step;
      const Pose2 odometry_prediction = prediction;
      const ScanMatch m = match_predicted(local, points, result.scans, scan, config, stats, prediction);
      // The odometry's step, as recorded: not a stall or the step that catches up after one, and not where
      // another prediction was kept.
      const bool stalled = !moved(prev.T_world_odom, scan.T_world_odom, 1e-9, 1e-9);
      p.odometry_step = !stalled && !after_stall && !moved(prediction, odometry_prediction, 1e-12, 1e-12);
      after_stall = stalled;
      if (m.score >= config.min_score) {
        out.T_world_laser = accepted_pose(local, points, scan, m.pose, p, odometry_moves, config, odometry_error,
                                          odometry_scale, stats);
        score_sum += m.score;
        ++matched;
        if (m.score < stats.weakest_score) stats.weakest_score = m.score, stats.weakest_scan = result.scans.size();
        stats.weak_matches += m.score < kWeakMatch;
      } else {
        out.T_world_laser = prediction;
        odometry_scale.drop();
        ++stats.rejected;
      }
      if (odometry_moves) count_heading_jump(prev, scan, out.T_world_laser, result.scans.size(), config, stats);
    }
    if (result.scans.empty() ||
        moved(last_key, out.T_world_laser, config.key_translation, config.key_rotation)) {
      local.add(transform(out.T_world_laser, points));
      last_key = out.T_world_laser;
    }
    result.scans.push_back(std::move(out));
    if (progress && (i + 1) % 100 == 0) progress("scan matching", i + 1, raw.size());
  }
  if (progress) progress("scan matching", raw.size(), raw.size());
  stats.scans = result.scans.size();
  stats.odometry_scale = odometry_scale.value();
  stats.mean_score = matched > 0 ? score_sum / static_cast<double>(matched) : 0.0;
  stats.seconds = ms_since(t0) / 1000.0;
  if (result.scans.size() > 1) stats.log_seconds = result.scans.back().timestamp - result.scans.front().timestamp;
  return result;
}

}  // namespace

std::string mirrored_description(const FrontEndStats& s) {
  if (!s.mirrored) return {};
  char what[300];
  std::snprintf(what, sizeof what,
                "the scans turned against the odometry (slope %.2f over %zu turning steps); read mirrored, as a laser "
                "mounted upside down (slope %.2f): the poses, maps and logs written are of the mirrored scans",
                s.unmirrored_turn_slope, s.turning_steps, s.turn_slope());
  return what;
}

FrontEndResult scan_match_log(const Scans& raw, const FrontEndConfig& config, const Progress& progress) {
  validate(config);
  FrontEndResult result = match_log(raw, config, progress);
  if (!config.mirror_check || !result.stats.turns_against_odometry()) return result;
  FrontEndResult again = match_log(mirrored(raw), config, progress);
  if (again.stats.turns_against_odometry()) return result;  // not a mirror either: the verdict says so
  again.stats.mirrored = true;
  again.stats.unmirrored_turn_slope = result.stats.turn_slope();
  again.stats.seconds += result.stats.seconds;
  return again;
}

}  // namespace partslam
