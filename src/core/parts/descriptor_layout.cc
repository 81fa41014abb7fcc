#include "core/parts/descriptor_layout.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <string>

#include "core/error.h"

namespace partslam {

namespace {

Box2 grown_bounding_box(const Points2& dictionary_points, double margin) {
  if (dictionary_points.empty()) throw InputError("codec: the dictionary map has no points");
  const Box2 box = bounding_box(dictionary_points);
  return {box.x_min - margin, box.x_max + margin, box.y_min - margin, box.y_max + margin};
}

// [lo, hi] grown to a multiple of `cell` at lo and to a whole number of cells per lattice step.
std::pair<double, double> snap_axis(double lo, double hi, double cell, int bits) {
  const double first = std::floor(lo / cell);
  const double steps = static_cast<double>((1u << bits) - 1);
  const double cells_per_step = std::max(1.0, std::ceil((hi / cell - first) / steps - 1e-9));
  return {first * cell, (first + cells_per_step * steps) * cell};
}

}  // namespace

CodecConfig dictionary_codec_config(const Points2& dictionary_points, const CodecConfig& base) {
  CodecConfig c = base;
  c.dictionary_extent = {0.0, 1.0, 0.0, 1.0};
  validate(c);  // every field but the extent, before the bit counts are used
  const Box2 grown = grown_bounding_box(dictionary_points, c.crop_size);
  const double cell = c.keypoint_resolution;
  const auto [x_min, x_max] = snap_axis(grown.x_min, grown.x_max, cell, c.origin_bits_x);
  const auto [y_min, y_max] = snap_axis(grown.y_min, grown.y_max, cell, c.origin_bits_y);
  c.dictionary_extent = {x_min, x_max, y_min, y_max};
  validate(c);
  return c;
}

CodecConfig descriptor_codec_config_v1(const Points2& dictionary_points, int k) {
  CodecConfig c;
  c.score_bits = score_bits_for_parts(k);
  c.dictionary_extent = grown_bounding_box(dictionary_points, c.crop_size);
  validate(c);
  return c;
}

int score_bits_for_parts(int k) {
  if (k < 1) throw InputError("codec: a descriptor holds K >= 1 parts, got K = " + std::to_string(k));
  return k <= kMaxUnscoredParts ? 0 : kQueryScoreBits;
}

CodecConfig descriptor_codec_config(const Points2& dictionary_points, int k, const CodecConfig& base) {
  CodecConfig c = base;
  c.score_bits = score_bits_for_parts(k);
  return dictionary_codec_config(dictionary_points, c);
}

MapDescriptor decode_stored(const PackedDescriptor& packed, int k, const CodecConfig& codec) {
  MapDescriptor d = decode(packed, codec);
  if (static_cast<int>(d.parts.size()) > k) {
    throw InputError("codec: a descriptor stored under K = " + std::to_string(k) + " holds " +
                     std::to_string(d.parts.size()) + " parts");
  }
  return d;
}

}  // namespace partslam
