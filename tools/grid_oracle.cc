// grid_oracle INPUT_LOG [GRID_SPEC_ARGS]: is a coarse grid's information or its pose search what limits it?
// For 300 tasks (R = 2 m, N = 100, seed 1, 8 m usable range) it compares, for the relevant map, the Jaccard
// similarity of the query's grid at the TRUE relative pose (the query's points moved into the relevant map's
// frame, then binned on its grid) with the best similarity the search finds, and with the best searched
// similarity of the N - 1 irrelevant maps. Prints the means, how often each beats every irrelevant map, and
// the ANR the relevant map would get if its score were the true-pose one (an upper bound for any pose search
// on this descriptor). Grid: 11 x 11 cells over the box, query shifts +-shift cells in 1/sub steps.
// Usage: grid_oracle LOG [BOX_M=10] [SHIFT=1] [SUB=2]
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "core/matching/grid_descriptor.h"
#include "core/maps/submap.h"
#include "core/evaluation/tasks.h"
#include "io/logs/scan_source.h"

using namespace partslam;

int main(int argc, char** argv) {
  if (argc < 2 || argc > 5) {
    std::fprintf(stderr, "usage: grid_oracle LOG [BOX_M=10] [SHIFT=1] [SUB=2]\n");
    return 2;
  }
  try {
    const Submaps maps = build_submaps(io::load_scan_source(argv[1]).scans);
    GridConfig g;
    g.box_size = argc > 2 ? std::atof(argv[2]) : 10.0;
    g.max_shift = argc > 3 ? std::atoi(argv[3]) : 1;
    g.substeps = argc > 4 ? std::atoi(argv[4]) : 2;
    validate(g);
    TaskConfig tc;
    tc.num_tasks = 300;
    const std::vector<Task> tasks = make_tasks(maps, tc);
    std::vector<GridBits> stored;
    for (const Submap& m : maps) stored.push_back(make_grid(m.points, g));
    double sum_true = 0, sum_searched = 0, sum_irrelevant = 0, anr = 0;
    int true_wins = 0, searched_wins = 0;
    for (const Task& t : tasks) {
      const Submap& q = maps[t.query];
      const Submap& r = maps[t.relevant];
      const std::vector<GridBits> query = make_query_grids(q.points, g);
      const Pose2 T_map_query = r.T_world_map.inverse() * q.T_world_map;
      const double truth = jaccard(make_grid(transform(T_map_query, q.points), g), stored[t.relevant]);
      const double searched = grid_similarity(query, stored[t.relevant]);
      double best_irrelevant = 0, rank = 1;
      for (std::size_t m : t.database) {
        if (m == t.relevant) continue;
        const double s = grid_similarity(query, stored[m]);
        best_irrelevant = std::max(best_irrelevant, s);
        rank += s > truth ? 1.0 : s == truth ? 0.5 : 0.0;
      }
      anr += rank / static_cast<double>(t.database.size());
      sum_true += truth, sum_searched += searched, sum_irrelevant += best_irrelevant;
      true_wins += truth > best_irrelevant;
      searched_wins += searched > best_irrelevant;
    }
    const double n = static_cast<double>(tasks.size());
    std::printf("%s: %zu tasks, grid 11x11 over %.1f m, shift %d, sub %d\n", argv[1], tasks.size(), g.box_size,
                g.max_shift, g.substeps);
    std::printf("mean Jaccard of the relevant map: true pose %.3f, searched %.3f; best irrelevant %.3f\n",
                sum_true / n, sum_searched / n, sum_irrelevant / n);
    std::printf("relevant beats every irrelevant map: true pose %.2f, searched %.2f\n", true_wins / n,
                searched_wins / n);
    std::printf("ANR with the true-pose score: %.1f %%\n", 100 * anr / n);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grid_oracle: error: %s\n", e.what());
    return 1;
  }
}
