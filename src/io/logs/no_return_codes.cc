#include "io/logs/no_return_codes.h"

#include <algorithm>
#include <cmath>

namespace partslam::io {

std::vector<double> find_no_return_codes(const Scans& scans, const LogReadOptions& options) {
  std::vector<double> codes;
  if (options.no_return_code_share <= 0.0) return codes;
  // 1 cm bins from min_range up to no_return_range (the farthest a kept beam can be).
  const double lo = options.no_return_code_min_range;
  const double hi = std::max(lo, std::min(options.max_usable_range, options.no_return_range));
  const auto bins = static_cast<std::size_t>(std::ceil((hi - lo) * 100.0)) + 1;
  std::vector<std::size_t> count(bins, 0);
  std::size_t beams = 0;
  for (const Scan& s : scans) {
    beams += s.points_laser.size();
    for (const Vec2& p : s.points_laser) {
      const double r = p.norm();
      if (r < lo || r >= hi + 0.01) continue;
      ++count[std::min(bins - 1, static_cast<std::size_t>(std::lround((r - lo) * 100.0)))];
    }
  }
  const double least = options.no_return_code_share * static_cast<double>(beams);
  for (std::size_t b = 0; b < bins; ++b)
    if (count[b] > 0 && static_cast<double>(count[b]) >= least) codes.push_back(lo + 0.01 * static_cast<double>(b));
  return codes;
}

std::size_t drop_no_return_codes(Scans& scans, const std::vector<double>& codes) {
  if (codes.empty()) return 0;
  const double beyond = codes.back() - kNoReturnCodeWindow;
  const auto is_code = [&](const Vec2& p) {
    const double r = p.norm();
    if (r >= beyond) return true;
    return std::any_of(codes.begin(), codes.end(), [r](double c) { return std::abs(r - c) <= kNoReturnCodeWindow; });
  };
  std::size_t dropped = 0;
  for (Scan& s : scans) {
    const auto end = std::remove_if(s.points_laser.begin(), s.points_laser.end(), is_code);
    dropped += static_cast<std::size_t>(s.points_laser.end() - end);
    s.points_laser.erase(end, s.points_laser.end());
  }
  return dropped;
}

}  // namespace partslam::io
