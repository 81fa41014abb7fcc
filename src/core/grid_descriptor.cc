#include "core/grid_descriptor.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

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

// Occupancy of the points moved by (quarter turns, offset) on the S x S grid.
GridBits bin(const Points2& points, const GridConfig& c, int quarter_turns, const Vec2& offset) {
  const double cell = c.box_size / c.cells, half = c.box_size / 2;
  std::vector<int> counts(static_cast<std::size_t>(c.cells * c.cells), 0);
  for (const Vec2& p0 : points) {
    Vec2 p = p0;
    for (int k = 0; k < quarter_turns; ++k) p = Vec2{-p.y(), p.x()};
    p += offset;
    const double fx = std::floor((p.x() + half) / cell), fy = std::floor((p.y() + half) / cell);
    if (fx < 0 || fy < 0 || fx >= c.cells || fy >= c.cells) continue;
    ++counts[static_cast<std::size_t>(static_cast<int>(fx) + c.cells * static_cast<int>(fy))];
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
  for (int i = 0; i < c.cells * c.cells; ++i)
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
}

GridBits make_grid(const Points2& points, const GridConfig& config) {
  validate(config);
  return bin(points, config, 0, Vec2::Zero());
}

QueryGrids make_query_grids(const Points2& points, const GridConfig& config) {
  validate(config);
  const double step = config.box_size / config.cells / config.substeps;
  const int reach = config.max_shift * config.substeps;
  QueryGrids out;
  for (int k = 0; k < 4; ++k)
    for (int j = -reach; j <= reach; ++j)
      for (int i = -reach; i <= reach; ++i) {
        out.grids.push_back(bin(points, config, k, Vec2{i * step, j * step}));
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
  }

  double bits_per_map() const override { return config_.cells * config_.cells; }

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
      r.scores[j] = grid_similarity(q, stored_.at(c), dilated_.at(c), config_);
    });
    r.match_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return r;
  }

 private:
  GridConfig config_;
  std::vector<GridBits> stored_, dilated_;
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
    else if (key == "keep") c.keep_percent = parse_spec_int(text, value, "keep (%)", 1, 100);
    else if (key == "sim" && (value == "jaccard" || value == "tolerant" || value == "cosine" || value == "overlap"))
      c.similarity = value == "jaccard"    ? GridSimilarity::kJaccard
                     : value == "tolerant" ? GridSimilarity::kTolerant
                     : value == "cosine"   ? GridSimilarity::kCosine
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
  if (c.keep_percent != d.keep_percent) s += ":keep=" + std::to_string(c.keep_percent);
  static const char* names[] = {"jaccard", "tolerant", "cosine", "overlap"};
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
