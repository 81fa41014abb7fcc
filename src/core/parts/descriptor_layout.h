// How descriptors described against a dictionary are bit-packed (paper §"Map Descriptor", §"Space
// Efficiency"; docs/DESIGN.md "MD"). One place chooses the CodecConfig of a descriptor set; the map database
// stores it beside the descriptors (schema version 2), so a reader decodes without the dictionary's points:
//  * dictionary_extent covers the dictionary's points grown by the crop size on every side (a descriptor box
//    may reach past the dictionary's points by up to one crop), snapped so that the origin lattice lies on the
//    keypoint grid: its corner is a multiple of keypoint_resolution and its step a whole number of cells.
//    Every corner of a decoded descriptor box (origin + whole cells) is then a point of the 0.1 m grid on
//    which DescriptorDatabase lays out its 16-bit cells: the stored fields are the matcher's cells, with one
//    quantisation (at encoding) between the parts CPD found and the SIMD kernel.
//    Schema version 1 stored no codec; its rule (the grown bounding box, unsnapped) is kept for migration.
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
/// side, snapped to the keypoint grid as described above. Throws InputError when there are no points or the
/// config is invalid.
CodecConfig dictionary_codec_config(const Points2& dictionary_points, const CodecConfig& base = {});

/// Score bits of a descriptor stored under K parts: 0 for K <= kMaxUnscoredParts, else kQueryScoreBits.
int score_bits_for_parts(int k);

/// The codec of a descriptor stored under K parts against the dictionary with these points:
/// dictionary_codec_config with score_bits_for_parts(k). Throws InputError for k < 1.
CodecConfig descriptor_codec_config(const Points2& dictionary_points, int k, const CodecConfig& base = {});

/// The codec that schema version 1 databases implied (the grown bounding box, not snapped), for migrating
/// their descriptor sets.
CodecConfig descriptor_codec_config_v1(const Points2& dictionary_points, int k);

/// Decodes a stored descriptor of up to K parts (its part count is bits / bits_per_part). Throws InputError
/// when the blob does not fit the layout or holds more than K parts.
MapDescriptor decode_stored(const PackedDescriptor& packed, int k, const CodecConfig& codec);

}  // namespace partslam
