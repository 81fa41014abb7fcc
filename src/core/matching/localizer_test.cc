#include "core/matching/localizer.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/maps/grid_map.h"
#include "core/maps/submap.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

const Scans& building_scans() {
  static const Scans scans = simulate(SimulatorConfig{}).scans;
  return scans;
}

// The simulated building mapped from its exact poses; local maps of the same log found in it, by the default
// search and by one whose candidates lie closer together than "elsewhere" (its margin is still over other
// places).
class LocalizerSearch : public ::testing::TestWithParam<double> {};

TEST_P(LocalizerSearch, FindsLocalMapsInTheBuildingMapWithTheirPose) {
  const Scans& scans = building_scans();
  LocalizerConfig config;
  config.candidate_distance = GetParam();
  config.candidates = config.candidate_distance < config.elsewhere.distance ? 48 : config.candidates;
  const Localizer localizer(build_grid_map(scans), config);
  const std::vector<double> travel = travel_distances(scans);
  int tried = 0, correct = 0;
  double confidence_correct = 0;
  for (double s = 5.0; s + 2.0 < travel.back(); s += 0.2 * travel.back()) {
    const Submap query = build_local_map(scans, s, s + 2.0);
    const Localization l = localizer.locate(query.points, query.origins);
    const Pose2 error = query.T_world_map.inverse() * l.T_map_query;  // map frame = the log's world frame
    ++tried;
    // Refined below the lattice: within 0.1 m / 1 degree.
    if (std::hypot(error.x, error.y) < 0.1 && std::abs(error.theta) < 1 * kDegree) {
      ++correct;
      confidence_correct += l.confidence;
    }
    EXPECT_TRUE(l.calibrated);  // the building map's free cells, the local map's beams
    // The answer is the most probable of the verified candidates, so another place may score higher: margin
    // 0. The margin is from the best score at the answer's place, the answer's own or a candidate's beside
    // it.
    if (GetParam() == config.elsewhere.distance) {
      EXPECT_NEAR(l.confidence, std::max(0.0, l.score - l.elsewhere_score), 1e-12);
    } else {
      EXPECT_GE(l.confidence, std::max(0.0, l.score - l.elsewhere_score) - 1e-12);
    }
    EXPECT_NEAR(l.score, (l.inliers - l.free_conflicts) / static_cast<double>(query.points.size()), 1e-12);
    EXPECT_GE(l.terms.query.occupied, l.terms.query.free);
    // Refining moves the local map's centre by the restarts (0.5 m), the refinement window (+-0.15 m) and
    // what Gauss-Newton adds on the likelihood field after it (its reach: a few sigma, 0.1 m each).
    const Vec2 centre = centroid(query.points);
    EXPECT_LE((l.T_map_query * centre - l.T_map_lattice * centre).norm(),
              config.restart_distance + 0.15 * std::sqrt(2.0) + 0.3);
    // The margin is over another place: 2 m away from the answer's lattice pose (measured at the local map's
    // centre, within 0.1 m of its frame's origin) or turned by more than 10 degrees.
    EXPECT_GT(
        (l.T_map_elsewhere.translation() - l.T_map_lattice.translation()).norm() +
            (std::abs(wrap_angle(l.T_map_elsewhere.theta - l.T_map_lattice.theta)) > 10 * kDegree ? 10.0 : 0.0),
        2.0 - 0.1);
  }
  EXPECT_EQ(tried, 5);
  EXPECT_GE(correct, 4);
  EXPECT_GT(confidence_correct / correct, 0.1);
}

INSTANTIATE_TEST_SUITE_P(CandidateDistances, LocalizerSearch, ::testing::Values(2.0, 0.5));

// The global search spread over calls with a small budget (a tracker's slices) pauses, then gives the
// hypotheses the whole search gives, in the same order, poses and probabilities.
TEST(Localizer, AHypothesisSearchInSlicesGivesTheWholeSearchsHypotheses) {
  const Scans& scans = building_scans();
  const Localizer localizer(build_grid_map(scans));
  const std::vector<double> travel = travel_distances(scans);
  for (const double s : {5.0, 0.5 * travel.back()}) {
    const Submap query = build_local_map(scans, s, s + 2.0);
    const std::vector<Verified> whole = localizer.hypotheses(query.points, query.origins, 8, 8);
    Localizer::HypothesisSearch sliced(localizer, query.points, localizer.verify_query(query.points, query.origins),
                                       8, 8);
    int calls = 1;
    while (!sliced.advance(2000)) {
      EXPECT_TRUE(sliced.result().empty());
      ASSERT_LT(++calls, 1000000);
    }
    EXPECT_GT(calls, 2) << "the budget never paused the search";
    EXPECT_TRUE(sliced.done());
    EXPECT_TRUE(sliced.advance(2000));  // done: nothing more
    ASSERT_EQ(sliced.result().size(), whole.size());
    ASSERT_FALSE(whole.empty());
    for (std::size_t i = 0; i < whole.size(); ++i) {
      EXPECT_EQ(sliced.result()[i].T_map_query.x, whole[i].T_map_query.x) << i;
      EXPECT_EQ(sliced.result()[i].T_map_query.y, whole[i].T_map_query.y) << i;
      EXPECT_EQ(sliced.result()[i].T_map_query.theta, whole[i].T_map_query.theta) << i;
      EXPECT_EQ(sliced.result()[i].probability, whole[i].probability) << i;
    }
  }
  EXPECT_THROW(Localizer::HypothesisSearch(localizer, Points2{}, Localizer::VerifyQuery{}, 8), InputError);
}

