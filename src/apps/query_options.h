// Shared by `partslam match` and `locate`: where a new local map comes from. Either a log (CARMEN, ROS bag,
// sim[:SEED]) and a stretch of it, or a point file (--query-points FILE.ply|csv, in any frame). A stretch is given
// either by travel along the log's own poses (--from-m M --to-m M, or --at-m M for one window from there; --from /
// --to are the old names of --from-m / --to-m) or by the log's clock (--from-time T --to-time T, or --at T for one
// window from the first scan at or after T). The log's clock is each scan's own timestamp as the file stores it
// (CARMEN: the message's ipc_timestamp; a bag: the LaserScan header stamp), in seconds, not seconds since the first
// scan; the converted benchmark bags are re-timed, so their clock is not the .clf's. Either way the local map is
// built as stored maps are (the submap settings given), so it can be ranked against them or located in a building
// map. With --scan-match only the stretch and a margin of travel before it are scan-matched. The stretch, its scan
// matching and its local map are the library's (core/slam/log_stretch.h); this file reads the options and the log.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <optional>
#include <string>

#include "core/maps/submap.h"
#include "core/slam/front_end_config.h"
#include "core/slam/log_stretch.h"
#include "io/logs/log_read_options.h"

namespace partslam::apps {

struct QueryOptions {
  std::string log;     ///< --query-log
  std::string points;  ///< --query-points
  StretchSpec stretch;  ///< --from-m, --to-m, --at-m, --from-time, --to-time, --at
  bool scan_match = false;
  io::LogReadOptions read;  ///< reading --query-log (--skip-damaged)
  bool offers_every = false;  ///< locate: --every M may stand in for a stretch (named in the error)

  bool given() const { return !log.empty() || !points.empty(); }
};

/// --query-log, --query-points, --from-m/--from, --to-m/--to, --at-m, --from-time, --to-time, --at, --scan-match,
/// --skip-damaged on `cmd`.
void add_query_options(CLI::App& cmd, QueryOptions& query);

/// Checks the combination before any work: exactly one source, and exactly one kind of stretch for a log
/// (every_given: --every stands in for it). Throws InputError naming the options.
void check_query_options(const QueryOptions& query, bool every_given = false);

/// The log of --query-log as the query uses it: its stretch, and the reader's warnings (a recording cut short,
/// damage skipped), also printed.
struct QueryLog : LogStretch {
  std::vector<std::string> warnings;
};

/// Loads the log named by --query-log and finds the stretch given (none for --every: the whole log) with
/// find_log_stretch; with --scan-match the poses come from `front_end`. `window` is the travel a one-window stretch
/// (--at, --at-m) covers. Throws InputError naming the options and the log's span for a stretch outside the log.
QueryLog load_query_log(const QueryOptions& query, const FrontEndConfig& front_end, double window);

/// The local map of the stretch of `log` (from --query-log), or of the point file; `label` gets a one-line
/// description (travel, log time and scans of a stretch). Throws InputError naming the file for a bad point file
/// or too few points.
Submap build_query(const QueryOptions& query, const QueryLog& log, const SubmapConfig& config, std::string& label);

}  // namespace partslam::apps
