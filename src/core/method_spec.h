// Method specs for `partslam match` and `partslam eval` (DESIGN.md, "Schemes"):
//   dmm | dmm-ransac | dmm-exhaustive          direct matching (Eq. 1)
//   imm:K[:maxmax|summax|smw]                  K parts on both sides (default Sum-Max)
//   hmm:K[:maxmax|summax|smw]                  many query parts, K stored parts (default Sum-Max-Weighted)
//   rerank:R:K                                 hMM cpd:K ranks, the top R are reordered by dMM
#pragma once

#include <string>
#include <vector>

#include "core/descriptor_matcher.h"

namespace partslam {

enum class SchemeKind { kDmm, kDmmRansac, kDmmExhaustive, kImm, kHmm, kRerank };

struct MethodSpec {
  SchemeKind scheme = SchemeKind::kDmm;
  int parts = 0;   ///< K: parts per stored map (iMM, hMM, rerank)
  int rerank = 0;  ///< R: maps reordered by dMM (rerank)
  Matcher matcher = Matcher::kSumMax;
  std::string spec;  ///< the text it was parsed from, normalised

  /// The paper's name: "dMM", "iMM cpd:3", "hMM cpd:3", "Max-Max hMM cpd:3", "rerank10 hMM cpd:3".
  std::string label() const;
  bool uses_descriptors() const { return parts > 0; }
  bool uses_points() const { return scheme != SchemeKind::kImm && scheme != SchemeKind::kHmm; }
};

/// Parses one spec; throws InputError naming the spec and what is wrong.
MethodSpec parse_method_spec(const std::string& text);

/// Parses a comma-separated list of specs.
std::vector<MethodSpec> parse_method_list(const std::string& text);

/// Largest K parts per stored map that any of the methods needs.
int max_parts(const std::vector<MethodSpec>& methods);

}  // namespace partslam
