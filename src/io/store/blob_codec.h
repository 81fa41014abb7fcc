// Byte encodings of the map database's blobs, little-endian whatever the host:
//   points:     float32 x, float32 y per point (8 bytes a point). Rounding to float32 moves a point by at
//               most |coordinate| * 2^-24, i.e. < 0.4 um inside a 12.8 m submap, < 6 um at 100 m.
//   timestamps: float64 per value (8 bytes), exact.
// Decoders check the length against what the caller expects and throw InputError naming the context.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/types.h"

namespace partslam::io {

using Bytes = std::vector<std::uint8_t>;

/// Throws InputError when a coordinate is not finite or does not fit in a float32.
Bytes encode_points_f32(const Points2& points, const std::string& context);

/// Decodes exactly expected_count points; throws InputError "<context>: ..." on a length mismatch or a
/// non-finite coordinate.
Points2 decode_points_f32(std::span<const std::uint8_t> bytes, std::size_t expected_count,
                          const std::string& context);

Bytes encode_f64(const std::vector<double>& values);

/// Throws InputError "<context>: ..." when the length is not a multiple of 8.
std::vector<double> decode_f64(std::span<const std::uint8_t> bytes, const std::string& context);

}  // namespace partslam::io
