#include "core/slam/map_check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/maps/cell_walk.h"
#include "core/maps/submap.h"

namespace partslam {
namespace {

// Per cell: how many endpoints fell in it, and which visits they came from: bit (travel / min_gap) mod 64 (a run
// longer than 64 gaps folds onto itself, which can only hide a crossing, never make one).
struct Cell {
  std::uint32_t hits = 0;
  std::uint64_t visits = 0;
};

// A visit's bit in Cell::visits.
std::uint64_t visit_bit(int bucket) { return std::uint64_t{1} << (((bucket % 64) + 64) % 64); }

// The visits within one gap of a scan's own: its bucket and the two beside it.
std::uint64_t own_visits(int bucket) { return visit_bit(bucket - 1) | visit_bit(bucket) | visit_bit(bucket + 1); }

class WallGrid {
 public:
  WallGrid(const Box2& box, double resolution) {
    resolution_ = resolution;
    const double cells = (box.x_max - box.x_min) * (box.y_max - box.y_min) / (resolution * resolution);
    if (cells > kMaxCells) resolution_ *= std::sqrt(cells / kMaxCells);
    x0_ = box.x_min, y0_ = box.y_min;
    width_ = static_cast<int>(std::ceil((box.x_max - box.x_min) / resolution_)) + 1;
    height_ = static_cast<int>(std::ceil((box.y_max - box.y_min) / resolution_)) + 1;
    cells_.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  }
  double resolution() const { return resolution_; }
  /// Grid coordinates (in cells, continuous) of a world point.
  Vec2 grid(const Vec2& p) const { return {(p.x() - x0_) / resolution_, (p.y() - y0_) / resolution_}; }
  const Cell* at(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return nullptr;
    return &cells_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)];
  }
  Cell* at(int x, int y) { return const_cast<Cell*>(std::as_const(*this).at(x, y)); }
  void hit(const Vec2& p, int bucket) {
    const Vec2 g = grid(p);
    if (Cell* c = at(static_cast<int>(g.x()), static_cast<int>(g.y()))) {
      ++c->hits;
      c->visits |= visit_bit(bucket);
    }
  }
  /// A wall another visit saw, where this visit (`own`) saw none: a beam grazing a wall that its own visit saw
  /// too is not a crossing.
  bool wall_of_another_visit(int x, int y, std::uint64_t own, const MapCheckConfig& c) const {
    const Cell* cell = at(x, y);
    if (cell == nullptr || cell->hits < static_cast<std::uint32_t>(c.min_hits) || (cell->visits & ~own) == 0)
      return false;
    for (int dy = -c.own_cells; dy <= c.own_cells; ++dy)
      for (int dx = -c.own_cells; dx <= c.own_cells; ++dx)
        if (const Cell* n = at(x + dx, y + dy); n != nullptr && (n->visits & own) != 0) return false;
    return true;
  }
  /// A cell another visit than `own` hit.
  bool seen_by_another_visit(int x, int y, std::uint64_t own) const {
    const Cell* cell = at(x, y);
    return cell != nullptr && (cell->visits & ~own) != 0;
  }

 private:
  static constexpr double kMaxCells = 16777216.0;  // 2^24 (16 bytes each)
  double resolution_ = 0.1, x0_ = 0, y0_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<Cell> cells_;
};

// The scans read: the first, then each one at least key_spacing of travel after the one read before it.
std::vector<std::size_t> key_scan_indices(const std::vector<double>& travel, double key_spacing) {
  std::vector<std::size_t> keys;
  for (std::size_t i = 0; i < travel.size(); ++i)
    if (keys.empty() || travel[i] - travel[keys.back()] >= key_spacing) keys.push_back(i);
  return keys;
}

// Per key scan, its beams' endpoints within max_range in the world frame and its laser, last; `box` grown to hold
// them all (every beam).
std::vector<Points2> key_scan_beams(const Scans& scans, const std::vector<std::size_t>& keys, double max_range,
                                    Box2& box) {
  std::vector<Points2> ends(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const Scan& s = scans[keys[k]];
    ends[k] = points_world(s, max_range);
    ends[k].push_back(s.T_world_laser.translation());  // the laser, last: the box holds every beam
    for (const Vec2& p : ends[k]) {
      box.x_min = std::min(box.x_min, p.x()), box.x_max = std::max(box.x_max, p.x());
      box.y_min = std::min(box.y_min, p.y()), box.y_max = std::max(box.y_max, p.y());
    }
  }
  return ends;
}

// Revisiting and crossing beams per square of place_size where the robot was (its index along x and y).
using PlaceBeams = std::map<std::pair<int, int>, std::pair<std::size_t, std::size_t>>;

