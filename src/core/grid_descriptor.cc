#include "core/grid_descriptor.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/ranking.h"

namespace partslam {

int GridBits::count() const { return std::popcount(words[0]) + std::popcount(words[1]); }

namespace {

void set_bit(GridBits& g, int i) { g.words[static_cast<std::size_t>(i >> 6)] |= std::uint64_t{1} << (i & 63); }
bool get_bit(const GridBits& g, int i) { return (g.words[static_cast<std::size_t>(i >> 6)] >> (i & 63)) & 1; }

int common(const GridBits& a, const GridBits& b) {
  return std::popcount(a.words[0] & b.words[0]) + std::popcount(a.words[1] & b.words[1]);
}

// Wall class of every point: 0 clutter, 1 on a wall along x, 2 on a wall along y (its neighbourhood within
// 0.5 m is a line within ~15 deg of the axis).
std::vector<int> wall_classes(const Points2& points) {
  std::vector<int> out(points.size(), 0);
  const double r2 = 0.25;
  for (std::size_t i = 0; i < points.size(); ++i) {
    double sxx = 0, sxy = 0, syy = 0;
    int n = 0;
    for (const Vec2& q : points) {
      const Vec2 d = q - points[i];
      if (d.squaredNorm() > r2) continue;
      sxx += d.x() * d.x(), sxy += d.x() * d.y(), syy += d.y() * d.y(), ++n;
    }
    if (n < 5) continue;
    const double ht = (sxx + syy) / 2, disc = std::sqrt(std::max(0.0, ht * ht - (sxx * syy - sxy * sxy)));
    const double lmax = ht + disc, lmin = ht - disc;
    if (lmax <= 0 || lmin > 0.1 * lmax) continue;
    const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);  // principal direction
    const double a = std::abs(angle);
    if (a < 0.26) out[i] = 1;
    else if (std::abs(a - std::numbers::pi / 2) < 0.26) out[i] = 2;
  }
  return out;
}

// Occupancy of the points moved by (quarter turns, offset) on the S x S grid (per channel).
GridBits bin(const Points2& points, const std::vector<int>& classes, const GridConfig& c, int quarter_turns,
             const Vec2& offset) {
  const double cell = c.box_size / c.cells, half = c.box_size / 2;
  const int plane = c.cells * c.cells, channels = c.walls == 2 ? 2 : 1;
  std::vector<int> counts(static_cast<std::size_t>(plane * channels), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (c.walls > 0 && classes[i] == 0) continue;
    Vec2 p = points[i];
    for (int k = 0; k < quarter_turns; ++k) p = Vec2{-p.y(), p.x()};
    p += offset;
    const double fx = std::floor((p.x() + half) / cell), fy = std::floor((p.y() + half) / cell);
    if (fx < 0 || fy < 0 || fx >= c.cells || fy >= c.cells) continue;
    const int channel = channels == 1 ? 0 : (classes[i] - 1 + quarter_turns) % 2;
    ++counts[static_cast<std::size_t>(channel * plane + static_cast<int>(fx) + c.cells * static_cast<int>(fy))];
  }
  int threshold = c.min_points;
  if (c.keep_percent < 100) {
    std::vector<int> nonzero;
    for (int n : counts)
      if (n > 0) nonzero.push_back(n);
    if (!nonzero.empty()) {
      std::sort(nonzero.begin(), nonzero.end(), std::greater<>());
      const std::size_t k = std::min(nonzero.size() - 1, nonzero.size() * static_cast<std::size_t>(c.keep_percent) / 100);
      threshold = std::max(threshold, nonzero[k]);
    }
  }
  GridBits g;
  for (int i = 0; i < plane * channels; ++i)
    if (counts[static_cast<std::size_t>(i)] >= threshold) set_bit(g, i);
  return g;
}

}  // namespace

void validate(const GridConfig& c) {
  if (c.cells < 1 || c.cells > 11) throw InputError("grid: cells must be in [1, 11] (S^2 <= 128 bits), got " + std::to_string(c.cells));
  if (!(c.box_size > 0) || !std::isfinite(c.box_size)) throw InputError("grid: box_size must be > 0 [m]");
  if (c.min_points < 1 || c.min_points > 10000) throw InputError("grid: min_points must be in [1, 10000]");
  if (c.max_shift < 0 || c.max_shift > c.cells) throw InputError("grid: max_shift must be in [0, cells]");
  if (c.substeps < 1 || c.substeps > 8) throw InputError("grid: substeps must be in [1, 8]");
  if (c.keep_percent < 1 || c.keep_percent > 100) throw InputError("grid: keep_percent must be in [1, 100]");
  if (c.walls < 0 || c.walls > 2) throw InputError("grid: walls must be 0, 1 or 2");
  if (!(c.hub_weight >= 0) || !std::isfinite(c.hub_weight)) throw InputError("grid: hub_weight must be >= 0");
  if (c.hub_sample < 1) throw InputError("grid: hub_sample must be >= 1");
  if (c.hub_bits < 1 || c.hub_bits > 16) throw InputError("grid: hub_bits must be in [1, 16]");
  if (c.walls == 2 && c.cells > 8) throw InputError("grid: two wall channels need cells <= 8 (2 S^2 <= 128 bits)");
  if (c.walls == 2 && c.similarity == GridSimilarity::kTolerant) throw InputError("grid: sim=tolerant has one channel");
}

