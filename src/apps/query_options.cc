#include "apps/query_options.h"

#include "apps/log_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/timing.h"
#include "io/point_export.h"
#include "io/scan_source.h"
#include "apps/scan_input.h"

namespace partslam::apps {

namespace {

constexpr const char* kStretchChoices =
    "--from-m M --to-m M or --at-m M (travel along the log), or --from-time T --to-time T or --at T (the log's "
    "clock: the scans' own timestamps [s])";

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

void check_finite(const std::optional<double>& v, const char* name) {
  if (v && !std::isfinite(*v)) throw InputError(std::string(name) + " must be a finite number, got " + number(*v));
}

// The first scan at or after index `from` whose key is >= value (keys ascending, or not: the first such scan).
std::size_t first_at_or_after(const std::vector<double>& keys, double value, std::size_t from = 0) {
  std::size_t i = from;
  while (i < keys.size() && keys[i] < value) ++i;
  return i;
}

std::string travel_span(const std::vector<double>& s) {
  return "the log covers 0 .. " + number(s.empty() ? 0.0 : s.back()) + " m of travel";
}

std::string time_span(const Scans& scans) {
  if (scans.empty()) return "the log has no scan";
  return "the log's scans are stamped " + number(scans.front().timestamp) + " .. " + number(scans.back().timestamp) +
         " s";
}

}  // namespace

void add_query_options(CLI::App& cmd, QueryOptions& q) {
  cmd.add_option("--query-log", q.log,
                 "a log to build a new local map from, as the stored maps were built: " + kLogInputs);
  cmd.add_option("--query-points", q.points,
                 "a point file (.ply or .csv, any frame; one written by 'partslam export' in either frame) to use "
                 "as the local map");
  cmd.add_option("--from-m,--from", q.from_m,
                 "--query-log: travel along the log's own poses (odometry for a raw log, also with --scan-match) "
                 "where the local map starts [m]");
  cmd.add_option("--to-m,--to", q.to_m, "--query-log: travel along the log's own poses where it ends [m]");
  cmd.add_option("--at-m", q.at_m, "--query-log: one window of travel (--window) from this travel along the log [m]");
  cmd.add_option("--from-time", q.from_time,
                 "--query-log: the local map holds the scans stamped from this log time on [s]; the log's clock is "
                 "each scan's own timestamp (CARMEN ipc_timestamp, a bag's LaserScan header stamp), not seconds "
                 "since the first scan");
  cmd.add_option("--to-time", q.to_time, "--query-log: ... and stamped before this log time [s]");
  cmd.add_option("--at,--at-time", q.at_time,
                 "--query-log: one window of travel from the first scan stamped at or after this log time [s] "
                 "(the log's clock, as --from-time)");
  cmd.add_flag("--scan-match", q.scan_match,
               "--query-log: poses from scan matching (raw logs); only the stretch and 10 m of travel before it are "
               "scan-matched");
  add_log_read_options(cmd, q.read);
}

void check_query_options(const QueryOptions& q, bool every_given) {
  if (!q.log.empty() && !q.points.empty()) throw InputError("give either --query-log or --query-points, not both");
  if (!q.points.empty() && (q.stretch_given() || q.scan_match))
    throw InputError("--from-m, --to-m, --at-m, --from-time, --to-time, --at and --scan-match go with --query-log, "
                     "not --query-points");
  if (q.log.empty()) return;
  check_finite(q.from_m, "--from-m");
  check_finite(q.to_m, "--to-m");
  check_finite(q.at_m, "--at-m");
  check_finite(q.from_time, "--from-time");
  check_finite(q.to_time, "--to-time");
  check_finite(q.at_time, "--at");
  if (q.from_m.has_value() != q.to_m.has_value()) throw InputError("--from-m and --to-m go together");
  if (q.from_time.has_value() != q.to_time.has_value()) throw InputError("--from-time and --to-time go together");
  const int kinds = (q.from_m ? 1 : 0) + (q.at_m ? 1 : 0) + (q.from_time ? 1 : 0) + (q.at_time ? 1 : 0);
  if (kinds > 1) throw InputError(std::string("give one stretch of the log: ") + kStretchChoices);
  if (q.from_m && !(*q.from_m >= 0 && *q.to_m > *q.from_m))
    throw InputError("--from-m and --to-m: need 0 <= from < to [m of travel], got " + number(*q.from_m) + " .. " +
                     number(*q.to_m));
  if (q.at_m && !(*q.at_m >= 0)) throw InputError("--at-m must be >= 0 [m of travel], got " + number(*q.at_m));
  if (q.from_time && !(*q.to_time > *q.from_time))
    throw InputError("--from-time and --to-time: need from < to [s of log time], got " + number(*q.from_time) +
                     " .. " + number(*q.to_time));
  if (kinds == 0 && !every_given)
    throw InputError(std::string("--query-log needs a stretch: ") + kStretchChoices +
                     (q.offers_every ? ", or --every M (a local map every M of travel along the whole log)" : ""));
}

namespace {

// A stretch of the log: scans[first, end) and its travel window along the log's own poses, as asked (a time range:
// its scans' travel).
struct Stretch {
  std::size_t first = 0, end = 0;
  double from_m = 0, to_m = 0;
};

// The stretch the options give, on the log's own poses (travel s) and clock (stamps t). Throws InputError naming
// the options and the log's span when it holds no scan.
Stretch find_stretch(const QueryOptions& q, const Scans& scans, const std::vector<double>& s,
                     const std::vector<double>& t, double window) {
  Stretch r;
  if (q.from_m || q.at_m) {
    const double from = q.from_m ? *q.from_m : *q.at_m, to = q.from_m ? *q.to_m : *q.at_m + window;
    r.from_m = from, r.to_m = to;
    r.first = first_at_or_after(s, from);
    r.end = first_at_or_after(s, to, r.first);
    if (r.first == r.end)
      throw InputError(q.log + ": no scan between " + number(from) + " and " + number(to) + " m of travel (" +
                       (q.from_m ? "--from-m/--to-m" : "--at-m") + "; " + travel_span(s) + ")");
  } else if (q.from_time) {
    if (!t.empty() && *q.from_time < t.front() - 1.0)
      throw InputError(q.log + ": --from-time " + number(*q.from_time) + " s lies before the log's first scan (the "
                       "log's clock; " + time_span(scans) + ")");
    r.first = first_at_or_after(t, *q.from_time);
    r.end = r.first;
    while (r.end < scans.size() && t[r.end] < *q.to_time) ++r.end;
    if (r.first != r.end) r.from_m = s[r.first], r.to_m = s[r.end - 1];
    if (r.first == r.end)
      throw InputError(q.log + ": no scan stamped in [" + number(*q.from_time) + ", " + number(*q.to_time) +
                       ") s (--from-time/--to-time, the log's clock; " + time_span(scans) + ")");
  } else {
    r.first = first_at_or_after(t, *q.at_time);
    if (!t.empty() && *q.at_time < t.front() - 1.0)  // not "seconds since the first scan": the log's own clock
      throw InputError(q.log + ": --at " + number(*q.at_time) + " s lies before the log's first scan (--at, the log's "
                       "clock; " + time_span(scans) + ")");
    if (r.first == scans.size())
      throw InputError(q.log + ": no scan stamped at or after " + number(*q.at_time) + " s (--at, the log's clock; " +
                       time_span(scans) + ")");
    r.end = first_at_or_after(s, s[r.first] + window, r.first);
    r.from_m = s[r.first], r.to_m = s[r.first] + window;
  }
  return r;
}

// --scan-match with a stretch: the front end over the margin before the stretch and the stretch only, not the
// whole log; out.scans, first, end and the front end's figures are set.
void scan_match_stretch(const QueryOptions& q, const Scans& scans, const std::vector<double>& s, const Stretch& r,
                        const FrontEndConfig& front_end, QueryLog& out) {
  const std::size_t start = first_at_or_after(s, s[r.first] - kScanMatchMargin);
  const Scans part(scans.begin() + static_cast<std::ptrdiff_t>(start),
                   scans.begin() + static_cast<std::ptrdiff_t>(r.end));
  const auto t0 = Clock::now();
  FrontEndResult matched = scan_match_log(part, front_end);
  out.match_ms = ms_since(t0);
  out.matched_scans = part.size();
  out.scans = std::move(matched.scans);
  if (out.scans.size() == part.size()) {
    out.first = r.first - start, out.end = r.end - start;
    return;
  }
  // The front end dropped scans whose time went backwards: find the stretch by its scans' stamps.
  std::size_t i = 0;
  while (i < out.scans.size() && out.scans[i].timestamp < out.from_time) ++i;
  std::size_t j = i;
  while (j < out.scans.size() && out.scans[j].timestamp <= out.to_time) ++j;
  if (i == j) throw InputError(q.log + ": --scan-match dropped every scan of the stretch (time going backwards)");
  out.first = i, out.end = j;
}

}  // namespace

QueryLog load_query_log(const QueryOptions& q, const FrontEndConfig& front_end, double window) {
  QueryLog out;
  io::ScanSource source = load_scans(q.log, q.read);
  out.warnings = source.warnings;
  Scans scans = std::move(source.scans);
  out.log_scans = scans.size();
  if (!q.stretch_given()) {  // --every: the whole log
    if (q.scan_match) {
      const auto t0 = Clock::now();
      scans = scan_match_log(scans, front_end).scans;
      out.match_ms = ms_since(t0);
      out.matched_scans = out.log_scans;
    }
    out.scans = std::move(scans);
    return out;
  }
  // The stretch, on the log's own poses and clock.
  const std::vector<double> s = travel_distances(scans);
  std::vector<double> t(scans.size());
  for (std::size_t i = 0; i < scans.size(); ++i) t[i] = scans[i].timestamp;
  const Stretch r = find_stretch(q, scans, s, t, window);
  out.stretch = true;
  out.from_m = r.from_m, out.to_m = r.to_m;
  out.from_time = t[r.first], out.to_time = t[r.end - 1];
  if (q.scan_match) {
    scan_match_stretch(q, scans, s, r, front_end, out);
  } else {
    out.scans = std::move(scans);
    out.first = r.first, out.end = r.end;
  }
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
  if (!log.stretch) throw InputError("build_query: no stretch of " + q.log + " chosen");
  // The stretch's scans as a log of their own: the local map is built as build_local_map builds one (the travel
  // window covering all of them), then its anchor refers to log.scans again.
  const Scans stretch(log.scans.begin() + static_cast<std::ptrdiff_t>(log.first),
                      log.scans.begin() + static_cast<std::ptrdiff_t>(log.end));
  const std::vector<double> s = travel_distances(stretch);
  Submap m = build_local_map(stretch, 0.0, s.back() + 1.0, config);
  m.anchor_scan += static_cast<std::int64_t>(log.first);
  m.travel = log.from_m;
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
