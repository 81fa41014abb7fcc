#include "core/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace partslam {
namespace {

// Independent random streams (see the header).
enum Stream : std::uint64_t { kPlan = 1, kRoute, kClutter, kLaser, kOdometry };

constexpr double kMaxScans = 5e6;      // refuse configs that would need more scans than this
constexpr double kLegEndMargin = 0.5;  // a door this close to a loop vertex is not visited [m]

struct TimedPose {
  double timestamp = 0.0;
  Pose2 pose;
};

// The loop `laps` times; on the first lap, excursions into the chosen rooms: corridor point in front of the
// door, a point just inside, the room centre, and back the same way.
std::vector<Vec2> make_path(const FloorPlan& plan, const RouteConfig& route, Rng& rng) {
  const std::vector<Vec2>& loop = plan.loop;
  struct Visit {
    std::size_t leg = 0;
    double along = 0.0;
    std::size_t room = 0;
  };
  std::vector<Visit> eligible;
  for (std::size_t r = 0; r < plan.rooms.size(); ++r) {
    const Room& room = plan.rooms[r];
    if (!room.has_door) continue;
    const Vec2 q = room.door_centre + room.door_normal * (plan.corridor_width / 2);
    for (std::size_t k = 0; k + 1 < loop.size(); ++k) {
      const Vec2 e = loop[k + 1] - loop[k];
      const double len = e.norm();
      const Vec2 u = e / len, w = q - loop[k];
      const double along = w.dot(u), across = u.x() * w.y() - u.y() * w.x();
      if (std::abs(across) < 1e-9 && along >= kLegEndMargin && along <= len - kLegEndMargin) {
        eligible.push_back({k, along, r});
        break;
      }
    }
  }
  const std::size_t visits = std::min(eligible.size(), static_cast<std::size_t>(route.room_visits));
  for (std::size_t i = 0; i < visits; ++i)
    std::swap(eligible[i], eligible[i + rng.index(eligible.size() - i)]);
  eligible.resize(visits);
  std::sort(eligible.begin(), eligible.end(), [](const Visit& a, const Visit& b) {
    return a.leg != b.leg ? a.leg < b.leg : a.along < b.along;
  });

  std::vector<Vec2> path{loop.front()};
  for (int lap = 0; lap < route.laps; ++lap) {
    for (std::size_t k = 0; k + 1 < loop.size(); ++k) {
      for (const Visit& v : eligible) {
        if (lap != 0 || v.leg != k) continue;
        const Room& room = plan.rooms[v.room];
        const Vec2 n = room.door_normal;
        const double depth = std::abs(n.x()) * room.box.width() + std::abs(n.y()) * room.box.height();
        const Vec2 front = room.door_centre + n * (plan.corridor_width / 2);
        const Vec2 inside = room.door_centre - n * std::min(1.0, depth / 3);
        const Vec2 centre{0.5 * (room.box.x_min + room.box.x_max), 0.5 * (room.box.y_min + room.box.y_max)};
        path.insert(path.end(), {front, inside, centre, inside, front});
      }
      path.push_back(loop[k + 1]);
    }
  }
  return path;
}

// One pose per scan: turn on the spot towards each leg, then drive along it, in steps of at most
// turn_spacing / scan_spacing. Waypoints are hit exactly.
std::vector<TimedPose> sample_path(const std::vector<Vec2>& path, const RouteConfig& route) {
  double heading = 0.0;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const Vec2 e = path[k + 1] - path[k];
    if (e.norm() > 1e-9) {
      heading = std::atan2(e.y(), e.x());
      break;
    }
  }
  double count = 1.0;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    count += std::ceil((path[k + 1] - path[k]).norm() / route.scan_spacing) +
             std::numbers::pi / route.turn_spacing;
  }
  if (count > kMaxScans) {
    throw InputError("simulator config: route.scan_spacing / route.turn_spacing / route.laps give over " +
                     std::to_string(static_cast<long long>(kMaxScans)) + " scans");
  }
  double time = route.start_time;
  std::vector<TimedPose> poses{{time, {path[0].x(), path[0].y(), heading}}};
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const Vec2 p0 = path[k], p1 = path[k + 1], e = p1 - p0;
    const double len = e.norm();
    if (len < 1e-9) continue;
    const double target = std::atan2(e.y(), e.x());
    const double delta = wrap_angle(target - heading);
    if (std::abs(delta) > 1e-12) {
      const int n = static_cast<int>(std::ceil(std::abs(delta) / route.turn_spacing - 1e-9));
      for (int i = 1; i <= n; ++i) {
        time += std::abs(delta) / n / route.turn_rate;
        poses.push_back({time, {p0.x(), p0.y(), i == n ? target : wrap_angle(heading + delta * i / n)}});
      }
    }
    heading = target;
    const int m = std::max(1, static_cast<int>(std::ceil(len / route.scan_spacing - 1e-9)));
    for (int i = 1; i <= m; ++i) {
      time += len / m / route.speed;
      const Vec2 p = i == m ? p1 : Vec2(p0 + e * (static_cast<double>(i) / m));
      poses.push_back({time, {p.x(), p.y(), heading}});
    }
  }
  return poses;
}

}  // namespace

