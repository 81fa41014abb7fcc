// rerank:R:SPEC (docs/DESIGN.md, "Schemes"; the paper's rerank-R): a succinct method ranks every candidate,
// then its top R are reordered by dMM and put above all others (ties in dMM keep the first stage's order).
// rerank:R:K is the paper's spelling (first stage hmm:K). The stored form is both methods'.
// Tested by: core/ranking/ranking_test.cc, core/ranking/method_spec_test.cc
#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/ranking/ranking.h"

namespace partslam {
namespace {

// R and the first stage.
struct RerankOptions final : MethodOptions {
  int rerank = 0;
  MethodSpec first;
};

class RerankRanker final : public Ranker {
 public:
  RerankRanker(const MethodSpec& method, const RankingConfig& config)
      : rerank_(method.options_as<RerankOptions>().rerank),
        first_(make_ranker(method.options_as<RerankOptions>().first, config)),
        direct_(make_ranker(parse_method_spec("dmm"), config)) {}

  void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress) override {
    first_->prepare(maps, num_threads, progress);
    direct_->prepare(maps, num_threads, progress);
  }

  double bits_per_map() const override { return first_->bits_per_map() + direct_->bits_per_map(); }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    // A caller that reads only the top k (match --top K, loops) lets the first stage rank only its top R (a
    // large grid database answers through its index); every candidate is ranked otherwise (eval's ANR).
    const int first_k = options.top_k > 0 ? std::max(rerank_, options.top_k) : 0;
    Ranking r = first_->rank(query, candidates, {options.num_threads, first_k});
    r.shortlist_scores = r.scores;
    std::vector<std::size_t> order = ranking_order(r.scores);
    order.resize(std::min<std::size_t>(order.size(), static_cast<std::size_t>(rerank_)));
    std::vector<std::size_t> shortlist;
    for (std::size_t j : order) shortlist.push_back(candidates[j]);
    const Ranking d = direct_->rank(query, shortlist, {options.num_threads, 0, options.reuse, options.query_index});
    r.direct.assign(candidates.size(), std::nullopt);
    r.tiers.assign(candidates.size(), 0);
    r.probability.assign(candidates.size(), std::nullopt);
    r.runner_up.assign(candidates.size(), std::nullopt);
    // The top R move above every other map (tier 1), ordered by dMM; the first stage breaks dMM ties.
    for (std::size_t j = 0; j < order.size(); ++j) {
      r.tiers[order[j]] = 1;
      r.scores[order[j]] = d.scores[j];
      r.direct[order[j]] = d.direct[j];
      if (!d.probability.empty()) r.probability[order[j]] = d.probability[j];
      if (!d.runner_up.empty()) r.runner_up[order[j]] = d.runner_up[j];
    }
    r.prep_ms += d.prep_ms;
    r.match_ms += d.match_ms;
    return r;
  }

 private:
  int rerank_;
  std::unique_ptr<Ranker> first_, direct_;
};

void parse_rerank(const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
  if (args.empty()) throw InputError("method '" + text + "': expected rerank:R[:K|:SPEC]");
  auto o = std::make_shared<RerankOptions>();
  o->rerank = parse_spec_int(text, args[0], "R (maps to rerank)", 1, 1000000);
  std::string stage = "succinct";
  const auto digits = [](const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; });
  };
  if (args.size() == 2 && digits(args[1])) {  // rerank:R:K, the paper's spelling of rerank:R:hmm:K
    stage = "hmm:" + args[1];
  } else if (args.size() >= 2) {
    stage.clear();
    for (std::size_t i = 1; i < args.size(); ++i) stage += (i > 1 ? ":" : "") + args[i];
  }
  o->first = parse_method_spec(stage);
  const MethodSpec& first = o->first;
  if (first.traits.needs_points)
    throw InputError("method '" + text + "': the first stage of a rerank must be a succinct method, got '" + stage + "'");
  const std::string r = std::to_string(o->rerank);
  const std::string k = std::to_string(first.traits.parts);
  m.spec = "rerank:" + r + ":" + (first.spec == "hmm:" + k + ":smw" ? k : first.spec);  // the paper's spelling
  m.label = "rerank" + r + " " + first.label;
  m.traits = first.traits;
  m.traits.needs_points = true;
  m.traits.gives_pose = true;
  m.traits.calibrated = true;  // its dMM stage verifies
  m.traits.shardable = false;  // each process would shortlist its own slice
  m.traits.shortlist = o->rerank;
  m.options = std::move(o);
}

}  // namespace

const MethodEntry& rerank_method() {
  static const MethodEntry entry{"rerank", "rerank:R[:K|:SPEC]", parse_rerank,
                                 [](const MethodSpec& m, const RankingConfig& c) {
                                   return std::unique_ptr<Ranker>(new RerankRanker(m, c));
                                 }};
  return entry;
}

}  // namespace partslam
