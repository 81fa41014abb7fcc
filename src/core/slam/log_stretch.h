// A stretch of a log as the new local map of a query (`partslam match` and `locate`, and Python): found by
// travel along the log's own poses (from_m .. to_m, or one window from at_m) or by the log's clock (from_time
// .. to_time, or one window from the first scan stamped at or after at_time). The log's clock is each scan's
// own timestamp as the file stores it, in seconds, not seconds since the first scan. Optionally scan-matched
// (raw logs): then only the stretch and kScanMatchMargin of travel before it. Its local map is built as
// stored maps are (the submap settings given), so it can be ranked against them or located in a building map.
// The errors name the CLI's options (--from-m, --at, ...), which are these fields.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "core/maps/scan.h"
#include "core/maps/submap.h"
#include "core/slam/front_end_config.h"

namespace partslam {

/// With scan matching, the front end starts this much travel (along the log's own poses) before the stretch,
/// so its local map (30 key scans 0.2 m apart) is full when the stretch begins [m].
inline constexpr double kScanMatchMargin = 10.0;

/// Which stretch: exactly one of from_m (with to_m), at_m, from_time (with to_time) or at_time.
struct StretchSpec {
  std::optional<double> from_m, to_m, at_m;           ///< travel along the log's own poses [m]
  std::optional<double> from_time, to_time, at_time;  ///< the log's clock [s]
  bool given() const { return from_m || to_m || at_m || from_time || to_time || at_time; }
};

/// Throws InputError naming the options for a combination that is not one stretch, or values out of range.
/// every_given: a caller's alternative to a stretch (`locate --every`), named as `every_option` in the error.
void validate(const StretchSpec& spec, bool every_given = false, const std::string& every_option = "");

/// A log's stretch.
struct LogStretch {
  Scans scans;                     ///< the log's scans; scan-matched: only the margin and the stretch
  bool stretch = false;            ///< a stretch was given (first, end are set)
  std::size_t first = 0, end = 0;  ///< the stretch: scans[first, end)
  /// its travel window along the log's own poses, as asked (a time range: its scans') [m]
  double from_m = 0, to_m = 0;
  double from_time = 0, to_time = 0;  ///< the log time of its first and last scan [s]
  std::size_t log_scans = 0;          ///< scans in the whole log
  std::size_t matched_scans = 0;      ///< scans the front end ran over (scan matching)
  double match_ms = 0;                ///< its time [ms]
};

/// The stretch `spec` gives of the log `name` (scans in log order; no stretch given: the whole log). `window`
/// is the travel a one-window stretch (at_m, at_time) covers [m]. With `scan_match` the poses come from the
/// front end: over the stretch and kScanMatchMargin of travel before it, or over the whole log without a
/// stretch. Throws InputError naming the log, the options and the log's span for a stretch that holds no
/// scan.
LogStretch find_log_stretch(Scans scans, const StretchSpec& spec, double window,
                            const std::optional<FrontEndConfig>& scan_match, const std::string& name);

/// The local map of the stretch, built as stored maps are; its anchor_scan indexes stretch.scans and its
/// travel is the stretch's from_m. Throws InputError when no stretch was chosen.
Submap stretch_local_map(const LogStretch& stretch, const SubmapConfig& config, const std::string& name);

}  // namespace partslam
