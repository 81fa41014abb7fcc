// dMM on real submaps (fr079, skipped without the shared data folder): branch-and-bound returns exactly the
// exhaustive maximum over the same discretisation, beats the ground-truth pose's own score on relevant pairs,
// and recovers a known offset applied to a real submap.
#include <gtest/gtest.h>

#include <random>

#include "core/matching/dmm.h"
#include "core/matching/dmm_ransac.h"
#include "core/evaluation/tasks.h"
#include "io/logs/carmen_log.h"
#include "io/testing/test_files.h"

namespace partslam {
namespace {

double angle_error(double a, double b) { return std::abs(wrap_angle(a - b)); }

class Fr079Submaps : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::filesystem::path log = io::testing::shared_data() / "fr079" / "fr079-corrected.log.gz";
    if (!std::filesystem::exists(log)) return;
    SubmapConfig config;
    config.spacing = 5.0;  // one submap every 5 m of travel keeps the test fast
    maps_ = new Submaps(build_submaps(io::read_carmen_log(log).scans, config));
    pairs_ = new std::vector<RelevantPair>(relevant_pairs(*maps_, TaskConfig{}));
  }
  static void TearDownTestSuite() {
    delete maps_;
    delete pairs_;
    maps_ = nullptr;
    pairs_ = nullptr;
  }
  void SetUp() override {
    if (maps_ == nullptr) {
      GTEST_SKIP() << "fr079 log absent under " << io::testing::shared_data()
                   << "; set PARTSLAM_SHARED_DATA to run the real-data tests";
    }
  }
  static Submaps* maps_;
  static std::vector<RelevantPair>* pairs_;
};
Submaps* Fr079Submaps::maps_ = nullptr;
std::vector<RelevantPair>* Fr079Submaps::pairs_ = nullptr;

TEST_F(Fr079Submaps, BranchAndBoundEqualsExhaustive) {
  ASSERT_GE(pairs_->size(), 20u);
  const DmmConfig config;
  std::mt19937_64 rng(5);
  for (int t = 0; t < 20; ++t) {
    const bool relevant = t < 12;
    const RelevantPair p = relevant ? (*pairs_)[rng() % pairs_->size()]
                                    : RelevantPair{rng() % maps_->size(), rng() % maps_->size()};
    const PreparedQuery q = prepare_query((*maps_)[p.query].points, config);
    const PreparedMap m = prepare_map((*maps_)[p.global].points, config);
    const DmmResult bnb = match_dmm(q, m);
    ASSERT_EQ(bnb.inliers, match_exhaustive(q, m).inliers) << "pair " << p.query << " " << p.global;
    if (!relevant) continue;
    // The maximum is at least the score of the candidate nearest to the true relative pose.
    const Pose2 T = (*maps_)[p.global].T_world_map.inverse() * (*maps_)[p.query].T_world_map;
    std::size_t k_true = 0;
    for (std::size_t k = 0; k < q.rotations.size(); ++k) {
      if (angle_error(q.rotations[k].angle, T.theta) < angle_error(q.rotations[k_true].angle, T.theta)) k_true = k;
    }
    const int i = static_cast<int>(std::lround(T.x / config.resolution));
    const int j = static_cast<int>(std::lround(T.y / config.resolution));
    int at_truth = 0;
    for (std::size_t n = 0; n < q.rotations[k_true].x.size(); ++n) {
      at_truth += m.grid.at(q.rotations[k_true].x[n] + i, q.rotations[k_true].y[n] + j);
    }
    EXPECT_GE(bnb.inliers, at_truth);
  }
}

// A real submap against itself moved by a known pose (a quarter turn plus a residual, and a shift).
TEST_F(Fr079Submaps, RecoversAKnownOffsetOfARealSubmap) {
  const DmmConfig config;
  for (std::size_t m = 3; m < maps_->size(); m += maps_->size() / 6) {
    const Points2& map_points = (*maps_)[m].points;
    const Pose2 T_map_query{1.3, -0.8, -std::numbers::pi / 2 + 1.7 * kDegree};
    const Points2 query_points = transform(T_map_query.inverse(), map_points);
    const PreparedQuery q = prepare_query(query_points, config);
    const DmmResult r = match_dmm(q, prepare_map(map_points, config));
    EXPECT_GT(r.inlier_fraction, 0.9) << "submap " << m;
    EXPECT_LE(std::abs(r.T_map_query.x - T_map_query.x), config.resolution + 1e-9) << "submap " << m;
    EXPECT_LE(std::abs(r.T_map_query.y - T_map_query.y), config.resolution + 1e-9) << "submap " << m;
    EXPECT_LE(angle_error(r.T_map_query.theta, T_map_query.theta), q.angular_step + 1e-9) << "submap " << m;
    // The RANSAC baseline on the same pair finds a pose of at least comparable quality.
    DmmRansacConfig ransac;
    ransac.iterations = 2000;
    const DmmResult b = match_dmm_ransac(query_points, prepare_ransac_map(map_points, ransac), ransac);
    EXPECT_GT(b.inlier_fraction, 0.5) << "submap " << m;
  }
}

}  // namespace
}  // namespace partslam
