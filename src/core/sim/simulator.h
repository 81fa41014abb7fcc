// The embedded simulator (docs/DESIGN.md, "Embedded default"): a seeded procedural Manhattan building
// (core/sim/floor_plan.h), a robot driving its corridor loop(s) `laps` times and into a few rooms, a 180-degree
// laser simulated by exact ray casting (core/sim/ray_caster.h) with Gaussian range noise, and odometry
// integrated from noisy increments. Every scan carries the exact pose (T_world_laser) and the drifting
// odometry pose (T_world_odom), so tests and the demo get exact ground truth.
//
// Determinism: all randomness comes from partslam::Rng (std::mt19937_64 words, own uniform / Box-Muller
// normal), one independent stream per purpose (plan, route, clutter, laser, odometry): the same config
// gives bit-identical logs, and e.g. range_sigma = 0 gives the same building and path as the default.
#pragma once

#include <cstdint>
#include <numbers>
#include <vector>

#include "core/sim/floor_plan.h"
#include "core/sim/ray_caster.h"
#include "core/maps/scan.h"

namespace partslam {

struct RouteConfig {
  int laps = 2;               ///< passes around the corridor loop(s); places are revisited from the 2nd on
  int room_visits = 4;        ///< rooms entered (and left through the same door) during the first lap
  double scan_spacing = 0.1;  ///< max travel between consecutive scans [m]
  double turn_spacing = 0.1;  ///< max rotation between consecutive scans when turning on the spot [rad]
  double speed = 0.5;         ///< forward speed, sets the timestamps [m/s]
  double turn_rate = 0.5;     ///< rotation speed on the spot, sets the timestamps [rad/s]
  double start_time = 0.0;    ///< timestamp of the first scan [s]
  double clearance = 0.6;     ///< min distance from the path to any clutter box [m]
};

struct LaserSimConfig {
  int num_beams = 181;                      ///< beams evenly spread from -fov/2 to +fov/2
  double field_of_view = std::numbers::pi;  ///< [rad]
  double max_range = 30.0;                  ///< beams without a return closer than this are dropped [m]
  double range_sigma = 0.01;                ///< standard deviation of the Gaussian range noise [m]
};

/// Odometry increments are corrupted per scan step, scaled with the step so that the drift does not
/// depend on scan_spacing: a random walk in position and heading plus systematic scale and heading errors.
struct OdometryNoiseConfig {
  double translation_sigma = 0.01;  ///< per-axis position noise [m / sqrt(m travelled)]
  double heading_sigma = 0.002;     ///< heading random walk while driving [rad / sqrt(m travelled)]
  double turn_sigma = 0.01;         ///< heading noise while turning [rad / sqrt(rad turned)]
  double scale_error = 0.005;       ///< systematic relative error of the travelled distance [-]
  double heading_bias = 0.0005;     ///< systematic heading drift while driving [rad / m travelled]
};

struct SimulatorConfig {
  std::uint64_t seed = 1;  ///< everything random is drawn from this seed
  FloorPlanConfig building;
  RouteConfig route;
  LaserSimConfig laser;
  OdometryNoiseConfig odometry;
};

/// Throws InputError naming the offending field (e.g. "laser.max_range").
void validate(const SimulatorConfig& config);

struct SimulatedLog {
  FloorPlan plan;          ///< the building; plan.walls are exactly what the laser sees [m]
  std::vector<Vec2> path;  ///< waypoints the robot drives through, in order (straight legs) [m]
  Scans scans;             ///< T_world_laser exact, T_world_odom drifting, timestamps increasing
};

/// Runs the whole simulation (well under a second for the default config).
SimulatedLog simulate(const SimulatorConfig& config = {});

/// Angle of beam i in the laser frame [rad]: -fov/2 + i * fov / (num_beams - 1).
double beam_angle(const LaserSimConfig& laser, int i);

/// Noise-free range of every beam of a laser at T_world_laser [m]; +infinity where nothing is hit within
/// max_range.
std::vector<double> beam_ranges(const RayCaster& caster, const Pose2& T_world_laser,
                                const LaserSimConfig& laser);

}  // namespace partslam
