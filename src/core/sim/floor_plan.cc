#include "core/sim/floor_plan.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.h"

namespace partslam {
namespace {

constexpr double kDoorMargin = 0.3;   // solid wall kept on each side of a door [m]
constexpr double kDoorKeepOut = 0.5;  // clutter stays this far from door gaps [m]
constexpr double kBoxGap = 0.3;       // min distance between two clutter boxes [m]
constexpr int kAttempts = 20;         // placement tries per box

// An axis-aligned wall line x = c (vertical) or y = c over [lo, hi]; doors are gaps cut from it.
struct WallLine {
  bool vertical = false;
  double c = 0.0, lo = 0.0, hi = 0.0;
  std::vector<std::pair<double, double>> gaps;
};

Segment2 axis_segment(bool vertical, double c, double a, double b) {
  return vertical ? Segment2{{c, a}, {c, b}} : Segment2{{a, c}, {b, c}};
}

void emit(WallLine line, Segments2* out) {
  std::sort(line.gaps.begin(), line.gaps.end());
  double s = line.lo;
  for (const auto& [g0, g1] : line.gaps) {
    if (g0 > s) out->push_back(axis_segment(line.vertical, line.c, s, g0));
    s = std::max(s, g1);
  }
  if (line.hi > s) out->push_back(axis_segment(line.vertical, line.c, s, line.hi));
}

// Boundaries lo = b_0 < ... < b_n = hi of rooms whose nominal widths are drawn from [min_w, max_w] and
// scaled to fill the interval.
std::vector<double> split(double lo, double hi, double min_w, double max_w, Rng& rng) {
  const double len = hi - lo;
  const int n_max = std::max(1, static_cast<int>(std::floor(len / min_w + 1e-9)));
  const int n_min = std::clamp(static_cast<int>(std::ceil(len / max_w - 1e-9)), 1, n_max);
  const int n = n_min + static_cast<int>(rng.index(static_cast<std::uint64_t>(n_max - n_min + 1)));
  std::vector<double> widths(n);
  double sum = 0.0;
  for (double& w : widths) sum += (w = rng.uniform(min_w, max_w));
  std::vector<double> b{lo};
  double acc = 0.0;
  for (int k = 0; k + 1 < n; ++k) b.push_back(lo + (acc += widths[k]) * len / sum);
  b.push_back(hi);
  return b;
}

double point_box_distance(const Vec2& p, const Box2& b) {
  const double dx = std::max({b.x_min - p.x(), 0.0, p.x() - b.x_max});
  const double dy = std::max({b.y_min - p.y(), 0.0, p.y() - b.y_max});
  return std::hypot(dx, dy);
}

double point_segment_distance(const Vec2& p, const Segment2& s) {
  const Vec2 e = s.b - s.a;
  const double len2 = e.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - s.a).dot(e) / len2, 0.0, 1.0) : 0.0;
  return (s.a + t * e - p).norm();
}

double box_distance(const Box2& a, const Box2& b) {
  const double dx = std::max({a.x_min - b.x_max, b.x_min - a.x_max, 0.0});
  const double dy = std::max({a.y_min - b.y_max, b.y_min - a.y_max, 0.0});
  return std::hypot(dx, dy);
}

void add_box(const Box2& b, FloorPlan* plan) {
  plan->clutter.push_back(b);
  const Vec2 c[4] = {{b.x_min, b.y_min}, {b.x_max, b.y_min}, {b.x_max, b.y_max}, {b.x_min, b.y_max}};
  for (int k = 0; k < 4; ++k) plan->walls.push_back({c[k], c[(k + 1) % 4]});
}

}  // namespace

