// Exact 2D ray casting against line segments (the simulator's laser). A ray o + t d meets segment a + u e
// at t = (a - o) x e / (d x e), u = (a - o) x d / (d x e), u in [0, 1]; the range of a beam is the smallest
// such t > 0. The segments are bucketed in a uniform grid (each in every cell its bounding box touches,
// slightly inflated) and the ray walks the grid cell by cell (Amanatides & Woo 1987), stopping as soon as
// the nearest hit so far lies inside the current cell: the result equals the brute-force minimum exactly.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.h"

namespace partslam {

/// A line segment from a to b [m] (a wall, or one side of a box).
struct Segment2 {
  Vec2 a = Vec2::Zero();
  Vec2 b = Vec2::Zero();
};

using Segments2 = std::vector<Segment2>;

/// Distance t > 0 along the ray origin + t * direction to the segment, or +infinity when the ray misses it
/// (parallel rays miss). direction need not be unit length; t is then in units of |direction|.
double intersect_ray(const Vec2& origin, const Vec2& direction, const Segment2& segment);

/// Nearest hit over all segments by testing every one (the reference for RayCaster), or +infinity when
/// nothing is hit within max_range.
double cast_ray_brute_force(const Segments2& segments, const Vec2& origin, const Vec2& direction,
                            double max_range);

class RayCaster {
 public:
  /// cell_size: grid cell [m]; it is enlarged when the grid would exceed a few million cells.
  explicit RayCaster(Segments2 segments, double cell_size = 0.5);

  /// Distance along the unit direction to the nearest segment, or +infinity when none is hit within
  /// max_range.
  double cast(const Vec2& origin, const Vec2& direction, double max_range) const;

  const Segments2& segments() const { return segments_; }

 private:
  Segments2 segments_;
  double cell_size_ = 0.5;
  double x0_ = 0.0, y0_ = 0.0;  // grid origin [m]
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> cell_begin_;  // CSR: segments of cell c are items_[cell_begin_[c] .. [c + 1])
  std::vector<std::uint32_t> items_;
};

}  // namespace partslam
