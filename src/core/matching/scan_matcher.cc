#include "core/matching/scan_matcher.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/error.h"

namespace partslam {
namespace {

constexpr double kMaxFieldCells = double(1 << 26);
constexpr std::size_t kSearchPoints = 100;

void require_positive(double value, const char* field, const char* unit) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw InputError(std::string("scan matcher config: ") + field + " must be a positive finite number " + unit);
}

// Mean interpolated field value at the scan's points under `pose`.
double mean_value(const LikelihoodField& field, const Points2& points, const Pose2& pose) {
  double sum = 0.0;
  const Pose2::Applied apply = pose.applied();
  for (const Vec2& p : points) sum += field.interpolate(apply(p), nullptr);
  return sum / static_cast<double>(points.size());
}

struct SearchGrid {
  double angle_step;  // [rad]
  int angles;         // searched: -angles..angles steps around the centre
  int cell_step;      // [cells]
  int shifts;         // searched: -shifts..shifts steps in x and in y
};

// The best pose of a grid of poses around `center`, scored by the sum of the field's cell values at the
// points; ties keep the pose nearest the centre (searched first). Rotations are searched on up to num_threads
// threads, each keeping its own best; the bests are then compared in the serial order, so the result does not
// depend on the thread count.
Pose2 grid_search(const LikelihoodField& field, const Points2& points, const Pose2& center, const SearchGrid& g,
                  int num_threads) {
  const double res = field.resolution();
  const int rotations = 2 * g.angles + 1;
  std::vector<std::pair<double, Pose2>> best_of(static_cast<std::size_t>(rotations), {-1.0, center});
#pragma omp parallel num_threads(std::max(1, num_threads)) if (num_threads > 1 && rotations > 2)
  {
    std::vector<Eigen::Vector2i> cells(points.size());
    std::vector<double> sums;
#pragma omp for schedule(static)
    for (int ka = 0; ka < rotations; ++ka) {
      const int a = (ka % 2 == 0 ? 1 : -1) * ((ka + 1) / 2);  // 0, -1, 1, -2, 2, ...: nearest first
      const Pose2 turn{center.x, center.y, wrap_angle(center.theta + a * g.angle_step)};
      const Pose2::Applied apply = turn.applied();
      for (std::size_t i = 0; i < points.size(); ++i) cells[i] = field.cell_of(apply(points[i]));
      double& best_score = best_of[static_cast<std::size_t>(ka)].first;
      Pose2& best = best_of[static_cast<std::size_t>(ka)].second;
      field.shifted_sums(cells, g.cell_step, g.shifts, sums);
      const int n = 2 * g.shifts + 1;
      for (int sy = -g.shifts; sy <= g.shifts; ++sy) {
        for (int sx = -g.shifts; sx <= g.shifts; ++sx) {
          const int dx = sx * g.cell_step, dy = sy * g.cell_step;
          double score = sums[static_cast<std::size_t>((sy + g.shifts) * n + sx + g.shifts)];
          score -= 1e-9 * (sx * sx + sy * sy + a * a);  // ties: nearest the centre
          if (score > best_score) {
            best_score = score;
            best = {turn.x + dx * res, turn.y + dy * res, turn.theta};
          }
        }
      }
    }
  }
  std::pair<double, Pose2> best{-1.0, center};
  for (const auto& b : best_of)
    if (b.first > best.first) best = b;
  return best.second;
}

// Step 1: the window searched on a grid twice as coarse as the fine one (translations of two cells, rotations
// that move the farthest point by two cells), then the fine grid around the coarse best (one step each way).
// Scored on at most kSearchPoints of the scan's points (every k-th), since step 2 uses them all.
Pose2 correlative_search(const LikelihoodField& field, const Points2& all_points, const Pose2& prediction,
                         const ScanMatcherConfig& c) {
  const Points2 points = thinned(all_points, kSearchPoints);
  double max_range = 0.0;
  for (const Vec2& p : points) max_range = std::max(max_range, p.norm());
  const double res = field.resolution();
  const double fine_angle = res / std::max(max_range, 1.0);
  const SearchGrid coarse{2 * fine_angle, static_cast<int>(std::ceil(c.angular_window / (2 * fine_angle))), 2,
                          static_cast<int>(std::ceil(c.linear_window / (2 * res)))};
  const Pose2 best = grid_search(field, points, prediction, coarse, c.num_threads);
  return grid_search(field, points, best, SearchGrid{fine_angle, 1, 1, 1}, 1);
}

// Step 2: Gauss-Newton on sum (1 - M(T p))^2 (Levenberg-damped).
Pose2 refine(const LikelihoodField& field, const Points2& points, Pose2 pose, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    const Pose2::Applied apply = pose.applied();
    const double c = apply.c, s = apply.s;
    for (const Vec2& p : points) {
      Vec2 grad;
      const double m = field.interpolate(apply(p), &grad);
      const Eigen::Vector3d J(grad.x(), grad.y(),
                              grad.x() * (-s * p.x() - c * p.y()) + grad.y() * (c * p.x() - s * p.y()));
      H += J * J.transpose();
      g += J * (1.0 - m);
    }
    H.diagonal() += Eigen::Vector3d::Constant(1e-6 + 1e-3 * H.diagonal().maxCoeff());
    const Eigen::Vector3d step = H.ldlt().solve(g);
    if (!step.allFinite()) break;
    pose = {pose.x + step.x(), pose.y + step.y(), wrap_angle(pose.theta + step.z())};
    if (step.head<2>().norm() < 1e-4 && std::abs(step.z()) < 1e-5) break;
  }
  return pose;
}

}  // namespace

