#include "core/corner_descriptor.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/cpd.h"
#include "core/error.h"
#include "core/ranking.h"

namespace partslam {
namespace {

Points2 corners_of(const Points2& points, const CornerConfig& c, int count) {
  CpdConfig cpd;
  cpd.corners = count;
  cpd.corner_radius = c.corner_radius;
  cpd.corner_spacing = c.corner_spacing;
  return find_corners(points, cpd);
}

}  // namespace

void validate(const CornerConfig& c) {
  if (c.stored_corners < 1 || c.stored_corners > 64) throw InputError("corners: stored_corners must be in [1, 64]");
  if (c.query_corners < 1 || c.query_corners > 1000) throw InputError("corners: query_corners must be in [1, 1000]");
  auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v)) throw InputError(std::string("corners: ") + name + " must be > 0");
  };
  positive(c.corner_radius, "corner_radius");
  positive(c.corner_spacing, "corner_spacing");
  positive(c.tolerance, "tolerance");
  positive(c.max_translation, "max_translation");
  positive(c.quantum, "quantum");
}

Points2 stored_corners(const Points2& points, const CornerConfig& config) {
  validate(config);
  Points2 out = corners_of(points, config, config.stored_corners);
  for (Vec2& p : out) p = (p / config.quantum).array().floor() * config.quantum + config.quantum / 2;
  return out;
}

Points2 query_corners(const Points2& points, const CornerConfig& config) {
  validate(config);
  return corners_of(points, config, config.query_corners);
}

int match_corners(const Points2& query, const Points2& stored, const CornerConfig& config) {
  const double tol2 = config.tolerance * config.tolerance, tmax2 = config.max_translation * config.max_translation;
  int best = 0;
  Points2 turned = query;
  for (int k = 0; k < 4; ++k) {
    if (k > 0)
      for (Vec2& p : turned) p = Vec2{-p.y(), p.x()};
    for (const Vec2& q : turned) {
      for (const Vec2& s : stored) {
        const Vec2 t = s - q;
        if (t.squaredNorm() > tmax2) continue;
        int matched = 0;
        for (const Vec2& s2 : stored) {
          for (const Vec2& q2 : turned) {
            if ((q2 + t - s2).squaredNorm() <= tol2) {
              ++matched;
              break;
            }
          }
        }
        best = std::max(best, matched);
      }
    }
  }
  return best;
}

namespace {

using Clock = std::chrono::steady_clock;

class CornerRanker final : public Ranker {
 public:
  explicit CornerRanker(const CornerConfig& config) : config_(config) { validate(config_); }

  void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress) override {
    for (const MapView& m : maps)
      if (m.points == nullptr) throw InputError("corners: every map needs its points");
    stored_.assign(maps.size(), {});
    parallel_for(
        maps.size(), num_threads, [&](std::size_t i) { stored_[i] = stored_corners(*maps[i].points, config_); },
        "corners", progress);
  }

  double bits_per_map() const override { return 14.0 * config_.stored_corners; }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    if (query.points == nullptr) throw InputError("corners: the query has no points");
    Ranking r;
    auto t0 = Clock::now();
    const Points2 q = query_corners(*query.points, config_);
    r.prep_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    t0 = Clock::now();
    r.scores.resize(candidates.size());
    parallel_for(candidates.size(), options.num_threads, [&](std::size_t j) {
      const Points2& s = stored_.at(candidates[j]);
      const int m = match_corners(q, s, config_);
      r.scores[j] = s.empty() ? 0.0 : m / std::sqrt(static_cast<double>(s.size()));
    });
    r.match_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return r;
  }

 private:
  CornerConfig config_;
  std::vector<Points2> stored_;
};

CornerConfig parse_corner_args(const std::string& text, const std::vector<std::string>& args) {
  CornerConfig c;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const std::size_t eq = a.find('=');
    if (i == 0 && eq == std::string::npos) {
      c.stored_corners = parse_spec_int(text, a, "C (stored corners)", 1, 64);
      continue;
    }
    if (eq == std::string::npos) throw InputError("method '" + text + "': expected key=value, got '" + a + "'");
    const std::string key = a.substr(0, eq), value = a.substr(eq + 1);
    if (key == "q") c.query_corners = parse_spec_int(text, value, "q", 1, 1000);
    else if (key == "tol") c.tolerance = parse_spec_int(text, value, "tol (cm)", 1, 1000) / 100.0;
    else if (key == "t") c.max_translation = parse_spec_int(text, value, "t (dm)", 1, 1000) / 10.0;
    else if (key == "r") c.corner_radius = parse_spec_int(text, value, "r (dm)", 1, 100) / 10.0;
    else if (key == "sp") c.corner_spacing = parse_spec_int(text, value, "sp (dm)", 1, 100) / 10.0;
    else throw InputError("method '" + text + "': unknown corners option '" + a + "'");
  }
  validate(c);
  return c;
}

void parse_corners(const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
  const CornerConfig c = parse_corner_args(text, args);
  m.size = c.stored_corners;
  m.spec = text;
  m.name_label = text;
}

}  // namespace

const MethodEntry& corners_method() {
  static const MethodEntry entry{"corners", "corners[:C[:q=N:tol=CM:t=DM:r=DM:sp=DM]]", parse_corners,
                                 [](const MethodSpec& m, const RankingConfig&) {
                                   return std::unique_ptr<Ranker>(new CornerRanker(parse_corner_args(m.spec, m.args)));
                                 }};
  return entry;
}

}  // namespace partslam
