#include "core/sim/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace partslam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxCasterCells = 1 << 22;
// Segments are registered in every cell within this distance [m], so that a hit on a cell boundary is
// found whichever side of it the grid walk rounds to.
constexpr double kRegistrationMargin = 1e-6;

double cross(const Vec2& p, const Vec2& q) { return p.x() * q.y() - p.y() * q.x(); }

}  // namespace

double intersect_ray(const Vec2& origin, const Vec2& direction, const Segment2& segment) {
  const Vec2 e = segment.b - segment.a;
  const Vec2 w = segment.a - origin;
  double den = cross(direction, e);
  if (den == 0.0) return kInf;
  double t_num = cross(w, e);
  double u_num = cross(w, direction);
  if (den < 0.0) den = -den, t_num = -t_num, u_num = -u_num;
  if (u_num < 0.0 || u_num > den || t_num <= 0.0) return kInf;
  return t_num / den;
}

double cast_ray_brute_force(const Segments2& segments, const Vec2& origin, const Vec2& direction,
                            double max_range) {
  double best = kInf;
  for (const Segment2& s : segments) best = std::min(best, intersect_ray(origin, direction, s));
  return best <= max_range ? best : kInf;
}

RayCaster::RayCaster(Segments2 segments, double cell_size) : segments_(std::move(segments)) {
  if (!(cell_size > 0.0) || !std::isfinite(cell_size)) {
    throw InputError("ray caster: cell_size must be a positive finite number");
  }
  if (segments_.empty()) return;
  if (segments_.size() >= std::numeric_limits<std::uint32_t>::max())
    throw InputError("ray caster: too many segments");
  Box2 box{kInf, -kInf, kInf, -kInf};
  for (const Segment2& s : segments_) {
    for (const Vec2& p : {s.a, s.b}) {
      if (!std::isfinite(p.x()) || !std::isfinite(p.y())) {
        throw InputError("ray caster: segment coordinates must be finite");
      }
      box.x_min = std::min(box.x_min, p.x()), box.x_max = std::max(box.x_max, p.x());
      box.y_min = std::min(box.y_min, p.y()), box.y_max = std::max(box.y_max, p.y());
    }
  }
  const double w = box.width() + 2.0 * cell_size, h = box.height() + 2.0 * cell_size;
  cell_size_ = std::max(cell_size, std::sqrt(w * h / kMaxCasterCells));
  x0_ = box.x_min - cell_size_;
  y0_ = box.y_min - cell_size_;
  nx_ = static_cast<int>(std::ceil((box.width() + 2.0 * cell_size_) / cell_size_));
  ny_ = static_cast<int>(std::ceil((box.height() + 2.0 * cell_size_) / cell_size_));
  nx_ = std::max(nx_, 1), ny_ = std::max(ny_, 1);

  auto cell_range = [&](double lo, double hi, double origin, int n) {
    const int a = static_cast<int>(std::floor((lo - kRegistrationMargin - origin) / cell_size_));
    const int b = static_cast<int>(std::floor((hi + kRegistrationMargin - origin) / cell_size_));
    return std::pair{std::clamp(a, 0, n - 1), std::clamp(b, 0, n - 1)};
  };
  // Two passes (count, then fill) build the compressed cell -> segment lists.
  std::vector<std::uint32_t> count(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::uint32_t k = 0; k < segments_.size(); ++k) {
      const Segment2& s = segments_[k];
      const auto [ix0, ix1] = cell_range(std::min(s.a.x(), s.b.x()), std::max(s.a.x(), s.b.x()), x0_, nx_);
      const auto [iy0, iy1] = cell_range(std::min(s.a.y(), s.b.y()), std::max(s.a.y(), s.b.y()), y0_, ny_);
      for (int iy = iy0; iy <= iy1; ++iy) {
        for (int ix = ix0; ix <= ix1; ++ix) {
          const std::size_t c = static_cast<std::size_t>(iy) * nx_ + ix;
          if (pass == 0) {
            ++count[c + 1];
          } else {
            items_[cell_begin_[c] + count[c]++] = k;
          }
        }
      }
    }
    if (pass == 0) {
      for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
      cell_begin_ = count;
      items_.resize(cell_begin_.back());
      std::fill(count.begin(), count.end(), 0);
    }
  }
}

double RayCaster::cast(const Vec2& origin, const Vec2& direction, double max_range) const {
  if (nx_ == 0 || !(max_range > 0.0)) return kInf;
  // Clip the ray [0, max_range] to the grid box (slab method).
  double t_near = 0.0, t_far = max_range;
  const double lo[2] = {x0_, y0_};
  const double hi[2] = {x0_ + nx_ * cell_size_, y0_ + ny_ * cell_size_};
  for (int k = 0; k < 2; ++k) {
    const double o = origin[k], d = direction[k];
    if (d == 0.0) {
      if (o < lo[k] || o > hi[k]) return kInf;
      continue;
    }
    double t1 = (lo[k] - o) / d, t2 = (hi[k] - o) / d;
    if (t1 > t2) std::swap(t1, t2);
    t_near = std::max(t_near, t1);
    t_far = std::min(t_far, t2);
  }
  if (t_near > t_far) return kInf;

  const Vec2 start = origin + t_near * direction;
  int ix = std::clamp(static_cast<int>(std::floor((start.x() - x0_) / cell_size_)), 0, nx_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor((start.y() - y0_) / cell_size_)), 0, ny_ - 1);
  const int step_x = direction.x() > 0.0 ? 1 : -1;
  const int step_y = direction.y() > 0.0 ? 1 : -1;
  // Ray parameter at which the walk leaves the current column / row.
  auto exit_x = [&](int i) {
    if (direction.x() == 0.0) return kInf;
    return (x0_ + (i + (step_x > 0 ? 1 : 0)) * cell_size_ - origin.x()) / direction.x();
  };
  auto exit_y = [&](int i) {
    if (direction.y() == 0.0) return kInf;
    return (y0_ + (i + (step_y > 0 ? 1 : 0)) * cell_size_ - origin.y()) / direction.y();
  };
  double tx = exit_x(ix), ty = exit_y(iy);
  double best = kInf;
  while (true) {
    const std::size_t c = static_cast<std::size_t>(iy) * nx_ + ix;
    for (std::uint32_t k = cell_begin_[c]; k < cell_begin_[c + 1]; ++k) {
      best = std::min(best, intersect_ray(origin, direction, segments_[items_[k]]));
    }
    const double t_exit = std::min(tx, ty);
    if (best <= t_exit || t_exit > t_far) break;
    if (tx <= ty) {
      ix += step_x;
      if (ix < 0 || ix >= nx_) break;
      tx = exit_x(ix);
    } else {
      iy += step_y;
      if (iy < 0 || iy >= ny_) break;
      ty = exit_y(iy);
    }
  }
  return best <= max_range ? best : kInf;
}

}  // namespace partslam
