#include "core/matching/verification.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/maps/local_shape.h"
#include "core/matching/scan_matcher.h"

namespace partslam {
namespace {

constexpr double kMaxVerifyCells = double(1 << 24);
// A cell index's magnitude at most this, so that an index plus a grid's width stays an int.
constexpr double kMaxCellIndex = double(1 << 30);

// Visits the cells of the segment from cell a to cell b (Amanatides & Woo on the cell centres), b excluded;
// visit(x, y) returns false to stop early.
template <typename Visit>
void walk_cells(int ax, int ay, int bx, int by, Visit&& visit) {
  const int dx = std::abs(bx - ax), dy = std::abs(by - ay);
  const int sx = bx > ax ? 1 : -1, sy = by > ay ? 1 : -1;
  int err = dx - dy, x = ax, y = ay;
  while (x != bx || y != by) {
    if (!visit(x, y)) return;
    const int e2 = 2 * err;
    if (e2 > -dy) err -= dy, x += sx;
    if (e2 < dx) err += dx, y += sy;
  }
}

// What `from`'s points say of `other` moved by T_other_from: the shares on its cells (SideTerms), and the
// mean of `other_field` at the points, plain and weighted by the points' cornerness.
struct SideReading {
  SideTerms terms;
  double fit = 0, corner_fit = 0;
};
SideReading read_side(const VerifyMap& from, const VerifyMap& other, const LikelihoodField& other_field,
                      const Pose2& T_other_from) {
  SideReading r;
  const Points2& points = from.points();
  if (points.empty()) return r;
  const std::vector<double>& c = from.cornerness();
  int occupied = 0, free = 0;
  double fit = 0, weight = 0, corner = 0, corner_fit = 0;
  const Pose2::Applied apply = T_other_from.applied();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec2 p = apply(points[i]);
    const std::uint8_t s = other.at(p);
    const double f = other_field.at(p);
    occupied += s == VerifyMap::kOccupied;
    free += s == VerifyMap::kFree;
    fit += f;
    weight += c[i], corner += c[i] * (s == VerifyMap::kOccupied), corner_fit += c[i] * f;
  }
  const double n = static_cast<double>(points.size());
  r.terms.occupied = occupied / n;
  r.terms.free = free / n;
  r.terms.seen = (occupied + free) / n;
  r.fit = fit / n;
  if (weight > 0) r.terms.corner = corner / weight, r.corner_fit = corner_fit / weight;
  return r;
}

double logistic(double z) { return 1.0 / (1.0 + std::exp(-z)); }

// v's pose refined (refine_match) and verified there, when that is at least as probable as v; else v.
Verified refined(const VerifyMap& query, const VerifyMap& map, const PairFields& fields, const Verified& v,
                 const VerifyConfig& config) {
  const Verified r = verify_at(query, map, fields, refine_match(query, fields, v.T_map_query, config));
  return r.probability >= v.probability ? r : v;
}

}  // namespace

void validate(const VerifyConfig& c) {
  if (!(c.resolution > 0.0) || !std::isfinite(c.resolution) || c.resolution > 10.0)
    throw InputError("verify config: resolution must be in (0, 10] m");
  if (c.refined < 1 || c.refined > 100) throw InputError("verify config: refined must be in [1, 100]");
  if (c.dilation < 0 || c.dilation > 20) throw InputError("verify config: dilation must be in [0, 20] cells");
  if (!(c.max_ray > 0.0) || c.max_ray > 1000.0)
    throw InputError("verify config: max_ray must be in (0, 1000] m");
  if (!(c.refine_window >= 0.0) || c.refine_window > 5.0)
    throw InputError("verify config: refine_window must be in [0, 5] m");
  if (!(c.refine_angle >= 0.0) || c.refine_angle > 1.0)
    throw InputError("verify config: refine_angle must be in [0, 1] rad");
  if (c.alternatives < 0 || c.alternatives > 64)
    throw InputError("verify config: alternatives must be in [0, 64]");
  if (!(c.alternative_bar >= 0.0) || c.alternative_bar > 1.0)
    throw InputError("verify config: alternative_bar must be in [0, 1]");
  if (!(c.alternative_distance >= 0.0) || c.alternative_distance > 100.0)
    throw InputError("verify config: alternative_distance must be in [0, 100] m");
  if (!(c.alternative_angle >= 0.0) || c.alternative_angle > 4.0)
    throw InputError("verify config: alternative_angle must be in [0, 4] rad");
  if (!(c.corner_radius >= 0.05) || c.corner_radius > 10.0)
    throw InputError("verify config: corner_radius must be in [0.05, 10] m");
  if (!(c.keep_along_ratio >= 0.0) || c.keep_along_ratio >= 1.0)
    throw InputError("verify config: keep_along_ratio must be in [0, 1)");
  if (!(c.keep_along_slack >= 0.0) || c.keep_along_slack > 5.0)
    throw InputError("verify config: keep_along_slack must be in [0, 5] m");
}