GridBits make_grid(const Points2& points, const GridConfig& config) {
  validate(config);
  return bin(points, config.walls > 0 ? wall_classes(points) : std::vector<int>(points.size(), 0), config, 0,
             Vec2::Zero());
}

QueryGrids make_query_grids(const Points2& points, const GridConfig& config) {
  validate(config);
  const double step = config.box_size / config.cells / config.substeps;
  const int reach = config.max_shift * config.substeps;
  QueryGrids out;
  const std::vector<int> classes = config.walls > 0 ? wall_classes(points) : std::vector<int>(points.size(), 0);
  for (int k = 0; k < 4; ++k)
    for (int j = -reach; j <= reach; ++j)
      for (int i = -reach; i <= reach; ++i) {
        out.grids.push_back(bin(points, classes, config, k, Vec2{i * step, j * step}));
        if (config.similarity == GridSimilarity::kTolerant) out.dilated.push_back(dilate(out.grids.back(), config.cells));
      }
  return out;
}

GridBits dilate(const GridBits& g, int s) {
  GridBits out;
  for (int y = 0; y < s; ++y)
    for (int x = 0; x < s; ++x) {
      bool on = false;
      for (int dy = -1; dy <= 1 && !on; ++dy)
        for (int dx = -1; dx <= 1 && !on; ++dx) {
          const int xx = x + dx, yy = y + dy;
          on = xx >= 0 && yy >= 0 && xx < s && yy < s && get_bit(g, xx + s * yy);
        }
      if (on) set_bit(out, x + s * y);
    }
  return out;
}

double grid_similarity(const QueryGrids& query, const GridBits& stored, const GridBits& stored_dilated,
                       const GridConfig& config) {
  const int nb = stored.count();
  double best = 0;
  for (std::size_t v = 0; v < query.grids.size(); ++v) {
    const GridBits& a = query.grids[v];
    const int na = a.count();
    if (config.similarity == GridSimilarity::kJaccard) {
      const int both = common(a, stored), either = na + nb - both;
      if (either > 0) best = std::max(best, static_cast<double>(both) / either);
    } else if (config.similarity == GridSimilarity::kCosine) {
      if (na > 0 && nb > 0) best = std::max(best, common(a, stored) / std::sqrt(static_cast<double>(na) * nb));
    } else if (config.similarity == GridSimilarity::kCount) {
      best = std::max(best, static_cast<double>(common(a, stored)));
    } else if (config.similarity == GridSimilarity::kOverlap) {
      if (na > 0 && nb > 0) best = std::max(best, static_cast<double>(common(a, stored)) / std::min(na, nb));
    } else if (na + nb > 0) {
      const int hits = common(a, stored_dilated) + common(query.dilated[v], stored);
      best = std::max(best, static_cast<double>(hits) / (na + nb));
    }
  }
  return best;
}

// ---- the rankers: `grid` (the baseline) ----
namespace {

using Clock = std::chrono::steady_clock;

class GridRanker final : public Ranker {
 public:
  explicit GridRanker(const GridConfig& config) : config_(config) { validate(config_); }

  void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress) override {
    stored_.assign(maps.size(), {});
    dilated_.assign(maps.size(), {});
    for (const MapView& m : maps)
      if (m.points == nullptr) throw InputError("grid: every map needs its points to build its grid");
    parallel_for(
        maps.size(), num_threads,
        [&](std::size_t i) {
          stored_[i] = make_grid(*maps[i].points, config_);
          dilated_[i] = dilate(stored_[i], config_.cells);
        },
        "grids", progress);
    hub_.assign(maps.size(), 0.0);
    if (config_.hub_weight <= 0 || maps.size() < 2) return;
    const std::size_t n = maps.size(), sample = std::min<std::size_t>(n - 1, config_.hub_sample);
    const double levels = std::ldexp(1.0, config_.hub_bits) - 1;
    parallel_for(
        n, num_threads,
        [&](std::size_t i) {
          const QueryGrids q = make_query_grids(*maps[i].points, config_);
          double sum = 0;
          for (std::size_t k = 0; k < sample; ++k) {
            const std::size_t j = (i + 1 + k * (n - 1) / sample) % n;  // spread over the others, never i
            sum += grid_similarity(q, stored_[j], dilated_[j], config_);
          }
          hub_[i] = std::round(sum / static_cast<double>(sample) * levels) / levels;
        },
        "grid hubness", progress);
  }

