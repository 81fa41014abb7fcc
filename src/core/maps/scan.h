// One laser scan as every source yields it (CARMEN logs, the simulator): timestamp, poses, and the
// points of its valid beams in the laser frame. Max-range / no-return beams are already dropped.
#pragma once

#include <string>

#include "core/types.h"

namespace partslam {

struct Scan {
  double timestamp = 0.0;  ///< ipc_timestamp of the message [s]
  Pose2 T_world_laser;     ///< laser pose from the log (corrected pose in corrected logs; truth in the simulator)
  Pose2 T_world_odom;      ///< raw odometry pose of the laser (equals T_world_laser in corrected logs)
  Points2 points_laser;    ///< endpoints of valid beams, laser frame [m]
  int num_beams = 0;       ///< beams in the message, valid or not
};

using Scans = std::vector<Scan>;

/// Scan endpoints in the world frame.
inline Points2 points_world(const Scan& scan) { return transform(scan.T_world_laser, scan.points_laser); }

/// Scan endpoints within max_range of the laser [m], in the world frame (the usable-range cap of submaps and
/// dictionaries: far returns are sparse and drag a map's centroid away from where the robot was).
inline Points2 points_world(const Scan& scan, double max_range) {
  Points2 out;
  out.reserve(scan.points_laser.size());
  for (const Vec2& p : scan.points_laser)
    if (p.squaredNorm() <= max_range * max_range) out.push_back(scan.T_world_laser * p);
  return out;
}

/// Where a scan shows a surface: for every endpoint i whose neighbours i - 1 and i + 1 both lie within 0.5 m of it
/// (one surface, not a jump from one object to another) and that lies within `max_range` of the laser, calls
/// fn(tangent) with the chord p[i + 1] - p[i - 1] (laser frame, not normalised, never shorter than 1e-6 m); the
/// surface's normal is the chord turned by +90 degrees. The front end's degeneracy test (the normals' scatter) and
/// log_wall_axis (the walls' direction, core/maps/manhattan.h) read the same surfaces through it.
template <class Fn>
void for_each_surface_tangent(const Points2& p, double max_range, Fn&& fn) {
  const double r2 = max_range * max_range;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    if (p[i].squaredNorm() > r2 || (p[i + 1] - p[i]).norm() > 0.5 || (p[i] - p[i - 1]).norm() > 0.5) continue;
    const Vec2 d = p[i + 1] - p[i - 1];
    if (d.norm() < 1e-6) continue;
    fn(d);
  }
}

/// Plausibility limit of a pose coordinate [m]: readers refuse poses farther than this from the log's origin
/// (a building, or a campus, is far smaller), naming the file, line and field (docs/NOTES.md, "Limits").
inline constexpr double kMaxCoordinate = 1e5;
/// Plausibility limit of one map's extent [m]: the exact matcher (dMM) refuses a map whose points span more
/// (its grid pyramid grows with the area: one stray scan 3 km away took a dictionary from 26 MB to 4.8 GB).
inline constexpr double kMaxMapExtent = 1000.0;

/// The usable-range cap of submaps and dictionaries unless told otherwise [m] (docs/NOTES.md, "Usable range").
inline constexpr double kDefaultMaxRange = 8.0;

}  // namespace partslam