void VerifyMap::allocate(std::initializer_list<const Points2*> sets, int margin) {
  // The cell bounds in double first: a finite point far out has no int cell index.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Points2* set : sets)
    for (const Vec2& p : *set) {
      const Eigen::Vector2d c = (p * inv_resolution_).array().floor();
      lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    }
  lo.array() -= margin, hi.array() += margin;
  const double w = hi.x() - lo.x() + 1, h = hi.y() - lo.y() + 1;
  if (!(w * h <= kMaxVerifyCells))
    throw InputError("verify map: points and origins spread over " + std::to_string(w * resolution_) + " x " +
                     std::to_string(h * resolution_) + " m, more than 2^24 cells");
  if (!(lo.cwiseAbs().maxCoeff() <= kMaxCellIndex && hi.cwiseAbs().maxCoeff() <= kMaxCellIndex))
    throw InputError("verify map: a point or origin lies more than " +
                     std::to_string(kMaxCellIndex * resolution_) + " m from the map's origin");
  x0_ = static_cast<int>(lo.x()), y0_ = static_cast<int>(lo.y());
  width_ = static_cast<int>(w), height_ = static_cast<int>(h);
  cells_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), kUnknown);
}

void VerifyMap::set_shapes(double radius) {
  const std::vector<LocalShape> shapes = local_shapes(points_, radius);
  cornerness_.resize(shapes.size());
  std::transform(shapes.begin(), shapes.end(), cornerness_.begin(), [](const LocalShape& s) { return s.cornerness(); });
  wall_scatter_ = partslam::wall_scatter(shapes);
}

void VerifyMap::mark_occupied(const Eigen::Vector2i& c, int d) {
  for (int dy = -d; dy <= d; ++dy)
    for (int dx = -d; dx <= d; ++dx)
      if (dx * dx + dy * dy <= d * d) cells_[index_of(c.x() + dx, c.y() + dy)] = kOccupied;
}

VerifyMap::VerifyMap(const Points2& points, const Points2& origins, const VerifyConfig& config)
    : resolution_(config.resolution), inv_resolution_(1.0 / config.resolution), points_(points) {
  validate(config);
  for (const Points2* set : {&points, &origins})
    for (const Vec2& p : *set)
      if (!p.allFinite()) throw InputError("verify map: a point or origin is not finite");
  if (points.empty()) return;
  has_beams_ = !origins.empty();
  const int d = config.dilation;
  allocate({&points, &origins}, d + 1);  // throws for points spread too far
  set_shapes(config.corner_radius);
  // The points' own cells (for choosing each beam's origin), then the dilated occupied grid.
  std::vector<std::uint8_t> hit(cells_.size(), 0);
  std::vector<Eigen::Vector2i> point_cells;
  point_cells.reserve(points.size());
  for (const Vec2& p : points)
    point_cells.push_back(cell_of(p)), hit[index_of(point_cells.back().x(), point_cells.back().y())] = 1;
  for (const Eigen::Vector2i& c : point_cells) mark_occupied(c, d);
  if (!has_beams_) return;
  std::vector<Eigen::Vector2i> origin_cells;
  for (const Vec2& o : origins) origin_cells.push_back(cell_of(o));
  const double max_cells = config.max_ray * inv_resolution_;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2i& b = point_cells[i];
    int best = -1, best_blocked = std::numeric_limits<int>::max();
    double best_distance = 0;
    for (std::size_t k = 0; k < origin_cells.size(); ++k) {
      const Eigen::Vector2i& a = origin_cells[k];
      const double distance = (b - a).cast<double>().norm();
      if (distance > max_cells) continue;
      // Occupied cells the beam crosses before the last two (a wall grazed next to its endpoint is its own).
      int blocked = 0, steps = 0;
      const int length = std::max(std::abs(b.x() - a.x()), std::abs(b.y() - a.y()));
      walk_cells(a.x(), a.y(), b.x(), b.y(), [&](int x, int y) {
        if (++steps < length - 1 && hit[index_of(x, y)]) ++blocked;
        return blocked <= best_blocked;
      });
      if (blocked < best_blocked || (blocked == best_blocked && distance < best_distance))
        best = static_cast<int>(k), best_blocked = blocked, best_distance = distance;
    }
    if (best < 0) continue;
    const Eigen::Vector2i& a = origin_cells[static_cast<std::size_t>(best)];
    walk_cells(a.x(), a.y(), b.x(), b.y(), [&](int x, int y) {
      std::uint8_t& s = cells_[index_of(x, y)];
      if (s == kUnknown) s = kFree;
      return true;
    });
  }
}

