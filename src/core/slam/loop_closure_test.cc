#include "core/slam/loop_closure.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <thread>

#include "core/error.h"
#include "core/evaluation/loop_evaluation.h"
#include "core/sim/simulator.h"
#include "core/testing/thread_split.h"

namespace partslam {
namespace {

// The simulator drives its corridor loop twice: the second lap revisits the first's places.
const Submaps& two_laps() {
  static const Submaps maps = [] {
    SubmapConfig c;
    c.spacing = 1.0;
    return build_submaps(simulate(SimulatorConfig{}).scans, c);
  }();
  return maps;
}

std::vector<std::optional<Pose2>> exact_frames(const Submaps& maps) {
  std::vector<std::optional<Pose2>> frames;
  for (const Submap& m : maps) frames.emplace_back(m.T_world_map);
  return frames;
}

TEST(LoopClosure, FindsTheSecondLapsPlacesWithTheirPoses) {
  const Submaps& maps = two_laps();
  LoopClosureConfig config;
  config.num_threads = 2;
  const std::vector<LoopClosure> closures = find_loop_closures(maps, config);
  ASSERT_FALSE(closures.empty());
  for (const LoopClosure& c : closures) {
    EXPECT_LT(c.match, c.query);
    EXPECT_GE(maps[c.query].travel - maps[c.match].travel, config.min_travel_gap);
    EXPECT_LE(c.confidence, c.context_score);
    EXPECT_GT(c.context_score, 0.0);
  }
  const LoopEvaluation e = evaluate_loop_closures(closures, maps, exact_frames(maps));
  EXPECT_GT(e.relevant_pairs, 50u);
  EXPECT_GT(e.max_f1, 0.5) << e.max_f1;
  EXPECT_GT(e.recall_at_full_precision, 0.0);
  ASSERT_FALSE(e.curve.empty());
  EXPECT_NEAR(e.curve.back().precision, static_cast<double>(e.correct) / static_cast<double>(e.hypotheses), 1e-12);
  for (std::size_t i = 1; i < e.curve.size(); ++i) EXPECT_GE(e.curve[i].recall, e.curve[i - 1].recall);

  config.num_threads = 1;  // the same answer on one thread
  const std::vector<LoopClosure> serial = find_loop_closures(maps, config);
  ASSERT_EQ(serial.size(), closures.size());
  for (std::size_t i = 0; i < serial.size(); ++i) {
    EXPECT_EQ(serial[i].match, closures[i].match);
    EXPECT_EQ(serial[i].confidence, closures[i].confidence);
  }
}

// Split over two processes (threads exchanging like MPI ranks): each gets the one-process hypotheses.
TEST(LoopClosure, SplitOverTwoProcessesGivesTheSameHypotheses) {
  const Submaps maps = two_laps();
  LoopClosureConfig config;
  const std::vector<LoopClosure> whole = find_loop_closures(maps, config);
  testing::ThreadExchange exchange(2);
  std::array<std::vector<LoopClosure>, 2> split;
  std::array<std::size_t, 2> values{0, 0};
  std::vector<std::thread> threads;
  for (int r = 0; r < 2; ++r) {
    threads.emplace_back([&, r] {
      const auto i = static_cast<std::size_t>(r);
      split[i] = find_loop_closures(maps, config, {}, testing::ThreadSplit(r, &exchange, &values[i]));
    });
  }
  for (std::thread& t : threads) t.join();
  ASSERT_FALSE(whole.empty());
  for (const std::vector<LoopClosure>& s : split) {
    ASSERT_EQ(s.size(), whole.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
      EXPECT_EQ(s[i].query, whole[i].query);
      EXPECT_EQ(s[i].match, whole[i].match);
      EXPECT_EQ(s[i].T_match_query.x, whole[i].T_match_query.x);
      EXPECT_EQ(s[i].confidence, whole[i].confidence);
    }
  }
  EXPECT_GT(values[0], 0u);  // both processes found hypotheses of their own queries
  EXPECT_GT(values[1], 0u);
}

// dMM verified (verify_dmm) and not: the verified hypotheses carry the same-place probability of their pair,
// higher for the correct ones; Eq. 1's carry none. A shortlist of 5 instead of 20: the sanitizer build pays each
// verification.
TEST(LoopClosure, VerifiedDmmGivesEachHypothesisItsProbability) {
  const Submaps& maps = two_laps();
  for (const bool verify : {false, true}) {
    LoopClosureConfig config;
    config.method = "rerank:5";
    config.verify_dmm = verify;
    config.num_threads = 2;
    const std::vector<LoopClosure> closures = find_loop_closures(maps, config);
    ASSERT_FALSE(closures.empty());
    const LoopEvaluation e = evaluate_loop_closures(closures, maps, exact_frames(maps));
    double right = 0, wrong = 0;
    std::size_t n_right = 0, n_wrong = 0;
    for (std::size_t i = 0; i < closures.size(); ++i) {
      if (!verify) {
        EXPECT_EQ(closures[i].probability, -1.0);
        continue;
      }
      EXPECT_GE(closures[i].probability, 0.0);
      EXPECT_LE(closures[i].probability, 1.0);
      (e.verdicts[i] == 1 ? right : wrong) += closures[i].probability;
      (e.verdicts[i] == 1 ? n_right : n_wrong) += 1;
    }
    if (!verify) continue;
    EXPECT_GT(e.max_f1, 0.5) << e.max_f1;
    if (n_wrong > 0 && n_right > 0) {
      EXPECT_GT(right / static_cast<double>(n_right), wrong / static_cast<double>(n_wrong));
    }
  }
}

TEST(LoopClosure, RefusesMethodsWithoutAPoseAndAbsurdConfigs) {
  LoopClosureConfig c;
  c.method = "succinct";
  EXPECT_THROW(validate(c), InputError);  // before any work, not when the closures are sought
  EXPECT_THROW(find_loop_closures(two_laps(), c), InputError);
  c.method = "rerank:5:3";  // needs CPD parts
  EXPECT_THROW(validate(c), InputError);
  EXPECT_THROW(find_loop_closures(two_laps(), c), InputError);
  c.method = "bogus";
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.other_place.distance = 0;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.min_score = 2;
  EXPECT_THROW(validate(c), InputError);
  c = {};
  c.min_travel_gap = std::nan("");
  EXPECT_THROW(validate(c), InputError);
  // A thread count OpenMP cannot start crashed the search (libgomp); 0 meant nothing either.
  for (const int threads : {0, 1025, 100000}) {
    c = {};
    c.num_threads = threads;
    EXPECT_THROW(validate(c), InputError) << threads;
  }
  c.num_threads = 1024;
  EXPECT_NO_THROW(validate(c));
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

TEST(LoopClosure, DriftGateDropsMatchesFarFromTheStoredRelativePose) {
  // Stored frames that put the second lap 30 m from where it really is: no closure across the laps passes a
  // gate of 2 m, and some do when the gate is off.
  Submaps maps = two_laps();
  const double lap_start = maps.back().travel / 2;
  for (Submap& m : maps)
    if (m.travel > lap_start) m.T_world_map.x += 30.0;
  LoopClosureConfig tight;
  tight.drift_rate = tight.drift_turn_rate = 0.0;
  tight.num_threads = 2;
  const auto across = [&](const std::vector<LoopClosure>& closures) {
    std::size_t n = 0;
    for (const LoopClosure& c : closures) n += maps[c.query].travel > lap_start && maps[c.match].travel <= lap_start;
    return n;
  };
  EXPECT_EQ(across(find_loop_closures(maps, tight)), 0u);
  LoopClosureConfig off = tight;
  off.drift_offset = 0.0;
  EXPECT_GT(across(find_loop_closures(maps, off)), 10u);
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

// graph_pose: the same hypotheses with the same confidences; a consistent one's pose is the optimised graph's
// (within the consistency tolerance of its own match), and no fewer hypotheses are right against the truth.
TEST(LoopClosure, GraphPosesKeepTheHypothesesAndPullTheirPosesOntoTheGraph) {
  const Submaps& maps = two_laps();
  LoopClosureConfig measured;
  measured.num_threads = 2;
  LoopClosureConfig graph = measured;
  graph.graph_pose = true;
  const std::vector<LoopClosure> a = find_loop_closures(maps, measured), b = find_loop_closures(maps, graph);
  ASSERT_EQ(a.size(), b.size());
  std::size_t moved = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].query, b[i].query);
    EXPECT_EQ(a[i].match, b[i].match);
    EXPECT_EQ(a[i].confidence, b[i].confidence);
    const bool consistent = a[i].confidence > a[i].context_score - 1.0;  // neither check took any off
    if (!consistent) {
      EXPECT_EQ(a[i].T_match_query.x, b[i].T_match_query.x);
      continue;
    }
    EXPECT_TRUE((PoseTolerance{0.5, 0.1}.accepts(a[i].T_match_query, b[i].T_match_query)));
    moved += a[i].T_match_query.x != b[i].T_match_query.x;
  }
  EXPECT_GT(moved, 0u);
  const LoopEvaluation ea = evaluate_loop_closures(a, maps, exact_frames(maps));
  const LoopEvaluation eb = evaluate_loop_closures(b, maps, exact_frames(maps));
  EXPECT_GE(eb.correct, ea.correct);
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

// gate_candidates ranks only the earlier submaps that can pass the drift gate: a submap's rank among fewer only
// rises, so every hypothesis found among all of them is found among the gated ones, with the same pose and score.
TEST(LoopClosure, RankingOnlyTheGatedSubmapsLosesNoHypothesisTheGateKeeps) {
  const Submaps& maps = two_laps();
  LoopClosureConfig gated;
  gated.num_threads = 2;
  gated.graph_check = false;
  gated.consistency.enabled = false;
  LoopClosureConfig all = gated;
  all.gate_candidates = false;
  const std::vector<LoopClosure> a = find_loop_closures(maps, all), g = find_loop_closures(maps, gated);
  ASSERT_FALSE(a.empty());
  for (const LoopClosure& h : a) {
    const auto same = [&](const LoopClosure& o) { return o.query == h.query && o.match == h.match; };
    const auto it = std::find_if(g.begin(), g.end(), same);
    ASSERT_NE(it, g.end()) << h.query << " -> " << h.match;
    EXPECT_EQ(it->score, h.score);
    EXPECT_EQ(it->context_score, h.context_score);
  }
}

// The consistent group and the graph check on the simulator's two laps: every wrong hypothesis of positive
// confidence loses at least 1 (so it ranks below every right one that kept its confidence), and at most a tenth of
// the right ones lose any.
TEST(LoopClosure, TheChecksTakeConfidenceFromWrongHypothesesAndSpareRightOnes) {
  const Submaps& maps = two_laps();
  LoopClosureConfig config;
  config.num_threads = 2;
  const std::vector<LoopClosure> checked = find_loop_closures(maps, config);
  config.consistency.enabled = false;
  config.graph_check = false;
  const std::vector<LoopClosure> unchecked = find_loop_closures(maps, config);
  ASSERT_EQ(checked.size(), unchecked.size());
  const LoopEvaluation e = evaluate_loop_closures(unchecked, maps, exact_frames(maps));
  std::size_t right = 0, right_lost = 0, wrong = 0;
  for (std::size_t i = 0; i < checked.size(); ++i) {
    const double lost = unchecked[i].confidence - checked[i].confidence;
    // Each failed check, as the hypothesis records it, took 1 of confidence.
    EXPECT_NEAR(lost, !checked[i].in_group + !checked[i].graph_agrees, 1e-9);
    EXPECT_TRUE(unchecked[i].in_group && unchecked[i].graph_agrees);
    if (unchecked[i].confidence <= 0 || e.verdicts[i] < 0) continue;
    if (e.verdicts[i] == 0) {
      wrong += 1;
      EXPECT_GE(lost, 1.0 - 1e-12) << checked[i].query << " -> " << checked[i].match;
    } else {
      right += 1, right_lost += lost > 0;
    }
  }
  ASSERT_GT(right, 10u);
  EXPECT_LE(right_lost * 10, right) << right_lost << " of " << right;
  EXPECT_GT(wrong, 0u);  // the simulator's corridors do give a few (7 when written)
}

}  // namespace
}  // namespace partslam
