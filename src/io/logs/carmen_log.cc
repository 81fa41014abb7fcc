#include "io/logs/carmen_log.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "io/files/atomic_file.h"
#include "io/files/line_reader.h"
#include "io/files/text_fields.h"
#include "io/logs/no_return_codes.h"

namespace partslam::io {
namespace {

/// Upper bound on beams (and remissions) per message; real scanners have at most a few thousand.
constexpr long kMaxBeams = 100000;

constexpr std::string_view kFlaser = "FLASER";
constexpr std::string_view kRobotLaser = "ROBOTLASER1";
constexpr std::string_view kOdom = "ODOM";

/// Fields after the ranges of a FLASER message.
constexpr const char* kFlaserTail[] = {
    "x", "y", "theta", "odom_x", "odom_y", "odom_theta", "ipc_timestamp", "hostname", "logger_timestamp"};
/// Fields of ROBOTLASER1 before the ranges (after the message name).
constexpr const char* kRobotLaserHead[] = {"laser_type",     "start_angle", "fov",
                                           "angular_res",    "max_range",   "accuracy",
                                           "remission_mode", "num_readings"};
/// Fields of ROBOTLASER1 after the remissions.
constexpr const char* kRobotLaserTail[] = {"laser_x",
                                           "laser_y",
                                           "laser_theta",
                                           "robot_x",
                                           "robot_y",
                                           "robot_theta",
                                           "tv",
                                           "rv",
                                           "forward_safety_dist",
                                           "side_safety_dist",
                                           "turn_axis",
                                           "ipc_timestamp",
                                           "hostname",
                                           "logger_timestamp"};
/// Fields of ODOM after the message name.
constexpr const char* kOdomFields[] = {
    "x", "y", "theta", "tv", "rv", "accel", "ipc_timestamp", "hostname", "logger_timestamp"};

bool is_message_name(std::string_view token) {
  if (token.empty() || token[0] < 'A' || token[0] > 'Z') return false;
  return std::all_of(token.begin(), token.end(),
                     [](char c) { return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'; });
}

/// Throws for a line whose field count differs from the expected one; first_missing names the field
/// at index have (used when fields are missing).
[[noreturn]] void fail_count(const LineReader& reader, std::string_view message, std::size_t have,
                             std::size_t want, const FieldName& first_missing, std::string_view hint) {
  const std::string counts = " (line has " + std::to_string(have) + " fields, expected " +
                             std::to_string(want) + std::string(hint) + ")";
  if (have < want) fail_field(reader, first_missing, "missing" + counts);
  fail_field(reader, {message, "", -1}, std::to_string(have - want) + " extra field(s)" + counts);
}

std::string beam_hint(long n) { return "; does num_readings " + std::to_string(n) + " match the ranges?"; }

Pose2 make_pose(double x, double y, double theta) { return {x, y, wrap_angle(theta)}; }

// Refuses a pose coordinate beyond kMaxCoordinate (a 1e300 pose would otherwise pass as a number and break
// every later step quietly).
void check_coordinate(const LineReader& reader, double value, const FieldName& field) {
  if (std::abs(value) > kMaxCoordinate) {
    char text[96];
    std::snprintf(text, sizeof text, "implausible coordinate %g m (beyond +-%g m)", value, kMaxCoordinate);
    fail_field(reader, field, text);
  }
}

}  // namespace

double flaser_angle_increment(int num_beams, FlaserSpacing spacing) {
  if (num_beams < 2) return std::numbers::pi;  // a single beam: the increment is never used
  const double n = num_beams;
  switch (spacing) {
    case FlaserSpacing::kPiOverN:
      return std::numbers::pi / n;
    case FlaserSpacing::kPiOverNMinus1:
      return std::numbers::pi / (n - 1.0);
    case FlaserSpacing::kCarmen:
      break;
  }
  return num_beams % 2 == 0 ? std::numbers::pi / n : std::numbers::pi / (n - 1.0);
}

CarmenReader::CarmenReader(const std::filesystem::path& path, const LogReadOptions& options)
    : options_(options) {
  validate(options_);
  lines_ = std::make_unique<LineReader>(path, LineReader::Tolerance::kCutAndBinary);
}

CarmenReader::~CarmenReader() = default;

std::size_t CarmenReader::line() const { return lines_->line_number(); }

std::optional<Scan> CarmenReader::next() {
  if (finished_) return std::nullopt;
  std::string_view line;
  while (lines_->next(line)) {
    ++stats_.lines;
    if (lines_->binary_column() != 0) {
      char what[64];
      std::snprintf(what, sizeof what, "binary data (byte 0x%02x at column %zu)", lines_->binary_byte(),
                    lines_->binary_column());
      if (damaged(lines_->name() + ":" + std::to_string(lines_->line_number()) + ": " + what, false)) continue;
      break;
    }
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string_view::npos) {
      ++stats_.blank;
      continue;
    }
    if (line[start] == '#') {
      ++stats_.comments;
      continue;
    }
    const std::size_t stop = line.find_first_of(" \t", start);
    const std::string_view name = line.substr(start, stop == std::string_view::npos ? stop : stop - start);
    const bool known = name == kFlaser || name == kRobotLaser || name == kOdom;
    // The last line of a gzip stream cut short, or a last line without its '\n' that is no scan or odometry
    // ("FLAS", "NEFF 1"): the end of a recording cut short, whatever it parses to.
    if (lines_->unterminated() && (lines_->cut_short() || !known)) {
      damaged("", true);  // the cut: reading stops
      break;
    }
    std::optional<Scan> scan;
    try {
      if (name == kFlaser) {
        split_fields(line, tokens_);
        scan = parse_flaser();
      } else if (name == kRobotLaser) {
        split_fields(line, tokens_);
        scan = parse_robotlaser();
      } else if (name == kOdom) {
        split_fields(line, tokens_);
        parse_odom();
        ++stats_.odom;
        continue;
      } else if (!is_message_name(name)) {
        lines_->fail("not a CARMEN message: line starts with '" + std::string(name.substr(0, 40)) + "'");
      }
    } catch (const InputError& e) {
      if (damaged(e.what(), known)) continue;
      break;
    }
    if (!scan) {
      const auto it = stats_.skipped.find(name);
      if (it != stats_.skipped.end()) {
        ++it->second;
      } else {
        stats_.skipped.emplace(std::string(name), 1);
      }
      continue;
    }
    if (jumps(*scan)) continue;
    stats_.beams += static_cast<std::size_t>(scan->num_beams);
    stats_.valid_beams += scan->points_laser.size();
    if (stats_.valid_beams > options_.max_points) {
      lines_->fail("the log holds more than " + std::to_string(options_.max_points) +
                   " valid beams (LogReadOptions.max_points); split it or raise the limit");
    }
    ++(name == kFlaser ? stats_.flaser : stats_.robotlaser);
    previous_pose_ = scan->T_world_laser;
    previous_line_ = lines_->line_number();
    return scan;
  }
  finish();
  return std::nullopt;
}

bool CarmenReader::damaged(const std::string& what, bool known_message) {
  // The last line, without its '\n', is the end of a recording cut short when it does not parse (a line that
  // parses without its '\n' is whole: the file simply lacks the final newline).
  if (lines_->unterminated() && (known_message || lines_->cut_short() || lines_->binary_column() != 0)) {
    stats_.cut_short = true;
    cut_line_ = lines_->line_number();
    cut_offset_ = lines_->line_offset();
    return false;
  }
  if (!options_.skip_damaged) throw InputError(what);
  if (stats_.damaged++ == 0) first_damage_ = what;
  return true;
}

bool CarmenReader::jumps(const Scan& scan) {
  if (!previous_pose_) return false;
  const double d = std::hypot(scan.T_world_laser.x - previous_pose_->x, scan.T_world_laser.y - previous_pose_->y);
  if (!(d > options_.max_scan_jump)) return false;
  char numbers[200];
  std::snprintf(numbers, sizeof numbers,
                "the scan's pose (x %g, y %g) lies %.1f m from the previous scan's (line %zu), beyond "
                "LogReadOptions.max_scan_jump %g m: a damaged pose",
                scan.T_world_laser.x, scan.T_world_laser.y, d, previous_line_, options_.max_scan_jump);
  const std::string text = lines_->name() + ":" + std::to_string(lines_->line_number()) + ": " + numbers;
  if (!options_.skip_damaged) throw InputError(text + " (skip_damaged skips such scans)");
  if (stats_.pose_jumps++ == 0) first_jump_ = text;
  return true;
}

void CarmenReader::finish() {
  finished_ = true;
  if (lines_->cut_short()) stats_.cut_short = true;
  const std::string& name = lines_->name();
  if (cut_line_ == 0) cut_offset_ = lines_->text_bytes();
  const std::string where = " after byte " + std::to_string(cut_offset_) + " (line " +
                            std::to_string(cut_line_ != 0 ? cut_line_ : lines_->line_number()) + ")";
  const std::string ends = std::string(lines_->cut_short() ? "the gzip data is cut short: its text ends"
                                                           : "the file ends") +
                           (cut_line_ != 0 ? " mid-record" : "") + where;
  if (stats_.flaser + stats_.robotlaser + stats_.odom == 0) {
    if (stats_.cut_short) throw InputError(name + ": " + ends + ", before any whole FLASER, ROBOTLASER1 or ODOM message");
    throw InputError(name + ": not a CARMEN log (no FLASER, ROBOTLASER1 or ODOM message in " +
                     std::to_string(stats_.lines) + " lines)");
  }
  if (stats_.cut_short)
    warnings_.push_back(name + ": " + ends + "; read the " + std::to_string(stats_.flaser + stats_.robotlaser) +
                        " scans before it");
  if (stats_.damaged > 0)
    warnings_.push_back(name + ": skipped " + std::to_string(stats_.damaged) +
                        " damaged line(s) (skip_damaged); the first: " + first_damage_);
  if (stats_.pose_jumps > 0)
    warnings_.push_back(name + ": skipped " + std::to_string(stats_.pose_jumps) +
                        " scan(s) whose pose jumps (skip_damaged); the first: " + first_jump_);
}

void CarmenReader::add_points(Scan& scan, std::size_t first, int n, double start, double increment,
                              double max_range, std::string_view message) {
  if (n != directions_n_ || start != directions_start_ || increment != directions_increment_) {
    directions_.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const double angle = start + increment * i;
      directions_[static_cast<std::size_t>(i)] = Vec2(std::cos(angle), std::sin(angle));
    }
    directions_n_ = n;
    directions_start_ = start;
    directions_increment_ = increment;
  }
  const double limit = std::min({options_.max_usable_range, options_.no_return_range, max_range});
  scan.points_laser.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double r =
        parse_number(*lines_, tokens_[first + static_cast<std::size_t>(i)], {message, "range", i});
    if (r > options_.min_range && r < limit)
      scan.points_laser.push_back(r * directions_[static_cast<std::size_t>(i)]);
  }
}

