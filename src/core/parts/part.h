// Parts and map descriptors (paper §"Common Pattern Discovery", §"Map Descriptor"; docs/DESIGN.md "MD").
// A part is a pair of bounding boxes found by common pattern discovery: the keypoint box crops the input map,
// the descriptor box crops the dictionary map where those points fit best (Eq. 2). The descriptor box is the
// keypoint box moved by T_dict_map, a translation plus `rotation` quarter turns, so both boxes have the same
// shape up to a width/height swap for odd quarter turns. A map descriptor keeps the K parts of highest
// appearance score (MD); the descriptor matcher only looks at descriptor boxes and scores.
#pragma once

#include <vector>

#include "core/types.h"

namespace partslam {

struct Part {
  /// Box on the input map [m], in the map's canonical frame (origin = the map's centroid), inside the
  /// square crop of the submap (|x|, |y| <= crop_size / 2 = 6.4 m by default).
  Box2 keypoint_box;
  /// Box on the dictionary map [m], in the dictionary's frame: the axis-aligned box of keypoint_box under
  /// T_dict_map. Same width and height as keypoint_box, swapped when `rotation` is odd.
  Box2 descriptor_box;
  /// AS, Eq. 2: how well the cropped points fit the dictionary there. By convention the inlier *fraction*
  /// (inliers / points in the crop, in [0, 1]); the codec's score range says otherwise when a producer stores
  /// counts. Sum-Max-Weighted weights by this value.
  double appearance_score = 0.0;
  /// k in {0, 1, 2, 3}: T_dict_map rotates by k * 90 degrees (counter-clockwise).
  int rotation = 0;
};

/// The K parts that describe one map (query or database), best appearance score first.
struct MapDescriptor {
  std::vector<Part> parts;
};

/// The axis-aligned box that `keypoint_box` occupies after `rotation` quarter turns, with its minimum corner
/// placed at `origin` [m]. This is how a descriptor box is reconstructed from a keypoint box and an origin.
inline Box2 place_rotated_box(const Box2& keypoint_box, int rotation, const Vec2& origin) {
  const bool swap = (rotation & 1) != 0;
  const double w = swap ? keypoint_box.height() : keypoint_box.width();
  const double h = swap ? keypoint_box.width() : keypoint_box.height();
  return {origin.x(), origin.x() + w, origin.y(), origin.y() + h};
}

/// Where the part puts the origin of its map's frame on the dictionary: the descriptor box's centre minus the
/// keypoint box's centre turned by `rotation` quarter turns (T_dict_map applied to the origin, up to the
/// residual rotation). Two parts of maps of the same place that fit the same dictionary spot agree on it up to
/// the offset between the two map frames; the descriptor matcher's origin gate uses that.
inline Vec2 dictionary_origin(const Part& part) {
  Vec2 c{(part.keypoint_box.x_min + part.keypoint_box.x_max) / 2, (part.keypoint_box.y_min + part.keypoint_box.y_max) / 2};
  for (int k = 0; k < (part.rotation & 3); ++k) c = Vec2{-c.y(), c.x()};
  return Vec2{(part.descriptor_box.x_min + part.descriptor_box.x_max) / 2 - c.x(),
              (part.descriptor_box.y_min + part.descriptor_box.y_max) / 2 - c.y()};
}

/// MD selection (paper §"Map Descriptor"): the K parts of highest appearance score, best first; ties keep
/// their input order, so the result is deterministic. Fewer than K parts are all kept; K < 0 throws
/// InputError.
MapDescriptor select_top_parts(std::vector<Part> parts, int k);

}  // namespace partslam
