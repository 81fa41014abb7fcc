// Scan Context (Kim & Kim, IROS 2018; core/matching/scan_context.h) as a ranker: `sc` and `sc:128`.
#include "core/ranking/scan_context_ranker.h"

#include <algorithm>
#include <numeric>

#include "core/error.h"
#include "core/timing.h"

namespace partslam {
namespace {

class ScanContextRanker final : public Ranker {
 public:
  explicit ScanContextRanker(const ScanContextConfig& config) : config_(config) { validate(config_); }

  void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress) override {
    maps_ = prepare_from_points<ScanContext>(
        maps, num_threads, progress, "scan context", "scan contexts",
        [&](const Points2& points) { return make_scan_context(points, config_); });
  }

  /// The bins only: the ring key, column norms and masks are recomputed from them.
  double bits_per_map() const override {
    return static_cast<double>(config_.rings) * config_.sectors * (config_.binary ? 1.0 : 8.0);
  }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    if (query.points == nullptr) throw InputError("scan context: the query has no points");
    Ranking r;
    auto t0 = Clock::now();
    const ScanContext q = make_scan_context(*query.points, config_);
    r.prep_ms = ms_since(t0);
    t0 = Clock::now();
    // Step 1: the ring-key shortlist (ties keep the candidates' order).
    std::vector<std::size_t> order(candidates.size());
    std::iota(order.begin(), order.end(), 0);
    const std::size_t keep = config_.shortlist == 0
                                 ? order.size()
                                 : std::min(order.size(), static_cast<std::size_t>(config_.shortlist));
    std::vector<double> key(candidates.size(), 0.0);
    if (keep < order.size()) {
      for (std::size_t j = 0; j < candidates.size(); ++j)
        key[j] = ring_key_distance(q, maps_.at(candidates[j]));
      std::stable_sort(order.begin(), order.end(),
                       [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
      order.resize(keep);
    }
    // Step 2: the column-shift distance over the shortlist; the rest below it, in ring-key order.
    r.scores.resize(candidates.size());
    for (std::size_t j = 0; j < candidates.size(); ++j) r.scores[j] = kScanContextShortlistOut - key[j];
    parallel_for(order.size(), options.num_threads, [&](std::size_t k) {
      const std::size_t j = order[k];
      r.scores[j] = -match_scan_contexts(q, maps_.at(candidates[j])).distance;
    });
    r.match_ms = ms_since(t0);
    return r;
  }

 private:
  ScanContextConfig config_;
  std::vector<ScanContext> maps_;
};

// The configuration as a method's options.
struct ScanContextOptions final : MethodOptions {
  ScanContextConfig config;
};

// sc (the native descriptor) or sc:128 (a 128-bit one). The stored form is the descriptor: its ranker
// describes the points given, so it needs no points at match time (traits.needs_points stays false).
void parse_scan_context(const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
  if (args.size() > 1) throw InputError("method '" + text + "': expected sc or sc:128");
  const int bits = args.empty() ? 0 : parse_spec_int(text, args[0], "size (bits; only 128 is defined)", 128, 128);
  m.spec = bits == 0 ? "sc" : "sc:128";
  m.label = bits == 0 ? "Scan Context" : "Scan Context 128";
  m.traits.stage_score = "sc score";
  auto o = std::make_shared<ScanContextOptions>();
  o->config = bits == 128 ? scan_context_128_config() : ScanContextConfig{};
  m.options = std::move(o);
}

}  // namespace

std::unique_ptr<Ranker> make_scan_context_ranker(const ScanContextConfig& config) {
  return std::make_unique<ScanContextRanker>(config);
}

const MethodEntry& scan_context_method() {
  static const MethodEntry entry{
      "sc", "sc[:128]", parse_scan_context, [](const MethodSpec& m, const RankingConfig&) {
        return make_scan_context_ranker(m.options_as<ScanContextOptions>().config);
      }};
  return entry;
}

}  // namespace partslam
