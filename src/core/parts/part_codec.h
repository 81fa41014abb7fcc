// Bit-packed map descriptors (paper §"Map Descriptor" and §"Space Efficiency"; docs/DESIGN.md "MD").
//
// The paper stores a part in 42 bits: 7 bits for each keypoint coordinate x_begin, x_end, y_begin, y_end at
// 0.1 m inside the 12.8 m crop, and 14 bits for the descriptor box's origin (x_begin, y_begin) on the
// dictionary map; the descriptor box's far corner is redundant because both boxes have the same shape.
// The paper leaves two things open, fixed here:
//  * 14 bits cannot address a whole building at 0.1 m, so the origin is quantised on a lattice of
//    2^origin_bits_x x 2^origin_bits_y points spanning the dictionary's extent, both ends included
//    (step = extent / (2^bits - 1); 128 x 128 points by default, e.g. 0.39 m steps on a 50 m building).
//  * Our canonical frames leave a quarter-turn ambiguity, so T_dict_map may rotate the part: rotation_bits =
//  2
//    store k in {0..3} (the relative pose survives), 1 bit stores only k mod 2 (enough for the descriptor
//    box's shape, which is all the matcher needs), 0 bits is the paper's literal layout and requires even k.
// Optionally the appearance score (AS) is kept in score_bits for Sum-Max-Weighted matching.
// Default cost: 7*4 + 7 + 7 + 2 = 44 bits per part (the paper's 42 + 2 rotation bits).
//
// Keypoint coordinates are cell indices c = round((x + crop_size / 2) / resolution); a box stores its first
// cell and its last cell (end - 1), so the full crop [0, 128] fits in 7 bits; a box thinner than one cell is
// widened to one cell. Bit stream: parts in order, fields in the order x_begin, x_last, y_begin, y_last,
// origin_x, origin_y, rotation, score, each least significant bit first, bytes filled from bit 0; the padding
// bits of the last byte are zero.
//
// Decoding is exact up to: keypoint coordinates +-resolution / 2, descriptor origin +-lattice step / 2,
// rotation modulo 2^rotation_bits, AS +-score_max / (2 (2^score_bits - 1)) (score_max when score_bits = 0).
#pragma once

#include <cstdint>
#include <vector>

#include "core/parts/part.h"

namespace partslam {

struct CodecConfig {
  double crop_size = kCropSize;       ///< side of the square crop holding keypoint boxes, centred on 0 [m]
  double keypoint_resolution = kMapResolution;  ///< keypoint quantisation step [m]
  int keypoint_bits = 7;             ///< bits per keypoint coordinate; 2^bits cells must cover the crop
  Box2 dictionary_extent;  ///< descriptor origins lie in this box of the dictionary frame [m]; required
  int origin_bits_x = 7;   ///< lattice bits of the descriptor origin along x (paper: 14 in total)
  int origin_bits_y = 7;   ///< lattice bits of the descriptor origin along y
  int rotation_bits = 2;   ///< 0, 1 or 2 (see the header comment)
  int score_bits = 0;      ///< 0..16 bits for the appearance score (0: not stored)
  double score_max = 1.0;  ///< AS range [0, score_max] quantised on 2^score_bits levels
};

/// Throws InputError naming the offending field when a value is out of range.
void validate(const CodecConfig& config);

/// Bits one part costs under `config` (42 + rotation_bits + score_bits with the paper's layout).
int bits_per_part(const CodecConfig& config);

/// Exact bits of a descriptor with `num_parts` parts (no header: the part count is num_parts).
int packed_bits(int num_parts, const CodecConfig& config);

/// Lattice step of the descriptor origin along x and y [m].
Vec2 origin_step(const CodecConfig& config);

struct PackedDescriptor {
  std::vector<std::uint8_t> bytes;  ///< ceil(bits / 8) bytes, padding bits zero
  int bits = 0;                     ///< meaningful bits, a multiple of bits_per_part(config)
};

/// Packs a descriptor. Throws InputError (naming the part and field) for a keypoint box outside the crop or
/// empty, a descriptor origin outside the dictionary extent, a descriptor box whose shape does not match the
/// keypoint box rotated by `rotation`, a rotation outside {0..3} (or odd with rotation_bits = 0), or an
/// appearance score outside [0, score_max] when it is stored.
PackedDescriptor encode(const MapDescriptor& descriptor, const CodecConfig& config);

/// Unpacks a descriptor (see the header comment for what is lost). Throws InputError for a blob whose bit
/// count is not a multiple of bits_per_part, whose byte count is not ceil(bits / 8), whose padding bits are
/// not zero, or whose fields are out of range.
MapDescriptor decode(const PackedDescriptor& packed, const CodecConfig& config);

/// Same, for a stored blob whose part count is known (e.g. a database row of K parts).
MapDescriptor decode(const std::vector<std::uint8_t>& bytes, int num_parts, const CodecConfig& config);

}  // namespace partslam
