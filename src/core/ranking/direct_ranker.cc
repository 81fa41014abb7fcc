// Direct matching as rankers (docs/DESIGN.md, "dMM"): `dmm` (Eq. 1's exact branch-and-bound finds the poses, the
// verification scores them: core/matching/verification.h), `dmm:eq1` (the paper's Eq. 1 score), `dmm-exhaustive`
// (Eq. 1, the reference) and `dmm-ransac` (the paper's baseline). They store the map's points (bits_per_point
// each) and return the relative pose T_map_query of every candidate.
// Tested by: core/ranking/ranking_test.cc, core/ranking/method_spec_test.cc
#include <numeric>
#include <optional>

#include "core/error.h"
#include "core/timing.h"
#include "core/ranking/ranking.h"

namespace partslam {
namespace {

double mean_points(std::span<const MapView> maps) {
  double sum = 0;
  for (const MapView& m : maps) sum += static_cast<double>(m.points->size());
  return maps.empty() ? 0.0 : sum / static_cast<double>(maps.size());
}

const Points2 kNoOrigins;

const Points2& origins_of(const MapView& m) { return m.origins != nullptr ? *m.origins : kNoOrigins; }

enum class DmmScore { kVerified, kEq1, kExhaustive };

class DmmRanker final : public Ranker {
 public:
  DmmRanker(const RankingConfig& config, DmmScore score)
      : dmm_(config.dmm), verify_(config.verify), bits_per_point_(config.bits_per_point), score_(score) {
    validate(dmm_);
    validate(verify_);
  }

  void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress) override {
    maps_ = prepare_from_points<PreparedMap>(maps, num_threads, progress, "dmm", "grids",
                                             [&](const Points2& points) { return prepare_map(points, dmm_); });
    mean_points_ = mean_points(maps);
    if (score_ != DmmScore::kVerified) return;
    verify_maps_.assign(maps.size(), {});
    parallel_for(
        maps.size(), num_threads,
        [&](std::size_t i) { verify_maps_[i] = VerifyMap(*maps[i].points, origins_of(maps[i]), verify_); },
        "free space", progress);
  }

  double bits_per_map() const override { return bits_per_point_ * mean_points_; }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    if (query.points == nullptr) throw InputError("dmm: the query has no points");
    Ranking r;
    auto t0 = Clock::now();
    const PreparedQuery prepared = prepare_query(*query.points, dmm_);
    r.prep_ms = ms_since(t0);
    t0 = Clock::now();
    std::vector<DmmResult> results;
    if (score_ == DmmScore::kVerified) {
      const VerifyMap query_verify(*query.points, origins_of(query), verify_);
      results.resize(candidates.size());
      r.probability.resize(candidates.size());
      r.runner_up.resize(candidates.size());
      std::vector<double> pair_ms(candidates.size(), 0.0);
      parallel_for(candidates.size(), options.num_threads, [&](std::size_t j) {
        const std::size_t c = candidates[j];
        std::optional<VerifiedPair> kept;
        if (options.reuse != nullptr) kept = options.reuse->find(options.query_index, c);
        if (!kept) {
          const auto p0 = Clock::now();
          const VerifiedDmm v = verify_dmm(prepared, maps_.at(c), query_verify, verify_maps_.at(c), verify_);
          kept.emplace();
          kept->direct = v.eq1;
          kept->direct.T_map_query = v.best.T_map_query;
          kept->direct.inlier_fraction = v.best.terms.query.occupied;
          kept->direct.inliers = static_cast<int>(std::lround(kept->direct.inlier_fraction * prepared.num_points));
          kept->probability = v.best.probability;
          kept->runner_up = v.runner_up;
          kept->ms = ms_since(p0);
          if (options.reuse != nullptr) options.reuse->insert(options.query_index, c, *kept);
        }
        results[j] = kept->direct;
        r.probability[j] = kept->probability;
        r.runner_up[j] = kept->runner_up;
        pair_ms[j] = kept->ms;
      });
      r.match_ms = options.reuse != nullptr ? std::accumulate(pair_ms.begin(), pair_ms.end(), 0.0) : ms_since(t0);
      for (std::size_t j = 0; j < results.size(); ++j)
        r.scores.push_back(*r.probability[j]), r.direct.emplace_back(results[j]);
      return r;
    }
    if (score_ == DmmScore::kExhaustive) {
      results.resize(candidates.size());
      parallel_for(candidates.size(), options.num_threads,
                   [&](std::size_t j) { results[j] = match_exhaustive(prepared, maps_.at(candidates[j])); });
    } else {
      std::vector<const PreparedMap*> chosen;
      for (std::size_t c : candidates) chosen.push_back(&maps_.at(c));
      results = match_dmm_many(prepared, chosen, options.num_threads == 1 ? options.top_k : 0,
                               options.num_threads);
    }
    r.match_ms = ms_since(t0);
    for (const DmmResult& d : results) r.scores.push_back(d.inliers), r.direct.emplace_back(d);
    return r;
  }

