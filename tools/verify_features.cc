// verify_features LOG OUT.csv [TASKS=500] [DB=100] [SEED=1] [THREADS=2] [RADIUS=2] [CORNER=0.7]: the terms of
// the match verification (core/matching/verification.h) for every (query, stored map) pair of the
// evaluation's tasks, at Eq. 1's optimum (dMM), at that pose refined, and at the true pose; with the pose
// errors, whether the map is the task's relevant one, and corner-weighted terms at the refined pose (points
// weighted by how little they lie on a line within CORNER m; an ablation, not in the product's model).
// tools/fit_verification.py fits the same-place probability on these rows (tuning split) and checks its
// calibration (validation split).
#include <Eigen/Eigenvalues>
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
#include "io/scan_source.h"

using namespace partslam;

namespace {

std::string terms_csv(const MatchTerms& t) {
  char b[256];
  std::snprintf(b, sizeof b, "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f", t.query.occupied, t.query.free,
                t.query.seen, t.map.occupied, t.map.free, t.map.seen, t.query_fit, t.map_fit);
  return b;
}

std::string pose_error_csv(const Pose2& a, const Pose2& truth) {
  const Pose2 e = truth.inverse() * a;
  char b[128];
  std::snprintf(b, sizeof b, "%.4f,%.5f,%.4f", e.translation().norm(), std::abs(wrap_angle(e.theta)),
                a.translation().norm());
  return b;
}

// Per point: how little it lies on a line, the smaller over the larger eigenvalue of the scatter of the
// points within `radius` (0 on a straight wall, up to 1 in a corner or clutter; 1 with fewer than three
// points).
std::vector<double> cornerness(const Points2& points, double radius) {
  std::vector<double> c(points.size(), 1.0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    Points2 near;
    for (const Vec2& q : points)
      if ((q - points[i]).squaredNorm() <= radius * radius) near.push_back(q);
    if (near.size() < 3) continue;
    Vec2 mean = Vec2::Zero();
    for (const Vec2& q : near) mean += q;
    mean /= static_cast<double>(near.size());
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const Vec2& q : near) scatter += (q - mean) * (q - mean).transpose();
    const Eigen::Vector2d l = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvalues();
    c[i] = l(1) > 0 ? std::max(0.0, l(0)) / l(1) : 1.0;
  }
  return c;
}

// The points weighted by their cornerness c, moved by T onto the other map: the weighted share on its
// occupied cells, the weighted mean of its likelihood field, and the share of the points with c > 0.15 on its
// occupied cells (docs/NOTES.md, "Corner-weighted terms").
std::string corner_csv(const Points2& points, const std::vector<double>& c, const VerifyMap& other,
                       const LikelihoodField& field, const Pose2& T) {
  double weight = 0, occupied = 0, fit = 0, corners = 0, corners_occupied = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec2 p = T * points[i];
    const bool on = other.at(p) == VerifyMap::kOccupied;
    weight += c[i], occupied += c[i] * on, fit += c[i] * field.at(p);
    if (c[i] > 0.15) corners += 1, corners_occupied += on;
  }
  char b[96];
  std::snprintf(b, sizeof b, "%.4f,%.4f,%.4f", weight > 0 ? occupied / weight : 0,
                weight > 0 ? fit / weight : 0, corners > 0 ? corners_occupied / corners : 0);
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
    const VerifyConfig verify_config;
    std::vector<PreparedMap> prepared(maps.size());
    std::vector<VerifyMap> verify(maps.size());
    std::vector<std::vector<double>> corner(maps.size());
    const double corner_radius = argc > 8 ? std::atof(argv[8]) : 0.7;
    parallel_for(maps.size(), threads, [&](std::size_t i) {
      corner[i] = cornerness(maps[i].points, corner_radius);
      prepared[i] = prepare_map(maps[i].points, dmm);
      verify[i] = VerifyMap(maps[i].points, maps[i].origins);
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
          rows[t] +=
              head + terms_csv(match_terms(verify[task.query], verify[m], fields, d.T_map_query)) + "," +
              terms_csv(match_terms(verify[task.query], verify[m], fields, refined)) + "," + at_truth + "," +
              pose_error_csv(d.T_map_query, truth) + "," + pose_error_csv(refined, truth) + "," +
              corner_csv(q.points, corner[task.query], verify[m], fields.map, refined) + "," +
              corner_csv(maps[m].points, corner[m], verify[task.query], fields.query, refined.inverse()) +
              "\n";
        }
      }
    });
    FILE* f = std::fopen(argv[2], "w");
    if (f == nullptr) throw std::runtime_error(std::string("cannot write ") + argv[2]);
    std::fprintf(
        f,
        "task,map,k,relevant,inliers,nq,nm,dist,e_qo,e_qf,e_qs,e_mo,e_mf,e_ms,e_qfit,e_mfit,r_qo,r_qf,r_qs,r_"
        "mo,"
        "r_mf,r_ms,r_qfit,r_mfit,t_qo,t_qf,t_qs,t_mo,t_mf,t_ms,t_qfit,t_mfit,e_dt,e_da,e_t,r_dt,r_da,r_t,r_"
        "qc,r_qcfit,r_qch,r_mc,r_mcfit,r_mch\n");
    for (const std::string& r : rows) std::fputs(r.c_str(), f);
    std::fclose(f);
    std::fprintf(stderr, "%zu maps, %zu tasks -> %s\n", maps.size(), tasks.size(), argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "verify_features: %s\n", e.what());
    return 1;
  }
  return 0;
}