// Candidates with no more than half the best one's inliers not searched for: the most probable hypothesis is the
// same where the true place is also the best-scoring one (the simulated building's), and at most as many.
TEST(Localizer, HypothesesAboveAShareOfTheBestAreASubsetsWorth) {
  const Scans& scans = building_scans();
  const Localizer localizer(build_grid_map(scans));
  const std::vector<double> travel = travel_distances(scans);
  for (const double s : {5.0, 0.3 * travel.back(), 0.6 * travel.back()}) {
    const Submap query = build_local_map(scans, s, s + 2.0);
    const std::vector<Verified> all = localizer.hypotheses(query.points, query.origins, 8, 8);
    const std::vector<Verified> some = localizer.hypotheses(query.points, query.origins, 8, 8, 0.5);
    ASSERT_FALSE(some.empty());
    EXPECT_LE(some.size(), all.size());
    EXPECT_TRUE((PoseTolerance{0.3, 3 * kDegree}.accepts(some.front().T_map_query, query.T_world_map))) << s;
    EXPECT_EQ(some.front().T_map_query.x, all.front().T_map_query.x) << s;
    EXPECT_EQ(some.front().probability, all.front().probability) << s;
  }
  EXPECT_THROW(localizer.hypotheses(Points2{Vec2(1, 1), Vec2(2, 1)}, Points2{}, 8, 8, 1.0), InputError);
}

// Verifying more candidates answers with the most probable of them: never a less probable answer than the
// best-scoring candidate's, which is the answer with one verified (and then scores at least as high as any other).
TEST(Localizer, VerifyingMoreCandidatesAnswersWithTheMostProbable) {
  const Scans& scans = building_scans();
  const GridMap map = build_grid_map(scans);
  LocalizerConfig one;  // candidates a place apart, so that the best-scoring other one is the margin's
  one.candidate_distance = one.elsewhere.distance;
  one.restart_distance = 0;  // the candidates' own verification
  one.verified = 1;
  LocalizerConfig many = one;
  many.verified = 8;
  const Localizer first(map, one), most(map, many);
  const std::vector<double> travel = travel_distances(scans);
  for (double s = 7.0; s + 2.0 < travel.back(); s += 0.25 * travel.back()) {
    const Submap query = build_local_map(scans, s, s + 2.0);
    const Localization a = first.locate(query.points, query.origins), b = most.locate(query.points, query.origins);
    EXPECT_GE(a.score, a.elsewhere_score);
    EXPECT_GE(b.probability, a.probability - 1e-12);
    EXPECT_EQ(a.candidates, b.candidates);  // the same searches
    if (b.T_map_lattice.x != a.T_map_lattice.x || b.T_map_lattice.y != a.T_map_lattice.y) {
      EXPECT_GT(b.probability, a.probability);  // another candidate only when strictly more probable
      EXPECT_EQ(b.confidence, std::max(0.0, b.score - a.score));
    }
  }
}

// Restarting the answer's verification around it keeps the same candidates and answer, and only moves the
// pose to a more probable one.
TEST(Localizer, RestartsAroundTheAnswerOnlyMakeItMoreProbable) {
  const Scans& scans = building_scans();
  const GridMap map = build_grid_map(scans);
  LocalizerConfig once;
  once.restart_distance = 0;
  const Localizer plain(map, once), restarted(map);
  const std::vector<double> travel = travel_distances(scans);
  for (double s = 6.0; s + 2.0 < travel.back(); s += 0.25 * travel.back()) {
    const Submap query = build_local_map(scans, s, s + 2.0);
    const Localization a = plain.locate(query.points, query.origins);
    const Localization b = restarted.locate(query.points, query.origins);
    EXPECT_EQ(a.T_map_lattice.x, b.T_map_lattice.x);  // the same answer among the candidates
    EXPECT_EQ(a.T_map_lattice.y, b.T_map_lattice.y);
    EXPECT_EQ(a.confidence, b.confidence);
    EXPECT_GE(b.probability, a.probability);
    if (b.T_map_query.x != a.T_map_query.x || b.T_map_query.y != a.T_map_query.y) {
      EXPECT_GT(b.probability, a.probability);  // moved only when strictly more probable
    }
  }
}

// Bare points (a point file): the same search, no calibrated probability.
TEST(Localizer, BarePointsAreLocatedButNotCalibrated) {
  const Scans& scans = building_scans();
  const Localizer localizer(build_grid_map(scans));
  const Submap query = build_local_map(scans, 10.0, 12.0);
  const Localization bare = localizer.locate(query.points);
  const Localization beams = localizer.locate(query.points, query.origins);
  EXPECT_FALSE(bare.calibrated);
  EXPECT_TRUE(beams.calibrated);
  const Pose2 error = query.T_world_map.inverse() * bare.T_map_query;
  EXPECT_LT(std::hypot(error.x, error.y), 0.1);
  EXPECT_LT(std::abs(error.theta), 1 * kDegree);
}