 private:
  DmmConfig dmm_;
  VerifyConfig verify_;
  double bits_per_point_;
  DmmScore score_;
  std::vector<PreparedMap> maps_;
  std::vector<VerifyMap> verify_maps_;
  double mean_points_ = 0;
};

class RansacRanker final : public Ranker {
 public:
  explicit RansacRanker(const RankingConfig& config)
      : ransac_(config.ransac), bits_per_point_(config.bits_per_point) {
    validate(ransac_);
  }

  void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress) override {
    maps_ = prepare_from_points<PreparedRansacMap>(
        maps, num_threads, progress, "dmm-ransac", "ransac grids",
        [&](const Points2& points) { return prepare_ransac_map(points, ransac_); });
    mean_points_ = mean_points(maps);
  }

  double bits_per_map() const override { return bits_per_point_ * mean_points_; }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    if (query.points == nullptr) throw InputError("dmm-ransac: the query has no points");
    Ranking r;
    const auto t0 = Clock::now();
    std::vector<DmmResult> results(candidates.size());
    parallel_for(candidates.size(), options.num_threads, [&](std::size_t j) {
      results[j] = match_dmm_ransac(*query.points, maps_.at(candidates[j]), ransac_);
    });
    r.match_ms = ms_since(t0);
    for (const DmmResult& d : results) r.scores.push_back(d.inliers), r.direct.emplace_back(d);
    return r;
  }

 private:
  DmmRansacConfig ransac_;
  double bits_per_point_;
  std::vector<PreparedRansacMap> maps_;
  double mean_points_ = 0;
};

// dmm, dmm-ransac and dmm-exhaustive take no arguments; `label` is the paper's name.
void parse_direct(const std::string& text, const std::vector<std::string>& args, MethodSpec& m, const char* label) {
  if (!args.empty()) throw InputError("method '" + text + "': " + m.name + " takes no arguments");
  m.spec = m.name;
  m.label = label;
  m.traits.needs_points = true;
  m.traits.gives_pose = true;
}

}  // namespace

const MethodEntry& dmm_method() {
  static const MethodEntry entry{
      "dmm", "dmm[:eq1]",
      [](const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
        if (args.size() == 1 && args[0] == "eq1") {  // the paper's score
          parse_direct(text, {}, m, "dMM Eq. 1");
          m.spec = "dmm:eq1";
          return;
        }
        parse_direct(text, args, m, "dMM");
        m.traits.calibrated = true;
      },
      [](const MethodSpec& m, const RankingConfig& c) {
        return std::unique_ptr<Ranker>(
            new DmmRanker(c, m.traits.calibrated && c.verify_dmm ? DmmScore::kVerified : DmmScore::kEq1));
      }};
  return entry;
}

const MethodEntry& dmm_exhaustive_method() {
  static const MethodEntry entry{
      "dmm-exhaustive", "dmm-exhaustive",
      [](const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
        parse_direct(text, args, m, "dMM-exhaustive");
      },
      [](const MethodSpec&, const RankingConfig& c) { return std::unique_ptr<Ranker>(new DmmRanker(c, DmmScore::kExhaustive)); }};
  return entry;
}

const MethodEntry& dmm_ransac_method() {
  static const MethodEntry entry{
      "dmm-ransac", "dmm-ransac",
      [](const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
        parse_direct(text, args, m, "dMM-RANSAC");
      },
      [](const MethodSpec&, const RankingConfig& c) { return std::unique_ptr<Ranker>(new RansacRanker(c)); }};
  return entry;
}

}  // namespace partslam
