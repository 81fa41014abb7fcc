#include "io/logs/ros_bag.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "core/error.h"
#include "io/logs/no_return_codes.h"
#include "io/logs/ros_bag_messages.h"

namespace partslam::io {
namespace {

using rosbag_messages::LaserScanMessage;
using rosbag_messages::OdometryMessage;

double yaw_of(double qx, double qy, double qz, double qw) {
  return std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz));
}

struct Stamped {
  double t;
  Pose2 pose;
};

Pose2 odometry_at(const std::vector<Stamped>& odom, double t) {
  if (odom.empty()) return {};
  auto after = std::lower_bound(odom.begin(), odom.end(), t, [](const Stamped& s, double v) { return s.t < v; });
  if (after == odom.begin()) return odom.front().pose;
  if (after == odom.end()) return odom.back().pose;
  const Stamped& a = *(after - 1);
  const Stamped& b = *after;
  const double f = b.t > a.t ? (t - a.t) / (b.t - a.t) : 0.0;
  return {a.pose.x + f * (b.pose.x - a.pose.x), a.pose.y + f * (b.pose.y - a.pose.y),
          wrap_angle(a.pose.theta + f * wrap_angle(b.pose.theta - a.pose.theta))};
}

// mirror: the laser is mounted upside down (LaserMount), its beams are read turning the other way.
Scan to_scan(const LaserScanMessage& msg, const LogReadOptions& o, const std::string& where, bool mirror) {
  if (!std::isfinite(msg.stamp) || !std::isfinite(msg.angle_min) || !std::isfinite(msg.angle_increment) ||
      std::isnan(msg.range_max) || std::isnan(msg.range_min))
    throw InputError(where + ": a non-finite stamp, angle_min, angle_increment or range limit");
  if (msg.ranges.size() > 100000) throw InputError(where + ": more than 100000 ranges");
  Scan scan;
  scan.timestamp = msg.stamp;
  scan.num_beams = static_cast<int>(msg.ranges.size());
  const double lo = std::max(o.min_range, msg.range_min);
  const double hi = std::min({o.max_usable_range, o.no_return_range, msg.range_max});
  for (std::size_t i = 0; i < msg.ranges.size(); ++i) {
    const double r = msg.ranges[i];
    if (!(r > lo && r < hi)) continue;  // NaN and inf (no return in ROS) fail too
    const double a = msg.angle_min + static_cast<double>(i) * msg.angle_increment;
    scan.points_laser.emplace_back(r * std::cos(a), (mirror ? -r : r) * std::sin(a));
  }
  return scan;
}

Stamped to_pose(const OdometryMessage& m, const std::string& where) {
  const double yaw = yaw_of(m.qx, m.qy, m.qz, m.qw);
  const Stamped s{m.stamp, {m.x, m.y, wrap_angle(yaw)}};
  if (!std::isfinite(s.t) || !std::isfinite(s.pose.x) || !std::isfinite(s.pose.y) || !std::isfinite(yaw) ||
      std::abs(s.pose.x) > kMaxCoordinate || std::abs(s.pose.y) > kMaxCoordinate)
    throw InputError(where + ": a non-finite or implausible pose (beyond +-100 km)");
  return s;
}

// The laser's mount on the robot: the chain of transforms from the odometry's base frame to the scans' frame
// (e.g. base_link -> laser on /tf_static), each edge usable either way, composed in 3D, then seen from above. A
// laser mounted upside down (its scan plane's normal pointing down: rolled or pitched by pi) sees its beams turn
// clockwise from above, so its points are mirrored (y -> -y) before the mount's 2D pose applies; a scan plane
// tilted from the base's is projected onto it, with a warning. nullopt when there is no such chain.
struct LaserMount {
  Pose2 T_base_laser;
  bool upside_down = false;
};

std::optional<LaserMount> laser_mount(const rosbag_messages::BagMessages& m, const std::string& where,
                                      std::vector<std::string>& warnings) {
  const std::string base = m.base_frame.empty() ? "base_link" : m.base_frame;
  const std::string laser = m.scans.empty() ? "" : m.scans.front().frame_id;
  if (laser.empty() || laser == base) return std::nullopt;
  std::vector<std::optional<Eigen::Isometry3d>> edges;  // each transform, checked once
  for (const rosbag_messages::FrameTransform& f : m.transforms) {
    const Eigen::Vector4d q(f.qx, f.qy, f.qz, f.qw);
    if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(q.norm()) || std::abs(f.x) > 100 ||
        std::abs(f.y) > 100)
      throw InputError(where + ": transform " + f.parent + " -> " + f.child + " is not finite or not on a robot");
    if (q.norm() < 1e-6) {  // no rotation at all (tf2 discards such a transform too)
      warnings.push_back(where + ": transform " + f.parent + " -> " + f.child +
                         " has a zero quaternion; not used for the laser's mount");
      edges.emplace_back();
      continue;
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Quaterniond(f.qw, f.qx, f.qy, f.qz).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(f.x, f.y, 0.0);
    edges.push_back(T);
  }
  // Breadth first, at most 64 frames.
  std::vector<std::pair<std::string, Eigen::Isometry3d>> reached{{base, Eigen::Isometry3d::Identity()}};
  for (std::size_t at = 0; at < reached.size() && at < 64; ++at) {
    const auto [frame, T_base_frame] = reached[at];
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const rosbag_messages::FrameTransform& f = m.transforms[k];
      std::string next;
      Eigen::Isometry3d T_base_next;
      if (!edges[k]) continue;
      if (f.parent == frame) next = f.child, T_base_next = T_base_frame * *edges[k];
      else if (f.child == frame) next = f.parent, T_base_next = T_base_frame * edges[k]->inverse();
      else continue;
      if (next == laser) {
        const Eigen::Matrix3d R = T_base_next.linear();
        LaserMount mount;
        mount.T_base_laser = {T_base_next.translation().x(), T_base_next.translation().y(),
                              std::atan2(R(1, 0), R(0, 0))};
        mount.upside_down = R(2, 2) < 0;
        // Between the scan plane and the base's plane, up to pi / 2 (a plane turned over is parallel).
        const double tilt = std::acos(std::clamp(std::abs(R(2, 2)), 0.0, 1.0));
        if (tilt > 5.0 * std::numbers::pi / 180) {
          char what[200];
          std::snprintf(what, sizeof what,
                        "the laser frame %s is tilted %.1f degrees from %s's plane; its beams are projected onto "
                        "that plane as they are",
                        laser.c_str(), tilt * kDegreesPerRadian, base.c_str());
          warnings.push_back(where + ": " + what);
        }
        return mount;
      }
      const auto seen = [&next](const auto& r) { return r.first == next; };
      if (std::none_of(reached.begin(), reached.end(), seen)) reached.emplace_back(next, T_base_next);
    }
  }
  return std::nullopt;
}

}  // namespace