Scan CarmenReader::parse_flaser() {
  const LineReader& reader = *lines_;
  const auto& t = tokens_;
  if (t.size() < 2) fail_field(reader, {kFlaser, "num_readings"}, "missing");
  const long n = parse_count(reader, t[1], {kFlaser, "num_readings"}, kMaxBeams);
  if (n == 0) fail_field(reader, {kFlaser, "num_readings"}, "no beams");
  const std::size_t tail = 2 + static_cast<std::size_t>(n);
  const std::size_t want = tail + std::size(kFlaserTail);
  if (t.size() != want) {
    const FieldName missing = t.size() < tail
                                  ? FieldName{kFlaser, "range", static_cast<long>(t.size()) - 2}
                                  : FieldName{kFlaser, kFlaserTail[std::min(t.size(), want - 1) - tail]};
    fail_count(reader, kFlaser, t.size(), want, missing, beam_hint(n));
  }
  double v[7] = {};
  for (std::size_t k = 0; k < 7; ++k) v[k] = parse_number(reader, t[tail + k], {kFlaser, kFlaserTail[k]});
  parse_number(reader, t[tail + 8], {kFlaser, kFlaserTail[8]});
  for (std::size_t k : {0, 1, 3, 4}) check_coordinate(reader, v[k], {kFlaser, kFlaserTail[k]});
  Scan scan;
  scan.timestamp = v[6];
  scan.T_world_laser = make_pose(v[0], v[1], v[2]);
  scan.T_world_odom = make_pose(v[3], v[4], v[5]);
  scan.num_beams = static_cast<int>(n);
  add_points(scan, 2, static_cast<int>(n), -std::numbers::pi / 2.0,
             flaser_angle_increment(static_cast<int>(n), options_.flaser_spacing),
             std::numeric_limits<double>::infinity(), kFlaser);
  return scan;
}

