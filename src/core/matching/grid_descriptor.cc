#include "core/matching/grid_descriptor.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>

#include "core/error.h"
#include "core/timing.h"

namespace partslam {

int GridBits::count() const { return std::popcount(words[0]) + std::popcount(words[1]); }

GridConfig succinct_grid_config() {
  GridConfig c;
  c.cells = 11;
  c.box_size = 8.0;
  c.max_shift = 4;
  c.substeps = 2;
  c.hub_weight = 1.0;
  return c;
}

void validate(const GridConfig& c) {
  if (c.cells < 1 || c.cells > 11)
    throw InputError("grid: cells must be in [1, 11] (S^2 <= 121 bits), got " + std::to_string(c.cells));
  if (!(c.box_size > 0) || !std::isfinite(c.box_size) || c.box_size > 1000)
    throw InputError("grid: box_size must be in (0, 1000] m");
  if (c.min_points < 1 || c.min_points > 10000) throw InputError("grid: min_points must be in [1, 10000]");
  if (c.max_shift < 0 || c.max_shift > c.cells) throw InputError("grid: max_shift must be in [0, cells]");
  if (c.substeps < 1 || c.substeps > 8) throw InputError("grid: substeps must be in [1, 8]");
  if (!(c.hub_weight >= 0) || !std::isfinite(c.hub_weight) || c.hub_weight > 10)
    throw InputError("grid: hub_weight must be in [0, 10]");
  if (c.hub_sample < 1) throw InputError("grid: hub_sample must be >= 1");
  if (c.hub_bits < 1 || c.hub_bits > 16) throw InputError("grid: hub_bits must be in [1, 16]");
}

int grid_bits_per_map(const GridConfig& config) {
  return config.cells * config.cells + (config.hub_weight > 0 ? config.hub_bits : 0);
}

namespace {

void set_bit(GridBits& g, int i) { g.words[static_cast<std::size_t>(i >> 6)] |= std::uint64_t{1} << (i & 63); }

int common(const GridBits& a, const GridBits& b) {
  return std::popcount(a.words[0] & b.words[0]) + std::popcount(a.words[1] & b.words[1]);
}

// The column (or row) of a coordinate on the S x S grid over [-box/2, box/2); -1 outside (NaN too).
int grid_cell(double coordinate, const GridConfig& c) {
  const double f = std::floor((coordinate + c.box_size / 2) / (c.box_size / c.cells));
  return f >= 0 && f < c.cells ? static_cast<int>(f) : -1;
}

// The grid of n points whose columns are xs and rows ys (-1: outside): a cell is set when at least min_points
// points fall in it. `counts` is scratch space of S^2 cells.
GridBits occupancy(const int* xs, const int* ys, std::size_t n, const GridConfig& c, std::vector<int>& counts) {
  const int s = c.cells;
  GridBits g;
  if (c.min_points == 1) {
    for (std::size_t q = 0; q < n; ++q)
      if (xs[q] >= 0 && ys[q] >= 0) set_bit(g, xs[q] + s * ys[q]);
    return g;
  }
  counts.assign(static_cast<std::size_t>(s * s), 0);
  for (std::size_t q = 0; q < n; ++q)
    if (xs[q] >= 0 && ys[q] >= 0) ++counts[static_cast<std::size_t>(xs[q] + s * ys[q])];
  for (int i = 0; i < s * s; ++i)
    if (counts[static_cast<std::size_t>(i)] >= c.min_points) set_bit(g, i);
  return g;
}

}  // namespace

GridBits make_grid(const Points2& points, const GridConfig& config) {
  validate(config);
  std::vector<int> xs, ys, counts;
  for (const Vec2& p : points) xs.push_back(grid_cell(p.x(), config)), ys.push_back(grid_cell(p.y(), config));
  return occupancy(xs.data(), ys.data(), points.size(), config, counts);
}

std::vector<GridBits> make_query_grids(const Points2& points, const GridConfig& config) {
  validate(config);
  const double step = config.box_size / config.cells / config.substeps;
  const int reach = config.max_shift * config.substeps, shifts = 2 * reach + 1;
  const std::size_t n = points.size();
  std::vector<GridBits> out;
  out.reserve(static_cast<std::size_t>(4 * shifts * shifts));
  // Computed separably: under a quarter turn, a point's column depends only on the x shift, its row only on
  // the y shift. The grids equal make_grid of the turned and shifted points.
  std::vector<int> column(static_cast<std::size_t>(shifts) * n), row(static_cast<std::size_t>(shifts) * n), counts;
  for (int k = 0; k < 4; ++k) {
    for (int t = 0; t < shifts; ++t) {
      const double offset = (t - reach) * step;
      for (std::size_t q = 0; q < n; ++q) {
        Vec2 p = points[q];
        for (int turn = 0; turn < k; ++turn) p = Vec2{-p.y(), p.x()};
        column[static_cast<std::size_t>(t) * n + q] = grid_cell(p.x() + offset, config);
        row[static_cast<std::size_t>(t) * n + q] = grid_cell(p.y() + offset, config);
      }
    }
    for (int tj = 0; tj < shifts; ++tj)
      for (int ti = 0; ti < shifts; ++ti)
        out.push_back(occupancy(&column[static_cast<std::size_t>(ti) * n], &row[static_cast<std::size_t>(tj) * n], n,
                                config, counts));
  }
  return out;
}

double jaccard(const GridBits& a, const GridBits& b) {
  const int both = common(a, b), either = a.count() + b.count() - both;
  return either > 0 ? static_cast<double>(both) / either : 0.0;
}

// The best Jaccard both / either as an exact fraction (integer cross-multiplication, no division per pose):
// the same maximum as max over poses of jaccard(), in a few integer operations per pose. Compiled twice, with
// the POPCNT instruction and without (baseline x86-64 has none: std::popcount is then a libgcc call), and the
// loader picks one; popcounts are exact either way. Not under ASan, which does not take target clones.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("popcnt", "default")))
#endif
double grid_similarity(const std::vector<GridBits>& query, const std::vector<int>& counts, const GridBits& stored) {
  const int nb = stored.count();
  int best_both = 0, best_either = 1;
  for (std::size_t v = 0; v < query.size(); ++v) {
    const int both = common(query[v], stored), either = counts[v] + nb - both;
    if (both * best_either > best_both * either) best_both = both, best_either = either;
  }
  return static_cast<double>(best_both) / best_either;
}

std::vector<int> grid_counts(const std::vector<GridBits>& grids) {
  std::vector<int> counts;
  counts.reserve(grids.size());
  for (const GridBits& g : grids) counts.push_back(g.count());
  return counts;
}

double grid_similarity(const std::vector<GridBits>& query, const GridBits& stored) {
  return grid_similarity(query, grid_counts(query), stored);
}

std::vector<double> grid_hubness(std::span<const Points2* const> points, const std::vector<GridBits>& stored,
                                 const GridConfig& config, int num_threads, const Progress& progress) {
  const std::size_t n = stored.size();
  if (points.size() != n)
    throw InputError("grid hubness: " + std::to_string(points.size()) + " point sets for " + std::to_string(n) +
                     " grids");
  std::vector<double> mu(n, 0.0);
  if (config.hub_weight <= 0 || n < 2) return mu;
  // mu_m: how well the queries of other stored maps (a spread sample of up to hub_sample of them, as probes)
  // match m, i.e. how much m looks like everything.
  const std::size_t probes = std::min<std::size_t>(n, config.hub_sample);
  std::vector<std::vector<GridBits>> probe_grids(probes);
  std::vector<std::vector<int>> probe_counts(probes);
  parallel_for(
      probes, num_threads,
      [&](std::size_t k) {
        probe_grids[k] = make_query_grids(*points[k * n / probes], config);
        probe_counts[k] = grid_counts(probe_grids[k]);
      },
      "grid hubness probes", progress);
  const double levels = std::ldexp(1.0, config.hub_bits) - 1;
  parallel_for(
      n, num_threads,
      [&](std::size_t i) {
        double sum = 0;
        int count = 0;
        for (std::size_t k = 0; k < probes; ++k) {
          if (k * n / probes == i) continue;  // never the map itself
          sum += grid_similarity(probe_grids[k], probe_counts[k], stored[i]);
          ++count;
        }
        mu[i] = count > 0 ? std::round(sum / count * levels) / levels : 0.0;
      },
      "grid hubness", progress);
  return mu;
}

}  // namespace partslam
