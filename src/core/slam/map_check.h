// A check of a finished map by evidence that did not build it (docs/NOTES.md "Map check"): the beams of one
// visit that pass through walls another visit of the same place saw. In a right map a beam stops at the first
// wall on its way, whichever visit saw that wall; where a wing is drawn twice, turned or shifted, the beams of one
// visit cross the walls of the other. Loop closures and the front end only ever compare a scan with its
// neighbours in the graph; this reads every beam against the whole map.
//
// Scans are taken every key_spacing of travel; a visit is a stretch of min_gap of travel, and a scan's own visit
// is its stretch and the two beside it. A beam crosses another visit's wall when a cell on its way from the laser
// to end_margin short of its endpoint holds at least min_hits endpoints, some from another visit and none from
// its own (a beam grazing a wall its own visit saw too is not a crossing). A beam revisits a place when it crosses
// such a wall or its endpoint lands next to a cell another visit hit. The share of crossing beams among the
// revisiting ones is the check's figure, over the whole map and per place (a square of place_size where the robot
// was): a map whose share exceeds max_crossing_share, or max_place_share at any place, is flagged. A log that
// never comes back has nothing to disagree with and is not judged.
#pragma once

#include <cstddef>
#include <vector>

#include "core/maps/scan.h"
#include "core/types.h"

namespace partslam {

struct MapCheckConfig {
  double resolution = 0.1;        ///< grid cell [m] (coarsened when the map would exceed 2^24 cells)
  double max_range = 8.0;         ///< beams longer than this are not cast [m]
  double key_spacing = 0.25;      ///< a scan every this much travel is read [m]
  double min_gap = 20.0;          ///< scans this much travel apart are different visits [m]
  double end_margin = 0.3;        ///< the last stretch of a beam before its endpoint is not read [m]
  int min_hits = 2;               ///< endpoints that make a cell a wall
  int own_cells = 1;              ///< a wall with an endpoint of the beam's own visit this near is its own [cells]
  double place_size = 5.0;        ///< side of the squares the robot's places are counted in [m]
  int min_place_beams = 1000;     ///< a place with fewer revisiting beams is not judged on its own
  /// Limits: about twice the largest shares a right map of the tuning split shows (aces raw: 10.4 % overall,
  /// 36.9 % at a place; docs/NOTES.md "SLAM on real raw logs"), the overall one raised to 30 % because people
  /// and glass alone give a right map of fhw 24 %.
  double max_crossing_share = 0.3;   ///< a larger share of all revisiting beams through walls fails the check
  double max_place_share = 0.75;     ///< so does a larger share at any one place (min_place_beams or more)
  int min_revisiting_beams = 2000;  ///< fewer revisiting beams than this: too little to judge
};

/// Throws InputError naming the offending field.
void validate(const MapCheckConfig& config);

struct MapCheck {
  std::size_t scans = 0;            ///< scans read (one per key_spacing of travel)
  std::size_t beams = 0;            ///< beams cast
  std::size_t revisiting_beams = 0; ///< beams that cross another visit's wall or end next to its endpoints
  std::size_t crossing_beams = 0;   ///< beams that cross another visit's wall
  double crossing_share = 0.0;      ///< crossing_beams / revisiting_beams (0 when there are none)
  /// Per square of place_size where the robot was: its centre, revisiting and crossing beams cast from there.
  struct Place {
    Vec2 centre;
    std::size_t revisiting = 0, crossing = 0;
  };
  std::vector<Place> places;
  /// The place (with at least min_place_beams revisiting beams) of the largest crossing share [m, world frame].
  Vec2 worst_place = Vec2::Zero();
  double worst_place_share = 0.0;
  std::size_t worst_place_crossings = 0;
  bool judged = false;              ///< enough revisiting beams to judge
  bool passed = true;               ///< not judged, or both shares within their limits
};

/// The check over scans in the world frame (T_world_laser), in the order driven.
MapCheck check_map(const Scans& scans, const MapCheckConfig& config = {});

}  // namespace partslam