Scan CarmenReader::parse_robotlaser() {
  const LineReader& reader = *lines_;
  const auto& t = tokens_;
  constexpr std::size_t kHead = std::size(kRobotLaserHead);  // fields 1..8, num_readings last
  if (t.size() <= kHead) {
    fail_field(reader, {kRobotLaser, kRobotLaserHead[t.size() - 1]}, "missing");
  }
  double head[kHead - 1] = {};
  for (std::size_t k = 0; k + 1 < kHead; ++k) {
    head[k] = parse_number(reader, t[1 + k], {kRobotLaser, kRobotLaserHead[k]});
  }
  const long n = parse_count(reader, t[kHead], {kRobotLaser, "num_readings"}, kMaxBeams);
  if (n == 0) fail_field(reader, {kRobotLaser, "num_readings"}, "no beams");
  const double start_angle = head[1], angular_res = head[3], max_range = head[4];
  if (angular_res == 0.0) fail_field(reader, {kRobotLaser, "angular_res"}, "must not be zero");
  if (max_range <= 0.0) fail_field(reader, {kRobotLaser, "max_range"}, "must be positive");

  const std::size_t first_range = kHead + 1;
  const std::size_t rem_count = first_range + static_cast<std::size_t>(n);
  if (t.size() <= rem_count) {
    const FieldName missing = t.size() < rem_count
                                  ? FieldName{kRobotLaser, "range", static_cast<long>(t.size() - first_range)}
                                  : FieldName{kRobotLaser, "num_remissions"};
    fail_count(reader, kRobotLaser, t.size(), rem_count + 1 + std::size(kRobotLaserTail), missing,
               beam_hint(n));
  }
  const long n_rem = parse_count(reader, t[rem_count], {kRobotLaser, "num_remissions"}, kMaxBeams);
  const std::size_t tail = rem_count + 1 + static_cast<std::size_t>(n_rem);
  const std::size_t want = tail + std::size(kRobotLaserTail);
  if (t.size() != want) {
    const FieldName missing =
        t.size() < tail ? FieldName{kRobotLaser, "remission", static_cast<long>(t.size() - rem_count - 1)}
                        : FieldName{kRobotLaser, kRobotLaserTail[std::min(t.size(), want - 1) - tail]};
    fail_count(reader, kRobotLaser, t.size(), want, missing, "; do num_readings and num_remissions match?");
  }
  for (std::size_t i = rem_count + 1; i < tail; ++i) {
    parse_number(reader, t[i], {kRobotLaser, "remission", static_cast<long>(i - rem_count - 1)});
  }
  double v[std::size(kRobotLaserTail)] = {};
  for (std::size_t k = 0; k < std::size(kRobotLaserTail); ++k) {
    if (k != 12) v[k] = parse_number(reader, t[tail + k], {kRobotLaser, kRobotLaserTail[k]});  // 12: hostname
  }
  for (std::size_t k : {0, 1, 3, 4}) check_coordinate(reader, v[k], {kRobotLaser, kRobotLaserTail[k]});
  Scan scan;
  scan.timestamp = v[11];
  scan.T_world_laser = make_pose(v[0], v[1], v[2]);
  scan.T_world_odom = make_pose(v[3], v[4], v[5]);
  scan.num_beams = static_cast<int>(n);
  add_points(scan, first_range, static_cast<int>(n), start_angle, angular_res, max_range, kRobotLaser);
  return scan;
}

