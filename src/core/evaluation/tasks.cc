#include "core/evaluation/tasks.h"

#include <cmath>
#include <numeric>
#include <random>
#include <string>

#include "core/error.h"
#include "core/maps/occupancy_grid.h"
#include "core/parallel.h"

namespace partslam {
namespace {

double pose_distance(const Submap& a, const Submap& b) {
  return (a.T_world_map.translation() - b.T_world_map.translation()).norm();
}

}  // namespace

void validate(const TaskConfig& c) {
  if (!(c.radius > 0) || !std::isfinite(c.radius))
    throw InputError("tasks: radius (R, --radius) must be a positive number of metres, got " +
                     std::to_string(c.radius));
  if (!(c.min_travel_gap >= 0) || !std::isfinite(c.min_travel_gap))
    throw InputError("tasks: min_travel_gap (G, --gap) must be a number of metres >= 0, got " +
                     std::to_string(c.min_travel_gap));
  if (c.db_size < 2 || c.db_size > 10000000) throw InputError("tasks: db_size (N) must be in [2, 1e7], got " +
                                                             std::to_string(c.db_size));
  if (c.num_tasks < 1 || c.num_tasks > 10000000) throw InputError("tasks: num_tasks must be in [1, 1e7], got " +
                                                                 std::to_string(c.num_tasks));
}

void seeded_shuffle(std::vector<std::size_t>& v, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[rng() % i]);
}

std::vector<RelevantPair> relevant_pairs(const Submaps& maps, const TaskConfig& config) {
  validate(config);
  std::vector<RelevantPair> pairs;
  for (std::size_t q = 0; q < maps.size(); ++q) {
    for (std::size_t g = 0; g < maps.size(); ++g) {
      if (q == g) continue;
      if (pose_distance(maps[q], maps[g]) <= config.radius &&
          std::abs(maps[q].travel - maps[g].travel) > config.min_travel_gap) {
        pairs.push_back({q, g});
      }
    }
  }
  return pairs;
}

std::vector<Task> make_tasks(const Submaps& maps, const TaskConfig& config) {
  const std::vector<RelevantPair> pairs = relevant_pairs(maps, config);
  std::vector<std::size_t> order(pairs.size());
  std::iota(order.begin(), order.end(), 0);
  seeded_shuffle(order, config.seed);
  if (order.size() > static_cast<std::size_t>(config.num_tasks)) order.resize(config.num_tasks);

  std::vector<Task> tasks;
  tasks.reserve(order.size());
  for (std::size_t t = 0; t < order.size(); ++t) {
    const RelevantPair& pair = pairs[order[t]];
    std::vector<std::size_t> irrelevant;
    for (std::size_t i = 0; i < maps.size(); ++i) {
      if (pose_distance(maps[pair.query], maps[i]) > 2.0 * config.radius) irrelevant.push_back(i);
    }
    // Per-task seed: tasks do not depend on each other, so any subset is reproducible on its own.
    seeded_shuffle(irrelevant, config.seed * 0x9E3779B97F4A7C15ULL + t + 1);
    if (irrelevant.size() > static_cast<std::size_t>(config.db_size - 1)) irrelevant.resize(config.db_size - 1);
    Task task{pair.query, pair.global, std::move(irrelevant)};
    task.database.push_back(pair.global);
    seeded_shuffle(task.database, config.seed ^ (0xD1B54A32D192ED03ULL * (t + 1)));
    tasks.push_back(std::move(task));
  }
  return tasks;
}

namespace {

double overlap_on(const Submap& query, const Submap& map, const OccupancyGrid& grid) {
  if (query.points.empty()) return 0.0;
  const Pose2 T_map_query = map.T_world_map.inverse() * query.T_world_map;
  std::size_t hits = 0;
  for (const Vec2& p : query.points) hits += grid.at(T_map_query * p);
  return static_cast<double>(hits) / static_cast<double>(query.points.size());
}

}  // namespace

double true_overlap(const Submap& query, const Submap& map, double resolution, int dilation) {
  return overlap_on(query, map, build_occupancy_grid(map.points, resolution, dilation));
}

double low_overlap_share(const Submaps& maps, const std::vector<RelevantPair>& pairs, double threshold,
                         int num_threads) {
  if (pairs.empty()) return 0.0;
  std::vector<OccupancyGrid> grids(maps.size());
  parallel_for(maps.size(), num_threads,
               [&](std::size_t i) { grids[i] = build_occupancy_grid(maps[i].points, kMapResolution, 1); });
  std::size_t low = 0;
  for (const RelevantPair& p : pairs) low += overlap_on(maps[p.query], maps[p.global], grids[p.global]) < threshold;
  return static_cast<double>(low) / static_cast<double>(pairs.size());
}

}  // namespace partslam
