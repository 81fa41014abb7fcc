#include "core/slam/closure_refinement.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

struct TwoVisits {
  Scans scans;  // exact poses
  Submaps maps;
  std::vector<LoopClosure> truth;  // second-lap submaps against the first lap's at the same place, exact poses
};

// The simulator drives its corridor loop twice; closures between the laps' submaps within 0.5 m of each other.
const TwoVisits& two_visits() {
  static const TwoVisits t = [] {
    TwoVisits out;
    out.scans = simulate(SimulatorConfig{}).scans;
    SubmapConfig c;
    c.spacing = 1.0;
    out.maps = build_submaps(out.scans, c);
    for (std::size_t q = 0; q < out.maps.size() && out.truth.size() < 12; q += 3)
      for (std::size_t m = 0; m < q; ++m) {
        const Submap &a = out.maps[q], &b = out.maps[m];
        if (a.travel - b.travel < 20.0 || (a.T_world_map.translation() - b.T_world_map.translation()).norm() > 0.5)
          continue;
        out.truth.push_back({q, m, b.T_world_map.inverse() * a.T_world_map, 1.0, 1.0, 1.0});
        break;
      }
    return out;
  }();
  return t;
}

double translation_error(const Pose2& a, const Pose2& b) { return (a.translation() - b.translation()).norm(); }

TEST(ClosureRefinement, PlacesTwoVisitsOfAPlaceOnTopOfEachOther) {
  const TwoVisits& t = two_visits();
  ASSERT_GE(t.truth.size(), 6u);
  std::vector<LoopClosure> off = t.truth;
  const Pose2 nudge{0.03, -0.025, 0.012};  // what 10 cm cells leave: a few centimetres, under a degree
  for (LoopClosure& l : off) l.T_match_query = l.T_match_query * nudge;
  ClosureRefinementConfig config;
  const std::vector<LoopClosure> refined = refine_closures(t.scans, t.maps, 2.0, off, config);
  ASSERT_EQ(refined.size(), off.size());
  double sum = 0;
  for (std::size_t k = 0; k < refined.size(); ++k) {
    EXPECT_EQ(refined[k].query, off[k].query);
    EXPECT_EQ(refined[k].match, off[k].match);
    const double e = translation_error(refined[k].T_match_query, t.truth[k].T_match_query);
    EXPECT_LT(e, 0.5 * nudge.translation().norm()) << "closure " << k;
    EXPECT_LT(std::abs(wrap_angle(refined[k].T_match_query.theta - t.truth[k].T_match_query.theta)), 0.5 * nudge.theta);
    sum += e;
  }
  EXPECT_LT(sum / static_cast<double>(refined.size()), 0.01);

  config.num_threads = 2;  // the same answer on two threads
  const std::vector<LoopClosure> parallel = refine_closures(t.scans, t.maps, 2.0, off, config);
  for (std::size_t k = 0; k < refined.size(); ++k) {
    EXPECT_EQ(parallel[k].T_match_query.x, refined[k].T_match_query.x);
    EXPECT_EQ(parallel[k].T_match_query.theta, refined[k].T_match_query.theta);
  }

  config.enabled = false;
  const std::vector<LoopClosure> kept = refine_closures(t.scans, t.maps, 2.0, off, config);
  for (std::size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(kept[k].T_match_query.x, off[k].T_match_query.x);
}

TEST(ClosureRefinement, NeverMovesAPoseFartherThanTwiceItsWindow) {
  const TwoVisits& t = two_visits();
  std::vector<LoopClosure> far = t.truth;
  for (LoopClosure& l : far) l.T_match_query = l.T_match_query * Pose2{0.6, 0.0, 0.0};  // another cell of the corridor
  const ClosureRefinementConfig config;
  const std::vector<LoopClosure> refined = refine_closures(t.scans, t.maps, 2.0, far, config);
  for (std::size_t k = 0; k < refined.size(); ++k) {
    const Pose2 d = far[k].T_match_query.inverse() * refined[k].T_match_query;
    EXPECT_LE(d.translation().norm(), 2 * config.linear_window + 1e-9);
    EXPECT_LE(std::abs(d.theta), 2 * config.angular_window + 1e-9);
  }
}

TEST(ClosureRefinement, RefusesAbsurdSettingsAndClosuresOutOfRange) {
  const TwoVisits& t = two_visits();
  ClosureRefinementConfig bad;
  bad.sigma = 0;
  try {
    refine_closures(t.scans, t.maps, 2.0, t.truth, bad);
    FAIL() << "sigma 0 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sigma"), std::string::npos) << e.what();
  }
  std::vector<LoopClosure> out_of_range = t.truth;
  out_of_range[0].query = t.maps.size();
  EXPECT_THROW(refine_closures(t.scans, t.maps, 2.0, out_of_range), InputError);
  EXPECT_TRUE(refine_closures(t.scans, t.maps, 2.0, {}).empty());
}

}  // namespace
}  // namespace partslam