void CarmenReader::parse_odom() {
  const LineReader& reader = *lines_;
  const auto& t = tokens_;
  const std::size_t want = 1 + std::size(kOdomFields);
  if (t.size() != want) {
    fail_count(reader, kOdom, t.size(), want, {kOdom, kOdomFields[std::min(t.size(), want - 1) - 1]}, "");
  }
  double v[std::size(kOdomFields)] = {};
  for (std::size_t k = 0; k < std::size(kOdomFields); ++k) {
    if (k != 7) v[k] = parse_number(reader, t[1 + k], {kOdom, kOdomFields[k]});  // 7: hostname
  }
  for (std::size_t k : {0, 1}) check_coordinate(reader, v[k], {kOdom, kOdomFields[k]});
  odometry_.push_back({v[6], make_pose(v[0], v[1], v[2]), v[3], v[4], v[5]});
}

namespace {

// The laser's mount when every scan's laser pose is its odometry pose carried by one fixed transform (a raw log
// whose laser pose fields are the robot's odometry times the mount: ROBOTLASER1's laser_pose and robot_pose,
// FLASER's x y theta and odom_x ..; to 1 mm and 1 mrad, CARMEN's six decimals), nullopt for none or when it
// varies (a corrected log: its laser poses are not the odometry's). Only a robot that turned tells a mount from
// an offset between two frames (kMountEvidence): a few scans, or a robot that drove straight, say nothing.
struct MountEvidence {
  std::size_t scans = 5;
  double turn = 0.5;  // [rad] between the odometry's headings, at least
};
constexpr MountEvidence kMountEvidence;

std::optional<Pose2> constant_mount(const Scans& scans) {
  if (scans.size() < kMountEvidence.scans) return std::nullopt;
  const Pose2 first = scans.front().T_world_odom.inverse() * scans.front().T_world_laser;
  if (first.translation().norm() < 1e-3 && std::abs(first.theta) < 1e-3) return std::nullopt;
  double turned = 0;
  for (const Scan& s : scans)
    turned = std::max(turned, std::abs(wrap_angle(s.T_world_odom.theta - scans.front().T_world_odom.theta)));
  if (turned < kMountEvidence.turn) return std::nullopt;
  for (const Scan& s : scans) {
    const Pose2 m = s.T_world_odom.inverse() * s.T_world_laser;
    if ((m.translation() - first.translation()).norm() > 1e-3 || std::abs(wrap_angle(m.theta - first.theta)) > 1e-3)
      return std::nullopt;
  }
  return first;
}

}  // namespace

