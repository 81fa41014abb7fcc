// Shared by `partslam match` and `locate`: where a new local map comes from. Either a log (CARMEN, ROS bag,
// sim[:SEED]) and a stretch of it (--from M --to M of travel, or --at TIME for one window from that scan on), or
// a point file (--query-points FILE.ply|csv, in any frame). Either way the local map is built as stored maps are
// (the submap settings given), so it can be ranked against them or located in a building map.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "core/maps/submap.h"
#include "core/slam/front_end.h"
#include "io/carmen_log.h"

namespace partslam::apps {

struct QueryOptions {
  std::string log;     ///< --query-log
  std::string points;  ///< --query-points
  double from = -1, to = -1, at = -1;
  bool scan_match = false;
  io::LogReadOptions read;  ///< reading --query-log (--skip-damaged)

  bool given() const { return !log.empty() || !points.empty(); }
};

/// --query-log, --query-points, --from, --to, --at, --scan-match, --skip-damaged on `cmd`.
void add_query_options(CLI::App& cmd, QueryOptions& query);

/// Checks the combination before any work: exactly one source, and a stretch for a log (with_every: --every
/// may stand in for --from/--to). Throws InputError.
void check_query_options(const QueryOptions& query, bool with_every = false);

/// Loads the log named by --query-log (scan-matched with `front_end` when --scan-match).
Scans load_query_scans(const QueryOptions& query, const FrontEndConfig& front_end);

/// The local map of the options' stretch of `scans` (from --query-log), or of the point file; `label` gets a
/// one-line description. Throws InputError naming the file for a bad point file or an empty stretch.
Submap build_query(const QueryOptions& query, const Scans& scans, const SubmapConfig& config, std::string& label);

}  // namespace partslam::apps
