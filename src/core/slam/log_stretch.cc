#include "core/slam/log_stretch.h"

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/slam/front_end.h"
#include "core/timing.h"

namespace partslam {
namespace {

constexpr const char* kStretchChoices =
    "--from-m M --to-m M or --at-m M (travel along the log), or --from-time T --to-time T or --at T (the "
    "log's "
    "clock: the scans' own timestamps [s])";

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

void check_finite(const std::optional<double>& v, const char* name) {
  if (v && !std::isfinite(*v))
    throw InputError(std::string(name) + " must be a finite number, got " + number(*v));
}

// The first scan at or after index `from` whose key is >= value (keys ascending, or not: the first such
// scan).
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
  return "the log's scans are stamped " + number(scans.front().timestamp) + " .. " +
         number(scans.back().timestamp) + " s";
}

// A stretch of the log: scans[first, end) and its travel window along the log's own poses, as asked (a time
// range: its scans' travel).
struct Stretch {
  std::size_t first = 0, end = 0;
  double from_m = 0, to_m = 0;
};

Stretch by_travel(const StretchSpec& q, const std::vector<double>& s, double window,
                  const std::string& name) {
  Stretch r;
  const double from = q.from_m ? *q.from_m : *q.at_m, to = q.from_m ? *q.to_m : *q.at_m + window;
  r.from_m = from, r.to_m = to;
  r.first = first_at_or_after(s, from);
  r.end = first_at_or_after(s, to, r.first);
  if (r.first == r.end)
    throw InputError(name + ": no scan between " + number(from) + " and " + number(to) + " m of travel (" +
                     (q.from_m ? "--from-m/--to-m" : "--at-m") + "; " + travel_span(s) + ")");
  return r;
}

Stretch by_time_range(const StretchSpec& q, const Scans& scans, const std::vector<double>& s,
                      const std::vector<double>& t, const std::string& name) {
  Stretch r;
  if (!t.empty() && *q.from_time < t.front() - 1.0)
    throw InputError(name + ": --from-time " + number(*q.from_time) +
                     " s lies before the log's first scan (the "
                     "log's clock; " +
                     time_span(scans) + ")");
  r.first = first_at_or_after(t, *q.from_time);
  r.end = r.first;
  while (r.end < scans.size() && t[r.end] < *q.to_time) ++r.end;
  if (r.first != r.end) r.from_m = s[r.first], r.to_m = s[r.end - 1];
  if (r.first == r.end)
    throw InputError(name + ": no scan stamped in [" + number(*q.from_time) + ", " + number(*q.to_time) +
                     ") s (--from-time/--to-time, the log's clock; " + time_span(scans) + ")");
  return r;
}

Stretch by_time_window(const StretchSpec& q, const Scans& scans, const std::vector<double>& s,
                       const std::vector<double>& t, double window, const std::string& name) {
  Stretch r;
  r.first = first_at_or_after(t, *q.at_time);
  if (!t.empty() && *q.at_time < t.front() - 1.0)  // not "seconds since the first scan": the log's own clock
    throw InputError(name + ": --at " + number(*q.at_time) +
                     " s lies before the log's first scan (--at, the log's "
                     "clock; " +
                     time_span(scans) + ")");
  if (r.first == scans.size())
    throw InputError(name + ": no scan stamped at or after " + number(*q.at_time) +
                     " s (--at, the log's clock; " + time_span(scans) + ")");
  r.end = first_at_or_after(s, s[r.first] + window, r.first);
  r.from_m = s[r.first], r.to_m = s[r.first] + window;
  return r;
}

// Scan matching with a stretch: the front end over the margin before the stretch and the stretch only, not
// the whole log; out.scans, first, end and the front end's figures are set.
void scan_match_stretch(const Scans& scans, const std::vector<double>& s, const Stretch& r,
                        const FrontEndConfig& front_end, const std::string& name, LogStretch& out) {
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
  if (i == j)
    throw InputError(name + ": --scan-match dropped every scan of the stretch (time going backwards)");
  out.first = i, out.end = j;
}

}  // namespace