// A local map of another building fits nowhere in particular: its confidence is below the true matches'.
TEST(Localizer, AQueryFromElsewhereHasLowConfidence) {
  const Localizer localizer(build_grid_map(building_scans()));
  SimulatorConfig other;
  other.seed = 7;
  const Scans other_scans = simulate(other).scans;
  const Submap stranger = build_local_map(other_scans, 10.0, 12.0);
  const Submap own = build_local_map(building_scans(), 10.0, 12.0);
  EXPECT_LT(localizer.locate(stranger.points, stranger.origins).confidence,
            localizer.locate(own.points, own.origins).confidence);
}

TEST(Localizer, RefusesEmptyOrBadInput) {
  EXPECT_THROW(Localizer(Points2{}), InputError);
  EXPECT_THROW(Localizer(Points2{{0.0, 0.0}, {1e9, 0.0}}), InputError);
  LocalizerConfig c;
  c.elsewhere.distance = -1;
  EXPECT_THROW(Localizer(Points2{{0.0, 0.0}}, c), InputError);
  c = {};
  c.candidate_distance = 0;  // the search needs distinct poses
  EXPECT_THROW(Localizer(Points2{{0.0, 0.0}}, c), InputError);
  c.candidate_distance = c.elsewhere.distance + 0.5;  // finer than "elsewhere" or the same
  EXPECT_THROW(Localizer(Points2{{0.0, 0.0}}, c), InputError);
  c = {};
  c.restart_distance = -0.5;
  EXPECT_THROW(Localizer(Points2{{0.0, 0.0}}, c), InputError);
  c = {};
  c.verified = 0;
  EXPECT_THROW(Localizer(Points2{{0.0, 0.0}}, c), InputError);
  c = {};
  c.wall_direction_share = 2;
  EXPECT_THROW(Localizer(Points2{{0.0, 0.0}}, c), InputError);
  const Localizer ok(Points2{{0.0, 0.0}, {1.0, 0.0}});
  EXPECT_THROW(ok.locate(Points2{}), InputError);
  EXPECT_THROW(ok.locate(Points2{{NAN, 0.0}}), InputError);
}

TEST(Localizer, ConsecutiveAnswersAgreeWhenTheyMoveAsTheLogDoes) {
  const Pose2 log_a{10.0, 5.0, 0.3}, log_b = log_a * Pose2{2.0, 0.1, 0.05};  // 2 m along, a little turn
  const Pose2 map_a{-3.0, 7.0, 1.2};
  EXPECT_TRUE(answers_agree(map_a, map_a * Pose2{2.0, 0.1, 0.05}, log_a, log_b));
  EXPECT_TRUE(answers_agree(map_a, map_a * Pose2{2.3, 0.3, 0.1}, log_a, log_b));  // odometry's drift allowed
  EXPECT_FALSE(answers_agree(map_a, map_a * Pose2{-2.0, 0.1, 0.05}, log_a, log_b));  // the twin of a corridor
  EXPECT_FALSE(answers_agree(map_a, map_a * Pose2{2.0, 0.1, 0.05 + std::numbers::pi / 2}, log_a, log_b));
  EXPECT_FALSE(answers_agree(map_a, Pose2{30.0, 7.0, 1.2}, log_a, log_b));
}

TEST(Localizer, ConfidentNeedsAMarginAndWhereCalibratedAProbability) {
  Localization l;
  l.confidence = 0.3, l.calibrated = true, l.probability = 0.01;
  EXPECT_FALSE(is_confident(l));  // unique, but improbable: a place the map may not hold
  l.probability = 0.03;
  EXPECT_TRUE(is_confident(l));
  l.confidence = 0.1;
  EXPECT_FALSE(is_confident(l));  // probable, but another candidate scores nearly as well
  l.confidence = 0.3, l.calibrated = false, l.probability = 0.0;
  EXPECT_TRUE(is_confident(l));  // bare points: the probability is not calibrated, the margin decides
  EXPECT_EQ(not_confident_because(l), "");
  ConfidenceRule stricter;
  stricter.min_margin = 0.5;
  EXPECT_FALSE(is_confident(l, stricter));
  EXPECT_EQ(not_confident_because(l, stricter), "margin 0.300 < 0.5");
  l.calibrated = true, l.probability = 0.01;
  EXPECT_EQ(not_confident_because(l, stricter), "margin 0.300 < 0.5; same-place probability 0.010 < 0.025");
  // A ranking's answer: a decision probability when calibrated, a margin otherwise.
  EXPECT_TRUE(ConfidenceRule{}.confident_answer(0.3, false));
  EXPECT_FALSE(ConfidenceRule{}.confident_answer(0.3, true));
  EXPECT_TRUE(ConfidenceRule{}.confident_answer(0.6, true));
}

}  // namespace
}  // namespace partslam
