// How every log reader (CARMEN: carmen_log.h, ROS 1 bags: ros_bag.h, ROS 2 bags: ros2_bag.h; chosen by
// scan_source.h) turns a recording into scans: which beams are kept, which topics of a bag are read, how damage
// is treated, the limits that refuse absurd input. The CLI sets them with --skip-damaged, --scan-topic and
// --odom-topic.
#pragma once

#include <cstddef>
#include <string>

namespace partslam::io {

/// Angle between consecutive FLASER beams, which the message does not state.
enum class FlaserSpacing {
  kCarmen,         ///< pi/n for even n, pi/(n-1) for odd n: the SICK 1 deg / 0.5 deg steps, as CARMEN guesses
  kPiOverN,        ///< pi/n for every n: the last beam stops one step short of +90 deg
  kPiOverNMinus1,  ///< pi/(n-1) for every n: first beam at -90 deg, last at +90 deg
};

struct LogReadOptions {
  /// Beams with range <= min_range are dropped [m].
  double min_range = 0.0;
  /// Beams with range >= max_usable_range are dropped [m]. 80 m: the farthest a SICK LMS reports (its long-range
  /// mode); a scanner's no-return code below it is found per recording (no_return_code_share). Outdoors the
  /// returns beyond 30 m are what holds the front end along a road (docs/NOTES.md, "Far returns kept"); the maps cap
  /// their own range (SubmapConfig::max_range, 8 m).
  double max_usable_range = 80.0;
  /// Ranges >= no_return_range are CARMEN's "no return" codes (81.83 .. 81.92) and always dropped [m],
  /// whatever max_usable_range says. ROBOTLASER1 beams >= the message's own max_range are dropped too.
  double no_return_range = 81.0;
  /// A scanner's own no-return code (50.0 m in aces, ~51.1 m in acapulco, 32.77 m in orebro): a 1 cm range bin
  /// beyond no_return_code_min_range holding at least this share of the recording's beams; its beams are dropped
  /// once the whole recording is read (io/logs/no_return_codes.h). 0: no codes looked for.
  double no_return_code_share = 0.003;
  /// Codes are looked for at or beyond this range [m].
  double no_return_code_min_range = 20.0;
  /// FLASER beam spacing convention; kCarmen matches CARMEN's readlog and the SICK hardware.
  FlaserSpacing flaser_spacing = FlaserSpacing::kCarmen;
  /// A log with more valid beams than this is refused (a small gzip file can expand to gigabytes of points;
  /// the largest log here, intel, has 2.3 M; 20 M points take ~320 MB) [points].
  std::size_t max_points = 20'000'000;
  /// Bags (ROS 1 and 2): the sensor_msgs LaserScan topic to read; empty: the first one in the bag.
  std::string scan_topic;
  /// Bags: the nav_msgs Odometry topic that poses the scans, or a tf topic whose odom -> base_link transforms do;
  /// empty: the first Odometry topic, else the odom -> base_link transforms of the first tf topic with them.
  std::string odom_topic;
  /// Damage in the middle of a log — a malformed or binary line, a scan whose pose jumps more than
  /// max_scan_jump; in a ROS bag (io/logs/ros_bag.h) a corrupt chunk or message, a damaged index — is an InputError
  /// naming the line (or byte); with skip_damaged it is skipped and counted instead, with a warning giving the
  /// count (CarmenLog::warnings, RosBagLog::warnings). A recording cut short is read up to its last whole line
  /// (or chunk) either way. Corrupt gzip data stays an error: nothing after it can be read. CLI: --skip-damaged.
  bool skip_damaged = false;
  /// Largest distance between the laser poses of consecutive scans (in a bag: between consecutive odometry poses)
  /// [m]. The shared logs' largest is 3.3 m
  /// (orebro-corrected, a subsampled corrected log; 0.86 m in the raw ones); a scan moved kilometres is damage.
  double max_scan_jump = 20.0;
};

/// Throws InputError naming the offending field.
void validate(const LogReadOptions& options);

}  // namespace partslam::io