VerifyMap VerifyMap::with_free_space(const Points2& points, const Points2& free_points,
                                     const VerifyConfig& config) {
  for (const Vec2& p : free_points)
    if (!p.allFinite()) throw InputError("verify map: a free point is not finite");
  VerifyMap m({}, {}, config);  // validates the config
  for (const Vec2& p : points)
    if (!p.allFinite()) throw InputError("verify map: a point or origin is not finite");
  if (points.empty() && free_points.empty()) return m;
  m.points_ = points;
  m.allocate({&points, &free_points}, config.dilation + 1);  // throws for points spread too far
  m.set_shapes(config.corner_radius);
  for (const Vec2& p : points) m.mark_occupied(m.cell_of(p), config.dilation);
  for (const Vec2& p : free_points) {
    const Eigen::Vector2i c = m.cell_of(p);
    std::uint8_t& s = m.cells_[m.index_of(c.x(), c.y())];
    if (s == kUnknown) s = kFree;
  }
  m.has_beams_ = !free_points.empty();
  return m;
}

VerifyMap VerifyMap::cropped(const Vec2& lo, const Vec2& hi) const {
  VerifyMap out;
  out.resolution_ = resolution_, out.inv_resolution_ = inv_resolution_, out.has_beams_ = has_beams_;
  out.wall_scatter_ = wall_scatter_;  // of the whole map, as the cornerness is
  if (lo.hasNaN() || hi.hasNaN()) return out;
  // The box's cells clamped to the grid in double (a box far out has no int cell), then cast.
  const double x0d = std::max<double>(x0_, std::floor(lo.x() * inv_resolution_));
  const double y0d = std::max<double>(y0_, std::floor(lo.y() * inv_resolution_));
  const double x1d = std::min<double>(x0_ + width_ - 1, std::floor(hi.x() * inv_resolution_));
  const double y1d = std::min<double>(y0_ + height_ - 1, std::floor(hi.y() * inv_resolution_));
  if (!(x1d >= x0d && y1d >= y0d)) return out;
  const int x0 = static_cast<int>(x0d), y0 = static_cast<int>(y0d);
  const int x1 = static_cast<int>(x1d), y1 = static_cast<int>(y1d);
  out.x0_ = x0, out.y0_ = y0, out.width_ = x1 - x0 + 1, out.height_ = y1 - y0 + 1;
  out.cells_.resize(static_cast<std::size_t>(out.width_) * static_cast<std::size_t>(out.height_));
  for (int y = y0; y <= y1; ++y) {
    const auto row =
        cells_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y - y0_) * width_ + (x0 - x0_));
    std::copy(
        row, row + out.width_,
        out.cells_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y - y0) * out.width_));
  }
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector2i c = cell_of(points_[i]);
    if (c.x() >= x0 && c.x() <= x1 && c.y() >= y0 && c.y() <= y1)
      out.points_.push_back(points_[i]), out.cornerness_.push_back(cornerness_[i]);
  }
  return out;
}

std::size_t VerifyMap::free_cells() const {
  return static_cast<std::size_t>(std::count(cells_.begin(), cells_.end(), kFree));
}

