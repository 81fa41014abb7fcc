// Streaming reader for CARMEN laser logs (.clf / .log, plain or gzip). Each FLASER or ROBOTLASER1
// message becomes a Scan: timestamp = ipc_timestamp, T_world_laser from the laser pose fields,
// T_world_odom from the odometry (FLASER odom_x..) or robot pose (ROBOTLASER1) fields, and
// points_laser = the endpoints r_i (cos a_i, sin a_i) of the valid beams, a_i = start + i * increment.
// FLASER beams start at -90 deg and cover 180 deg (increment per FlaserSpacing); ROBOTLASER1 carries
// start_angle and angular_res itself. ODOM messages are collected as OdomReadings. Comments (#),
// blank lines, PARAM, NEFF, SYNC, VERTEX2, EDGE2 and any other message (RLASER, ROBOTLASER2, ...) are
// skipped and counted. Anything malformed — wrong beam count, missing or extra fields, non-numeric or
// non-finite numbers, binary data, corrupt gzip, a scan whose pose jumps more than max_scan_jump from the
// previous one, a file that is not a CARMEN log — throws InputError "<file>:<line>: <MESSAGE field>: <problem>".
// A recording cut short is read up to its last whole line: a last line without its '\n' that is not a whole
// FLASER, ROBOTLASER1 or ODOM message (and any last line of a gzip stream that ends early) is dropped, with a
// warning (CarmenReader::warnings) saying where the file stopped and how many scans were read. With
// LogReadOptions::skip_damaged, malformed lines and jumping scans elsewhere are skipped and counted too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/maps/scan.h"
#include "core/types.h"
#include "io/logs/log_read_options.h"

namespace partslam::io {

class LineReader;

/// Angle between consecutive beams of an n-beam FLASER message under the given convention [rad].
double flaser_angle_increment(int num_beams, FlaserSpacing spacing);

/// One ODOM message.
struct OdomReading {
  double timestamp = 0.0;  ///< ipc_timestamp [s]
  Pose2 T_world_odom;      ///< odometry pose of the robot [m, rad]
  double tv = 0.0;         ///< translational velocity [m/s]
  double rv = 0.0;         ///< rotational velocity [rad/s]
  double accel = 0.0;      ///< acceleration [m/s^2]
};

/// What a log held, by line and message.
struct CarmenLogStats {
  std::size_t lines = 0;        ///< lines read
  std::size_t flaser = 0;       ///< FLASER messages parsed
  std::size_t robotlaser = 0;   ///< ROBOTLASER1 messages parsed
  std::size_t odom = 0;         ///< ODOM messages parsed
  std::size_t comments = 0;     ///< lines starting with '#'
  std::size_t blank = 0;        ///< empty or whitespace-only lines
  std::size_t beams = 0;        ///< beams in all scans
  std::size_t valid_beams = 0;  ///< beams kept as points
  /// Beams dropped as the scanner's no-return code once the log was read (read_carmen_log; io/logs/no_return_codes.h).
  std::size_t no_return_code_beams = 0;
  /// Skipped messages by name (PARAM, NEFF, VERTEX2, EDGE2, SYNC, unknown ones).
  std::map<std::string, std::size_t, std::less<>> skipped;
  std::size_t damaged = 0;     ///< malformed or binary lines skipped (LogReadOptions::skip_damaged)
  std::size_t pose_jumps = 0;  ///< scans skipped for jumping beyond max_scan_jump (skip_damaged)
  bool cut_short = false;      ///< the file ended mid-record (its last line, or its gzip stream, cut off)
};

/// Reads one log message by message; holds the file open. Not copyable.
class CarmenReader {
 public:
  /// Opens path and validates options; throws InputError on a missing/unreadable file or bad options.
  explicit CarmenReader(const std::filesystem::path& path, const LogReadOptions& options = {});
  ~CarmenReader();
  CarmenReader(const CarmenReader&) = delete;
  CarmenReader& operator=(const CarmenReader&) = delete;

  /// The next scan, or nullopt at the end of the log. ODOM messages met on the way are appended to
  /// odometry(). Throws InputError on a malformed line (unless options.skip_damaged, or it is the cut-off
  /// last line), and at the end of a file that held no FLASER, ROBOTLASER1 or ODOM message at all (not a
  /// CARMEN log).
  std::optional<Scan> next();