// Reads one key scan's beams (`ends`: endpoints, then the laser) against the walls of the other visits than
// `own`: counts them into out's beam totals and into their place.
void read_scan_beams(const WallGrid& grid, const Points2& ends, std::uint64_t own, const MapCheckConfig& c,
                     MapCheck& out, PlaceBeams& places) {
  const double margin_cells = c.end_margin / grid.resolution();
  const Vec2 laser = grid.grid(ends.back());
  for (std::size_t j = 0; j + 1 < ends.size(); ++j) {
    ++out.beams;
    const Vec2 end = grid.grid(ends[j]);
    const double length = (end - laser).norm();
    // The endpoint agrees with another visit when it lands on (or next to) that visit's wall.
    bool agrees = false;
    const int ex = static_cast<int>(end.x()), ey = static_cast<int>(end.y());
    for (int dy = -1; dy <= 1 && !agrees; ++dy)
      for (int dx = -1; dx <= 1 && !agrees; ++dx) agrees = grid.seen_by_another_visit(ex + dx, ey + dy, own);
    bool crosses = false;
    if (length > margin_cells) {
      const Vec2 stop = laser + (end - laser) * ((length - margin_cells) / length);
      crosses = walk_cells(laser, stop, [&](int x, int y) { return grid.wall_of_another_visit(x, y, own, c); });
    }
    if (!agrees && !crosses) continue;
    ++out.revisiting_beams;
    const Vec2& p = ends.back();  // the robot's place
    auto& place = places[{static_cast<int>(std::floor(p.x() / c.place_size)),
                          static_cast<int>(std::floor(p.y() / c.place_size))}];
    ++place.first;
    if (!crosses) continue;
    ++out.crossing_beams;
    ++place.second;
  }
}

// The places, the worst judged one, the shares and the verdict, from the beams counted.
void judge_places(const PlaceBeams& places, const MapCheckConfig& c, MapCheck& out) {
  for (const auto& [square, n] : places) {
    const Vec2 centre((square.first + 0.5) * c.place_size, (square.second + 0.5) * c.place_size);
    out.places.push_back({centre, n.first, n.second});
    if (n.first < static_cast<std::size_t>(c.min_place_beams)) continue;
    const double share = static_cast<double>(n.second) / static_cast<double>(n.first);
    if (share <= out.worst_place_share) continue;
    out.worst_place_share = share;
    out.worst_place_crossings = n.second;
    out.worst_place = centre;
  }
  out.crossing_share = out.revisiting_beams > 0
                           ? static_cast<double>(out.crossing_beams) / static_cast<double>(out.revisiting_beams)
                           : 0.0;
  out.judged = out.revisiting_beams >= static_cast<std::size_t>(c.min_revisiting_beams);
  out.passed = !out.judged ||
               (out.crossing_share <= c.max_crossing_share && out.worst_place_share <= c.max_place_share);
}

}  // namespace

void validate(const MapCheckConfig& c) {
  const std::pair<double, const char*> positive[] = {{c.resolution, "resolution"}, {c.max_range, "max_range"},
                                                     {c.key_spacing, "key_spacing"}, {c.min_gap, "min_gap"}};
  for (const auto& [v, name] : positive)
    if (!(v > 0) || !(v <= 1e4)) throw InputError(std::string("map check config: ") + name + " must be in (0, 10000]");
  if (!(c.end_margin >= 0 && c.end_margin <= 100)) throw InputError("map check config: end_margin must be in [0, 100]");
  if (c.min_hits < 1 || c.min_hits > 1000) throw InputError("map check config: min_hits must be in [1, 1000]");
  if (c.min_place_beams < 1 || c.min_revisiting_beams < 1)
    throw InputError("map check config: min_place_beams and min_revisiting_beams must be at least 1");
  if (!(c.max_crossing_share >= 0 && c.max_crossing_share <= 1))
    throw InputError("map check config: max_crossing_share must be in [0, 1]");
  if (!(c.max_place_share >= 0 && c.max_place_share <= 1))
    throw InputError("map check config: max_place_share must be in [0, 1]");
  if (c.own_cells < 0 || c.own_cells > 10) throw InputError("map check config: own_cells must be in [0, 10]");
  if (!(c.place_size > 0 && c.place_size <= 1000)) throw InputError("map check config: place_size must be in (0, 1000]");
}

MapCheck check_map(const Scans& scans, const MapCheckConfig& c) {
  validate(c);
  MapCheck out;
  const std::vector<double> travel = travel_distances(scans);
  const std::vector<std::size_t> keys = key_scan_indices(travel, c.key_spacing);
  out.scans = keys.size();
  if (keys.empty()) return out;
  Box2 box{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  const std::vector<Points2> ends = key_scan_beams(scans, keys, c.max_range, box);
  WallGrid grid(box, c.resolution);
  const auto bucket = [&](std::size_t k) { return static_cast<int>(travel[keys[k]] / c.min_gap); };
  for (std::size_t k = 0; k < keys.size(); ++k)
    for (std::size_t j = 0; j + 1 < ends[k].size(); ++j) grid.hit(ends[k][j], bucket(k));
  PlaceBeams places;
  for (std::size_t k = 0; k < keys.size(); ++k) read_scan_beams(grid, ends[k], own_visits(bucket(k)), c, out, places);
  judge_places(places, c, out);
  return out;
}

}  // namespace partslam
