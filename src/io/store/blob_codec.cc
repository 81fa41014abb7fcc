#include "io/store/blob_codec.h"

#include <bit>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace partslam::io {
namespace {

template <typename Word>
void put_le(Word word, Bytes& out) {
  for (std::size_t i = 0; i < sizeof(Word); ++i) out.push_back(static_cast<std::uint8_t>(word >> (8 * i)));
}

template <typename Word>
Word get_le(const std::uint8_t* in) {
  Word word = 0;
  for (std::size_t i = 0; i < sizeof(Word); ++i) word |= static_cast<Word>(in[i]) << (8 * i);
  return word;
}

}  // namespace

Bytes encode_points_f32(const Points2& points, const std::string& context) {
  Bytes out;
  out.reserve(points.size() * 8);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (const double v : {points[i].x(), points[i].y()}) {
      if (!std::isfinite(v) || std::abs(v) > std::numeric_limits<float>::max()) {
        throw InputError(context + ": point " + std::to_string(i) + " has a non-finite or huge coordinate (" +
                         std::to_string(v) + ")");
      }
      put_le(std::bit_cast<std::uint32_t>(static_cast<float>(v)), out);
    }
  }
  return out;
}

Points2 decode_points_f32(std::span<const std::uint8_t> bytes, std::size_t expected_count,
                          const std::string& context) {
  if (bytes.size() != expected_count * 8) {
    throw InputError(context + ": points blob holds " + std::to_string(bytes.size()) + " bytes, expected " +
                     std::to_string(expected_count * 8) + " for " + std::to_string(expected_count) +
                     " points (corrupt database)");
  }
  Points2 points(expected_count);
  for (std::size_t i = 0; i < expected_count; ++i) {
    const float x = std::bit_cast<float>(get_le<std::uint32_t>(&bytes[8 * i]));
    const float y = std::bit_cast<float>(get_le<std::uint32_t>(&bytes[8 * i + 4]));
    if (!std::isfinite(x) || !std::isfinite(y)) {
      throw InputError(context + ": point " + std::to_string(i) + " is not finite (corrupt database)");
    }
    points[i] = Vec2(x, y);
  }
  return points;
}

Bytes encode_f64(const std::vector<double>& values) {
  Bytes out;
  out.reserve(values.size() * 8);
  for (const double v : values) put_le(std::bit_cast<std::uint64_t>(v), out);
  return out;
}

std::vector<double> decode_f64(std::span<const std::uint8_t> bytes, const std::string& context) {
  if (bytes.size() % 8 != 0) {
    throw InputError(context + ": blob of " + std::to_string(bytes.size()) +
                     " bytes is not a whole number of float64 values (corrupt database)");
  }
  std::vector<double> values(bytes.size() / 8);
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = std::bit_cast<double>(get_le<std::uint64_t>(&bytes[8 * i]));
  }
  return values;
}

}  // namespace partslam::io
