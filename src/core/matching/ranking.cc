#include "core/matching/ranking.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"

namespace partslam {

// ---- The method registry: one line per method. Each function is defined in the method's own file. ----
const MethodEntry& dmm_method();             // direct_ranker.cc
const MethodEntry& dmm_ransac_method();      // direct_ranker.cc
const MethodEntry& dmm_exhaustive_method();  // direct_ranker.cc
const MethodEntry& imm_method();             // part_ranker.cc
const MethodEntry& hmm_method();             // part_ranker.cc
const MethodEntry& rerank_method();          // rerank_ranker.cc
const MethodEntry& grid_method();            // grid_descriptor.cc
const MethodEntry& scan_context_method();    // scan_context.cc
const MethodEntry& succinct_method();        // grid_descriptor.cc

const std::vector<MethodEntry>& method_registry() {
  static const std::vector<MethodEntry> methods = {
      dmm_method(), dmm_ransac_method(), dmm_exhaustive_method(), imm_method(), hmm_method(), rerank_method(),
      grid_method(), scan_context_method(), succinct_method(),
  };
  return methods;
}

const MethodEntry* find_method(std::string_view name) {
  for (const MethodEntry& e : method_registry())
    if (e.name == name) return &e;
  return nullptr;
}

std::string method_syntax_list() {
  std::string out;
  for (const MethodEntry& e : method_registry()) out += (out.empty() ? "" : ", ") + std::string(e.syntax);
  return out;
}

void validate(const RankingConfig& config) {
  validate(config.dmm);
  validate(config.ransac);
  if (config.codec) validate(*config.codec);
  if (config.hmm_query_parts < 1) throw InputError("ranking: hmm_query_parts must be >= 1");
  if (!(config.origin_gate >= 0) || !std::isfinite(config.origin_gate))
    throw InputError("ranking: origin_gate must be a finite number >= 0 [m]");
  if (!(config.bits_per_point >= 0) || !std::isfinite(config.bits_per_point))
    throw InputError("ranking: bits_per_point must be a finite number >= 0");
}

std::unique_ptr<Ranker> make_ranker(const MethodSpec& method, const RankingConfig& config) {
  const MethodEntry* entry = find_method(method.name);
  if (entry == nullptr) throw InputError("ranking: unknown method '" + method.name + "'");
  validate(config);
  return entry->make(method, config);
}

std::vector<std::size_t> ranking_order(const std::vector<double>& scores) {
  std::vector<std::size_t> order(scores.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
  return order;
}

}  // namespace partslam
