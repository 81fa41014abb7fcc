#include "core/ranking/verified_pairs.h"

#include <string>

#include "core/error.h"

namespace partslam {

std::uint64_t VerifiedPairs::key(std::size_t query, std::size_t map) {
  constexpr std::size_t kLimit = std::size_t{1} << 32;
  if (query >= kLimit || map >= kLimit)
    throw InputError("verified pairs: map index " + std::to_string(query >= kLimit ? query : map) +
                     " out of range (at most 2^32 maps)");
  return static_cast<std::uint64_t>(query) << 32 | static_cast<std::uint64_t>(map);
}

std::optional<VerifiedPair> VerifiedPairs::find(std::size_t query, std::size_t map) const {
  const std::uint64_t k = key(query, map);
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto it = pairs_.find(k);
  if (it == pairs_.end()) return std::nullopt;
  ++hits_;
  return it->second;
}

void VerifiedPairs::insert(std::size_t query, std::size_t map, const VerifiedPair& pair) {
  const std::uint64_t k = key(query, map);
  const std::lock_guard<std::mutex> lock(mutex_);
  pairs_.emplace(k, pair);
}

std::size_t VerifiedPairs::size() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return pairs_.size();
}

std::size_t VerifiedPairs::hits() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return hits_;
}

}  // namespace partslam
