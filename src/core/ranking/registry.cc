#include "core/ranking/registry.h"

namespace partslam {

// The table: one line per method, naming the function (defined in the method's own file) that returns its entry,
// in the order `--help` lists them.
#define PARTSLAM_METHODS(METHOD)                                                              \
  METHOD(dmm_method)            /* direct_ranker.cc */                                        \
  METHOD(dmm_ransac_method)     /* direct_ranker.cc */                                        \
  METHOD(dmm_exhaustive_method) /* direct_ranker.cc */                                        \
  METHOD(imm_method)            /* part_ranker.cc */                                          \
  METHOD(hmm_method)            /* part_ranker.cc */                                          \
  METHOD(rerank_method)         /* rerank_ranker.cc */                                        \
  METHOD(grid_method)           /* grid_ranker.cc */                                          \
  METHOD(scan_context_method)   /* scan_context_ranker.cc */                                  \
  METHOD(succinct_method)       /* grid_ranker.cc */

#define PARTSLAM_DECLARE(entry) const MethodEntry& entry();
#define PARTSLAM_LIST(entry) entry(),
PARTSLAM_METHODS(PARTSLAM_DECLARE)

const std::vector<MethodEntry>& method_registry() {
  static const std::vector<MethodEntry> methods = {PARTSLAM_METHODS(PARTSLAM_LIST)};
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
