// Shared by `partslam match` and `locate`: where a new local map comes from. Either a log (CARMEN, ROS bag,
// sim[:SEED]) and a stretch of it, or a point file (--query-points FILE.ply|csv, in any frame). A stretch is given
// either by travel along the log's own poses (--from-m M --to-m M, or --at-m M for one window from there; --from /
// --to are the old names of --from-m / --to-m) or by the log's clock (--from-time T --to-time T, or --at T for one
// window from the first scan at or after T). The log's clock is each scan's own timestamp as the file stores it
// (CARMEN: the message's ipc_timestamp; a bag: the LaserScan header stamp), in seconds, not seconds since the first
// scan; the converted benchmark bags are re-timed, so their clock is not the .clf's. Either way the local map is
// built as stored maps are (the submap settings given), so it can be ranked against them or located in a building
// map. With --scan-match only the stretch and a margin of travel before it are scan-matched.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <optional>
#include <string>

#include "core/maps/submap.h"
#include "core/slam/front_end.h"
#include "io/log_read_options.h"

namespace partslam::apps {

/// With --scan-match and a stretch, the front end starts this much travel (along the log's own poses) before the
/// stretch, so its local map (30 key scans 0.2 m apart) is full when the stretch begins [m].
inline constexpr double kScanMatchMargin = 10.0;

struct QueryOptions {
  std::string log;     ///< --query-log
  std::string points;  ///< --query-points
  std::optional<double> from_m, to_m, at_m;           ///< travel along the log's own poses [m]
  std::optional<double> from_time, to_time, at_time;  ///< the log's clock [s]
  bool scan_match = false;
  io::LogReadOptions read;  ///< reading --query-log (--skip-damaged)
  bool offers_every = false;  ///< locate: --every M may stand in for a stretch (named in the error)

  bool given() const { return !log.empty() || !points.empty(); }
  bool stretch_given() const { return from_m || to_m || at_m || from_time || to_time || at_time; }
};

/// --query-log, --query-points, --from-m/--from, --to-m/--to, --at-m, --from-time, --to-time, --at, --scan-match,
/// --skip-damaged on `cmd`.
void add_query_options(CLI::App& cmd, QueryOptions& query);

/// Checks the combination before any work: exactly one source, and exactly one kind of stretch for a log
/// (every_given: --every stands in for it). Throws InputError naming the options.
void check_query_options(const QueryOptions& query, bool every_given = false);

/// The log of --query-log as the query uses it.
struct QueryLog {
  Scans scans;  ///< the log's scans; with --scan-match and a stretch, only the margin and the stretch, scan-matched
  bool stretch = false;            ///< a stretch was given (first, end are set)
  std::size_t first = 0, end = 0;  ///< the stretch: scans[first, end)
  double from_m = 0, to_m = 0;     ///< its travel window along the log's own poses, as asked (time range: its scans') [m]
  double from_time = 0, to_time = 0;  ///< the log time of its first and last scan [s]
  std::size_t log_scans = 0;       ///< scans in the whole log
  std::size_t matched_scans = 0;   ///< scans the front end ran over (--scan-match)
  double match_ms = 0;             ///< its time [ms]
  std::vector<std::string> warnings;  ///< the reader's (a recording cut short, damage skipped), also printed
};

/// Loads the log named by --query-log and finds the stretch given (none for --every: the whole log). With
/// --scan-match the poses come from `front_end`: over the stretch and kScanMatchMargin of travel before it when a
/// stretch is given, else over the whole log. `window` is the travel a one-window stretch (--at, --at-m) covers.
/// Throws InputError naming the options and the log's span for a stretch outside the log.
QueryLog load_query_log(const QueryOptions& query, const FrontEndConfig& front_end, double window);

/// The local map of the stretch of `log` (from --query-log), or of the point file; `label` gets a one-line
/// description (travel, log time and scans of a stretch). Throws InputError naming the file for a bad point file
/// or too few points.
Submap build_query(const QueryOptions& query, const QueryLog& log, const SubmapConfig& config, std::string& label);

}  // namespace partslam::apps
