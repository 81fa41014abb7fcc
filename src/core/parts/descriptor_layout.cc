#include "core/parts/descriptor_layout.h"

#include <string>

#include "core/error.h"

namespace partslam {

CodecConfig dictionary_codec_config(const Points2& dictionary_points, const CodecConfig& base) {
  if (dictionary_points.empty()) throw InputError("codec: the dictionary map has no points");
  const Box2 box = bounding_box(dictionary_points);
  const double margin = base.crop_size;
  CodecConfig c = base;
  c.dictionary_extent = {box.x_min - margin, box.x_max + margin, box.y_min - margin, box.y_max + margin};
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