void validate(const FloorPlanConfig& c) {
  auto fail = [](const std::string& field, const std::string& what) {
    throw InputError("simulator config: building." + field + " " + what);
  };
  auto positive = [&](double v, const char* field, double max = 1000.0) {
    if (!(v > 0.0) || !(v <= max))
      fail(field, "must be in (0, " + std::to_string(max) + "], got " + std::to_string(v));
  };
  positive(c.width, "width");
  positive(c.height, "height");
  positive(c.corridor_width, "corridor_width");
  positive(c.room_depth, "room_depth");
  positive(c.door_width, "door_width");
  positive(c.min_room_width, "min_room_width");
  positive(c.max_room_width, "max_room_width");
  positive(c.min_clutter_size, "min_clutter_size");
  positive(c.max_clutter_size, "max_clutter_size");
  if (c.min_room_width < c.door_width + 2 * kDoorMargin) {
    fail("min_room_width", "must be >= door_width + " + std::to_string(2 * kDoorMargin) + " m");
  }
  if (c.room_depth < c.door_width + 2 * kDoorMargin) {
    fail("room_depth", "must be >= door_width + " + std::to_string(2 * kDoorMargin) + " m");
  }
  if (c.max_room_width < c.min_room_width) fail("max_room_width", "must be >= min_room_width");
  if (c.max_clutter_size < c.min_clutter_size) fail("max_clutter_size", "must be >= min_clutter_size");
  if (c.max_clutter_size > c.min_room_width / 2) fail("max_clutter_size", "must be <= min_room_width / 2");
  const double ring = 2 * (c.room_depth + c.corridor_width);
  const double need_w =
      ring + c.min_room_width + (c.cross_corridor ? c.corridor_width + c.min_room_width : 0.0);
  if (c.width < need_w) {
    fail("width",
         "is too small for room_depth, corridor_width and min_room_width: need >= " + std::to_string(need_w));
  }
  if (c.height < ring + c.min_room_width) {
    fail("height", "is too small for room_depth, corridor_width and min_room_width: need >= " +
                       std::to_string(ring + c.min_room_width));
  }
  if (c.clutter_per_room < 0 || c.clutter_per_room > 100) fail("clutter_per_room", "must be in [0, 100]");
  if (c.corridor_clutter < 0 || c.corridor_clutter > 1000) fail("corridor_clutter", "must be in [0, 1000]");
}

namespace {

// Corridor centreline: a figure-eight through the cross corridor (at x = cx), or the plain ring.
std::vector<Vec2> corridor_loop(const FloorPlanConfig& config, double cx) {
  const double d = config.room_depth, cw = config.corridor_width;
  const double x0 = d + cw / 2, x1 = config.width - d - cw / 2, y0 = d + cw / 2, y1 = config.height - d - cw / 2;
  if (config.cross_corridor) {
    const Vec2 j0{cx, y0}, j1{cx, y1};
    return {j0, {x1, y0}, {x1, y1}, j1, j0, {x0, y0}, {x0, y1}, j1, j0};
  }
  const Vec2 m{0.5 * (x0 + x1), y0};
  return {m, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}, m};
}

}  // namespace

