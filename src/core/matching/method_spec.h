// Method specs for `partslam match` and `partslam eval` (docs/DESIGN.md, "Schemes"). A spec is a method name and
// colon-separated arguments; the methods and their syntax are the registry of core/matching/ranking.h:
//   dmm | dmm-ransac | dmm-exhaustive          direct matching (Eq. 1)
//   imm:K[:maxmax|summax|smw]                  K parts on both sides (default Sum-Max)
//   hmm:K[:maxmax|summax|smw]                  many query parts, K stored parts (default Sum-Max-Weighted)
//   rerank:R:K | rerank:R:SPEC                 a succinct method ranks (hmm:K, or SPEC), the top R are reordered by dMM
#pragma once

#include <string>
#include <vector>

#include "core/parts/descriptor_matcher.h"

namespace partslam {

struct MethodSpec {
  std::string name;        ///< registry name: "dmm", "imm", "hmm", "rerank", ...
  int parts = 0;           ///< K: parts per stored map (iMM, hMM, a rerank over hMM)
  int rerank = 0;          ///< R: maps reordered by dMM (rerank)
  int size = 0;            ///< the method's own size parameter (e.g. grid cells per side), 0 when it has none
  Matcher matcher = Matcher::kSumMax;
  std::vector<std::string> args;   ///< the fields after the name, as given (a ranker may re-read them)
  std::vector<MethodSpec> stages;  ///< rerank: its first-stage method
  std::string spec;        ///< the text it was parsed from, normalised
  std::string name_label;  ///< the paper's name: "dMM", "iMM cpd:3", "Max-Max hMM cpd:3", "rerank10 hMM cpd:3"
  bool needs_points = false;  ///< the stored form includes the map's points (direct matching)
  bool needs_parts = false;   ///< needs every map's CPD parts (a part descriptor)

  std::string label() const { return name_label; }
  bool uses_descriptors() const { return needs_parts; }
  bool uses_points() const { return needs_points; }
};

/// Parses one spec; throws InputError naming the spec and what is wrong.
MethodSpec parse_method_spec(const std::string& text);

/// Parses a comma-separated list of specs.
std::vector<MethodSpec> parse_method_list(const std::string& text);

/// Largest K parts per stored map that any of the methods needs.
int max_parts(const std::vector<MethodSpec>& methods);

/// For method parsers: an integer argument in [lo, hi]; throws InputError naming spec, what and the field.
int parse_spec_int(const std::string& spec, const std::string& field, const std::string& what, int lo, int hi);
/// For method parsers: "maxmax", "summax" or "smw".
Matcher parse_spec_matcher(const std::string& spec, const std::string& name);
/// "maxmax", "summax", "smw" (the spec spelling) and "Max-Max", "Sum-Max", "Sum-Max-Weighted" (the label).
const char* matcher_spec_name(Matcher matcher);
const char* matcher_label(Matcher matcher);

}  // namespace partslam
