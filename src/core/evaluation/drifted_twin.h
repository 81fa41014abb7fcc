// Drifted twins of a corrected log, and the relations that judge a SLAM run on them (docs/NOTES.md, "SLAM bench").
//
// A corrected log's scans are real, and its poses are as good a truth as there is. Its drifted twin keeps the
// scans and replaces the poses by synthetic odometry: the true trajectory's increments, each corrupted by a
// per-run scale error, a heading bias per metre travelled, Gaussian noise growing with the increment, and now and
// then a slip (a jump of heading and position, as a wheel spinning on a threshold). The twin is a raw log
// (odometry in both pose fields); the corrected poses are its ground truth.
//
// Its relations are those of the Freiburg benchmark (Kuemmerle et al. 2009) built from the truth: every scan
// paired with the scans a fixed travel further on, plus every revisit (scans of the same place, true positions
// within revisit_radius, at least revisit_gap of travel apart), on a thinned set of scans so the count stays
// bounded. The metric is relations_error (trajectory_check.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/evaluation/relation_check.h"
#include "core/maps/scan.h"

namespace partslam {

struct OdometryNoise {
  double scale_error = 0.0;        ///< per run, drawn uniformly in +-this: travel is (1 + e) times the truth
  double heading_bias = 0.0;       ///< per run, drawn uniformly in +-this: heading error per metre [rad/m]
  double translation_noise = 0.0;  ///< sigma of each increment's x and y, times sqrt(its length in m) [m]
  double rotation_noise = 0.0;     ///< sigma of each increment's turn, times sqrt(its length in m) [rad]
  double slips_per_km = 0.0;       ///< mean rate of slips along the travel [1/km]
  double slip_translation = 0.0;   ///< a slip moves the odometry by up to this, uniformly [m]
  double slip_rotation = 0.0;      ///< and turns it by up to this, uniformly in +- [rad]
};

/// The named levels of the SLAM bench: "mild" (a well-calibrated wheeled robot: 1 % scale, 0.3 degrees per
/// metre) and "harsh" (5 % scale, 2 degrees per metre, noisy increments, a 0.3 m / 11 degree slip every 50 m).
/// Throws InputError for another name.
OdometryNoise odometry_noise(const std::string& level);

/// Throws InputError naming the field when a value is negative or not finite.
void validate(const OdometryNoise& noise);

/// The twin: the same scans in order, with T_world_laser = T_world_odom = the corrupted odometry, starting at
/// the first scan's true pose. Deterministic given the seed.
Scans drifted_twin(const Scans& truth, const OdometryNoise& noise, std::uint64_t seed);

struct BenchRelationsConfig {
  std::vector<double> travel_offsets = {1.0, 5.0, 20.0};  ///< a scan is paired with the one this much further [m]
  double spacing = 1.0;         ///< relations start at scans this much travel apart [m]
  double revisit_radius = 1.0;  ///< true positions this close are the same place [m]
  double revisit_gap = 20.0;    ///< of scans at least this much travel apart [m]
  std::size_t max_revisits = 20000;  ///< revisit pairs kept at most (evenly thinned) to bound the count
};

/// Relations (t1, t2, T_1_2) of the true trajectory: fixed travel offsets plus revisits, as described above.
/// Scans are named by timestamp: a scan less than 1 ms from another is never named (relations_error could not
/// tell the two apart). Throws InputError when no relation can be made (too short a log).
Relations bench_relations(const Scans& truth, const BenchRelationsConfig& config = {});

}  // namespace partslam