FloorPlan make_floor_plan(const FloorPlanConfig& config, Rng& rng) {
  validate(config);
  const double W = config.width, H = config.height, d = config.room_depth, cw = config.corridor_width;
  const double min_w = config.min_room_width, max_w = config.max_room_width, dw = config.door_width;
  FloorPlan plan;
  plan.bounds = {0.0, W, 0.0, H};
  plan.corridor_width = cw;
  plan.door_width = dw;

  std::vector<WallLine> lines;
  auto line = [&](bool vertical, double c, double lo, double hi) {
    lines.push_back({vertical, c, lo, hi, {}});
    return lines.size() - 1;
  };
  // A room whose side on wall line `wall` faces a corridor over [f0, f1]; the door goes somewhere in there.
  auto room = [&](const Box2& box, std::size_t wall, double f0, double f1, const Vec2& normal) {
    Room r{box};
    if (f1 - f0 >= dw + 2 * kDoorMargin) {
      const double c = rng.uniform(f0 + kDoorMargin + dw / 2, f1 - kDoorMargin - dw / 2);
      lines[wall].gaps.push_back({c - dw / 2, c + dw / 2});
      r.has_door = true;
      r.door_centre = lines[wall].vertical ? Vec2(lines[wall].c, c) : Vec2(c, lines[wall].c);
      r.door_normal = normal;
    }
    plan.rooms.push_back(r);
  };

  line(false, 0.0, 0.0, W), line(false, H, 0.0, W), line(true, 0.0, 0.0, H), line(true, W, 0.0, H);
  // Outer band. The bottom and top bands span the full width (their corner rooms reach the outer walls).
  const std::size_t ring_wall[4] = {line(false, d, 0.0, W), line(false, H - d, 0.0, W),
                                    line(true, d, d, H - d), line(true, W - d, d, H - d)};
  for (int side = 0; side < 2; ++side) {
    const double ya = side == 0 ? 0.0 : H - d, yb = ya + d;
    std::vector<double> b = split(d, W - d, min_w, max_w, rng);
    b.front() = 0.0, b.back() = W;
    for (std::size_t k = 0; k + 1 < b.size(); ++k) {
      if (k > 0) line(true, b[k], ya, yb);
      room({b[k], b[k + 1], ya, yb}, ring_wall[side], std::max(b[k], d), std::min(b[k + 1], W - d),
           Vec2(0.0, side == 0 ? 1.0 : -1.0));
    }
  }
  for (int side = 0; side < 2; ++side) {
    const double xa = side == 0 ? 0.0 : W - d, xb = xa + d;
    const std::vector<double> b = split(d, H - d, min_w, max_w, rng);
    for (std::size_t k = 0; k + 1 < b.size(); ++k) {
      if (k > 0) line(false, b[k], xa, xb);
      room({xa, xb, b[k], b[k + 1]}, ring_wall[2 + side], b[k], b[k + 1], Vec2(side == 0 ? 1.0 : -1.0, 0.0));
    }
  }
  // Inner block(s): one or two rows of rooms, doors onto the ring's bottom / top corridor.
  const double ix0 = d + cw, ix1 = W - d - cw, iy0 = d + cw, iy1 = H - d - cw;
  const double cx = config.cross_corridor ? rng.uniform(ix0 + min_w + cw / 2, ix1 - min_w - cw / 2) : 0.0;
  std::vector<std::pair<double, double>> blocks;
  if (config.cross_corridor) {
    blocks = {{ix0, cx - cw / 2}, {cx + cw / 2, ix1}};
  } else {
    blocks = {{ix0, ix1}};
  }
  for (const auto& [bx0, bx1] : blocks) {
    const std::size_t bottom = line(false, iy0, bx0, bx1), top = line(false, iy1, bx0, bx1);
    line(true, bx0, iy0, iy1), line(true, bx1, iy0, iy1);
    const bool two_rows = iy1 - iy0 >= 2 * min_w;
    const double mid = two_rows ? 0.5 * (iy0 + iy1) : iy1;
    if (two_rows) line(false, mid, bx0, bx1);
    for (int row = 0; row < (two_rows ? 2 : 1); ++row) {
      const double ya = row == 0 ? iy0 : mid, yb = row == 0 ? mid : iy1;
      const std::vector<double> b = split(bx0, bx1, min_w, max_w, rng);
      for (std::size_t k = 0; k + 1 < b.size(); ++k) {
        if (k > 0) line(true, b[k], ya, yb);
        room({b[k], b[k + 1], ya, yb}, row == 0 ? bottom : top, b[k], b[k + 1],
             Vec2(0.0, row == 0 ? -1.0 : 1.0));
      }
    }
  }
  for (const WallLine& l : lines) emit(l, &plan.walls);
  plan.loop = corridor_loop(config, cx);
  return plan;
}

double distance(const Segment2& s, const Box2& b) {
  // Liang-Barsky: does the segment cross the box?
  const Vec2 e = s.b - s.a;
  const double p[4] = {-e.x(), e.x(), -e.y(), e.y()};
  const double q[4] = {s.a.x() - b.x_min, b.x_max - s.a.x(), s.a.y() - b.y_min, b.y_max - s.a.y()};
  double t0 = 0.0, t1 = 1.0;
  bool crosses = true;
  for (int k = 0; k < 4 && crosses; ++k) {
    if (p[k] == 0.0) {
      crosses = q[k] >= 0.0;
    } else if (p[k] < 0.0) {
      t0 = std::max(t0, q[k] / p[k]);
    } else {
      t1 = std::min(t1, q[k] / p[k]);
    }
  }
  if (crosses && t0 <= t1) return 0.0;
  double best = std::min(point_box_distance(s.a, b), point_box_distance(s.b, b));
  for (const Vec2& c :
       {Vec2(b.x_min, b.y_min), Vec2(b.x_max, b.y_min), Vec2(b.x_min, b.y_max), Vec2(b.x_max, b.y_max)}) {
    best = std::min(best, point_segment_distance(c, s));
  }
  return best;
}

