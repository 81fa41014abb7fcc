#include "core/evaluation/evaluation.h"

#include <gtest/gtest.h>

#include <array>
#include <thread>

#include "core/maps/dictionary.h"
#include "core/error.h"
#include "core/sim/simulator.h"
#include "core/testing/thread_split.h"

namespace partslam {
namespace {

struct SimData {
  Submaps maps;
  Dictionary dictionary;
};

const SimData& sim_data() {
  static const SimData d = [] {
    SimData d;
    SimulatorConfig input, other;
    other.seed = 2;
    d.maps = build_submaps(simulate(input).scans);
    d.dictionary = build_dictionary("sim-2", simulate(other).scans);
    return d;
  }();
  return d;
}

EvalConfig small_config(int threads) {
  EvalConfig c;
  c.tasks.num_tasks = 24;
  c.tasks.db_size = 20;
  c.num_threads = threads;
  c.ranking.parts.hmm_query_parts = 20;
  return c;
}

TEST(Evaluation, DirectMatchingRanksTheRevisitFirstOnTheSimulator) {
  const SimData& d = sim_data();
  const EvalReport r = evaluate(d.maps, d.dictionary.points, parse_method_list("dmm"), small_config(1));
  ASSERT_EQ(r.methods.size(), 1u);
  EXPECT_EQ(r.tasks, 24u);
  EXPECT_GT(r.relevant_pairs, 100u);
  const MethodResult& m = r.methods[0];
  EXPECT_EQ(m.normalized_ranks.size(), 24u);
  // Exact Eq. 1 on a noise-light simulated building: the relevant map is nearly always first.
  EXPECT_LT(m.summary.anr_percent, 15.0);
  EXPECT_GT(m.summary.recall_at_1, 0.6);
  EXPECT_GT(m.ms_per_pair, 0.0);
  EXPECT_NEAR(m.bits_per_map, 14.0 * r.mean_points, 1e-9);
  // Every relevant pair is posed; nearly all poses agree with the simulator's exact map poses.
  EXPECT_EQ(m.poses_checked, 24u);
  EXPECT_GT(m.pose_within_tolerance, 0.9);
}

TEST(Evaluation, EveryMethodRunsAndThreadsDoNotChangeRanks) {
  const SimData& d = sim_data();
  const auto methods = parse_method_list("imm:3,hmm:3,hmm:3:maxmax,rerank:5:3");
  const EvalReport serial = evaluate(d.maps, d.dictionary.points, methods, small_config(1));
  const EvalReport parallel = evaluate(d.maps, d.dictionary.points, methods, small_config(2));
  ASSERT_EQ(serial.methods.size(), 4u);
  for (std::size_t i = 0; i < methods.size(); ++i) {
    EXPECT_EQ(serial.methods[i].normalized_ranks, parallel.methods[i].normalized_ranks) << methods[i].label;
    for (double r : serial.methods[i].normalized_ranks) {
      EXPECT_GT(r, 0.0);
      EXPECT_LE(r, 1.0);
    }
  }
  EXPECT_EQ(serial.methods[0].bits_per_map, 132.0);  // 3 parts x 44 bits
  EXPECT_GT(serial.cpd_ms_per_map, 0.0);
  // Reranking by dMM moves the relevant map up whenever hMM put it in the top R.
  EXPECT_GE(serial.methods[3].summary.recall_at_1, serial.methods[1].summary.recall_at_1);
}

TEST(Evaluation, StagesRunASliceOfTasksWithTheSameOutcomes) {
  const SimData& d = sim_data();
  const EvalConfig config = small_config(1);
  const MethodSpec method = parse_method_spec("hmm:3");
  const EvalReport whole = evaluate(d.maps, d.dictionary.points, {method}, config);
  CpdConfig cpd = config.cpd;
  cpd.max_parts = config.ranking.parts.hmm_query_parts;
  const DescribedMaps described = describe_maps(d.maps, d.dictionary.points, cpd, config.codec, 2);
  RankingConfig ranking = config.ranking;
  ranking.parts.codec = described.codec;
  const std::unique_ptr<Ranker> ranker = make_ranker(method, ranking);
  ranker->prepare(map_views(d.maps, described), 1);
  const std::vector<Task> tasks = make_tasks(d.maps, config.tasks);
  const std::span<const Task> slice(tasks.begin() + 5, tasks.begin() + 12);
  const std::vector<TaskOutcome> outcomes = run_tasks(*ranker, method, d.maps, described, slice, config);
  ASSERT_EQ(outcomes.size(), 7u);
  for (std::size_t t = 0; t < outcomes.size(); ++t) {
    EXPECT_EQ(outcomes[t].rank / static_cast<double>(outcomes[t].db_size),
              whole.methods[0].normalized_ranks[5 + t]);
  }
  const MethodResult summary = summarize(method, outcomes, ranker->bits_per_map());
  EXPECT_EQ(summary.summary.tasks, 7u);
  EXPECT_EQ(summary.bits_per_map, 132.0);
}

// Two processes played by two threads that exchange their slices like MPI ranks (testing/thread_split.h): each
// report must equal a single process's (timings apart), and each process ran only its slice of the tasks.
TEST(Evaluation, SplitOverTwoProcessesGivesTheSameReport) {
  const SimData& d = sim_data();
  const auto methods = parse_method_list("dmm,hmm:3,succinct");
  EvalConfig config = small_config(1);
  config.ranking.dmm = DmmConfig{};  // the narrower search loops make: this test is about the split
  const EvalReport whole = evaluate(d.maps, d.dictionary.points, methods, config);
  testing::ThreadExchange exchange(2);
  std::array<EvalReport, 2> reports;
  std::array<std::size_t, 2> values{0, 0};
  std::vector<std::thread> threads;
  for (int r = 0; r < 2; ++r) {
    threads.emplace_back([&, r] {
      reports[static_cast<std::size_t>(r)] =
          evaluate(d.maps, d.dictionary.points, methods, config, {}, testing::ThreadSplit(r, &exchange, &values[static_cast<std::size_t>(r)]));
    });
  }
  for (std::thread& t : threads) t.join();
  for (const EvalReport& split : reports) {
    ASSERT_EQ(split.methods.size(), whole.methods.size());
    for (std::size_t i = 0; i < methods.size(); ++i) {
      EXPECT_EQ(split.methods[i].normalized_ranks, whole.methods[i].normalized_ranks) << methods[i].label;
      EXPECT_EQ(split.methods[i].poses_checked, whole.methods[i].poses_checked);
      EXPECT_EQ(split.methods[i].pose_within_tolerance, whole.methods[i].pose_within_tolerance);
      EXPECT_EQ(split.methods[i].bits_per_map, whole.methods[i].bits_per_map);
    }
  }
  // Each process contributed the outcomes of 12 of the 24 tasks per method (a record each) besides its CPD.
  EXPECT_GT(values[0], 3u * 12);
  EXPECT_GT(values[1], 3u * 12);
  // Slices: contiguous, the first n % size one longer.
  EXPECT_EQ(testing::ThreadSplit(1, &exchange, &values[0]).slice(7), (std::pair<std::size_t, std::size_t>(4, 7)));
  EXPECT_EQ(testing::ThreadSplit(0, &exchange, &values[0]).slice(7), (std::pair<std::size_t, std::size_t>(0, 4)));
}

// Evaluations of the same maps at two radii sharing their verified pairs (`eval --radius 2,4`) report what each
// reports alone; the second reuses answers of the first (its queries meet many of the same maps).
TEST(Evaluation, TwoRadiiSharingVerifiedPairsReportWhatEachReportsAlone) {
  const SimData& d = sim_data();
  const auto methods = parse_method_list("dmm,rerank:5:succinct");
  EvalConfig near = small_config(2), far = small_config(2);
  far.tasks.radius = 4.0;
  VerifiedPairs shared;
  const EvalReport near_shared = evaluate(d.maps, d.dictionary.points, methods, near, {}, local_work(), &shared);
  const std::size_t kept = shared.size(), hits = shared.hits();
  EXPECT_GT(kept, 0u);
  EXPECT_GE(hits, 5u * 24);  // the rerank's shortlist of every task was verified by dmm before it
  const EvalReport far_shared = evaluate(d.maps, d.dictionary.points, methods, far, {}, local_work(), &shared);
  EXPECT_GT(shared.hits() - hits, 5u * 24);
  const EvalReport near_alone = evaluate(d.maps, d.dictionary.points, methods, near);
  const EvalReport far_alone = evaluate(d.maps, d.dictionary.points, methods, far);
  for (const auto& [with, alone] : {std::pair{&near_shared, &near_alone}, std::pair{&far_shared, &far_alone}}) {
    ASSERT_EQ(with->methods.size(), alone->methods.size());
    for (std::size_t i = 0; i < methods.size(); ++i) {
      EXPECT_EQ(with->methods[i].normalized_ranks, alone->methods[i].normalized_ranks) << methods[i].label;
      EXPECT_EQ(with->methods[i].pose_within_tolerance, alone->methods[i].pose_within_tolerance);
      EXPECT_EQ(with->methods[i].calibration_error, alone->methods[i].calibration_error);
      EXPECT_GT(with->methods[i].ms_per_pair, 0.0);
    }
  }
  EXPECT_NE(near_alone.methods[0].normalized_ranks, far_alone.methods[0].normalized_ranks);  // other tasks
}

TEST(Evaluation, NoLoopClosureIsAClearError) {
  const SimData& d = sim_data();
  Submaps few(d.maps.begin(), d.maps.begin() + 10);  // 5 m of travel: no revisit
  try {
    evaluate(few, d.dictionary.points, parse_method_list("dmm"), small_config(1));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no relevant pair"), std::string::npos);
  }
}

}  // namespace
}  // namespace partslam