CarmenLog read_carmen_log(const std::filesystem::path& path, const LogReadOptions& options) {
  CarmenReader reader(path, options);
  CarmenLog log;
  while (std::optional<Scan> scan = reader.next()) log.scans.push_back(std::move(*scan));
  // The odometry pose of the laser, not of the robot: increments of the robot's pose are not the laser's where it
  // sits off the axis it turns about (0.22 m ahead turns 2 cm sideways with every 0.1 rad).
  log.T_base_laser = constant_mount(log.scans);
  if (log.T_base_laser)
    for (Scan& s : log.scans) s.T_world_odom = s.T_world_odom * *log.T_base_laser;
  log.odometry = reader.take_odometry();
  log.stats = reader.stats();
  log.stats.no_return_code_beams = drop_no_return_codes(log.scans, find_no_return_codes(log.scans, options));
  log.stats.valid_beams -= log.stats.no_return_code_beams;
  log.warnings = reader.warnings();
  return log;
}

void write_carmen_log(const std::filesystem::path& path, const Scans& scans, const std::string& header) {
  write_atomically(path, [&](std::ostream& out) {
    out << "# " << (header.empty() ? "written by partslam" : header) << "\n";
    char buf[64];
    for (std::size_t k = 0; k < scans.size(); ++k) {
      const Scan& scan = scans[k];
      if (scan.num_beams < 1)
        throw InputError(path.string() + ": scan " + std::to_string(k) + " has no beams to write");
      const double increment = flaser_angle_increment(scan.num_beams, FlaserSpacing::kCarmen);
      std::vector<double> ranges(static_cast<std::size_t>(scan.num_beams), 81.92);
      for (const Vec2& p : scan.points_laser) {
        const long beam = std::lround((std::atan2(p.y(), p.x()) + std::numbers::pi / 2) / increment);
        if (beam >= 0 && beam < scan.num_beams) ranges[static_cast<std::size_t>(beam)] = p.norm();
      }
      out << "FLASER " << scan.num_beams;
      for (double r : ranges) {
        std::snprintf(buf, sizeof buf, " %.4f", r);
        out << buf;
      }
      const Pose2& T = scan.T_world_laser;
      std::snprintf(buf, sizeof buf, " %.6f %.6f %.6f", T.x, T.y, T.theta);
      out << buf << buf;
      std::snprintf(buf, sizeof buf, " %.6f partslam %.6f\n", scan.timestamp, scan.timestamp);
      out << buf;
    }
  });
}

}  // namespace partslam::io
