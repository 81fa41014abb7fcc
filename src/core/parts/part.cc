#include "core/parts/part.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace partslam {

MapDescriptor select_top_parts(std::vector<Part> parts, int k) {
  if (k < 0) throw InputError("select_top_parts: k must be >= 0, got " + std::to_string(k));
  std::stable_sort(parts.begin(), parts.end(),
                   [](const Part& a, const Part& b) { return a.appearance_score > b.appearance_score; });
  if (parts.size() > static_cast<std::size_t>(k)) parts.resize(static_cast<std::size_t>(k));
  return MapDescriptor{std::move(parts)};
}

}  // namespace partslam