void validate(const ScanMatcherConfig& c) {
  require_positive(c.resolution, "resolution", "[m]");
  require_positive(c.sigma, "sigma", "[m]");
  if (!(c.linear_window >= 0.0) || !std::isfinite(c.linear_window) || c.linear_window > 5.0)
    throw InputError("scan matcher config: linear_window must be in [0, 5] m");
  if (!(c.angular_window >= 0.0) || c.angular_window > 1.0)
    throw InputError("scan matcher config: angular_window must be in [0, 1] rad");
  if (c.max_iterations < 0 || c.max_iterations > 1000)
    throw InputError("scan matcher config: max_iterations must be in [0, 1000]");
  if (c.num_threads < 1 || c.num_threads > 1024) throw InputError("scan matcher config: num_threads must be in [1, 1024]");
  if (c.linear_window / c.resolution > 200)
    throw InputError("scan matcher config: linear_window spans more than 200 cells of resolution");
}

LikelihoodField::LikelihoodField(const Points2& points, double resolution, double sigma)
    : resolution_(resolution) {
  if (points.empty()) return;
  const double margin = 3.0 * sigma;
  const Box2 box = bounding_box(points);
  const double w = std::ceil((box.width() + 2 * margin) / resolution) + 1;
  const double h = std::ceil((box.height() + 2 * margin) / resolution) + 1;
  if (!(w * h <= kMaxFieldCells)) {
    throw InputError("likelihood field: map points spread over " + std::to_string(box.width()) + " x " +
                     std::to_string(box.height()) + " m, more than 2^26 cells of " + std::to_string(resolution) +
                     " m");
  }
  width_ = static_cast<int>(w), height_ = static_cast<int>(h);
  origin_ = Vec2(box.x_min - margin, box.y_min - margin);
  values_.assign(static_cast<std::size_t>(width_) * height_, 0.0f);
  const int r = static_cast<int>(std::ceil(margin / resolution));
  const double inv = 1.0 / (2.0 * sigma * sigma);
  // The Gaussian is separable: exp(-(dx^2 + dy^2) k) = exp(-dx^2 k) exp(-dy^2 k), 2 (2r + 1) exps a point
  // instead of (2r + 1)^2.
  std::vector<double> gx(static_cast<std::size_t>(2 * r + 1)), gy(gx.size());
  for (const Vec2& p : points) {
    const Vec2 f = (p - origin_) / resolution;
    const int cx = static_cast<int>(std::lround(f.x())), cy = static_cast<int>(std::lround(f.y()));
    for (int k = -r; k <= r; ++k) {
      const double dx = (cx + k - f.x()) * resolution, dy = (cy + k - f.y()) * resolution;
      gx[static_cast<std::size_t>(k + r)] = std::exp(-dx * dx * inv);
      gy[static_cast<std::size_t>(k + r)] = std::exp(-dy * dy * inv);
    }
    for (int y = std::max(0, cy - r); y <= std::min(height_ - 1, cy + r); ++y) {
      const double wy = gy[static_cast<std::size_t>(y - cy + r)];
      float* row = &values_[static_cast<std::size_t>(y) * width_];
      for (int x = std::max(0, cx - r); x <= std::min(width_ - 1, cx + r); ++x)
        row[x] = std::max(row[x], static_cast<float>(wy * gx[static_cast<std::size_t>(x - cx + r)]));
    }
  }
}

Eigen::Vector2i LikelihoodField::cell_of(const Vec2& q) const {
  const double fx = std::clamp((q.x() - origin_.x()) / resolution_, -1e6, 1e6);
  const double fy = std::clamp((q.y() - origin_.y()) / resolution_, -1e6, 1e6);
  return {static_cast<int>(std::lround(fx)), static_cast<int>(std::lround(fy))};
}

