#include "core/matching/verification.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/matching/scan_matcher.h"

namespace partslam {
namespace {

constexpr double kMaxCells = double(1 << 24);

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

SideTerms side_terms(const Points2& points, const VerifyMap& other, const Pose2& T_other_points) {
  SideTerms t;
  if (points.empty()) return t;
  int occupied = 0, free = 0;
  for (const Vec2& p : points) {
    const std::uint8_t s = other.at(T_other_points * p);
    occupied += s == VerifyMap::kOccupied;
    free += s == VerifyMap::kFree;
  }
  const double n = static_cast<double>(points.size());
  t.occupied = occupied / n;
  t.free = free / n;
  t.seen = (occupied + free) / n;
  return t;
}

// The mean of `field` at the points moved by T_field_points (0 for no points).
double mean_field(const LikelihoodField& field, const Points2& points, const Pose2& T_field_points) {
  double sum = 0;
  for (const Vec2& p : points) sum += field.at(T_field_points * p);
  return points.empty() ? 0.0 : sum / static_cast<double>(points.size());
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
}

void VerifyMap::allocate(std::initializer_list<const Points2*> sets, int margin) {
  Eigen::Vector2i lo(std::numeric_limits<int>::max(), std::numeric_limits<int>::max()), hi = -lo;
  for (const Points2* set : sets)
    for (const Vec2& p : *set) lo = lo.cwiseMin(cell_of(p)), hi = hi.cwiseMax(cell_of(p));
  lo.array() -= margin, hi.array() += margin;
  const double w = double(hi.x()) - lo.x() + 1, h = double(hi.y()) - lo.y() + 1;
  if (!(w * h <= kMaxCells))
    throw InputError("verify map: points and origins spread over " + std::to_string(w * resolution_) + " x " +
                     std::to_string(h * resolution_) + " m, more than 2^24 cells");
  x0_ = lo.x(), y0_ = lo.y(), width_ = static_cast<int>(w), height_ = static_cast<int>(h);
  cells_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), kUnknown);
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
  allocate({&points, &origins}, d + 1);
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
  m.allocate({&points, &free_points}, config.dilation + 1);
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
  const int x0 = std::max(x0_, static_cast<int>(std::floor(lo.x() * inv_resolution_)));
  const int y0 = std::max(y0_, static_cast<int>(std::floor(lo.y() * inv_resolution_)));
  const int x1 = std::min(x0_ + width_ - 1, static_cast<int>(std::floor(hi.x() * inv_resolution_)));
  const int y1 = std::min(y0_ + height_ - 1, static_cast<int>(std::floor(hi.y() * inv_resolution_)));
  if (x1 < x0 || y1 < y0) return out;
  out.x0_ = x0, out.y0_ = y0, out.width_ = x1 - x0 + 1, out.height_ = y1 - y0 + 1;
  out.cells_.resize(static_cast<std::size_t>(out.width_) * static_cast<std::size_t>(out.height_));
  for (int y = y0; y <= y1; ++y) {
    const auto row =
        cells_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y - y0_) * width_ + (x0 - x0_));
    std::copy(
        row, row + out.width_,
        out.cells_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y - y0) * out.width_));
  }
  for (const Vec2& p : points_) {
    const Eigen::Vector2i c = cell_of(p);
    if (c.x() >= x0 && c.x() <= x1 && c.y() >= y0 && c.y() <= y1) out.points_.push_back(p);
  }
  return out;
}

std::size_t VerifyMap::free_cells() const {
  return static_cast<std::size_t>(std::count(cells_.begin(), cells_.end(), kFree));
}

PairFields::PairFields(const VerifyMap& query_map, const VerifyMap& map_map) {
  const ScanMatcherConfig matcher;  // the front end's field: 0.05 m cells, sigma 0.1 m
  query = LikelihoodField(query_map.points(), matcher.resolution, matcher.sigma);
  map = LikelihoodField(map_map.points(), matcher.resolution, matcher.sigma);
}

MatchTerms match_terms(const VerifyMap& query, const VerifyMap& map, const PairFields& fields,
                       const Pose2& T_map_query) {
  MatchTerms t;
  t.query = side_terms(query.points(), map, T_map_query);
  t.map = side_terms(map.points(), query, T_map_query.inverse());
  t.query_fit = mean_field(fields.map, query.points(), T_map_query);
  t.map_fit = mean_field(fields.query, map.points(), T_map_query.inverse());
  t.beams = query.has_beams() && map.has_beams();
  return t;
}

double same_place_probability(const MatchTerms& t) {
  // Fitted by tools/fit_verification.py (listwise, then Platt-scaled) on the tuning split: data sets #1..#5,
  // 200 tasks each, N = 100, seed 1, build/verify_features rows; docs/NOTES.md, "Verifying a match". Bare
  // points (no beams) have no free or seen shares: their free terms are 0 and their seen shares equal their
  // occupied ones.
  constexpr double kIntercept = -7.7109;
  constexpr double kQueryOccupied = 1.0615, kMapOccupied = 0.1485, kQueryFree = -4.2506, kMapFree = -3.8222,
                   kQuerySeen = 0.1554, kMapSeen = -2.0241, kQueryFit = 4.9938, kMapFit = 3.8559;
  return logistic(kIntercept + kQueryOccupied * t.query.occupied + kMapOccupied * t.map.occupied +
                  kQueryFree * t.query.free + kMapFree * t.map.free + kQuerySeen * t.query.seen +
                  kMapSeen * t.map.seen + kQueryFit * t.query_fit + kMapFit * t.map_fit);
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
  return match_scan(fields.map, query.points(), T_map_query, matcher).pose;
}

Verified verify_match(const VerifyMap& query, const VerifyMap& map, const Pose2& T_map_query,
                      const VerifyConfig& config) {
  const PairFields fields(query, map);
  return refined(query, map, fields, verify_at(query, map, fields, T_map_query), config);
}

std::vector<DmmResult> dmm_poses(const PreparedQuery& query, const PreparedMap& map,
                                 const VerifyConfig& config) {
  DmmSearch search(query, map, config.alternative_distance, config.alternative_angle);
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
  for (std::size_t k = 0; k < count; ++k) {
    Verified v = refined(query_verify, map_verify, fields, lattice[k], config);
    if (k == 0 || v.probability > out.best.probability) out.best = std::move(v);
  }
  return out;
}

}  // namespace partslam
