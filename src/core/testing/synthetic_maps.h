// Synthetic Manhattan-ish point maps for tests and benchmarks: random
// axis-aligned wall segments sampled with noise, cropped and expressed in query / map frames with a known
// relative pose. Header-only, deterministic given the generator's seed.
#pragma once

#include <numbers>
#include <random>
#include <vector>

#include "core/maps/submap.h"
#include "core/types.h"

namespace partslam::testing {

/// Random axis-aligned walls in [-size/2, size/2]^2 (plus a partial outer boundary), and short clutter segments
/// of any orientation (furniture) that make places distinguishable.
struct SyntheticWorld {
  struct Wall {
    Vec2 a, b;
  };
  std::vector<Wall> walls;
};

inline SyntheticWorld random_world(std::mt19937_64& rng, double size, int num_walls) {
  std::uniform_real_distribution<double> coord(-size / 2, size / 2), length(1.0, size / 3);
  std::bernoulli_distribution horizontal(0.5);
  SyntheticWorld world;
  for (int w = 0; w < num_walls; ++w) {
    const Vec2 a(coord(rng), coord(rng));
    const double l = length(rng);
    const Vec2 b = horizontal(rng) ? Vec2(std::min(a.x() + l, size / 2), a.y()) : Vec2(a.x(), std::min(a.y() + l, size / 2));
    world.walls.push_back({a, b});
  }
  const double h = size / 2;
  world.walls.push_back({{-h, -h}, {h * 0.6, -h}});
  world.walls.push_back({{-h, -h}, {-h, h}});
  world.walls.push_back({{-h * 0.2, h}, {h, h}});
  std::uniform_real_distribution<double> clutter_length(0.2, 0.8), angle(0.0, std::numbers::pi);
  const int num_clutter = static_cast<int>(0.1 * size * size);
  for (int c = 0; c < num_clutter; ++c) {
    const Vec2 a(coord(rng), coord(rng));
    const double t = angle(rng);
    world.walls.push_back({a, a + clutter_length(rng) * Vec2(std::cos(t), std::sin(t))});
  }
  return world;
}

/// Noisy samples of every wall point inside `box` (world frame), downsampled to one point per `resolution` cell.
inline Points2 sample_world(const SyntheticWorld& world, const Box2& box, std::mt19937_64& rng, double noise = 0.01,
                            double step = 0.04, double resolution = 0.1) {
  std::normal_distribution<double> n(0.0, noise);
  std::uniform_real_distribution<double> phase(0.0, step);
  std::bernoulli_distribution keep(0.8);  // gaps, like occlusions
  Points2 points;
  for (const auto& wall : world.walls) {
    const double len = (wall.b - wall.a).norm();
    const Vec2 dir = len > 0 ? Vec2((wall.b - wall.a) / len) : Vec2(1, 0);
    for (double s = phase(rng); s <= len; s += step) {
      const Vec2 p = wall.a + s * dir + Vec2(n(rng), n(rng));
      if (box.contains(p) && keep(rng)) points.push_back(p);
    }
  }
  return voxel_downsample(points, resolution);
}

/// A map and a query of the same world with known relative pose T_map_query (maps query points into the map).
struct SyntheticPair {
  Points2 map;
  Points2 query;
  Pose2 T_map_query;
};

/// Map: the world inside a square of side `crop` around `map_centre`, centred on its centroid (axes kept).
/// Query: the world around map_centre + offset, resampled, centred on its centroid and rotated by theta_query.
inline SyntheticPair make_pair(const SyntheticWorld& world, std::mt19937_64& rng, const Vec2& map_centre,
                               const Vec2& offset, double theta_query, double crop = 12.8) {
  const auto square = [crop](const Vec2& c) {
    return Box2{c.x() - crop / 2, c.x() + crop / 2, c.y() - crop / 2, c.y() + crop / 2};
  };
  SyntheticPair pair;
  const Points2 map_world = sample_world(world, square(map_centre), rng);
  const Points2 query_world = sample_world(world, square(map_centre + offset), rng);
  const Vec2 cm = centroid(map_world), cq = centroid(query_world);
  const Pose2 T_world_map{cm.x(), cm.y(), 0.0};
  const Pose2 T_world_query{cq.x(), cq.y(), theta_query};
  pair.map = transform(T_world_map.inverse(), map_world);
  pair.query = transform(T_world_query.inverse(), query_world);
  pair.T_map_query = T_world_map.inverse() * T_world_query;
  return pair;
}

/// A query and sixteen maps for 1-to-N matching: the query is a random 30 m world's crop about its origin, turned
/// by 0.3 degrees; every fourth map is a crop of the same world about a random point within 3 m of the origin, the
/// others each a crop of another random world. Deterministic (seed 13).
struct QueryAndMaps {
  Points2 query;
  std::vector<Points2> maps;
};

inline QueryAndMaps query_and_sixteen_maps() {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> offset(-3.0, 3.0);
  const SyntheticWorld world = random_world(rng, 30.0, 40);
  QueryAndMaps out;
  out.query = make_pair(world, rng, {0, 0}, {0, 0}, 0.3 * kDegree).query;
  for (int m = 0; m < 16; ++m) {
    const SyntheticWorld& source = m % 4 == 0 ? world : random_world(rng, 30.0, 40);
    out.maps.push_back(make_pair(source, rng, {offset(rng), offset(rng)}, {0, 0}, 0.0).map);
  }
  return out;
}

}  // namespace partslam::testing
