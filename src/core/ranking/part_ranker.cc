// The paper's part descriptors as rankers (docs/DESIGN.md, "Schemes"; paper Eqs. 3-6):
//   imm:K  the query and every stored map as their top-K parts, as a database stores them;
//   hmm:K  the query with up to PartsConfig::hmm_query_parts parts at full precision (the local map is at
//          hand online), every stored map as its top-K parts.
// Stored maps go through PartsConfig::codec when it is set (what a database would hold). The whole stored
// database is scored per query (DescriptorDatabase::score_all), as a deployed system would; the time reported
// for the candidates is that time's share of them.
// Tested by: core/ranking/ranking_test.cc, core/ranking/method_spec_test.cc
#include <algorithm>

#include "core/parts/descriptor_database.h"
#include "core/error.h"
#include "core/timing.h"
#include "core/ranking/ranking.h"

namespace partslam {
namespace {

// K and the matcher (Eqs. 3-6); the query's parts are the method's traits.
struct PartOptions final : MethodOptions {
  int parts = 0;
  Matcher matcher = Matcher::kSumMax;
};

class PartRanker final : public Ranker {
 public:
  PartRanker(const MethodSpec& method, const RankingConfig& config)
      : label_(method.label),
        options_(method.options_as<PartOptions>()),
        query_parts_(method.traits.query_parts),
        config_(config.parts) {
    validate(config_);
  }

  void prepare(std::span<const MapView> maps, int /*num_threads*/, const Progress& /*progress*/) override {
    std::vector<MapDescriptor> stored(maps.size());
    for (std::size_t i = 0; i < maps.size(); ++i) {
      if (maps[i].parts == nullptr) throw InputError(label_ + ": map " + std::to_string(i) + " has no parts");
      stored[i] = stored_form(*maps[i].parts);
    }
    DescriptorDatabaseConfig dbc;
    dbc.parts_per_map = options_.parts;
    database_ = DescriptorDatabase(stored, dbc);
  }

  double bits_per_map() const override {
    return packed_bits(options_.parts, config_.codec.value_or(CodecConfig{}));
  }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    if (query.parts == nullptr) throw InputError(label_ + ": the query has no parts");
    const MapDescriptor descriptor = query_parts_ == QueryParts::kDescriptor
                                         ? stored_form(*query.parts)
                                         : select_top_parts(*query.parts, config_.hmm_query_parts);
    Ranking r;
    const auto t0 = Clock::now();
    const std::vector<float> all =
        database_.score_all(descriptor, options_.matcher, {options.num_threads, config_.origin_gate});
    const double ms = ms_since(t0);
    for (std::size_t c : candidates) r.scores.push_back(all.at(c));
    r.match_ms = all.empty() ? 0.0 : ms * static_cast<double>(candidates.size()) / static_cast<double>(all.size());
    return r;
  }

 private:
  MapDescriptor stored_form(const std::vector<Part>& parts) const {
    MapDescriptor top = select_top_parts(parts, options_.parts);
    return config_.codec ? decode(encode(top, *config_.codec), *config_.codec) : top;
  }

  std::string label_;
  PartOptions options_;
  QueryParts query_parts_;
  PartsConfig config_;
  DescriptorDatabase database_;
};

constexpr int kMaxParts = 100;

// imm:K[:matcher] and hmm:K[:matcher]; `imm`: the query as its own K-part descriptor (else its long list).
void parse_parts(const std::string& text, const std::vector<std::string>& args, MethodSpec& m, bool imm) {
  if (args.empty() || args.size() > 2) throw InputError("method '" + text + "': expected " + m.name + ":K[:matcher]");
  auto o = std::make_shared<PartOptions>();
  o->parts = parse_spec_int(text, args[0], "K (parts per map)", 1, kMaxParts);
  const Matcher usual = imm ? Matcher::kSumMax : Matcher::kSumMaxWeighted;
  o->matcher = args.size() == 2 ? parse_spec_matcher(text, args[1]) : usual;
  const std::string kind = imm ? "iMM" : "hMM";
  m.spec = m.name + ":" + std::to_string(o->parts) + ":" + matcher_spec_name(o->matcher);
  m.label = (o->matcher == usual ? "" : std::string(matcher_label(o->matcher)) + " ") + kind + " cpd:" +
            std::to_string(o->parts);
  m.traits.needs_parts = true;
  m.traits.parts = o->parts;
  m.traits.query_parts = imm ? QueryParts::kDescriptor : QueryParts::kList;
  m.traits.stage_score = kind + " score";
  m.options = std::move(o);
}

std::unique_ptr<Ranker> make_part_ranker(const MethodSpec& m, const RankingConfig& c) {
  return std::make_unique<PartRanker>(m, c);
}

}  // namespace

const MethodEntry& imm_method() {
  static const MethodEntry entry{"imm", "imm:K[:maxmax|summax|smw]",
                                 [](const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
                                   parse_parts(text, args, m, true);
                                 },
                                 make_part_ranker};
  return entry;
}

const MethodEntry& hmm_method() {
  static const MethodEntry entry{"hmm", "hmm:K[:maxmax|summax|smw]",
                                 [](const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
                                   parse_parts(text, args, m, false);
                                 },
                                 make_part_ranker};
  return entry;
}

}  // namespace partslam
