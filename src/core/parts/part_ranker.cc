// The paper's part descriptors as rankers (docs/DESIGN.md, "Schemes"; paper Eqs. 3-6):
//   imm:K  the query and every stored map as their top-K parts, as a database stores them;
//   hmm:K  the query with up to RankingConfig::hmm_query_parts parts at full precision (the local map is at
//          hand online), every stored map as its top-K parts.
// Stored maps go through RankingConfig::codec when it is set (what a database would hold). The whole stored
// database is scored per query (DescriptorDatabase::score_all), as a deployed system would; the time reported
// for the candidates is that time's share of them.
#include <algorithm>

#include "core/parts/descriptor_database.h"
#include "core/error.h"
#include "core/timing.h"
#include "core/matching/ranking.h"

namespace partslam {
namespace {

class PartRanker final : public Ranker {
 public:
  PartRanker(const MethodSpec& method, const RankingConfig& config) : method_(method), config_(config) {
    validate(config_);
  }

  void prepare(std::span<const MapView> maps, int /*num_threads*/, const Progress& /*progress*/) override {
    std::vector<MapDescriptor> stored(maps.size());
    for (std::size_t i = 0; i < maps.size(); ++i) {
      if (maps[i].parts == nullptr) throw InputError(method_.label() + ": map " + std::to_string(i) + " has no parts");
      stored[i] = stored_form(*maps[i].parts);
    }
    DescriptorDatabaseConfig dbc;
    dbc.parts_per_map = method_.parts;
    database_ = DescriptorDatabase(stored, dbc);
  }

  double bits_per_map() const override {
    return packed_bits(method_.parts, config_.codec.value_or(CodecConfig{}));
  }

  Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
               const RankOptions& options) const override {
    if (query.parts == nullptr) throw InputError(method_.label() + ": the query has no parts");
    const MapDescriptor descriptor = method_.name == "imm"
                                         ? stored_form(*query.parts)
                                         : select_top_parts(*query.parts, config_.hmm_query_parts);
    Ranking r;
    const auto t0 = Clock::now();
    const std::vector<float> all =
        database_.score_all(descriptor, method_.matcher, {options.num_threads, config_.origin_gate});
    const double ms = ms_since(t0);
    for (std::size_t c : candidates) r.scores.push_back(all.at(c));
    r.match_ms = all.empty() ? 0.0 : ms * static_cast<double>(candidates.size()) / static_cast<double>(all.size());
    return r;
  }

 private:
  MapDescriptor stored_form(const std::vector<Part>& parts) const {
    MapDescriptor top = select_top_parts(parts, method_.parts);
    return config_.codec ? decode(encode(top, *config_.codec), *config_.codec) : top;
  }

  MethodSpec method_;
  RankingConfig config_;
  DescriptorDatabase database_;
};

constexpr int kMaxParts = 100;

void parse_parts(const std::string& text, const std::vector<std::string>& args, MethodSpec& m) {
  if (args.empty() || args.size() > 2) throw InputError("method '" + text + "': expected " + m.name + ":K[:matcher]");
  const bool imm = m.name == "imm";
  m.parts = parse_spec_int(text, args[0], "K (parts per map)", 1, kMaxParts);
  m.matcher = args.size() == 2 ? parse_spec_matcher(text, args[1])
              : imm            ? Matcher::kSumMax
                               : Matcher::kSumMaxWeighted;
  m.spec = m.name + ":" + std::to_string(m.parts) + ":" + matcher_spec_name(m.matcher);
  const Matcher usual = imm ? Matcher::kSumMax : Matcher::kSumMaxWeighted;
  m.name_label = (m.matcher == usual ? "" : std::string(matcher_label(m.matcher)) + " ") + (imm ? "iMM" : "hMM") +
                 " cpd:" + std::to_string(m.parts);
  m.needs_parts = true;
}

std::unique_ptr<Ranker> make_part_ranker(const MethodSpec& m, const RankingConfig& c) {
  return std::make_unique<PartRanker>(m, c);
}

}  // namespace

const MethodEntry& imm_method() {
  static const MethodEntry entry{"imm", "imm:K[:maxmax|summax|smw]", parse_parts, make_part_ranker};
  return entry;
}

const MethodEntry& hmm_method() {
  static const MethodEntry entry{"hmm", "hmm:K[:maxmax|summax|smw]", parse_parts, make_part_ranker};
  return entry;
}

}  // namespace partslam