void validate(const SimulatorConfig& c) {
  auto fail = [](const std::string& field, const std::string& what) {
    throw InputError("simulator config: " + field + " " + what);
  };
  auto in_range = [&](double v, double lo, double hi, const char* field, bool open_lo) {
    if (!(open_lo ? v > lo : v >= lo) || !(v <= hi)) {
      fail(field, std::string("must be in ") + (open_lo ? "(" : "[") + std::to_string(lo) + ", " +
                      std::to_string(hi) + "], got " + std::to_string(v));
    }
  };
  validate(c.building);
  const RouteConfig& r = c.route;
  if (r.laps < 1 || r.laps > 1000) fail("route.laps", "must be in [1, 1000], got " + std::to_string(r.laps));
  if (r.room_visits < 0 || r.room_visits > 10000) fail("route.room_visits", "must be in [0, 10000]");
  in_range(r.scan_spacing, 0.0, 100.0, "route.scan_spacing", true);
  in_range(r.turn_spacing, 0.0, std::numbers::pi, "route.turn_spacing", true);
  in_range(r.speed, 0.0, 100.0, "route.speed", true);
  in_range(r.turn_rate, 0.0, 100.0, "route.turn_rate", true);
  in_range(r.start_time, -1e12, 1e12, "route.start_time", false);
  in_range(r.clearance, 0.0, c.building.corridor_width / 2, "route.clearance", false);
  const LaserSimConfig& l = c.laser;
  if (l.num_beams < 2 || l.num_beams > 100000) fail("laser.num_beams", "must be in [2, 100000]");
  in_range(l.field_of_view, 0.0, 2 * std::numbers::pi, "laser.field_of_view", true);
  in_range(l.max_range, 0.0, 10000.0, "laser.max_range", true);
  in_range(l.range_sigma, 0.0, 10.0, "laser.range_sigma", false);
  const OdometryNoiseConfig& o = c.odometry;
  in_range(o.translation_sigma, 0.0, 10.0, "odometry.translation_sigma", false);
  in_range(o.heading_sigma, 0.0, 10.0, "odometry.heading_sigma", false);
  in_range(o.turn_sigma, 0.0, 10.0, "odometry.turn_sigma", false);
  in_range(o.scale_error, -0.5, 0.5, "odometry.scale_error", false);
  in_range(o.heading_bias, -1.0, 1.0, "odometry.heading_bias", false);
}

double beam_angle(const LaserSimConfig& laser, int i) {
  return -laser.field_of_view / 2 + i * laser.field_of_view / (laser.num_beams - 1);
}

std::vector<double> beam_ranges(const RayCaster& caster, const Pose2& T_world_laser,
                                const LaserSimConfig& laser) {
  std::vector<double> ranges(static_cast<std::size_t>(std::max(laser.num_beams, 0)));
  const Vec2 origin = T_world_laser.translation();
  for (int i = 0; i < laser.num_beams; ++i) {
    const double a = T_world_laser.theta + beam_angle(laser, i);
    ranges[i] = caster.cast(origin, Vec2(std::cos(a), std::sin(a)), laser.max_range);
  }
  return ranges;
}

SimulatedLog simulate(const SimulatorConfig& config) {
  validate(config);
  Rng plan_rng(config.seed, kPlan), route_rng(config.seed, kRoute), clutter_rng(config.seed, kClutter);
  Rng laser_rng(config.seed, kLaser), odometry_rng(config.seed, kOdometry);
  SimulatedLog log;
  log.plan = make_floor_plan(config.building, plan_rng);
  log.path = make_path(log.plan, config.route, route_rng);
  add_clutter(config.building, log.path, config.route.clearance, clutter_rng, &log.plan);
  const std::vector<TimedPose> poses = sample_path(log.path, config.route);
  const RayCaster caster(log.plan.walls);

  const LaserSimConfig& laser = config.laser;
  std::vector<double> cos_a(laser.num_beams), sin_a(laser.num_beams);
  for (int i = 0; i < laser.num_beams; ++i) {
    cos_a[i] = std::cos(beam_angle(laser, i));
    sin_a[i] = std::sin(beam_angle(laser, i));
  }
  log.scans.resize(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    Scan& scan = log.scans[k];
    scan.timestamp = poses[k].timestamp;
    scan.T_world_laser = poses[k].pose;
    scan.num_beams = laser.num_beams;
    const std::vector<double> ranges = beam_ranges(caster, scan.T_world_laser, laser);
    scan.points_laser.reserve(ranges.size());
    for (int i = 0; i < laser.num_beams; ++i) {
      if (!std::isfinite(ranges[i])) continue;
      const double r = ranges[i] + laser_rng.normal(laser.range_sigma);
      if (r > 0.0 && r < laser.max_range) scan.points_laser.emplace_back(r * cos_a[i], r * sin_a[i]);
    }
  }

  // Odometry: the true increment between consecutive scans, corrupted, integrated from the true start.
  const OdometryNoiseConfig& o = config.odometry;
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    if (k == 0) {
      log.scans[k].T_world_odom = log.scans[k].T_world_laser;
      continue;
    }
    const Pose2 u = log.scans[k - 1].T_world_laser.inverse() * log.scans[k].T_world_laser;
    const double dist = std::hypot(u.x, u.y), turn = std::abs(u.theta);
    const double sigma_xy = o.translation_sigma * std::sqrt(dist);
    const double sigma_theta =
        std::sqrt(o.heading_sigma * o.heading_sigma * dist + o.turn_sigma * o.turn_sigma * turn);
    Pose2 noisy;
    noisy.x = u.x * (1.0 + o.scale_error) + odometry_rng.normal(sigma_xy);
    noisy.y = u.y * (1.0 + o.scale_error) + odometry_rng.normal(sigma_xy);
    noisy.theta = u.theta + odometry_rng.normal(sigma_theta) + o.heading_bias * dist;
    log.scans[k].T_world_odom = log.scans[k - 1].T_world_odom * noisy;
  }
  return log;
}

}  // namespace partslam
