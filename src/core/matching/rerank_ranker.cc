// rerank:R:SPEC (docs/DESIGN.md, "Schemes"; the paper's rerank-R): a succinct method ranks every candidate,
// then its top R are reordered by dMM and put above all others (ties in dMM keep the first stage's order).
// rerank:R:K is the paper's spelling (first stage hmm:K). The stored form is both methods'.
#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/matching/ranking.h"

namespace partslam {
namespace {

class RerankRanker final : public Ranker {
 public:
  RerankRanker(const MethodSpec& method, const RankingConfig& config)
      : rerank_(method.rerank),
        first_(make_ranker(method.stages.at(0), config)),
        direct_(make_ranker(parse_method_spec("dmm"), config)) {}

  void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress) override {
    first_->prepare(maps, num_threads, progress);
    direct_->prepare(maps, num_threads, progress);
  }

  double bits_per_map() const override { return first_->bits_per_map() + direct_->bits_per_map(); }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    Ranking r = first_->rank(query, candidates, {options.num_threads, 0});
    r.shortlist_scores = r.scores;
    std::vector<std::size_t> order = ranking_order(r.scores);
    order.resize(std::min<std::size_t>(order.size(), static_cast<std::size_t>(rerank_)));
    std::vector<std::size_t> shortlist;
    for (std::size_t j : order) shortlist.push_back(candidates[j]);
    const Ranking d = direct_->rank(query, shortlist, {options.num_threads, 0});
    r.direct.assign(candidates.size(), std::nullopt);
    // The top R move above every other map, ordered by dMM; the first stage breaks dMM ties.
    for (std::size_t j = 0; j < order.size(); ++j) {
      r.scores[order[j]] = 1e9 + d.scores[j] * 1e3 + r.shortlist_scores[order[j]];
      r.direct[order[j]] = d.direct[j];
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
  m.rerank = parse_spec_int(text, args[0], "R (maps to rerank)", 1, 1000000);
  std::string stage = "succinct";
  const auto digits = [](const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; });
  };
  if (args.size() == 2 && digits(args[1])) {
    stage = "hmm:" + args[1];
  } else if (args.size() >= 2) {
    stage.clear();
    for (std::size_t i = 1; i < args.size(); ++i) stage += (i > 1 ? ":" : "") + args[i];
  }
  MethodSpec first = parse_method_spec(stage);
  if (first.name == "rerank" || first.needs_points)
    throw InputError("method '" + text + "': the first stage of a rerank must be a succinct method, got '" + stage + "'");
  m.parts = first.parts;
  m.matcher = first.matcher;
  m.needs_points = true;
  m.needs_parts = first.needs_parts;
  m.spec = "rerank:" + std::to_string(m.rerank) + ":" + first.spec;
  if (first.name == "hmm" && first.matcher == Matcher::kSumMaxWeighted) {
    m.spec = "rerank:" + std::to_string(m.rerank) + ":" + std::to_string(first.parts);
  }
  m.name_label = "rerank" + std::to_string(m.rerank) + " " + first.label();
  m.stages = {std::move(first)};
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