float LikelihoodField::cell_value(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0.0f;
  return values_[static_cast<std::size_t>(y) * width_ + x];
}

namespace {

// sum[k] += row[k * step] for k < count.
template <int kStep>
void add_field_row(const float* row, double* sum, int count) {
  for (int k = 0; k < count; ++k) sum[k] += row[k * kStep];
}
void add_field_row(const float* row, double* sum, int count, int step) {
  for (int k = 0; k < count; ++k) sum[k] += row[k * step];
}

}  // namespace

void LikelihoodField::shifted_sums(std::span<const Eigen::Vector2i> cells, int step, int shifts,
                                   std::vector<double>& out) const {
  if (step < 1 || shifts < 0) throw std::invalid_argument("likelihood field: shifted sums need step >= 1, shifts >= 0");
  const int n = 2 * shifts + 1;
  out.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
  // Shift k of a cell at c lands on c + (k - shifts) step: the shifts that land inside [0, size) are k in
  // [lo, hi]. A cell value outside the grid is 0 and adding 0 to a sum of non-negative values changes nothing,
  // so those shifts are skipped.
  const auto inside = [&](int c, int size, int& lo, int& hi) {
    const std::int64_t first = std::int64_t{c} - std::int64_t{shifts} * step;  // where shift 0 lands
    // lo: the least k with first + k step >= 0; hi: the greatest with first + k step <= size - 1.
    const std::int64_t l = first >= 0 ? 0 : (-first + step - 1) / step;
    const std::int64_t h = size - 1 - first < 0 ? -1 : (size - 1 - first) / step;
    lo = static_cast<int>(std::clamp<std::int64_t>(l, 0, n)), hi = static_cast<int>(std::clamp<std::int64_t>(h, -1, n - 1));
  };
  const auto width = static_cast<std::size_t>(width_);
  for (const Eigen::Vector2i& q : cells) {
    int kx0 = 0, kx1 = -1, ky0 = 0, ky1 = -1;
    inside(q.x(), width_, kx0, kx1);
    inside(q.y(), height_, ky0, ky1);
    if (kx0 > kx1) continue;
    const int x_first = q.x() + (kx0 - shifts) * step;
    for (int ky = ky0; ky <= ky1; ++ky) {
      const float* row = &values_[static_cast<std::size_t>(q.y() + (ky - shifts) * step) * width +
                                  static_cast<std::size_t>(x_first)];
      double* sum = &out[static_cast<std::size_t>(ky) * static_cast<std::size_t>(n)];
      // The common steps with a constant stride, which the compiler vectorises.
      if (step == 2) add_field_row<2>(row, sum + kx0, kx1 - kx0 + 1);
      else if (step == 1) add_field_row<1>(row, sum + kx0, kx1 - kx0 + 1);
      else add_field_row(row, sum + kx0, kx1 - kx0 + 1, step);
    }
  }
}

float LikelihoodField::at(const Vec2& q) const {
  const Eigen::Vector2i c = cell_of(q);
  return cell_value(c.x(), c.y());
}

double LikelihoodField::interpolate(const Vec2& q, Vec2* gradient) const {
  if (gradient) gradient->setZero();
  const double fx = (q.x() - origin_.x()) / resolution_, fy = (q.y() - origin_.y()) / resolution_;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ - 1 && fy < height_ - 1)) return 0.0;
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const double tx = fx - x0, ty = fy - y0;
  const float* row0 = &values_[static_cast<std::size_t>(y0) * width_ + x0];
  const float* row1 = row0 + width_;
  const double v00 = row0[0], v10 = row0[1], v01 = row1[0], v11 = row1[1];
  if (gradient) {
    *gradient = Vec2(((v10 - v00) * (1 - ty) + (v11 - v01) * ty) / resolution_,
                     ((v01 - v00) * (1 - tx) + (v11 - v10) * tx) / resolution_);
  }
  return (v00 * (1 - tx) + v10 * tx) * (1 - ty) + (v01 * (1 - tx) + v11 * tx) * ty;
}

ScanMatch match_scan(const LikelihoodField& field, const Points2& scan_points, const Pose2& prediction,
                     const ScanMatcherConfig& config) {
  validate(config);
  if (scan_points.empty() || field.empty()) return {prediction, 0.0};
  const Pose2 coarse = correlative_search(field, scan_points, prediction, config);
  const double coarse_score = mean_value(field, scan_points, coarse);
  const Pose2 fine = refine(field, scan_points, coarse, config.max_iterations);
  const double fine_score = mean_value(field, scan_points, fine);
  return fine_score >= coarse_score ? ScanMatch{fine, fine_score} : ScanMatch{coarse, coarse_score};
}

}  // namespace partslam
