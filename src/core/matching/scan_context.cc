// Scan Context descriptors, their distance, and the `sc` / `sc:128` rankers (see scan_context.h).
#include "core/matching/scan_context.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

#include "core/error.h"
#include "core/timing.h"

namespace partslam {

void validate(const ScanContextConfig& c) {
  if (c.rings < 1 || c.rings > 1024) throw InputError("scan context: rings must be in [1, 1024]");
  if (c.sectors < 1 || c.sectors > 3600) throw InputError("scan context: sectors must be in [1, 3600]");
  if (!(c.max_radius > 0) || !std::isfinite(c.max_radius))
    throw InputError("scan context: max_radius must be a finite number > 0 [m]");
  if (c.shortlist < 0) throw InputError("scan context: shortlist must be >= 0 (0 = every candidate)");
}

ScanContextConfig scan_context_128_config() {
  ScanContextConfig c;
  c.rings = 8;
  c.sectors = 16;
  c.binary = true;
  return c;
}

double ScanContext::bits() const { return static_cast<double>(rings) * sectors * (binary ? 1.0 : 8.0); }

ScanContext make_scan_context(const Points2& points, const ScanContextConfig& config) {
  validate(config);
  ScanContext sc;
  sc.rings = config.rings;
  sc.sectors = config.sectors;
  sc.binary = config.binary;
  const std::size_t nr = static_cast<std::size_t>(config.rings),
                    ns = static_cast<std::size_t>(config.sectors);
  sc.bins.assign(nr * ns, 0.0f);
  constexpr double two_pi = 2.0 * std::numbers::pi;
  for (const Vec2& p : points) {
    const double r = p.norm();
    if (!(r < config.max_radius)) continue;  // beyond L_max (or not finite)
    double angle = std::atan2(p.y(), p.x());
    if (angle < 0) angle += two_pi;
    const std::size_t ring = std::min(nr - 1, static_cast<std::size_t>(r / config.max_radius * config.rings));
    const std::size_t sector = std::min(ns - 1, static_cast<std::size_t>(angle / two_pi * config.sectors));
    float& bin = sc.bins[sector * nr + ring];
    bin = config.binary ? 1.0f : std::min(bin + 1.0f, 255.0f);  // 8 bits of count
  }
  sc.ring_key.assign(nr, 0.0f);
  sc.column_norms.assign(ns, 0.0);
  if (config.binary && nr <= 64) sc.masks.assign(ns, 0);
  for (std::size_t s = 0; s < ns; ++s) {
    double norm2 = 0;
    for (std::size_t r = 0; r < nr; ++r) {
      const float v = sc.bins[s * nr + r];
      norm2 += static_cast<double>(v) * v;
      if (v > 0) {
        sc.ring_key[r] += 1.0f;
        if (!sc.masks.empty()) sc.masks[s] |= std::uint64_t{1} << r;
      }
    }
    sc.column_norms[s] = std::sqrt(norm2);
  }
  for (float& k : sc.ring_key) k /= static_cast<float>(ns);
  return sc;
}

double column_distance(const ScanContext& a, const ScanContext& b, int shift) {
  const int ns = a.sectors, nr = a.rings;
  shift = ((shift % ns) + ns) % ns;
  double sum = 0;
  int used = 0;
  if (!a.masks.empty() && !b.masks.empty()) {  // binary: popcounts of the column masks
    for (int j = 0; j < ns; ++j) {
      const std::uint64_t ca = a.masks[static_cast<std::size_t>((j + shift) % ns)];
      const std::uint64_t cb = b.masks[static_cast<std::size_t>(j)];
      if (ca == 0 || cb == 0) continue;
      const double both = std::popcount(ca & cb);
      sum += 1.0 - both / std::sqrt(static_cast<double>(std::popcount(ca)) * std::popcount(cb));
      ++used;
    }
  } else {
    for (int j = 0; j < ns; ++j) {
      const int ja = (j + shift) % ns;
      const double na = a.column_norms[static_cast<std::size_t>(ja)];
      const double nb = b.column_norms[static_cast<std::size_t>(j)];
      if (na == 0 || nb == 0) continue;
      const float* ca = a.bins.data() + static_cast<std::size_t>(ja) * static_cast<std::size_t>(nr);
      const float* cb = b.bins.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(nr);
      double dot = 0;
      for (int r = 0; r < nr; ++r) dot += static_cast<double>(ca[r]) * cb[r];
      sum += 1.0 - dot / (na * nb);
      ++used;
    }
  }
  return used == 0 ? 1.0 : sum / used;
}

ScanContextMatch match_scan_contexts(const ScanContext& a, const ScanContext& b) {
  if (a.rings != b.rings || a.sectors != b.sectors || a.binary != b.binary)
    throw InputError("scan context: descriptors of different configurations");
  ScanContextMatch best;
  best.distance = 2.0;
  for (int s = 0; s < a.sectors; ++s) {
    const double d = column_distance(a, b, s);
    if (d < best.distance) best.distance = d, best.shift = s;
  }
  best.yaw = wrap_angle(best.shift * 2.0 * std::numbers::pi / a.sectors);
  return best;
}

double ring_key_distance(const ScanContext& a, const ScanContext& b) {
  double d2 = 0;
  for (std::size_t r = 0; r < a.ring_key.size() && r < b.ring_key.size(); ++r) {
    const double d = static_cast<double>(a.ring_key[r]) - b.ring_key[r];
    d2 += d * d;
  }
  return std::sqrt(d2);
}

}  // namespace partslam
