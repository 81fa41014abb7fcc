// Procedural Manhattan floor plan for the simulator (docs/DESIGN.md, "Embedded default"). A rectangular building:
// a band of rooms along the outer walls, a corridor ring inside it, and an inner block of rooms, optionally
// split by a cross corridor so that the corridors form a figure-eight (two small loops and a large one).
// Room widths along a corridor are drawn at random, each room has a door (a gap in its corridor wall) at a
// random place, and boxes (furniture in rooms, cabinets along corridors) make places distinguishable.
// All walls are axis-aligned segments of zero thickness; everything is drawn from the given Rng.
#pragma once

#include <vector>

#include "core/random.h"
#include "core/sim/ray_caster.h"

namespace partslam {

struct FloorPlanConfig {
  double width = 28.0;            ///< outer extent along x [m]
  double height = 20.0;           ///< outer extent along y [m]
  double corridor_width = 2.0;    ///< [m]
  double room_depth = 5.0;        ///< depth of the rooms between the outer walls and the corridor ring [m]
  double min_room_width = 3.0;    ///< nominal room widths along a corridor lie in [min, max] [m]
  double max_room_width = 6.0;    ///< [m]
  double door_width = 1.0;        ///< [m]
  bool cross_corridor = true;     ///< split the inner block by a corridor: figure-eight instead of a ring
  int clutter_per_room = 2;       ///< boxes (furniture) tried per room
  int corridor_clutter = 10;      ///< boxes (cabinets) tried against the corridor walls
  double min_clutter_size = 0.3;  ///< box sides lie in [min, max] (cabinets: twice as long) [m]
  double max_clutter_size = 1.0;  ///< [m]
};

/// Throws InputError naming the offending field ("building.<field>").
void validate(const FloorPlanConfig& config);

/// A room off a corridor. The door is a gap of door_width in the wall it shares with the corridor.
struct Room {
  Box2 box;                         ///< [m]
  bool has_door = false;            ///< false when its corridor frontage is too short for a door
  Vec2 door_centre = Vec2::Zero();  ///< middle of the door gap, on the wall [m]
  Vec2 door_normal = Vec2::Zero();  ///< unit vector from the room through the door into the corridor
};

struct FloorPlan {
  Box2 bounds;                  ///< outer walls [m]
  double corridor_width = 0.0;  ///< [m]
  double door_width = 0.0;      ///< [m]
  Segments2 walls;              ///< all walls and the sides of all clutter boxes [m]
  std::vector<Room> rooms;
  std::vector<Box2> clutter;  ///< boxes; their sides are in walls too
  std::vector<Vec2> loop;     ///< one lap of the corridor centreline, a closed polyline (front == back)
};

/// Walls, corridors and rooms with their doors; no clutter yet (it must keep clear of the robot's path).
FloorPlan make_floor_plan(const FloorPlanConfig& config, Rng& rng);

/// Adds the clutter boxes: each at least `clearance` from every segment of the polyline `path` (what the
/// robot drives), clear of doors and of the other boxes. Candidates that do not fit are skipped.
void add_clutter(const FloorPlanConfig& config, const std::vector<Vec2>& path, double clearance, Rng& rng,
                 FloorPlan* plan);

/// Euclidean distance between a segment and an axis-aligned box (0 when they intersect).
double distance(const Segment2& segment, const Box2& box);

}  // namespace partslam
