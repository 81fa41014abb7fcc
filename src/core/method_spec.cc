#include "core/method_spec.h"

#include <algorithm>
#include <charconv>
#include <sstream>

#include "core/error.h"

namespace partslam {
namespace {

constexpr int kMaxParts = 100;

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

int parse_count(const std::string& spec, const std::string& field, const std::string& what, int lo, int hi) {
  int v = 0;
  const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (ec != std::errc() || ptr != field.data() + field.size() || v < lo || v > hi) {
    throw InputError("method '" + spec + "': " + what + " must be an integer in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got '" + field + "'");
  }
  return v;
}

Matcher parse_matcher(const std::string& spec, const std::string& name) {
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

const char* matcher_name(Matcher m) {
  switch (m) {
    case Matcher::kMaxMax: return "maxmax";
    case Matcher::kSumMax: return "summax";
    case Matcher::kSumMaxWeighted: return "smw";
  }
  return "";
}

}  // namespace

std::string MethodSpec::label() const {
  const std::string cpd = " cpd:" + std::to_string(parts);
  switch (scheme) {
    case SchemeKind::kDmm: return "dMM";
    case SchemeKind::kDmmRansac: return "dMM-RANSAC";
    case SchemeKind::kDmmExhaustive: return "dMM-exhaustive";
    case SchemeKind::kImm:
      return (matcher == Matcher::kSumMax ? "" : std::string(matcher_label(matcher)) + " ") + "iMM" + cpd;
    case SchemeKind::kHmm:
      return (matcher == Matcher::kSumMaxWeighted ? "" : std::string(matcher_label(matcher)) + " ") +
             "hMM" + cpd;
    case SchemeKind::kRerank: return "rerank" + std::to_string(rerank) + " hMM" + cpd;
  }
  return spec;
}

MethodSpec parse_method_spec(const std::string& text) {
  const std::vector<std::string> f = split(text, ':');
  MethodSpec m;
  if (f.empty()) throw InputError("method '': empty method spec");
  const std::string& kind = f[0];
  if (kind == "dmm" || kind == "dmm-ransac" || kind == "dmm-exhaustive") {
    if (f.size() != 1) throw InputError("method '" + text + "': " + kind + " takes no arguments");
    m.scheme = kind == "dmm" ? SchemeKind::kDmm
               : kind == "dmm-ransac" ? SchemeKind::kDmmRansac : SchemeKind::kDmmExhaustive;
    m.spec = kind;
  } else if (kind == "imm" || kind == "hmm") {
    if (f.size() < 2 || f.size() > 3) throw InputError("method '" + text + "': expected " + kind + ":K[:matcher]");
    m.scheme = kind == "imm" ? SchemeKind::kImm : SchemeKind::kHmm;
    m.parts = parse_count(text, f[1], "K (parts per map)", 1, kMaxParts);
    m.matcher = f.size() == 3 ? parse_matcher(text, f[2])
                : m.scheme == SchemeKind::kImm ? Matcher::kSumMax
                                               : Matcher::kSumMaxWeighted;
    m.spec = kind + ":" + std::to_string(m.parts) + ":" + matcher_name(m.matcher);
  } else if (kind == "rerank") {
    if (f.size() != 3) throw InputError("method '" + text + "': expected rerank:R:K");
    m.scheme = SchemeKind::kRerank;
    m.rerank = parse_count(text, f[1], "R (maps to rerank)", 1, 1000000);
    m.parts = parse_count(text, f[2], "K (parts per map)", 1, kMaxParts);
    m.matcher = Matcher::kSumMaxWeighted;
    m.spec = "rerank:" + std::to_string(m.rerank) + ":" + std::to_string(m.parts);
  } else {
    throw InputError("method '" + text + "': unknown scheme '" + kind +
                     "' (expected dmm, dmm-ransac, dmm-exhaustive, imm:K, hmm:K or rerank:R:K)");
  }
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
  for (const MethodSpec& m : methods) k = std::max(k, m.parts);
  return k;
}

}  // namespace partslam