  /// What the reader noticed but read past (a cut-off end, damaged lines skipped), "<file>: ..." each; complete
  /// once next() has returned nullopt.
  const std::vector<std::string>& warnings() const { return warnings_; }

  /// 1-based number of the line last read.
  std::size_t line() const;
  /// ODOM readings read so far, in file order.
  const std::vector<OdomReading>& odometry() const { return odometry_; }
  /// Moves the ODOM readings read so far out of the reader (odometry() is empty afterwards).
  std::vector<OdomReading> take_odometry() {
    std::vector<OdomReading> out;
    out.swap(odometry_);
    return out;
  }
  const CarmenLogStats& stats() const { return stats_; }

 private:
  Scan parse_flaser();
  Scan parse_robotlaser();
  void parse_odom();
  /// A damaged line: returns false when it is the cut-off end of the file (reading stops), true when it is
  /// skipped (skip_damaged); otherwise throws InputError(what).
  bool damaged(const std::string& what, bool known_message);
  /// Whether the scan's pose jumps beyond max_scan_jump from the previous scan's; throws unless skip_damaged.
  bool jumps(const Scan& scan);
  /// The warnings at the end of the input.
  void finish();
  /// Fills scan.points_laser from ranges tokens [first, first + n) with beam angles start + i * increment.
  void add_points(Scan& scan, std::size_t first, int n, double start, double increment, double max_range,
                  std::string_view message);

  const LogReadOptions options_;
  std::unique_ptr<LineReader> lines_;
  std::vector<std::string_view> tokens_;
  std::vector<OdomReading> odometry_;
  CarmenLogStats stats_;
  std::vector<std::string> warnings_;
  std::string first_damage_, first_jump_;
  std::optional<Pose2> previous_pose_;
  std::size_t previous_line_ = 0;
  std::size_t cut_line_ = 0;      ///< the line cut off at the end, 0: none
  std::uint64_t cut_offset_ = 0;  ///< where it starts in the text [bytes]
  bool finished_ = false;
  // Beam direction cache: unit vectors for the last (n, start, increment) seen.
  std::vector<Vec2> directions_;
  int directions_n_ = -1;
  double directions_start_ = 0.0;
  double directions_increment_ = 0.0;
};

/// A whole log in memory.
struct CarmenLog {
  Scans scans;                        ///< FLASER / ROBOTLASER1 scans in file order
  std::vector<OdomReading> odometry;  ///< ODOM messages in file order
  CarmenLogStats stats;
  std::vector<std::string> warnings;  ///< CarmenReader::warnings(): a cut-off end, damage skipped
  /// The laser's mount on the robot when every scan's laser pose is its odometry pose times one fixed transform
  /// (a raw log with an offset laser: ROBOTLASER1's laser_pose and robot_pose, FLASER's laser and odometry poses,
  /// to 1 mm / 1 mrad, over at least 5 scans of a robot that turned by 0.5 rad or more); the scans' T_world_odom
  /// then carry it (the odometry pose of the laser, as everywhere else). nullopt when the two are the same, differ
  /// from scan to scan (a corrected log), or the log is too short or too straight to tell.
  std::optional<Pose2> T_base_laser;
};

/// Reads a whole log, carries the odometry poses onto the laser when the log's two poses differ by a fixed mount
/// (CarmenLog::T_base_laser), then drops its scanner's no-return codes (io/logs/no_return_codes.h; CarmenReader::next does
/// not: a code is known only once the whole log is read); same errors as CarmenReader.
CarmenLog read_carmen_log(const std::filesystem::path& path, const LogReadOptions& options = {});

/// Writes scans as a CARMEN log of FLASER messages (atomically): each scan's ranges rebuilt from its points on
/// the beams of the kCarmen convention (-90 deg .. +90 deg, num_beams beams; beams without a point, dropped when
/// read, are written as 81.92 "no return"), both pose slots holding T_world_laser (a corrected log), ranges to
/// 0.1 mm. Reading it back gives the same points to 0.1 mm. Throws InputError naming the path when it cannot be
/// written, and for a scan with no beams.
void write_carmen_log(const std::filesystem::path& path, const Scans& scans, const std::string& header = {});

}  // namespace partslam::io
