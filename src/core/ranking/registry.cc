#include "core/ranking/registry.h"

namespace partslam {

// Each function is defined in the method's own file.
const MethodEntry& dmm_method();             // direct_ranker.cc
const MethodEntry& dmm_ransac_method();      // direct_ranker.cc
const MethodEntry& dmm_exhaustive_method();  // direct_ranker.cc
const MethodEntry& imm_method();             // part_ranker.cc
const MethodEntry& hmm_method();             // part_ranker.cc
const MethodEntry& rerank_method();          // rerank_ranker.cc
const MethodEntry& grid_method();            // grid_ranker.cc
const MethodEntry& scan_context_method();    // scan_context_ranker.cc
const MethodEntry& succinct_method();        // grid_ranker.cc

const std::vector<MethodEntry>& method_registry() {
  static const std::vector<MethodEntry> methods = {
      dmm_method(),  dmm_ransac_method(),  dmm_exhaustive_method(), imm_method(),      hmm_method(),
      rerank_method(), grid_method(),      scan_context_method(),   succinct_method(),
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

}  // namespace partslam
