#include "apps/query_options.h"

#include <cstdio>

#include "core/error.h"
#include "io/point_export.h"
#include "io/scan_source.h"
#include "apps/scan_input.h"

namespace partslam::apps {

void add_query_options(CLI::App& cmd, QueryOptions& q) {
  cmd.add_option("--query-log", q.log,
                 "a log (CARMEN, ROS bag, sim[:SEED]) to build a new local map from, as the stored maps were built");
  cmd.add_option("--query-points", q.points,
                 "a point file (.ply or .csv, any frame) to use as the local map");
  cmd.add_option("--from", q.from, "--query-log: travel along the log where the local map starts [m]");
  cmd.add_option("--to", q.to, "--query-log: travel along the log where the local map ends [m]");
  cmd.add_option("--at", q.at, "--query-log: the local map starts at the first scan at or after this log time [s]");
  cmd.add_flag("--scan-match", q.scan_match, "--query-log: poses from scan matching (raw logs)");
  add_log_read_options(cmd, q.read);
}

void check_query_options(const QueryOptions& q, bool with_every) {
  if (!q.log.empty() && !q.points.empty()) throw InputError("give either --query-log or --query-points, not both");
  const bool stretch = q.from >= 0 || q.to >= 0 || q.at >= 0;
  if (!q.points.empty() && (stretch || q.scan_match))
    throw InputError("--from, --to, --at and --scan-match go with --query-log, not --query-points");
  if (q.log.empty()) return;
  if (q.at >= 0 && (q.from >= 0 || q.to >= 0)) throw InputError("give either --at TIME or --from M --to M, not both");
  if (q.at < 0 && (q.from < 0) != (q.to < 0)) throw InputError("--from and --to go together");
  if (!stretch && !with_every) throw InputError("--query-log needs --from M --to M (travel along the log) or --at TIME");
}

Scans load_query_scans(const QueryOptions& q, const FrontEndConfig& front_end) {
  Scans scans = load_scans(q.log, q.read).scans;
  if (q.scan_match) scans = scan_match_log(scans, front_end).scans;
  return scans;
}

Submap build_query(const QueryOptions& q, const Scans& scans, const SubmapConfig& config, std::string& label) {
  char text[300];
  if (!q.points.empty()) {
    const Submap m = local_map_from_points(io::read_points(q.points), config);
    std::snprintf(text, sizeof text, "local map of %s (%zu points)", q.points.c_str(), m.points.size());
    label = text;
    return m;
  }
  double from = q.from, to = q.to;
  if (q.at >= 0) {
    const std::vector<double> s = travel_distances(scans);
    std::size_t i = 0;
    while (i < scans.size() && scans[i].timestamp < q.at) ++i;
    if (i == scans.size()) throw InputError(q.log + ": no scan at or after time " + std::to_string(q.at));
    from = s[i], to = s[i] + config.window_length;
  }
  const Submap m = build_local_map(scans, from, to, config);
  std::snprintf(text, sizeof text, "local map of %s (%.1f .. %.1f m of travel, %zu scans, %zu points)", q.log.c_str(),
                from, to, m.scan_timestamps.size(), m.points.size());
  label = text;
  return m;
}

}  // namespace partslam::apps