LikelihoodField verify_field(const VerifyMap& map) {
  const ScanMatcherConfig matcher;  // the front end's field: 0.05 m cells, sigma 0.1 m
  return LikelihoodField(map.points(), matcher.resolution, matcher.sigma);
}

PairFields::PairFields(const VerifyMap& query_map, const VerifyMap& map_map)
    : map(verify_field(map_map)), own_query_(verify_field(query_map)), query_(&own_query_) {}

PairFields::PairFields(const LikelihoodField& query_field, const VerifyMap& map_map)
    : map(verify_field(map_map)), query_(&query_field) {}

MatchTerms match_terms(const VerifyMap& query, const VerifyMap& map, const PairFields& fields,
                       const Pose2& T_map_query) {
  const SideReading q = read_side(query, map, fields.map, T_map_query);
  const SideReading m = read_side(map, query, fields.query(), T_map_query.inverse());
  MatchTerms t;
  t.query = q.terms, t.map = m.terms;
  t.query_fit = q.fit, t.map_fit = m.fit;
  t.query_corner_fit = q.corner_fit, t.map_corner_fit = m.corner_fit;
  t.beams = query.has_beams() && map.has_beams();
  return t;
}

double same_place_probability(const MatchTerms& t) {
  // Logistic in the twelve terms and every product of two of them, fitted by tools/fit_verification.py
  // (listwise, then Platt-scaled) on the tuning split: data sets #1..#5, 200 tasks each, N = 100, seed 1,
  // build/verify_features rows; docs/NOTES.md, "Verifying a match" and "Corner-weighted terms". Bare points
  // (no beams) have no free or seen shares: their free terms are 0 and their seen shares equal their
  // occupied ones.
  constexpr double kIntercept = -12.2275;
  constexpr std::array<double, 90> kWeights = {
      2.5258,   1.85797,    4.58989,   -2.02774,   4.30424,   1.32101,   6.31873,   4.00456,  0.555093,
      0.373035, 3.52568,    0.244908,  -1.0587,    -1.53589,  0.230385,  -8.67516,  -1.03338, -2.04159,
      -0.78056, 0.589359,   1.12086,   -1.15176,   -0.505791, -1.93281,  -0.921887, -3.02583, -6.79223,
      -1.61086, -1.16735,   1.52232,   -0.726561,  -1.19618,  1.18056,   -0.436645, 0.570961, -16.2244,
      -7.02866, -4.31308,   -2.86,     12.5872,    -16.0326,  -12.4719,  2.38751,   -1.68875, 16.0034,
      -2.03037, -4.95197,   -2.18158,  -0.0398623, 19.8118,   3.41474,   -15.8044,  7.45294,  7.9846,
      -1.33976, -2.32846,   -0.456316, 0.146782,   0.794117,  -0.901198, -0.503952, -1.23044, -1.38501,
      1.57592,  0.00449871, -0.945204, 0.532352,   -0.105135, 0.763488,  -0.712346, 3.2637,   0.322237,
      2.29226,  -1.47973,   0.613349,  -0.0579004, 0.909177,  0.914824,  1.70991,   0.462413, -1.43754,
      -1.04428, 1.25089,    0.496879,  -1.95767,   2.36431,   0.312473,  -2.19442,  1.07954,  -1.06558};
  const std::array<double, 12> x = {t.query.occupied, t.map.occupied, t.query.free,       t.map.free,
                                    t.query.seen,     t.map.seen,     t.query_fit,        t.map_fit,
                                    t.query.corner,   t.map.corner,   t.query_corner_fit, t.map_corner_fit};
  double z = kIntercept;
  std::size_t k = 0;
  for (const double v : x) z += kWeights[k++] * v;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i; j < x.size(); ++j) z += kWeights[k++] * x[i] * x[j];  // the products, row order
  return logistic(z);
}

Verified verify_at(const VerifyMap& query, const VerifyMap& map, const PairFields& fields,
                   const Pose2& T_map_query) {
  Verified v{T_map_query, match_terms(query, map, fields, T_map_query), 0.0};
  v.probability = same_place_probability(v.terms);
  return v;
}

