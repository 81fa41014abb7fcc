// The method registry: every ranking method, one table line each (registry.cc). A method is one file holding
// its ranker (a class deriving from Ranker, core/ranking/ranking.h), its options (a struct deriving from
// MethodOptions) and a MethodEntry function that parses its spec into a MethodSpec (name, label, traits,
// options) and makes its ranker. Adding a method is that file plus one line in the table; nothing else
// dispatches on a method's name: callers decide on MethodSpec::traits.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace partslam {

struct MethodSpec;  // core/ranking/method_spec.h, whose parsing looks methods up here
class Ranker;
struct RankingConfig;

/// One registered method: how its spec is parsed and its ranker made.
struct MethodEntry {
  std::string_view name;    ///< first field of the spec
  std::string_view syntax;  ///< for help and errors, e.g. "imm:K[:maxmax|summax|smw]"
  /// Fills spec's spec, label, traits and options from the fields after the name (spec.name is set); throws
  /// InputError naming `text`.
  void (*parse)(const std::string& text, const std::vector<std::string>& args, MethodSpec& spec);
  /// The ranker of a spec this entry parsed.
  std::unique_ptr<Ranker> (*make)(const MethodSpec& spec, const RankingConfig& config);
};

/// Every method, in the order `--help` lists them.
const std::vector<MethodEntry>& method_registry();
/// The entry named `name`, or nullptr.
const MethodEntry* find_method(std::string_view name);
/// "dmm, dmm-ransac, ...": every method's syntax, for help texts.
std::string method_syntax_list();

}  // namespace partslam
