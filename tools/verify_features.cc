// verify_features LOG OUT.csv [TASKS=500] [DB=100] [SEED=1] [THREADS=2] [RADIUS=2] [CORNER=0.7]: the terms of
// the match verification (core/matching/verification.h) for every (query, stored map) pair of the
// evaluation's tasks, at Eq. 1's optimum (dMM), at that pose refined, and at the true pose; with the pose
// errors and whether the map is the task's relevant one. CORNER is VerifyConfig::corner_radius (points are
// weighted by how little they lie on a line within it; ablations).
// tools/fit_verification.py fits the same-place probability on these rows (tuning split) and checks its
// calibration (validation split).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "core/evaluation/tasks.h"
#include "core/maps/submap.h"
#include "core/matching/dmm.h"
#include "core/matching/verification.h"
#include "core/parallel.h"
#include "core/ranking/ranking.h"
#include "io/logs/scan_source.h"

using namespace partslam;

namespace {

// The terms in the order of the header's columns after a prefix (e_, r_, t_).
constexpr const char* kTermColumns[] = {"qo",   "qf",   "qs", "mo", "mf",    "ms",
                                        "qfit", "mfit", "qc", "mc", "qcfit", "mcfit"};

std::string terms_csv(const MatchTerms& t) {
  char b[320];
  std::snprintf(b, sizeof b, "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f", t.query.occupied,
                t.query.free, t.query.seen, t.map.occupied, t.map.free, t.map.seen, t.query_fit, t.map_fit,
                t.query.corner, t.map.corner, t.query_corner_fit, t.map_corner_fit);
  return b;
}

std::string pose_error_csv(const Pose2& a, const Pose2& truth) {
  const Pose2 e = truth.inverse() * a;
  char b[128];
  std::snprintf(b, sizeof b, "%.4f,%.5f,%.4f", e.translation().norm(), std::abs(wrap_angle(e.theta)),
                a.translation().norm());
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 9) {
    std::fprintf(stderr,
                 "usage: verify_features LOG OUT.csv [TASKS=500] [DB=100] [SEED=1] [THREADS=2] [RADIUS=2] "
                 "[CORNER=0.7]\n");
    return 2;
  }
  try {
    const Submaps maps = build_submaps(io::load_scan_source(argv[1]).scans);
    TaskConfig tc;
    tc.num_tasks = argc > 3 ? std::atoi(argv[3]) : 500;
    tc.db_size = argc > 4 ? std::atoi(argv[4]) : 100;
    tc.seed = argc > 5 ? std::strtoull(argv[5], nullptr, 10) : 1;
    const int threads = argc > 6 ? std::atoi(argv[6]) : 2;
    tc.radius = argc > 7 ? std::atof(argv[7]) : 2.0;
    const std::vector<Task> tasks = make_tasks(maps, tc);
    const DmmConfig dmm = ranking_dmm_config();
    VerifyConfig verify_config;
    if (argc > 8) verify_config.corner_radius = std::atof(argv[8]);
    validate(verify_config);
    std::vector<PreparedMap> prepared(maps.size());
    std::vector<VerifyMap> verify(maps.size());
    parallel_for(maps.size(), threads, [&](std::size_t i) {
      prepared[i] = prepare_map(maps[i].points, dmm);
      verify[i] = VerifyMap(maps[i].points, maps[i].origins, verify_config);
    });
    std::vector<std::string> rows(tasks.size());
    parallel_for(tasks.size(), threads, [&](std::size_t t) {
      const Task& task = tasks[t];
      const Submap& q = maps[task.query];
      const PreparedQuery pq = prepare_query(q.points, dmm);
      for (std::size_t m : task.database) {
        const std::vector<DmmResult> poses = dmm_poses(pq, prepared[m], verify_config);  // verify_dmm's poses
        const Pose2 truth = maps[m].T_world_map.inverse() * q.T_world_map;
        const PairFields fields(verify[task.query], verify[m]);
        const std::string at_truth = terms_csv(match_terms(verify[task.query], verify[m], fields, truth));
        for (std::size_t k = 0; k < poses.size(); ++k) {
          const DmmResult& d = poses[k];
          const Pose2 refined = refine_match(verify[task.query], fields, d.T_map_query);
          char head[160];
          std::snprintf(head, sizeof head, "%zu,%zu,%zu,%d,%d,%zu,%zu,%.3f,", t, m, k,
                        m == task.relevant ? 1 : 0, d.inliers, q.points.size(), maps[m].points.size(),
                        (maps[m].T_world_map.translation() - q.T_world_map.translation()).norm());
          rows[t] += head + terms_csv(match_terms(verify[task.query], verify[m], fields, d.T_map_query)) +
                     "," + terms_csv(match_terms(verify[task.query], verify[m], fields, refined)) + "," +
                     at_truth + "," + pose_error_csv(d.T_map_query, truth) + "," +
                     pose_error_csv(refined, truth) + "\n";
        }
      }
    });
    FILE* f = std::fopen(argv[2], "w");
    if (f == nullptr) throw std::runtime_error(std::string("cannot write ") + argv[2]);
    std::string header = "task,map,k,relevant,inliers,nq,nm,dist";
    for (const char* prefix : {"e_", "r_", "t_"})
      for (const char* term : kTermColumns) header += std::string(",") + prefix + term;
    std::fprintf(f, "%s,e_dt,e_da,e_t,r_dt,r_da,r_t\n", header.c_str());
    for (const std::string& r : rows) std::fputs(r.c_str(), f);
    std::fclose(f);
    std::fprintf(stderr, "%zu maps, %zu tasks -> %s\n", maps.size(), tasks.size(), argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "verify_features: %s\n", e.what());
    return 1;
  }
  return 0;
}
