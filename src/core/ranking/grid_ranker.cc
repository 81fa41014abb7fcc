// The occupancy-grid descriptors (core/matching/grid_descriptor.h) as rankers: `grid[:S[:key=value...]]`, the
// baseline, and `succinct`, the product's default succinct matcher. A large database ranked for its top k
// answers through core/matching/grid_cascade.h's kernels: an exact scan, or its approximate cascade on the
// largest.
#include "core/ranking/grid_ranker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "core/error.h"
#include "core/matching/grid_cascade.h"
#include "core/timing.h"

namespace partslam {
namespace {

class GridRanker final : public Ranker {
 public:
  explicit GridRanker(const GridConfig& config) : config_(config) { validate(config_); }

  void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress) override {
    stored_ =
        prepare_from_points<GridBits>(maps, num_threads, progress, "grid", "grids",
                                      [&](const Points2& points) { return make_grid(points, config_); });
    std::vector<const Points2*> points;
    for (const MapView& m : maps) points.push_back(m.points);
    hub_ = grid_hubness(points, stored_, config_, num_threads, progress);
    // Top-k requests over the whole of a large database (rank with options.top_k > 0) go through the
    // cascade's kernels: with short lists as long as the database (the scan's exact top k), or from
    // cascade_min_maps on with its approximate stages.
    index_.reset();
    const std::size_t n = stored_.size();
    if (n >= config_.cascade_min_maps)
      index_ = std::make_unique<GridCascade>(stored_, hub_, config_);
    else if (n >= config_.index_min_maps)
      index_ = std::make_unique<GridCascade>(stored_, hub_, config_,
                                             GridCascadeConfig{.coarse_min = std::max<std::size_t>(1, n)});
  }

  double bits_per_map() const override { return grid_bits_per_map(config_); }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    if (query.points == nullptr) throw InputError("grid: the query has no points");
    Ranking r;
    auto t0 = Clock::now();
    const std::vector<GridBits> q = make_query_grids(*query.points, config_);
    const std::vector<int> counts = grid_counts(q);
    r.prep_ms = ms_since(t0);
    t0 = Clock::now();
    if (options.top_k > 0 && index_ != nullptr && is_prefix(candidates)) {
      // The k best (grid_cascade.h) among the candidates, the first stored maps (all of them, or a log's maps
      // before the query's for loops); the others rank below them.
      r.scores.assign(candidates.size(), -std::numeric_limits<double>::infinity());
      for (const GridMatch& m :
           index_->top_k(q, static_cast<std::size_t>(options.top_k), nullptr, candidates.size()))
        r.scores[m.index] = m.score;
      r.match_ms = ms_since(t0);
      return r;
    }
    r.scores.resize(candidates.size());
    parallel_for(candidates.size(), options.num_threads, [&](std::size_t j) {
      const std::size_t c = candidates[j];
      r.scores[j] = grid_similarity(q, counts, stored_.at(c)) - config_.hub_weight * hub_.at(c);
    });
    r.match_ms = ms_since(t0);
    return r;
  }

 private:
  GridConfig config_;
  std::vector<GridBits> stored_;
  std::vector<double> hub_;  // mu_m, quantised to hub_bits
  std::unique_ptr<GridCascade> index_;

  // Whether the candidates are stored maps 0, 1, ..., in order.
  bool is_prefix(std::span<const std::size_t> candidates) const {
    if (candidates.size() > stored_.size()) return false;
    for (std::size_t j = 0; j < candidates.size(); ++j)
      if (candidates[j] != j) return false;
    return true;
  }
};

// grid[:S[:key=value...]]: keys box (dm), shift (cells), sub (steps per cell), min (points), hub (percent).
GridConfig parse_grid_args(const std::string& text, const std::vector<std::string>& args) {
  GridConfig c;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const std::size_t eq = a.find('=');
    if (i == 0 && eq == std::string::npos) {
      c.cells = parse_spec_int(text, a, "S (cells per side)", 1, 11);
      continue;
    }
    if (eq == std::string::npos)
      throw InputError("method '" + text + "': expected key=value, got '" + a + "'");
    const std::string key = a.substr(0, eq), value = a.substr(eq + 1);
    if (key == "shift")
      c.max_shift = parse_spec_int(text, value, "shift (cells)", 0, 11);
    else if (key == "sub")
      c.substeps = parse_spec_int(text, value, "sub (steps per cell)", 1, 8);
    else if (key == "min")
      c.min_points = parse_spec_int(text, value, "min (points)", 1, 10000);
    else if (key == "box")
      c.box_size = parse_spec_int(text, value, "box (dm)", 10, 1000) / 10.0;
    else if (key == "hub")
      c.hub_weight = parse_spec_int(text, value, "hub (percent)", 0, 1000) / 100.0;
    else
      throw InputError("method '" + text + "': unknown grid option '" + a + "' (box, shift, sub, min, hub)");
  }
  validate(c);
  return c;
}

// A grid configuration as a method's options.
struct GridOptions final : MethodOptions {
  GridConfig config;
};

void parse_grid(const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
  const GridConfig c = parse_grid_args(text, args);
  const GridConfig d;
  m.spec = "grid:" + std::to_string(c.cells);
  if (c.box_size != d.box_size) m.spec += ":box=" + std::to_string(std::lround(c.box_size * 10));
  if (c.max_shift != d.max_shift) m.spec += ":shift=" + std::to_string(c.max_shift);
  if (c.substeps != d.substeps) m.spec += ":sub=" + std::to_string(c.substeps);
  if (c.min_points != d.min_points) m.spec += ":min=" + std::to_string(c.min_points);
  if (c.hub_weight != d.hub_weight) m.spec += ":hub=" + std::to_string(std::lround(c.hub_weight * 100));
  const std::string side = std::to_string(c.cells);
  m.label = m.spec == "grid:" + side ? "grid " + side + "x" + side : m.spec;
  m.traits.shardable = c.hub_weight == 0;  // the hubness term learns from every stored map
  m.traits.stage_score = "grid score";
  auto o = std::make_shared<GridOptions>();
  o->config = c;
  m.options = std::move(o);
}

void parse_succinct(const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
  if (!args.empty()) throw InputError("method '" + text + "': succinct takes no arguments");
  m.spec = "succinct";
  m.label = "succinct";
  m.traits.shardable = false;  // the hubness term learns from every stored map
  m.traits.stage_score = "succinct score";
}

}  // namespace

const MethodEntry& grid_method() {
  static const MethodEntry entry{"grid", "grid[:S[:box=DM:shift=C:sub=N:min=P:hub=PCT]]", parse_grid,
                                 [](const MethodSpec& m, const RankingConfig&) {
                                   return make_grid_ranker(m.options_as<GridOptions>().config);
                                 }};
  return entry;
}

const MethodEntry& succinct_method() {
  static const MethodEntry entry{
      "succinct", "succinct", parse_succinct,
      [](const MethodSpec&, const RankingConfig&) { return make_grid_ranker(succinct_grid_config()); }};
  return entry;
}

std::unique_ptr<Ranker> make_grid_ranker(const GridConfig& config) {
  return std::make_unique<GridRanker>(config);
}

}  // namespace partslam