void validate(const StretchSpec& q, bool every_given, const std::string& every_option) {
  check_finite(q.from_m, "--from-m");
  check_finite(q.to_m, "--to-m");
  check_finite(q.at_m, "--at-m");
  check_finite(q.from_time, "--from-time");
  check_finite(q.to_time, "--to-time");
  check_finite(q.at_time, "--at");
  if (q.from_m.has_value() != q.to_m.has_value()) throw InputError("--from-m and --to-m go together");
  if (q.from_time.has_value() != q.to_time.has_value())
    throw InputError("--from-time and --to-time go together");
  const int kinds = (q.from_m ? 1 : 0) + (q.at_m ? 1 : 0) + (q.from_time ? 1 : 0) + (q.at_time ? 1 : 0);
  if (kinds > 1) throw InputError(std::string("give one stretch of the log: ") + kStretchChoices);
  if (q.from_m && !(*q.from_m >= 0 && *q.to_m > *q.from_m))
    throw InputError("--from-m and --to-m: need 0 <= from < to [m of travel], got " + number(*q.from_m) +
                     " .. " + number(*q.to_m));
  if (q.at_m && !(*q.at_m >= 0))
    throw InputError("--at-m must be >= 0 [m of travel], got " + number(*q.at_m));
  if (q.from_time && !(*q.to_time > *q.from_time))
    throw InputError("--from-time and --to-time: need from < to [s of log time], got " +
                     number(*q.from_time) + " .. " + number(*q.to_time));
  if (kinds == 0 && !every_given)
    throw InputError(std::string("--query-log needs a stretch: ") + kStretchChoices +
                     (every_option.empty() ? "" : ", or " + every_option));
}

LogStretch find_log_stretch(Scans scans, const StretchSpec& spec, double window,
                            const std::optional<FrontEndConfig>& scan_match, const std::string& name) {
  LogStretch out;
  out.log_scans = scans.size();
  if (!spec.given()) {  // the whole log
    if (scan_match) {
      const auto t0 = Clock::now();
      scans = scan_match_log(scans, *scan_match).scans;
      out.match_ms = ms_since(t0);
      out.matched_scans = out.log_scans;
    }
    out.scans = std::move(scans);
    return out;
  }
  validate(spec);
  // The stretch, on the log's own poses and clock.
  const std::vector<double> s = travel_distances(scans);
  std::vector<double> t(scans.size());
  for (std::size_t i = 0; i < scans.size(); ++i) t[i] = scans[i].timestamp;
  const Stretch r = spec.from_m || spec.at_m ? by_travel(spec, s, window, name)
                    : spec.from_time         ? by_time_range(spec, scans, s, t, name)
                                             : by_time_window(spec, scans, s, t, window, name);
  out.stretch = true;
  out.from_m = r.from_m, out.to_m = r.to_m;
  out.from_time = t[r.first], out.to_time = t[r.end - 1];
  if (scan_match) {
    scan_match_stretch(scans, s, r, *scan_match, name, out);
  } else {
    out.scans = std::move(scans);
    out.first = r.first, out.end = r.end;
  }
  return out;
}

Submap stretch_local_map(const LogStretch& log, const SubmapConfig& config, const std::string& name) {
  if (!log.stretch) throw InputError("stretch_local_map: no stretch of " + name + " chosen");
  // The stretch's scans as a log of their own: the local map is built as build_local_map builds one (the
  // travel window covering all of them), then its anchor refers to log.scans again.
  const Scans stretch(log.scans.begin() + static_cast<std::ptrdiff_t>(log.first),
                      log.scans.begin() + static_cast<std::ptrdiff_t>(log.end));
  const std::vector<double> s = travel_distances(stretch);
  Submap m = build_local_map(stretch, 0.0, s.back() + 1.0, config);
  m.anchor_scan += static_cast<std::int64_t>(log.first);
  m.travel = log.from_m;
  return m;
}

}  // namespace partslam
