#include "core/evaluation/relation_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <unordered_map>

namespace partslam {
namespace {

double scan_difference(const Scan& a, const Scan& b) {
  if (a.points_laser.size() != b.points_laser.size() || a.points_laser.empty())
    return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (std::size_t i = 0; i < a.points_laser.size(); ++i) sum += (a.points_laser[i] - b.points_laser[i]).norm();
  return sum / static_cast<double>(a.points_laser.size());
}

constexpr double kSameScan = 0.02;  // [m] mean endpoint difference of the same scan printed twice
constexpr std::size_t kLookahead = 64;

}  // namespace

std::vector<std::optional<std::size_t>> associate_scans(const Scans& scans, const Scans& reference) {
  std::vector<std::optional<std::size_t>> out(scans.size());
  std::size_t next = 0;  // scans appear in the same order in both logs; the reference may hold extra ones
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const std::size_t end = std::min(reference.size(), next + (i == 0 ? 4 * kLookahead : kLookahead));
    double best = kSameScan;
    for (std::size_t j = next; j < end; ++j) {
      const double d = scan_difference(scans[i], reference[j]);
      if (d < best) best = d, out[i] = j;
    }
    if (out[i]) next = *out[i] + 1;
  }
  return out;
}

RelationCheck check_relevant_pairs(const Submaps& maps, const std::vector<RelevantPair>& pairs, const Scans& scans,
                                   const Scans& reference, const Relations& relations,
                                   const RelationCheckConfig& config) {
  RelationCheck result;
  result.relevant_pairs = pairs.size();
  const auto assoc = associate_scans(scans, reference);
  // reference timestamp -> index into `scans`
  std::map<double, std::size_t> by_reference_time;
  std::unordered_map<double, std::size_t> by_time;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    by_time.emplace(scans[i].timestamp, i);
    if (assoc[i]) by_reference_time.emplace(reference[*assoc[i]].timestamp, i), ++result.associated_scans;
  }
  auto lookup = [&](double t) -> std::optional<std::size_t> {
    auto it = by_reference_time.lower_bound(t - 1e-4);
    if (it != by_reference_time.end() && std::abs(it->first - t) <= 1e-4) return it->second;
    return std::nullopt;
  };
  // Per relation: the scans (of `scans`) it links, and whether the log agrees with it.
  std::map<std::pair<std::size_t, std::size_t>, bool> linked;
  for (const Relation& r : relations) {
    const auto a = lookup(r.t1), b = lookup(r.t2);
    if (!a || !b) continue;
    const Pose2 T_log = scans[*a].T_world_laser.inverse() * scans[*b].T_world_laser;
    const bool agrees = config.agreement.accepts(T_log, r.T_1_2);
    auto& v = linked[{std::min(*a, *b), std::max(*a, *b)}];
    v = v || agrees;
  }
  auto scan_set = [&](const Submap& m) {
    std::set<std::size_t> s;
    for (double t : m.scan_timestamps)
      if (auto it = by_time.find(t); it != by_time.end()) s.insert(it->second);
    return s;
  };
  for (const RelevantPair& p : pairs) {
    const auto sq = scan_set(maps[p.query]), sg = scan_set(maps[p.global]);
    bool any = false, ok = false;
    for (const auto& [key, agrees] : linked) {
      if ((sq.count(key.first) && sg.count(key.second)) || (sq.count(key.second) && sg.count(key.first))) {
        any = true;
        ok = ok || agrees;
      }
    }
    result.with_relation += any;
    result.confirmed += ok;
  }
  return result;
}

}  // namespace partslam
