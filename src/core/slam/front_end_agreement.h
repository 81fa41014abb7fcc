// A second opinion on the front end: the same log scan-matched once more with another setting, and the two paths
// compared over windows of travel. Nothing else in the verdict can see a stretch the robot never drives through
// twice: there the map is the front end's chain, the closures do not touch it and the map check has no other visit
// to hold it against. Where the scans fix the path, two settings of the matcher follow the same one (on every clean
// run of the SLAM bench, every window compared, they disagree by at most 5.4 degrees and 1.28 m over 30 m of
// travel); where they do not (the Freiburg hospital's corridor with people walking ahead), the two part by tens of
// degrees. At least one of them is then wrong, and nothing that built the map says which, so the result is not
// vouched for (docs/NOTES.md, "A second front end as a witness"). Where a used loop closure attaches within a
// window, the map there does not rest on the front end alone (the loops and the map check judge it), and the
// window is not judged: on intel's log with its laser 0.1 s late both front ends turn 25-80 degrees wrong while the
// robot spins on the spot, and the closures attached there put the map right (0.023 m).
#pragma once

#include <cstddef>
#include <vector>

#include "core/maps/scan.h"

namespace partslam {

struct SecondOpinionConfig {
  bool enabled = true;
  /// The second front end's FrontEndConfig::fine_sigma; every other front-end setting is the first's [m].
  double fine_sigma = 0.03;
  double window = 30.0;     ///< travel (along the first path) over which the two relative poses are compared [m]
  double max_turn = 0.26;   ///< a window whose two relative headings differ by more fails [rad] (about 15 deg)
  double max_shift = 3.0;   ///< so does one whose two relative positions lie farther apart [m]
};

/// Throws InputError naming the offending field.
void validate(const SecondOpinionConfig& config);

struct FrontEndAgreement {
  bool judged = false;     ///< at least one window of travel was compared
  std::size_t paired = 0;  ///< scans both front ends kept (matched by their timestamps)
  std::size_t windows = 0; ///< windows compared (one starting at each paired scan, not pinned)
  std::size_t pinned = 0;  ///< windows not compared: a loop closure attaches within them (see compare_front_ends)
  double max_turn = 0;     ///< the largest difference of the two relative headings over a window compared [rad]
  double max_shift = 0;    ///< the largest distance between the two relative positions over a window compared [m]
  /// The window nearest to its limits (the largest of turn / max_turn and shift / max_shift): its first and last
  /// scan, as indices into the first front end's scans.
  std::size_t worst_first = 0, worst_last = 0;
  bool passed = true;      ///< no window beyond max_turn or max_shift (true when nothing was judged)
};

/// Compares two front ends' results of one log (`first`, `second`: the scans each kept, in log order, their
/// T_world_laser the scan-matched poses). Scans are paired by timestamp; a timestamp that is not unique in either
/// is left out. For each paired scan i, the window runs to the first paired scan j at least `window` of the first
/// path's travel later; the two paths' relative poses T_i^-1 T_j are compared. `pins`: indices into `first` of the
/// scans where used loop closures attach (their submaps' anchor scans); a window holding a pin (paired scans i to j)
/// is pinned and not compared.
FrontEndAgreement compare_front_ends(const Scans& first, const Scans& second, const SecondOpinionConfig& config,
                                     const std::vector<std::size_t>& pins = {});

}  // namespace partslam
