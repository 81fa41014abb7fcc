#include "core/ranking/method_spec.h"

#include <algorithm>
#include <charconv>
#include <sstream>

#include "core/error.h"
#include "core/ranking/registry.h"

namespace partslam {
namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

}  // namespace

int parse_spec_int(const std::string& spec, const std::string& field, const std::string& what, int lo, int hi) {
  int v = 0;
  const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (ec != std::errc() || ptr != field.data() + field.size() || v < lo || v > hi) {
    throw InputError("method '" + spec + "': " + what + " must be an integer in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got '" + field + "'");
  }
  return v;
}

Matcher parse_spec_matcher(const std::string& spec, const std::string& name) {
  if (name == "maxmax") return Matcher::kMaxMax;
  if (name == "summax") return Matcher::kSumMax;
  if (name == "smw") return Matcher::kSumMaxWeighted;
  throw InputError("method '" + spec + "': unknown matcher '" + name + "' (expected maxmax, summax or smw)");
}

const char* matcher_label(Matcher m) {
  switch (m) {
    case Matcher::kMaxMax: return "Max-Max";
    case Matcher::kSumMax: return "Sum-Max";
    case Matcher::kSumMaxWeighted: return "Sum-Max-Weighted";
  }
  return "";
}

const char* matcher_spec_name(Matcher m) {
  switch (m) {
    case Matcher::kMaxMax: return "maxmax";
    case Matcher::kSumMax: return "summax";
    case Matcher::kSumMaxWeighted: return "smw";
  }
  return "";
}

MethodSpec parse_method_spec(const std::string& text) {
  std::vector<std::string> f = split(text, ':');
  if (f.empty() || f[0].empty()) throw InputError("method '" + text + "': empty method spec");
  const MethodEntry* entry = find_method(f[0]);
  if (entry == nullptr)
    throw InputError("method '" + text + "': unknown scheme '" + f[0] + "' (expected " + method_syntax_list() + ")");
  MethodSpec m;
  m.name = f[0];
  f.erase(f.begin());
  entry->parse(text, f, m);
  return m;
}

std::vector<MethodSpec> parse_method_list(const std::string& text) {
  std::vector<MethodSpec> out;
  for (const std::string& item : split(text, ',')) out.push_back(parse_method_spec(item));
  if (out.empty()) throw InputError("--methods: no method given");
  return out;
}

int max_parts(const std::vector<MethodSpec>& methods) {
  int k = 0;
  for (const MethodSpec& m : methods) k = std::max(k, m.traits.parts);
  return k;
}

}  // namespace partslam
