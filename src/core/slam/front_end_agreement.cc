#include "core/slam/front_end_agreement.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/error.h"

namespace partslam {

void validate(const SecondOpinionConfig& c) {
  const std::pair<double, const char*> positive[] = {
      {c.fine_sigma, "fine_sigma"}, {c.window, "window"}, {c.max_shift, "max_shift"}};
  for (const auto& [v, name] : positive)
    if (!(v > 0) || !(v <= 1e4))
      throw InputError(std::string("second opinion config: ") + name + " must be in (0, 10000], got " +
                       std::to_string(v));
  if (!(c.max_turn > 0) || !(c.max_turn <= std::numbers::pi))
    throw InputError("second opinion config: max_turn must be in (0, pi] [rad], got " + std::to_string(c.max_turn));
}

FrontEndAgreement compare_front_ends(const Scans& first, const Scans& second, const SecondOpinionConfig& config,
                                     const std::vector<std::size_t>& pins) {
  // Timestamps of `second`, those seen twice marked -1 (left out).
  std::unordered_map<double, long> in_second;
  for (std::size_t k = 0; k < second.size(); ++k) {
    auto [it, fresh] = in_second.emplace(second[k].timestamp, static_cast<long>(k));
    if (!fresh) it->second = -1;
  }
  std::unordered_map<double, int> seen_first;
  for (const Scan& s : first) ++seen_first[s.timestamp];
  std::vector<std::size_t> a, b;  // paired indices into first and second, in first's order
  for (std::size_t k = 0; k < first.size(); ++k) {
    const auto it = in_second.find(first[k].timestamp);
    if (it == in_second.end() || it->second < 0 || seen_first[first[k].timestamp] != 1) continue;
    a.push_back(k);
    b.push_back(static_cast<std::size_t>(it->second));
  }
  FrontEndAgreement out;
  out.paired = a.size();
  std::vector<double> travel(a.size(), 0.0);
  for (std::size_t k = 1; k < a.size(); ++k)
    travel[k] = travel[k - 1] +
                (first[a[k]].T_world_laser.translation() - first[a[k - 1]].T_world_laser.translation()).norm();
  // Pins counted along the paired scans: pinned_upto[k] = pins at paired scans before k.
  std::vector<char> is_pin(first.size(), 0);
  for (std::size_t p : pins)
    if (p < first.size()) is_pin[p] = 1;
  std::vector<std::size_t> pinned_upto(a.size() + 1, 0);
  for (std::size_t k = 0; k < a.size(); ++k) pinned_upto[k + 1] = pinned_upto[k] + is_pin[a[k]];
  double worst = -1;
  std::size_t j = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    j = std::max(j, i + 1);
    while (j < a.size() && travel[j] < travel[i] + config.window) ++j;
    if (j >= a.size()) break;
    if (pinned_upto[j + 1] > pinned_upto[i]) {  // a closure ties the window to another visit
      ++out.pinned;
      continue;
    }
    const Pose2 ra = first[a[i]].T_world_laser.inverse() * first[a[j]].T_world_laser;
    const Pose2 rb = second[b[i]].T_world_laser.inverse() * second[b[j]].T_world_laser;
    const double turn = std::abs(wrap_angle(ra.theta - rb.theta));
    const double shift = (ra.translation() - rb.translation()).norm();
    ++out.windows;
    out.max_turn = std::max(out.max_turn, turn);
    out.max_shift = std::max(out.max_shift, shift);
    // The window shown is the one nearest to (or farthest past) its limits.
    const double against_limits = std::max(turn / config.max_turn, shift / config.max_shift);
    if (against_limits > worst) worst = against_limits, out.worst_first = a[i], out.worst_last = a[j];
  }
  out.judged = out.windows > 0;
  out.passed = !(out.max_turn > config.max_turn || out.max_shift > config.max_shift);
  return out;
}

}  // namespace partslam