bool is_ros_bag(const std::filesystem::path& path) { return path.extension() == ".bag"; }

RosBagLog read_ros_bag(const std::filesystem::path& path, const LogReadOptions& options) {
  validate(options);
  const std::string name = path.string();
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) throw InputError(name + ": " + ec.message());
  if (!std::filesystem::exists(status)) throw InputError(name + ": no such file");
  if (!std::filesystem::is_regular_file(status)) throw InputError(name + ": not a regular file");
  rosbag_messages::BagMessages messages;
  try {
    messages = rosbag_messages::read_bag_messages(name, options.max_points, options.skip_damaged, options.scan_topic,
                                                  options.odom_topic);
  } catch (const rosbag_messages::BagError& e) {
    throw InputError(name + ": " + e.what());
  }
  return scans_from_bag_messages(messages, options, name);
}

RosBagLog scans_from_bag_messages(const rosbag_messages::BagMessages& messages, const LogReadOptions& options,
                                  const std::string& name) {
  RosBagLog log;
  for (const std::string& w : messages.warnings) log.warnings.push_back(name + ": " + w);
  log.scan_topic = messages.scan_topic;
  log.odometry_topic = messages.odometry_topic;
  log.odometry_messages = messages.odometry.size();
  std::vector<Stamped> odom;
  for (std::size_t i = 0; i < messages.odometry.size(); ++i)
    odom.push_back(to_pose(messages.odometry[i], name + ": " + log.odometry_topic + " message " + std::to_string(i)));
  std::stable_sort(odom.begin(), odom.end(), [](const Stamped& a, const Stamped& b) { return a.t < b.t; });
  // An odometry pose that jumps more than max_scan_jump from the one before is damage (a scan moved
  // kilometres): an error naming it, or with skip_damaged left out and counted. Across a gap in time (a chunk
  // skipped as damaged, a recording paused) the robot may have moved further: kMaxSpeed a second of the gap
  // is allowed too, else every pose after the gap would be measured from the one before it and left out.
  constexpr double kMaxSpeed = 5.0;  // [m/s]
  constexpr double kMaxGap = 120.0;  // [s]
  std::vector<Stamped> kept;
  std::size_t jumps = 0;
  for (const Stamped& o : odom) {
    if (!kept.empty()) {
      const double d = (o.pose.translation() - kept.back().pose.translation()).norm();
      // (At most kMaxGap of it: a damaged stamp far in the future does not excuse a damaged position.)
      const double dt = std::clamp(o.t - kept.back().t, 0.0, kMaxGap);
      if (d > options.max_scan_jump + kMaxSpeed * dt) {
        char what[240];
        std::snprintf(what, sizeof what,
                      "%s pose at stamp %.3f s jumps %.1f m from the one before, %.3f s earlier "
                      "(more than %.0f m plus %.0f m/s)",
                      log.odometry_topic.c_str(), o.t, d, dt, options.max_scan_jump, kMaxSpeed);
        if (!options.skip_damaged) throw InputError(name + ": " + what + "; skip_damaged leaves it out");
        if (jumps++ == 0) log.warnings.push_back(name + ": left out an odometry " + what);
        continue;
      }
    }
    kept.push_back(o);
  }
  if (jumps > 1) log.warnings.back() += " (" + std::to_string(jumps) + " such poses in all)";
  odom = std::move(kept);
  const std::optional<LaserMount> mount = laser_mount(messages, name, log.warnings);
  if (mount) {
    log.T_base_laser = mount->T_base_laser;
    log.laser_upside_down = mount->upside_down;
    log.laser_frame = messages.scans.front().frame_id;
  }
  for (std::size_t i = 0; i < messages.scans.size(); ++i) {
    Scan s = to_scan(messages.scans[i], options, name + ": " + log.scan_topic + " message " + std::to_string(i),
                     log.laser_upside_down);
    s.T_world_laser = s.T_world_odom = odometry_at(odom, s.timestamp) * log.T_base_laser;
    log.scans.push_back(std::move(s));
  }
  drop_no_return_codes(log.scans, find_no_return_codes(log.scans, options));
  return log;
}

}  // namespace partslam::io
