// A parsed method spec for `partslam match`, `partslam eval`, loop closures and the bindings (docs/DESIGN.md,
// "Schemes"). A spec is a method name and colon-separated arguments ("imm:3", "rerank:20:succinct",
// "grid:7:hub=50"); the registry (core/ranking/registry.h) says which names exist and how each is parsed.
//
// A MethodSpec is what callers may look at: the normalised text, the paper's label and the method's traits,
// i.e. what it can do and what it needs. The method's own parsed options are opaque to everyone but its ranker
// (MethodSpec::options, read back with options_as<T>()), so nothing outside the registry's files needs to
// know a method by its name.
#pragma once

#include <memory>
#include <string>
#include <typeinfo>
#include <vector>

#include "core/error.h"
#include "core/parts/descriptor_matcher.h"

namespace partslam {

/// Which of the query's parts a part-based method reads.
enum class QueryParts {
  kNone,        ///< none (point-based methods)
  kDescriptor,  ///< the query's own K-part descriptor, as a stored map's (iMM)
  kList,        ///< the query's long part list (hMM: the local map is at hand online)
};

/// What a method can do and what it needs: everything a caller decides on.
struct MethodTraits {
  bool needs_points = false;  ///< the stored form is built from every map's points at run time (direct matching)
  bool needs_parts = false;   ///< needs every map's CPD parts (a part descriptor)
  bool gives_pose = false;    ///< returns T_map_query (a dMM result) for the candidates it matches directly
  /// its score of a directly matched candidate is the calibrated probability that the query is the same place
  /// at that pose (Ranking::probability; the verified dMM and a rerank over it)
  bool calibrated = false;
  /// The score of a stored map depends on that map and the query alone, so stored maps can be split between
  /// processes (mpirun); false when the method learns from all stored maps or shortlists among them.
  bool shardable = true;
  /// rerank:R: R, the candidates it matches directly (a caller that reads only those asks for its top R);
  /// 0: every candidate the method scores can carry a direct match.
  int shortlist = 0;
  QueryParts query_parts = QueryParts::kNone;
  int parts = 0;  ///< K: parts per stored map it reads (0: none)
  /// The name of the score a succinct stage gives ("iMM score"), shown beside a pose; empty when the method's
  /// score is the direct match's.
  std::string stage_score;
};

/// A method's own parsed options: each method derives its options from this (e.g. rerank's R and first stage).
struct MethodOptions {
  virtual ~MethodOptions() = default;
};

struct MethodSpec {
  std::string name;   ///< registry name: the spec's first field
  std::string spec;   ///< the text it was parsed from, normalised
  std::string label;  ///< the paper's name: "dMM", "iMM cpd:3", "Max-Max hMM cpd:3", "rerank10 hMM cpd:3"
  MethodTraits traits;
  std::shared_ptr<const MethodOptions> options;  ///< the method's own options (its ranker reads them)

  /// The options as the method's own type; throws InputError when they are of another type (a spec not made
  /// by that method's parser).
  template <typename T>
  const T& options_as() const {
    const T* o = dynamic_cast<const T*>(options.get());
    if (o == nullptr) throw InputError("method '" + spec + "': its options are not " + typeid(T).name());
    return *o;
  }
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