  double bits_per_map() const override {
    return config_.cells * config_.cells * (config_.walls == 2 ? 2 : 1) + (config_.hub_weight > 0 ? config_.hub_bits : 0);
  }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    if (query.points == nullptr) throw InputError("grid: the query has no points");
    Ranking r;
    auto t0 = Clock::now();
    const QueryGrids q = make_query_grids(*query.points, config_);
    r.prep_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    t0 = Clock::now();
    r.scores.resize(candidates.size());
    parallel_for(candidates.size(), options.num_threads, [&](std::size_t j) {
      const std::size_t c = candidates[j];
      r.scores[j] = grid_similarity(q, stored_.at(c), dilated_.at(c), config_) - config_.hub_weight * hub_.at(c);
    });
    r.match_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return r;
  }

 private:
  GridConfig config_;
  std::vector<GridBits> stored_, dilated_;
  std::vector<double> hub_;  // mu_m, quantised
};

// grid[:S[:key=value...]] with keys shift, sub, min, sim (jaccard|tolerant), box.
GridConfig parse_grid_args(const std::string& text, const std::vector<std::string>& args, GridConfig c) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const std::size_t eq = a.find('=');
    if (i == 0 && eq == std::string::npos) {
      c.cells = parse_spec_int(text, a, "S (cells per side)", 1, 11);
      continue;
    }
    if (eq == std::string::npos) throw InputError("method '" + text + "': expected key=value, got '" + a + "'");
    const std::string key = a.substr(0, eq), value = a.substr(eq + 1);
    if (key == "shift") c.max_shift = parse_spec_int(text, value, "shift", 0, 11);
    else if (key == "sub") c.substeps = parse_spec_int(text, value, "sub", 1, 8);
    else if (key == "min") c.min_points = parse_spec_int(text, value, "min", 1, 10000);
    else if (key == "box") c.box_size = parse_spec_int(text, value, "box (dm)", 10, 1000) / 10.0;
    else if (key == "hub") c.hub_weight = parse_spec_int(text, value, "hub (%)", 0, 1000) / 100.0;
    else if (key == "walls") c.walls = parse_spec_int(text, value, "walls", 0, 2);
    else if (key == "keep") c.keep_percent = parse_spec_int(text, value, "keep (%)", 1, 100);
    else if (key == "sim" && (value == "jaccard" || value == "tolerant" || value == "cosine" || value == "overlap" ||
                              value == "count"))
      c.similarity = value == "jaccard"    ? GridSimilarity::kJaccard
                     : value == "tolerant" ? GridSimilarity::kTolerant
                     : value == "cosine"   ? GridSimilarity::kCosine
                     : value == "count"    ? GridSimilarity::kCount
                                           : GridSimilarity::kOverlap;
    else throw InputError("method '" + text + "': unknown grid option '" + a + "'");
  }
  validate(c);
  return c;
}

std::string grid_spec(const GridConfig& c) {
  std::string s = "grid:" + std::to_string(c.cells);
  const GridConfig d;
  if (c.max_shift != d.max_shift) s += ":shift=" + std::to_string(c.max_shift);
  if (c.substeps != d.substeps) s += ":sub=" + std::to_string(c.substeps);
  if (c.min_points != d.min_points) s += ":min=" + std::to_string(c.min_points);
  if (c.box_size != d.box_size) s += ":box=" + std::to_string(static_cast<int>(std::lround(c.box_size * 10)));
  if (c.walls != d.walls) s += ":walls=" + std::to_string(c.walls);
  if (c.hub_weight != d.hub_weight) s += ":hub=" + std::to_string(static_cast<int>(std::lround(c.hub_weight * 100)));
  if (c.keep_percent != d.keep_percent) s += ":keep=" + std::to_string(c.keep_percent);
  static const char* names[] = {"jaccard", "tolerant", "cosine", "overlap", "count"};
  if (c.similarity != d.similarity) s += std::string(":sim=") + names[static_cast<int>(c.similarity)];
  return s;
}

void parse_grid(const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
  const GridConfig c = parse_grid_args(text, args, GridConfig{});
  m.size = c.cells;
  m.spec = grid_spec(c);
  m.name_label = m.spec == "grid:" + std::to_string(c.cells) ? "grid " + std::to_string(c.cells) + "x" + std::to_string(c.cells)
                                                             : m.spec;
}

}  // namespace

const MethodEntry& grid_method() {
  static const MethodEntry entry{"grid", "grid[:S[:shift=C:sub=N:min=P:box=DM:sim=jaccard|tolerant]]", parse_grid,
                                 [](const MethodSpec& m, const RankingConfig&) {
                                   return std::unique_ptr<Ranker>(
                                       new GridRanker(parse_grid_args(m.spec, m.args, GridConfig{})));
                                 }};
  return entry;
}

}  // namespace partslam
