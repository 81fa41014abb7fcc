#include "io/logs/no_return_codes.h"

#include <algorithm>
#include <cmath>

namespace partslam::io {

std::vector<double> find_no_return_codes(const Scans& scans, const LogReadOptions& options) {
  std::vector<double> codes;
  if (options.no_return_code_share <= 0.0) return codes;
  // 1 cm bins from min_range up to the farthest a kept beam can be, at most kNoReturnCodeSpan beyond min_range
  // (the limits may be infinite).
  const double lo = options.no_return_code_min_range;
  const double hi = std::clamp(std::min(options.max_usable_range, options.no_return_range), lo, lo + kNoReturnCodeSpan);
  const auto bins = static_cast<long>(std::ceil((hi - lo) * 100.0)) + 1;
  std::vector<std::size_t> count(static_cast<std::size_t>(bins), 0);
  std::size_t beams = 0;
  for (const Scan& s : scans) {
    beams += s.points_laser.size();
    for (const Vec2& p : s.points_laser) {
      const double r = p.norm();
      if (r < lo || r >= hi + 0.01) continue;
      ++count[static_cast<std::size_t>(std::min(bins - 1, std::lround((r - lo) * 100.0)))];
    }
  }
  const double least = options.no_return_code_share * static_cast<double>(beams);
  const long near = std::lround(kNoReturnCodeWindow * 100.0), around = 5 * near;
  for (long b = 0; b < bins; ++b) {
    const double n = static_cast<double>(count[static_cast<std::size_t>(b)]);
    if (n == 0 || n < least) continue;
    // A code piles up in its bin; a far wall the robot faced for long (a false code) spreads into the bins around.
    double side = 0, side_bins = 0;
    for (long k = std::max(0L, b - around); k <= std::min(bins - 1, b + around); ++k)
      if (std::abs(k - b) > near) side += static_cast<double>(count[static_cast<std::size_t>(k)]), ++side_bins;
    if (n >= kNoReturnCodePeak * side / std::max(side_bins, 1.0)) codes.push_back(lo + 0.01 * static_cast<double>(b));
  }
  return codes;
}

std::size_t drop_no_return_codes(Scans& scans, const std::vector<double>& codes) {
  if (codes.empty()) return 0;
  // The scanner's maximum jitters above its code too: beyond the farthest code, beams go as well when no more than
  // stragglers lie there (a code is the scanner's maximum; real returns beyond it mean it is not).
  std::size_t beyond_count = 0, code_count = 0;
  const double farthest = codes.back() + kNoReturnCodeWindow;
  for (const Scan& s : scans)
    for (const Vec2& p : s.points_laser) {
      const double r = p.norm();
      beyond_count += r > farthest;
      code_count += std::abs(r - codes.back()) <= kNoReturnCodeWindow;
    }
  const bool drop_beyond = static_cast<double>(beyond_count) <= 0.01 * static_cast<double>(code_count);
  const auto is_code = [&](const Vec2& p) {
    const double r = p.norm();
    if (drop_beyond && r > farthest) return true;
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
