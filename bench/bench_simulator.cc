// Runtime of one default simulation (the embedded building the unit tests and the demo run on), and of its
// parts. Counters report the size of what is simulated: scans, walls, travel, submaps.
#include <benchmark/benchmark.h>

#include "core/sim/simulator.h"
#include "core/maps/submap.h"

namespace partslam {
namespace {

void BM_SimulateDefault(benchmark::State& state) {
  SimulatorConfig config;
  SimulatedLog log;
  for (auto _ : state) {
    log = simulate(config);
    benchmark::DoNotOptimize(log.scans.data());
  }
  std::size_t points = 0;
  for (const Scan& s : log.scans) points += s.points_laser.size();
  const std::vector<double> travel = travel_distances(log.scans);
  state.counters["scans"] = static_cast<double>(log.scans.size());
  state.counters["walls"] = static_cast<double>(log.plan.walls.size());
  state.counters["points"] = static_cast<double>(points);
  state.counters["travel_m"] = travel.empty() ? 0.0 : travel.back();
  state.counters["submaps"] = static_cast<double>(build_submaps(log.scans).size());
}
BENCHMARK(BM_SimulateDefault)->Unit(benchmark::kMillisecond);

void BM_CastRay(benchmark::State& state) {
  const SimulatedLog log = simulate();
  const RayCaster caster(log.plan.walls);
  const LaserSimConfig laser;
  std::size_t k = 0;
  for (auto _ : state) {
    const Scan& scan = log.scans[k++ % log.scans.size()];
    benchmark::DoNotOptimize(beam_ranges(caster, scan.T_world_laser, laser).data());
  }
  state.SetItemsProcessed(state.iterations() * laser.num_beams);
}
BENCHMARK(BM_CastRay)->Unit(benchmark::kMicrosecond);

void BM_CastRayBruteForce(benchmark::State& state) {
  const SimulatedLog log = simulate();
  const LaserSimConfig laser;
  std::size_t k = 0;
  for (auto _ : state) {
    const Scan& scan = log.scans[k++ % log.scans.size()];
    for (int i = 0; i < laser.num_beams; ++i) {
      const double a = scan.T_world_laser.theta + beam_angle(laser, i);
      benchmark::DoNotOptimize(cast_ray_brute_force(log.plan.walls, scan.T_world_laser.translation(),
                                                    Vec2(std::cos(a), std::sin(a)), laser.max_range));
    }
  }
  state.SetItemsProcessed(state.iterations() * laser.num_beams);
}
BENCHMARK(BM_CastRayBruteForce)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace partslam

BENCHMARK_MAIN();