Pose2 refine_match(const VerifyMap& query, const PairFields& fields, const Pose2& T_map_query,
                   const VerifyConfig& config) {
  validate(config);
  if (query.points().empty() || fields.map.empty()) return T_map_query;
  ScanMatcherConfig matcher;  // PairFields' field: 0.05 m cells, sigma 0.1 m
  matcher.linear_window = config.refine_window;
  matcher.angular_window = config.refine_angle;
  const Pose2 matched = match_scan(fields.map, query.points(), T_map_query, matcher).pose;
  // Along a direction the query's walls do not fix (a bare corridor's axis) the match fits about as well
  // anywhere: the translation along it stays within keep_along_slack of the input pose's.
  const std::optional<Vec2> weak = unconstrained_direction(query.wall_scatter(), config.keep_along_ratio);
  return weak ? keep_along(matched, T_map_query, *weak, config.keep_along_slack) : matched;
}

namespace {

Verified verify_match_with(const VerifyMap& query, const VerifyMap& map, const PairFields& fields,
                           const Pose2& T_map_query, const VerifyConfig& config, Verified* at_pose) {
  const Verified at = verify_at(query, map, fields, T_map_query);
  if (at_pose != nullptr) *at_pose = at;
  return refined(query, map, fields, at, config);
}

}  // namespace

Verified verify_match(const VerifyMap& query, const VerifyMap& map, const Pose2& T_map_query,
                      const VerifyConfig& config, Verified* at_pose) {
  return verify_match_with(query, map, PairFields(query, map), T_map_query, config, at_pose);
}

Verified verify_match(const VerifyMap& query, const LikelihoodField& query_field, const VerifyMap& map,
                      const Pose2& T_map_query, const VerifyConfig& config, Verified* at_pose) {
  return verify_match_with(query, map, PairFields(query_field, map), T_map_query, config, at_pose);
}

std::vector<DmmResult> dmm_poses(const PreparedQuery& query, const PreparedMap& map,
                                 const VerifyConfig& config) {
  DmmSearch search(query, map, config.alternative_distance, config.alternative_angle, /*lazy=*/true);
  std::vector<DmmResult> poses{search.next()};
  const int bar = static_cast<int>(config.alternative_bar * poses[0].inliers);
  for (int k = 0; k < config.alternatives && poses[0].inliers > 0; ++k) {
    const DmmResult alt = search.next(bar);
    if (!alt.exact || alt.inliers == 0) break;
    poses.push_back(alt);
  }
  return poses;
}

VerifiedDmm verify_dmm(const PreparedQuery& query, const PreparedMap& map, const VerifyMap& query_verify,
                       const VerifyMap& map_verify, const VerifyConfig& config) {
  const std::vector<DmmResult> poses = dmm_poses(query, map, config);
  VerifiedDmm out;
  out.eq1 = poses[0];
  out.poses = static_cast<int>(poses.size());
  // Every pose's terms at its lattice pose; the most probable few are refined, and the most probable of them
  // after that is the answer (ties: the more probable at the lattice).
  const PairFields fields(query_verify, map_verify);
  std::vector<Verified> lattice;
  for (const DmmResult& pose : poses) lattice.push_back(verify_at(query_verify, map_verify, fields, pose.T_map_query));
  std::stable_sort(lattice.begin(), lattice.end(),
                   [](const Verified& a, const Verified& b) { return a.probability > b.probability; });
  const std::size_t count = std::min(lattice.size(), static_cast<std::size_t>(config.refined));
  for (std::size_t k = 0; k < count; ++k)
    lattice[k] = refined(query_verify, map_verify, fields, lattice[k], config);
  const auto chosen =
      std::max_element(lattice.begin(), lattice.begin() + static_cast<std::ptrdiff_t>(count),
                       [](const Verified& a, const Verified& b) { return a.probability < b.probability; });
  out.best = *chosen;
  // The most probable pose elsewhere than the answer's, as dmm_poses tells poses apart.
  for (const Verified& v : lattice)
    if ((v.T_map_query.translation() - out.best.T_map_query.translation()).norm() >=
            config.alternative_distance ||
        std::abs(wrap_angle(v.T_map_query.theta - out.best.T_map_query.theta)) > config.alternative_angle)
      out.runner_up = std::max(out.runner_up, v.probability);
  return out;
}

}  // namespace partslam
