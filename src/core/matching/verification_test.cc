#include "core/matching/verification.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/maps/local_shape.h"
#include "core/testing/simulated_maps.h"

namespace partslam {
namespace {

// A corridor 2 m wide along x (walls at y = -1 and y = +1, x in [-4, 4]) with a cross wall at x = 4, seen
// from origins along its axis.
Points2 corridor() {
  Points2 p;
  for (double x = -4.0; x <= 4.0; x += 0.1) p.emplace_back(x, -1.0), p.emplace_back(x, 1.0);
  for (double y = -0.9; y <= 0.9; y += 0.1) p.emplace_back(4.0, y);
  return p;
}
Points2 axis_origins() { return {{-1.0, 0.0}, {-0.5, 0.0}, {0.0, 0.0}, {0.5, 0.0}}; }

TEST(VerifyMap, CastsFreeSpaceBetweenTheOriginsAndThePoints) {
  const VerifyMap m(corridor(), axis_origins());
  EXPECT_TRUE(m.has_beams());
  EXPECT_EQ(m.at({0.0, 0.0}), VerifyMap::kFree);
  EXPECT_EQ(m.at({2.0, 0.5}), VerifyMap::kFree);
  EXPECT_EQ(m.at({1.0, 1.0}), VerifyMap::kOccupied);
  EXPECT_EQ(m.at({1.0, 2.0}), VerifyMap::kUnknown);  // behind the wall
  EXPECT_EQ(m.at({5.0, 0.0}), VerifyMap::kUnknown);  // behind the cross wall
  EXPECT_GT(m.free_cells(), 500u);
}

TEST(VerifyMap, BarePointsHaveNoFreeSpace) {
  const VerifyMap m(corridor(), {});
  EXPECT_FALSE(m.has_beams());
  EXPECT_EQ(m.free_cells(), 0u);
  EXPECT_EQ(m.at({0.0, 0.0}), VerifyMap::kUnknown);
  EXPECT_EQ(m.at({1.0, 1.0}), VerifyMap::kOccupied);
}

TEST(VerifyMap, RefusesNonFinitePointsAndBadConfig) {
  Points2 bad = corridor();
  bad.emplace_back(std::numeric_limits<double>::quiet_NaN(), 0.0);
  EXPECT_THROW(VerifyMap(bad, axis_origins()), InputError);
  EXPECT_THROW(VerifyMap(corridor(), {{std::numeric_limits<double>::infinity(), 0.0}}), InputError);
  VerifyConfig c;
  c.resolution = 0;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.alternatives = -1;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.corner_radius = 0;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.alternative_bar = 2;
  try {
    validate(c);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("alternative_bar"), std::string::npos) << e.what();
  }
}

TEST(MatchTerms, AWallInTheOtherMapsFreeSpaceIsAContradiction) {
  const VerifyMap a(corridor(), axis_origins());
  const PairFields fields(a, a);
  const MatchTerms same = match_terms(a, a, fields, Pose2{});
  EXPECT_DOUBLE_EQ(same.query.occupied, 1.0);
  EXPECT_DOUBLE_EQ(same.map.occupied, 1.0);
  EXPECT_DOUBLE_EQ(same.query.free, 0.0);
  EXPECT_TRUE(same.beams);
  // Half a corridor sideways: the walls run down the other's free middle.
  const MatchTerms shifted = match_terms(a, a, fields, Pose2{0.0, 1.0, 0.0});
  EXPECT_LT(shifted.query.occupied, 0.6);
  EXPECT_GT(shifted.query.free + shifted.map.free, 0.3);
  EXPECT_GT(same_place_probability(same), same_place_probability(shifted) + 0.3);
  // Empty maps: zero shares, no crash.
  const VerifyMap empty(Points2{}, Points2{});
  const MatchTerms none = match_terms(empty, a, PairFields(empty, a), Pose2{});
  EXPECT_DOUBLE_EQ(none.query.occupied, 0.0);
  EXPECT_DOUBLE_EQ(none.query_fit, 0.0);
  EXPECT_DOUBLE_EQ(none.map_fit, 0.0);
  EXPECT_FALSE(none.beams);
}

TEST(MatchTerms, TheFitTellsWallsOnEachOtherFromWallsInsideTheDilation) {
  const VerifyMap a(corridor(), axis_origins());
  const PairFields fields(a, a);
  const MatchTerms same = match_terms(a, a, fields, Pose2{});
  EXPECT_GT(same.query_fit, 0.95);
  EXPECT_GT(same.map_fit, 0.95);
  // One cell across the walls: still on the dilated walls, but 0.1 m (one sigma) off them.
  const MatchTerms off = match_terms(a, a, fields, Pose2{0.0, 0.1, 0.0});
  EXPECT_GT(off.query.occupied, 0.9);
  EXPECT_LT(off.query_fit, 0.75);
  EXPECT_LT(off.map_fit, 0.75);
  EXPECT_GT(same_place_probability(same), same_place_probability(off));
}

TEST(MatchTerms, TheCornerTermsWeighTheCornersOverTheWalls) {
  const VerifyMap a(corridor(), axis_origins());
  ASSERT_EQ(a.cornerness().size(), a.points().size());
  const PairFields fields(a, a);
  const MatchTerms same = match_terms(a, a, fields, Pose2{});
  EXPECT_DOUBLE_EQ(same.query.corner, 1.0);
  EXPECT_GT(same.query_corner_fit, 0.95);
  // Along the corridor: its long walls still lie on each other, its corners at the cross wall do not.
  const MatchTerms along = match_terms(a, a, fields, Pose2{0.5, 0.0, 0.0});
  EXPECT_GT(along.query.occupied, 0.8);
  EXPECT_LT(along.query.corner, along.query.occupied - 0.2);
  EXPECT_LT(along.map.corner, along.map.occupied - 0.2);
  EXPECT_LT(along.query_corner_fit, along.query_fit - 0.2);
  EXPECT_LT(along.map_corner_fit, along.map_fit - 0.2);
}

TEST(VerifyMap, APointFarOutIsRefusedOrReadAsUnknown) {
  // A finite point whose cell index would not fit an int is refused by name, not cast.
  Points2 far = corridor(), far_origins = axis_origins();
  for (Points2* set : {&far, &far_origins})
    for (Vec2& p : *set) p.x() += 1e12;
  try {
    VerifyMap m(far, far_origins);
    FAIL() << "a map 1e12 m out was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("from the map's origin"), std::string::npos) << e.what();
  }
  // Reading a map anywhere, or a crop of it anywhere, is defined: unknown outside the grid.
  const VerifyMap m(corridor(), axis_origins());
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(m.at({1e12, 0.0}), VerifyMap::kUnknown);
  EXPECT_EQ(m.at({-1e300, 1e300}), VerifyMap::kUnknown);
  EXPECT_EQ(m.at({nan, 0.0}), VerifyMap::kUnknown);
  EXPECT_TRUE(m.cropped({1e12, 1e12}, {2e12, 2e12}).points().empty());
  EXPECT_TRUE(m.cropped({nan, -2.0}, {2.0, 2.0}).points().empty());
  EXPECT_EQ(m.cropped({-inf, -inf}, {inf, inf}).points().size(), m.points().size());
  // A map 1e7 m away (its cells still int) shares nothing with it at the identity.
  Points2 away = corridor();
  for (Vec2& p : away) p.y() -= 1e7;
  const VerifyMap other(away, {});
  const MatchTerms t = match_terms(m, other, PairFields(m, other), Pose2());
  EXPECT_EQ(t.query.occupied, 0.0);
  EXPECT_EQ(t.map.seen, 0.0);
}

TEST(VerifyMap, ACropKeepsEachPointsCornernessAndTheWallScatterFromTheWholeMap) {
  const VerifyMap a(corridor(), axis_origins());
  const VerifyMap crop = a.cropped({3.0, -2.0}, {5.0, 2.0});
  ASSERT_EQ(crop.cornerness().size(), crop.points().size());
  ASSERT_FALSE(crop.points().empty());
  for (std::size_t i = 0; i < crop.points().size(); ++i) {
    const auto at = std::find(a.points().begin(), a.points().end(), crop.points()[i]);
    ASSERT_NE(at, a.points().end());
    EXPECT_EQ(crop.cornerness()[i], a.cornerness()[static_cast<std::size_t>(at - a.points().begin())]);
  }
  EXPECT_EQ(crop.wall_scatter(), a.wall_scatter());  // so is its wall scatter
  EXPECT_GT(a.wall_scatter().trace(), 0.0);
}

TEST(RefineMatch, MovesALatticePoseBelowTheLattice) {
  const VerifyMap a(corridor(), axis_origins());
  // A map with a corner (the cross wall) pins x and y; the pose is off by 0.07 m / 0.8 deg.
  const Pose2 off{0.07, -0.06, 0.014};
  const Pose2 refined = refine_match(a, PairFields(a, a), off);
  EXPECT_LT(refined.translation().norm(), 0.03);
  EXPECT_LT(std::abs(refined.theta), 0.005);
}

// One query verified at many places (locate's candidates) builds its field once: the same answer, bit for bit.
TEST(VerifyMatch, AQueryFieldBuiltOnceGivesTheSameAnswer) {
  const VerifyMap a(corridor(), axis_origins());
  const LikelihoodField field = verify_field(a);
  for (const Pose2 pose : {Pose2{0.07, -0.06, 0.014}, Pose2{-0.2, 0.1, -0.05}, Pose2{1.0, 0.0, 0.3}}) {
    Verified at_each, at_once;
    const Verified each = verify_match(a, a, pose, {}, &at_each), once = verify_match(a, field, a, pose, {}, &at_once);
    EXPECT_EQ(each.T_map_query.x, once.T_map_query.x);
    EXPECT_EQ(each.T_map_query.y, once.T_map_query.y);
    EXPECT_EQ(each.T_map_query.theta, once.T_map_query.theta);
    EXPECT_EQ(each.probability, once.probability);
    EXPECT_EQ(each.terms.map_fit, once.terms.map_fit);
    EXPECT_EQ(at_each.probability, at_once.probability);
  }
}

TEST(RefineMatch, KeepsTheTranslationAlongABareCorridorWhenAsked) {
  // A corridor without a cross wall (nothing but its walls' ends and a doorway fixes x): the map's doorway in
  // the upper wall lies 0.3 m further along than the query's, so the match, left free, slides the query 0.3 m
  // along. The query starts 0.1 m short of that along and 0.08 m off across.
  const auto corridor_with_door = [](double from, double to, double door) {
    Points2 p;
    for (int i = 0; std::lround(from * 10) + i <= std::lround(to * 10); ++i) {
      const double x = from + 0.1 * i;
      p.emplace_back(x, -1.0);
      if (x < door - 0.01 || x > door + 0.41) p.emplace_back(x, 1.0);
    }
    return p;
  };
  const VerifyMap m(corridor_with_door(-6.0, 6.0, 0.3), {}), q(corridor_with_door(-2.0, 2.0, 0.0), {});
  ASSERT_TRUE(unconstrained_direction(q.wall_scatter(), 0.1).has_value());
  const PairFields fields(q, m);
  const Pose2 off{0.2, 0.08, 0.0};
  const Pose2 free = refine_match(q, fields, off, VerifyConfig{});
  EXPECT_NEAR(free.x, 0.3, 0.03);
  VerifyConfig keep;
  keep.keep_along_ratio = 0.1;
  const Pose2 kept = refine_match(q, fields, off, keep);
  EXPECT_NEAR(kept.x, 0.2, 1e-9);     // along: the input pose's
  EXPECT_LT(std::abs(kept.y), 0.02);  // across: matched
  keep.keep_along_slack = 0.05;       // along: at most 0.05 m from it
  EXPECT_NEAR(refine_match(q, fields, off, keep).x, 0.25, 1e-9);
  // A query with a wall across it leaves no direction free: refined in both.
  const VerifyMap closed(corridor(), axis_origins());
  const Pose2 refined = refine_match(closed, PairFields(closed, closed), Pose2{0.07, -0.06, 0.014}, keep);
  EXPECT_LT(refined.translation().norm(), 0.03);
  keep.keep_along_ratio = 1.0;
  EXPECT_THROW(validate(keep), InputError);
  keep.keep_along_ratio = 0.1, keep.keep_along_slack = -0.1;
  EXPECT_THROW(validate(keep), InputError);
}

TEST(VerifyDmm, FindsAndVerifiesTheTruePoseOfARealSubmap) {
  const Submaps& maps = testing::simulated_maps();
  ASSERT_GT(maps.size(), 10u);
  const Submap& m = maps[maps.size() / 2];
  ASSERT_FALSE(m.origins.empty());
  // The same map, moved by a known pose, as the query.
  const Pose2 T_map_query{0.33, -0.21, 0.02};
  const Points2 query_points = transform(T_map_query.inverse(), m.points);
  const Points2 query_origins = transform(T_map_query.inverse(), m.origins);
  DmmConfig dmm;
  const PreparedQuery q = prepare_query(query_points, dmm);
  const PreparedMap pm = prepare_map(m.points, dmm);
  const VerifyMap qv(query_points, query_origins), mv(m.points, m.origins);
  const VerifiedDmm v = verify_dmm(q, pm, qv, mv);
  EXPECT_GE(v.poses, 1);
  EXPECT_LT((v.best.T_map_query.translation() - T_map_query.translation()).norm(), 0.05);
  EXPECT_LT(std::abs(wrap_angle(v.best.T_map_query.theta - T_map_query.theta)), 0.01);
  EXPECT_GT(v.best.probability,
            0.4);  // the fitted model tops out near 0.5 (docs/NOTES.md, "Verifying a match")
  EXPECT_GT(v.best.terms.query.occupied, 0.9);
  // A real submap fits itself at one pose: no other pose comes near.
  EXPECT_LE(v.runner_up, v.best.probability);
  EXPECT_FALSE(pose_ambiguous(v.best.probability, v.runner_up))
      << v.runner_up << " vs " << v.best.probability;
}

// A room that a half turn maps onto itself fits the query at the true pose and at the half turn alike: the
// runner-up pose is as probable as the answer, and the answer's pose is ambiguous.
TEST(VerifyDmm, ReportsThePoseOfASymmetricRoomAsAmbiguous) {
  Points2 room;
  for (double x = -4.0; x <= 4.001; x += 0.1) room.emplace_back(x, -1.5), room.emplace_back(x, 1.5);
  for (double y = -1.4; y <= 1.401; y += 0.1) room.emplace_back(-4.0, y), room.emplace_back(4.0, y);
  const Points2 origins = {{-1.0, 0.0}, {0.0, 0.0}, {1.0, 0.0}};
  const Pose2 T_map_query{0.2, 0.1, 0.0};
  const Points2 query_points = transform(T_map_query.inverse(), room);
  const Points2 query_origins = transform(T_map_query.inverse(), origins);
  const DmmConfig dmm;
  const VerifiedDmm v = verify_dmm(prepare_query(query_points, dmm), prepare_map(room, dmm),
                                   VerifyMap(query_points, query_origins), VerifyMap(room, origins));
  EXPECT_GE(v.poses, 2);
  EXPECT_GT(v.best.probability, 0.0);
  EXPECT_LE(v.runner_up, v.best.probability);
  EXPECT_GT(v.runner_up, 0.9 * v.best.probability);
  EXPECT_TRUE(pose_ambiguous(v.best.probability, v.runner_up));
}

TEST(VerifyDmm, APoseIsAmbiguousWhenItsRunnerUpReachesHalfItsProbability) {
  EXPECT_TRUE(pose_ambiguous(0.4, 0.2));
  EXPECT_FALSE(pose_ambiguous(0.4, 0.19));
  EXPECT_FALSE(pose_ambiguous(0.0, 0.0));  // nothing verified: nothing to call ambiguous
}

// Refining more of the verified poses never answers with a less probable one, and refining k of them answers
// with the most probable of the k refined (each as verify_match gives it at its lattice pose).
TEST(VerifyDmm, RefiningMorePosesAnswersWithTheMostProbableAfterRefinement) {
  const Submaps& maps = testing::simulated_maps();
  ASSERT_GT(maps.size(), 20u);
  const DmmConfig dmm;
  int pairs = 0;
  for (std::size_t a = 2; a + 6 < maps.size(); a += 7) {
    const Submap& query = maps[a];
    const Submap& map = maps[a + 3];
    const PreparedQuery q = prepare_query(query.points, dmm);
    const PreparedMap pm = prepare_map(map.points, dmm);
    const VerifyMap qv(query.points, query.origins), mv(map.points, map.origins);
    VerifyConfig one, all;
    one.refined = 1;
    all.refined = 4;
    const VerifiedDmm v1 = verify_dmm(q, pm, qv, mv, one), v4 = verify_dmm(q, pm, qv, mv, all);
    EXPECT_GE(v4.best.probability, v1.best.probability) << "pair " << a;
    double most = 0.0;
    for (const DmmResult& pose : dmm_poses(q, pm, all))
      most = std::max(most, verify_match(qv, mv, pose.T_map_query, all).probability);
    EXPECT_DOUBLE_EQ(v4.best.probability, most) << "pair " << a;
    ++pairs;
  }
  EXPECT_GE(pairs, 2);
  VerifyConfig bad;
  bad.refined = 0;
  EXPECT_THROW(validate(bad), InputError);
}

}  // namespace
}  // namespace partslam
