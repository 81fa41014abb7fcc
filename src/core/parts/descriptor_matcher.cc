#include "core/parts/descriptor_matcher.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace partslam {

const char* to_string(Matcher matcher) {
  switch (matcher) {
    case Matcher::kMaxMax:
      return "max-max";
    case Matcher::kSumMax:
      return "sum-max";
    case Matcher::kSumMaxWeighted:
      return "sum-max-weighted";
  }
  return "?";
}

Matcher matcher_from_string(std::string_view name) {
  if (name == "max-max" || name == "mm") return Matcher::kMaxMax;
  if (name == "sum-max" || name == "sm") return Matcher::kSumMax;
  if (name == "sum-max-weighted" || name == "smw") return Matcher::kSumMaxWeighted;
  throw InputError("matcher: unknown name '" + std::string(name) +
                   "' (expected max-max, sum-max or sum-max-weighted)");
}

double region_similarity(const Box2& a, const Box2& b) {
  const double area_a = a.area(), area_b = b.area();
  if (!(area_a > 0) || !(area_b > 0)) return 0.0;
  const Box2 overlap{std::max(a.x_min, b.x_min), std::min(a.x_max, b.x_max), std::max(a.y_min, b.y_min),
                     std::min(a.y_max, b.y_max)};
  return overlap.area() / std::sqrt(area_a * area_b);
}

bool passes_origin_gate(const Part& query, const Part& stored, double origin_gate) {
  if (origin_gate <= 0) return true;
  const Vec2 d = dictionary_origin(query) - dictionary_origin(stored);
  return std::abs(d.x()) <= origin_gate && std::abs(d.y()) <= origin_gate;
}

double match_score(const MapDescriptor& query, const MapDescriptor& stored, Matcher matcher, double origin_gate) {
  if (!(origin_gate >= 0) || !std::isfinite(origin_gate)) throw InputError("matcher: origin_gate must be >= 0 [m]");
  double score = 0.0;
  for (const Part& q : query.parts) {
    double best = 0.0;
    for (const Part& s : stored.parts)
      if (passes_origin_gate(q, s, origin_gate))
        best = std::max(best, region_similarity(q.descriptor_box, s.descriptor_box));
    switch (matcher) {
      case Matcher::kMaxMax:
        score = std::max(score, best);
        break;
      case Matcher::kSumMax:
        score += best;
        break;
      case Matcher::kSumMaxWeighted:
        score += best * q.appearance_score;
        break;
    }
  }
  return score;
}

}  // namespace partslam
