// The direction of a building's walls in a log's world frame, modulo a quarter turn (docs/NOTES.md, "The bench's
// resolution"): slam's grids are laid along the world's axes and rasterise walls along them best, so a log whose
// odometry frame happens to lie at 35 degrees to its walls came out worse (intel 0.0230 m against 0.0203). run_slam
// turns the log onto its walls first (SlamConfig::align_to_walls) and its results back.
#pragma once

#include <cstddef>

#include "core/maps/scan.h"

namespace partslam {

/// The circular mean of four times the world angles of the surface normals the first `first` scans see (each
/// from three consecutive beam endpoints within 0.5 m of each other, on the scan's logged pose), divided by four:
/// the walls' direction modulo a quarter turn, in (-pi/4, pi/4]. 0 when no surface is seen or the angles cancel.
double wall_direction(const Scans& scans, std::size_t first = 300);

}  // namespace partslam
