// How descriptors described against a dictionary are bit-packed (paper §"Map Descriptor", §"Space
// Efficiency"; docs/DESIGN.md "MD"). One place fixes the CodecConfig, so that whoever writes a descriptor
// (partslam describe, evaluate) and whoever reads it back (partslam match, render) agree without storing any
// codec state:
//  * dictionary_extent is a pure function of the dictionary's points: their bounding box grown by the crop
//  size
//    on every side, since a descriptor box may reach past the dictionary's points by up to one crop.
//  * the bit layout is a pure function of K, the part count the descriptor is stored under: stored map
//    descriptors (K <= kMaxUnscoredParts, the paper's K = 1..5) use the paper's 42 bits + 2 rotation bits per
//    part and no score; longer ones are hMM query lists (the paper keeps ~100 parts) and also keep the
//    appearance score (AS, Eq. 2) in kQueryScoreBits bits, which Sum-Max-Weighted (Eq. 6) weighs by.
#pragma once

#include "core/parts/part_codec.h"

namespace partslam {

/// Descriptors of at most this many parts store no appearance score.
inline constexpr int kMaxUnscoredParts = 16;
/// Bits of the appearance score of a descriptor of more than kMaxUnscoredParts parts (AS steps of 1/255).
inline constexpr int kQueryScoreBits = 8;

/// `base` with dictionary_extent = bounding box of the dictionary points grown by base.crop_size on every
/// side. Throws InputError when there are no points or the config is invalid.
CodecConfig dictionary_codec_config(const Points2& dictionary_points, const CodecConfig& base = {});

/// Score bits of a descriptor stored under K parts: 0 for K <= kMaxUnscoredParts, else kQueryScoreBits.
int score_bits_for_parts(int k);

/// The codec of a descriptor stored under K parts against the dictionary with these points:
/// dictionary_codec_config with score_bits_for_parts(k). Throws InputError for k < 1.
CodecConfig descriptor_codec_config(const Points2& dictionary_points, int k, const CodecConfig& base = {});

/// Decodes a stored descriptor of up to K parts (its part count is bits / bits_per_part). Throws InputError
/// when the blob does not fit the layout or holds more than K parts.
MapDescriptor decode_stored(const PackedDescriptor& packed, int k, const CodecConfig& codec);

}  // namespace partslam
