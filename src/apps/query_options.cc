// Tested by: apps/cli_eval_test.cc, apps/cli_locate_test.cc

#include "apps/query_options.h"

#include "apps/log_inputs.h"

#include <cstdio>

#include "core/error.h"
#include "io/formats/point_export.h"
#include "io/logs/scan_source.h"
#include "apps/scan_input.h"

namespace partslam::apps {

void add_query_options(CLI::App& cmd, QueryOptions& q) {
  cmd.add_option("--query-log", q.log,
                 "a log to build a new local map from, as the stored maps were built: " + kLogInputs);
  cmd.add_option("--query-points", q.points,
                 "a point file (.ply or .csv, any frame; one written by 'partslam export' in either frame) to use "
                 "as the local map");
  cmd.add_option("--from-m,--from", q.stretch.from_m,
                 "--query-log: travel along the log's own poses (odometry for a raw log, also with --scan-match) "
                 "where the local map starts [m]");
  cmd.add_option("--to-m,--to", q.stretch.to_m, "--query-log: travel along the log's own poses where it ends [m]");
  cmd.add_option("--at-m", q.stretch.at_m,
                 "--query-log: one window of travel (--window) from this travel along the log [m]");
  cmd.add_option("--from-time", q.stretch.from_time,
                 "--query-log: the local map holds the scans stamped from this log time on [s]; the log's clock is "
                 "each scan's own timestamp (CARMEN ipc_timestamp, a bag's LaserScan header stamp), not seconds "
                 "since the first scan");
  cmd.add_option("--to-time", q.stretch.to_time, "--query-log: ... and stamped before this log time [s]");
  cmd.add_option("--at,--at-time", q.stretch.at_time,
                 "--query-log: one window of travel from the first scan stamped at or after this log time [s] "
                 "(the log's clock, as --from-time)");
  cmd.add_flag("--scan-match", q.scan_match,
               "--query-log: poses from scan matching (raw logs); only the stretch and 10 m of travel before it are "
               "scan-matched");
  add_log_read_options(cmd, q.read);
}

void check_query_options(const QueryOptions& q, bool every_given) {
  if (!q.log.empty() && !q.points.empty()) throw InputError("give either --query-log or --query-points, not both");
  if (!q.points.empty() && (q.stretch.given() || q.scan_match))
    throw InputError("--from-m, --to-m, --at-m, --from-time, --to-time, --at and --scan-match go with --query-log, "
                     "not --query-points");
  if (q.log.empty()) return;
  validate(q.stretch, every_given,
           q.offers_every ? "--every M (a local map every M of travel along the whole log)" : "");
}

QueryLog load_query_log(const QueryOptions& q, const FrontEndConfig& front_end, double window) {
  io::ScanSource source = load_scans(q.log, q.read);
  QueryLog out;
  static_cast<LogStretch&>(out) = find_log_stretch(std::move(source.scans), q.stretch, window,
                                                   q.scan_match ? std::optional(front_end) : std::nullopt, q.log);
  out.warnings = std::move(source.warnings);
  return out;
}

Submap build_query(const QueryOptions& q, const QueryLog& log, const SubmapConfig& config, std::string& label) {
  char text[400];
  if (!q.points.empty()) {
    const io::PointFile file = io::read_point_file(q.points);
    // A file that names its frame's pose (partslam export --frame map) is taken back into that world frame, so the
    // local map is built exactly as from the world-frame file (cells of the same grid).
    const auto world = [&](const Points2& xs) {
      return file.T_world_points ? transform(*file.T_world_points, xs) : xs;
    };
    const Submap m = local_map_from_points(world(file.points), config, world(file.laser_origins));
    std::snprintf(text, sizeof text, "local map of %s (%zu points%s%s)", q.points.c_str(), m.points.size(),
                  m.origins.empty() ? "" : ", with its laser origins",
                  file.T_world_points ? ", taken into the world frame its header names" : "");
    label = text;
    return m;
  }
  const Submap m = stretch_local_map(log, config, q.log);
  std::snprintf(text, sizeof text,
                "local map of %s (%.1f .. %.1f m of travel, log time %.3f .. %.3f s, %zu scans, %zu points%s)",
                q.log.c_str(), log.from_m, log.to_m, log.from_time, log.to_time, log.end - log.first,
                m.points.size(), q.scan_match ? ", scan-matched" : "");
  label = text;
  if (q.scan_match) {
    std::snprintf(text, sizeof text, "; the front end ran over %zu of the log's %zu scans in %.0f ms",
                  log.matched_scans, log.log_scans, log.match_ms);
    label += text;
  }
  return m;
}

}  // namespace partslam::apps