void add_clutter(const FloorPlanConfig& config, const std::vector<Vec2>& path, double clearance, Rng& rng,
                 FloorPlan* plan) {
  validate(config);
  Segments2 keep_out, doors;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) keep_out.push_back({path[k], path[k + 1]});
  for (const Room& r : plan->rooms) {
    if (!r.has_door) continue;
    const Vec2 t(-r.door_normal.y(), r.door_normal.x());
    doors.push_back({r.door_centre - t * (plan->door_width / 2), r.door_centre + t * (plan->door_width / 2)});
  }
  auto fits = [&](const Box2& box) {
    for (const Segment2& s : keep_out) {
      if (distance(s, box) < clearance) return false;
    }
    for (const Segment2& s : doors) {
      if (distance(s, box) < kDoorKeepOut) return false;
    }
    for (const Box2& other : plan->clutter) {
      if (box_distance(box, other) < kBoxGap) return false;
    }
    return true;
  };
  const double lo = config.min_clutter_size, hi = config.max_clutter_size;
  // Furniture: against a wall of the room or free-standing.
  for (std::size_t i = 0; i < plan->rooms.size(); ++i) {
    const Box2 room = plan->rooms[i].box;
    for (int n = 0; n < config.clutter_per_room; ++n) {
      for (int attempt = 0; attempt < kAttempts; ++attempt) {
        const double a = rng.uniform(lo, hi), b = rng.uniform(lo, hi);
        Box2 box;
        if (rng.uniform() < 0.5) {
          const int side = static_cast<int>(rng.index(4));
          const bool horizontal_wall = side < 2;
          const double span_lo = horizontal_wall ? room.x_min : room.y_min;
          const double span_hi = horizontal_wall ? room.x_max : room.y_max;
          if (span_hi - span_lo < a + 0.1) continue;
          const double t = rng.uniform(span_lo + 0.05, span_hi - 0.05 - a);
          if (horizontal_wall) {
            const double y = side == 0 ? room.y_min : room.y_max - b;
            box = {t, t + a, y, y + b};
          } else {
            const double x = side == 2 ? room.x_min : room.x_max - b;
            box = {x, x + b, t, t + a};
          }
        } else {
          if (room.width() < a + 0.6 || room.height() < b + 0.6) continue;
          const double x = rng.uniform(room.x_min + 0.3, room.x_max - 0.3 - a);
          const double y = rng.uniform(room.y_min + 0.3, room.y_max - 0.3 - b);
          box = {x, x + a, y, y + b};
        }
        if (fits(box)) {
          add_box(box, plan);
          break;
        }
      }
    }
  }
  // Cabinets against the corridor walls, away from corners and junctions (the loop's vertices).
  const double cw = plan->corridor_width;
  for (int n = 0; n < config.corridor_clutter && plan->loop.size() >= 2; ++n) {
    for (int attempt = 0; attempt < kAttempts; ++attempt) {
      const std::size_t k = rng.index(plan->loop.size() - 1);
      const Vec2 p = plan->loop[k], q = plan->loop[k + 1];
      const double len = rng.uniform(2 * lo, 2 * hi), depth = rng.uniform(0.1, 0.2) * cw;
      const double side = rng.index(2) == 0 ? 1.0 : -1.0;
      const double leg = (q - p).norm();
      if (leg < 2 * cw + len) continue;
      const Vec2 u = (q - p) / leg, v(-u.y(), u.x());
      const double t = rng.uniform(cw + len / 2, leg - cw - len / 2);
      const Vec2 c = p + t * u + side * (cw / 2 - depth / 2) * v;
      const double hx = std::abs(u.x()) * len / 2 + std::abs(v.x()) * depth / 2;
      const double hy = std::abs(u.y()) * len / 2 + std::abs(v.y()) * depth / 2;
      const Box2 box{c.x() - hx, c.x() + hx, c.y() - hy, c.y() + hy};
      if (fits(box)) {
        add_box(box, plan);
        break;
      }
    }
  }
}

}  // namespace partslam
