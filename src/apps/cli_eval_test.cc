// Runs the built partslam binary (PARTSLAM_BINARY): `partslam eval` on the simulator (no data needed), its JSON
// shape (the contract), the plot, thread independence and its error messages.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "apps/cli_testing.h"
#include "core/maps/submap.h"
#include "io/logs/scan_source.h"

namespace partslam {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using ::testing::HasSubstr;
using testing::kNarrowDmm;
using ::testing::Not;
using testing::quoted;
using testing::run_partslam;

class CliEvalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("partslam_cli_eval_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

const std::string kEval = "eval --input sim:1 --dict sim:2 --tasks 12 --db-size 20 --quiet ";

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// An N larger than the building holds is not reported as if it had been used.
TEST_F(CliEvalTest, SaysWhenTheDatabasesHoldFewerMapsThanN) {
  const fs::path json = dir_ / "big.json";
  const CliRun run = run_partslam(
      "eval --input sim:1 --dict sim:2 --tasks 4 --db-size 100000 --quiet --methods grid:11 --json " +
      quoted(json));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("warning: N = 100000 asked, but the task databases hold"));
  const nlohmann::json j = read_json(json);
  EXPECT_EQ(j["db_size"], 100000);
  const int smallest = j["database_sizes"][0], largest = j["database_sizes"][1];
  EXPECT_GE(smallest, 2);
  EXPECT_LE(smallest, largest);
  EXPECT_LT(largest, j["maps"].get<int>());
  // The R@1 % column goes by the databases' real sizes.
  EXPECT_EQ(run.output.find("R@1%") != std::string::npos, largest >= 200) << run.output;
}

TEST_F(CliEvalTest, WritesTheJsonShapeAndThePlot) {
  const fs::path json = dir_ / "out.json", plot = dir_ / "fig_d.png";
  const CliRun run = run_partslam(kEval + "--methods dmm,imm:2,hmm:3:maxmax,rerank:5:3 --json " + quoted(json) +
                                  " --plot " + quoted(plot));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("hMM cpd:3"));
  // N = 20: R@1 % is R@1 (rank <= max(1, 1 % of N)), so the table leaves that column out and says so.
  EXPECT_THAT(run.output, HasSubstr("R@5%"));
  EXPECT_THAT(run.output, Not(HasSubstr("R@1%")));
  EXPECT_THAT(run.output, HasSubstr("R@1 % is left out: below N = 200 it is R@1 again"));
  EXPECT_THAT(run.output, Not(HasSubstr("warning")));
  const nlohmann::json j = read_json(json);
  EXPECT_TRUE(j["input"].is_string());
  EXPECT_TRUE(j["dictionary"].is_string());
  EXPECT_EQ(j["db_size"], 20);
  EXPECT_EQ(j["database_sizes"], nlohmann::json::array({20, 20}));
  EXPECT_EQ(j["tasks"], 12);
  EXPECT_EQ(j["seed"], 1);
  EXPECT_GT(j["maps"].get<int>(), 20);
  EXPECT_GT(j["mean_points"].get<double>(), 0);
  EXPECT_EQ(j["parameters"]["origin_gate"], 2.0);
  EXPECT_EQ(j["parameters"]["cpd"]["candidates"], "corners");
  EXPECT_EQ(j["parameters"]["dmm"]["canonical_turns"], 8);  // the ranking's default
  ASSERT_EQ(j["methods"].size(), 4u);
  const char* labels[] = {"dMM", "iMM cpd:2", "Max-Max hMM cpd:3", "rerank5 hMM cpd:3"};
  for (std::size_t i = 0; i < 4; ++i) {
    const nlohmann::json& m = j["methods"][i];
    EXPECT_EQ(m["label"], labels[i]);
    EXPECT_TRUE(m["spec"].is_string());
    const double anr = m["anr"].get<double>();
    EXPECT_GE(anr, 100.0 / 20 - 1e-9) << m["label"];  // the best possible ANR is 1/N
    EXPECT_LE(anr, 100.0);
    EXPECT_GE(m["recall_at_1"].get<double>(), 0.0);
    EXPECT_LE(m["recall_at_1"].get<double>(), 1.0);
    EXPECT_GE(m["ms_per_pair"].get<double>(), 0.0);
    EXPECT_GE(m["ms_per_query"].get<double>(), m["ms_query_prep"].get<double>());
    EXPECT_GT(m["bits_per_map"].get<double>(), 0.0);
    EXPECT_EQ(m["normalized_ranks"].size(), 12u);
  }
  EXPECT_EQ(j["methods"][1]["bits_per_map"], 88.0);  // two 44-bit parts
  // The simulator's building is easy for dMM: far better than random.
  EXPECT_LT(j["methods"][0]["anr"].get<double>(), 25.0);
  std::ifstream png(plot, std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
}

TEST_F(CliEvalTest, ThreadsDoNotChangeTheRanks) {
  const fs::path one = dir_ / "one.json", two = dir_ / "two.json";
  const std::string eval = kEval + "--methods dmm,hmm:3" + kNarrowDmm;
  ASSERT_EQ(run_partslam(eval + " --threads 1 --json " + quoted(one)).exit_code, 0);
  ASSERT_EQ(run_partslam(eval + " --threads 2 --json " + quoted(two)).exit_code, 0);
  const nlohmann::json a = read_json(one), b = read_json(two);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(a["methods"][i]["normalized_ranks"], b["methods"][i]["normalized_ranks"]);
    EXPECT_EQ(a["methods"][i]["anr"], b["methods"][i]["anr"]);
  }
}

// --radius 2,4: both radii in one run, each written as its own run writes it (timings apart), the second to
// FILE_r4.json.
TEST_F(CliEvalTest, SeveralRadiiWriteWhatSeparateRunsWrite) {
  const std::string eval = kEval + "--methods dmm,rerank:3:succinct" + kNarrowDmm + " --json ";
  const fs::path both = dir_ / "both.json", two = dir_ / "two.json", four = dir_ / "four.json";
  const CliRun run = run_partslam(eval + quoted(both) + " --radius 2,4");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("== R = 2 m"));
  EXPECT_THAT(run.output, HasSubstr("== R = 4 m"));
  EXPECT_THAT(run.output, HasSubstr("wrote " + (dir_ / "both_r4.json").string()));
  ASSERT_EQ(run_partslam(eval + quoted(two) + " --radius 2").exit_code, 0);
  ASSERT_EQ(run_partslam(eval + quoted(four) + " --radius 4").exit_code, 0);
  const auto without_times = [](nlohmann::json j) {
    j.erase("seconds");
    for (nlohmann::json& m : j["methods"]) m.erase("ms_per_pair"), m.erase("ms_per_query"), m.erase("ms_query_prep");
    return j;
  };
  EXPECT_EQ(without_times(read_json(both)), without_times(read_json(two)));
  EXPECT_EQ(without_times(read_json(dir_ / "both_r4.json")), without_times(read_json(four)));
  EXPECT_EQ(read_json(dir_ / "both_r4.json")["parameters"]["radius"], 4.0);
}

TEST_F(CliEvalTest, BadOptionsExitNonZeroWithAMessageAndNoOutput) {
  const fs::path json = dir_ / "never.json";
  const std::pair<std::string, std::string> cases[] = {
      {"--methods hmm:x", "hmm:x"},
      {"--methods dmm --gate -1", "origin_gate"},
      {"--methods dmm --gate nan", "origin_gate"},
      {"--methods hmm:3 --cpd-candidates circles", "--cpd-candidates: expected partitions or corners"},
      {"--methods hmm:3 --cpd-box-sizes 0", "--cpd-box-sizes: must be in [0.2,100], got 0"},
      {"--methods hmm:3 --cpd-tsize nan", "--cpd-tsize: must be in [0,1], got nan"},
      {"--methods dmm --radius -1", "radius (R, --radius) must be a positive number of metres, got -1"},
      {"--methods dmm --radius 2,-1", "radius (R, --radius) must be a positive number of metres, got -1"},
      {"--methods dmm --radius 2,x", "--radius"},
      {"--methods dmm --dmm-turns 5", "canonical_turns must be 4 or 8"},
      {"--methods dmm --dmm-angular-window nan", "--dmm-angular-window must be in [0, 45] deg"},
  };
  for (const auto& [args, message] : cases) {
    const CliRun run = run_partslam(kEval + args + " --json " + quoted(json));
    EXPECT_EQ(run.exit_code, 1) << args << "\n" << run.output;
    EXPECT_THAT(run.output, HasSubstr("partslam: error: ")) << args;
    EXPECT_THAT(run.output, HasSubstr(message)) << args;
    EXPECT_FALSE(fs::exists(json)) << args;
  }
}

TEST_F(CliEvalTest, UnwritableOutputsFailBeforeAnyWork) {
  for (const fs::path& out : {dir_ / "no-such-folder" / "r.json", dir_}) {
    const CliRun run = run_partslam(kEval + "--methods dmm --json " + quoted(out));
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_THAT(run.output, HasSubstr("partslam: error: " + out.string())) << run.output;
    EXPECT_THAT(run.output, Not(HasSubstr("ANR"))) << run.output;  // failed before evaluating
  }
  const CliRun plot = run_partslam(kEval + "--methods dmm --plot " + quoted(dir_ / "nope" / "d.png"));
  EXPECT_EQ(plot.exit_code, 1) << plot.output;
  EXPECT_THAT(plot.output, HasSubstr("does not exist"));
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

// Raw logs: scan matching in `submaps` and `eval`, ground truth from a corrected twin (the simulator's exact
// poses play the twin here).
TEST_F(CliEvalTest, ScanMatchedSubmapsAreStoredAndMarked) {
  const fs::path db = dir_ / "raw.db";
  const CliRun run = run_partslam("submaps sim:1 --scan-match --spacing 2 --db " + quoted(db));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("scan matching: "));
  EXPECT_THAT(run.output, HasSubstr("0 matches rejected"));
  const CliRun info = run_partslam("info --json " + quoted(db));
  EXPECT_THAT(info.output, HasSubstr("\"scan_matched\": true"));
  EXPECT_NE(run_partslam("submaps sim:1 --scan-match --scan-match-window -1 --db " + quoted(dir_ / "x.db")).exit_code, 0);
  EXPECT_FALSE(fs::exists(dir_ / "x.db"));
}

TEST_F(CliEvalTest, BadRelationsStoreNothing) {
  const fs::path db = dir_ / "rel.db";
  const CliRun run = run_partslam("submaps sim:1 --db " + quoted(db) + " --relations " + quoted(dir_ / "none.relations"));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.output, HasSubstr("none.relations"));
  EXPECT_FALSE(fs::exists(db));  // a retry is not refused with "already exists"
  // Another log's relations: the check runs, and says that none of them links a pair.
  {
    std::ofstream out(dir_ / "other.relations");
    out << "1e9 2e9 0 0 0 0 0 0\n";
  }
  const std::string other = "submaps sim:1 --relations " + quoted(dir_ / "other.relations") + " --db ";
  // A radius checked after the database was written left a database behind a failed command.
  const CliRun radius = run_partslam(other + quoted(db) + " --radius -1");
  EXPECT_EQ(radius.exit_code, 1);
  EXPECT_THAT(radius.output, HasSubstr("--radius"));
  EXPECT_FALSE(fs::exists(db));
  const CliRun foreign = run_partslam(other + quoted(db));
  EXPECT_EQ(foreign.exit_code, 0) << foreign.output;
  EXPECT_THAT(foreign.output, HasSubstr("0 linked by a relation, 0 confirmed (no --raw"));
  EXPECT_THAT(foreign.output,
              HasSubstr("warning: " + (dir_ / "other.relations").string() + ": no relevant pair"));
}

TEST_F(CliEvalTest, EvaluatesARawLogAgainstItsTwin) {
  const CliRun run = run_partslam("eval --input sim:1 --dict sim:2 --tasks 12 --db-size 20 --methods dmm "
                                  "--scan-match --truth sim:1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("ground truth: corrected twin sim:1"));
  EXPECT_THAT(run.output, HasSubstr("0 submaps without a reference frame left out"));
  const CliRun foreign = run_partslam(kEval + "--methods dmm --truth sim:3");
  EXPECT_EQ(foreign.exit_code, 1);
  EXPECT_THAT(foreign.output, HasSubstr("not its ground truth"));
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

TEST_F(CliEvalTest, LoopsWritesClosuresGraphAndCurve) {
  const fs::path db = dir_ / "loops.db", json = dir_ / "loops.json", g2o = dir_ / "loops.g2o", png = dir_ / "pr.png";
  ASSERT_EQ(run_partslam("submaps sim:1 --spacing 1 --db " + quoted(db)).exit_code, 0);
  const CliRun run = run_partslam("loops " + quoted(db) + " --threads 2 --json " + quoted(json) + " --g2o " +
                                  quoted(g2o) + " --plot " + quoted(png));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("ground truth: the stored frames"));
  EXPECT_THAT(run.output, HasSubstr("recall at 100 % precision"));
  EXPECT_THAT(run.output, HasSubstr("outside the consistent group"));
  const nlohmann::json j = read_json(json);
  ASSERT_GT(j["closures"].size(), 0u);
  EXPECT_TRUE(j["closures"][0]["pose"]["theta"].is_number());
  EXPECT_GT(j["evaluation"]["relevant_pairs"].get<int>(), 0);
  EXPECT_GT(j["evaluation"]["max_f1"].get<double>(), 0.0);
  std::ifstream in(g2o);
  std::string first;
  in >> first;
  EXPECT_EQ(first, "VERTEX_SE2");
  EXPECT_GT(fs::file_size(png), 1000u);

  // Without the consistency checks: the same hypotheses, none of them less confident.
  const fs::path unchecked = dir_ / "unchecked.json";
  const CliRun off = run_partslam("loops " + quoted(db) + " --threads 2 --quiet --no-consistency-check --no-graph-check"
                                  " --json " + quoted(unchecked));
  ASSERT_EQ(off.exit_code, 0) << off.output;
  const nlohmann::json u = read_json(unchecked);
  ASSERT_EQ(u["closures"].size(), j["closures"].size());
  for (std::size_t i = 0; i < u["closures"].size(); ++i) {
    EXPECT_EQ(u["closures"][i]["match"], j["closures"][i]["match"]);
    EXPECT_GE(u["closures"][i]["confidence"].get<double>(), j["closures"][i]["confidence"].get<double>());
    EXPECT_TRUE(u["closures"][i]["consistent_group"].get<bool>() && u["closures"][i]["graph_agrees"].get<bool>());
    EXPECT_TRUE(j["closures"][i]["consistent_group"].is_boolean());
  }

  // A scan-matched dataset has no ground truth of its own: a curve needs --truth.
  const fs::path raw = dir_ / "raw.db";
  ASSERT_EQ(run_partslam("submaps sim:1 --spacing 1 --scan-match --db " + quoted(raw)).exit_code, 0);
  const CliRun no_truth = run_partslam("loops " + quoted(raw) + " --plot " + quoted(dir_ / "x.png"));
  EXPECT_EQ(no_truth.exit_code, 1);
  EXPECT_THAT(no_truth.output, HasSubstr("--truth"));
  const CliRun twin = run_partslam("loops " + quoted(raw) + " --truth sim:1 --quiet");
  EXPECT_EQ(twin.exit_code, 0) << twin.output;
  EXPECT_THAT(twin.output, HasSubstr("submaps have a reference frame"));
  EXPECT_NE(run_partslam("loops " + quoted(raw) + " --method succinct").exit_code, 0);
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

TEST_F(CliEvalTest, SlamWritesTheCorrectedLogMapLoopsAndRelationErrors) {
  // Relations of the simulated run from its exact poses (the simulator's log is the raw log here: its pose
  // fields are exact, so this checks the plumbing; core/slam/slam_test.cc checks the accuracy).
  const fs::path out = dir_ / "slam", relations = dir_ / "sim.relations";
  {
    const Scans scans = io::load_scan_source("sim:1").scans;  // a relation between two of its scans
    std::ofstream r(relations);
    r.precision(17);
    r << scans[10].timestamp << " " << scans[60].timestamp << " 0 0 0 0 0 0\n";
  }
  const CliRun run = run_partslam("slam sim:1 --out " + quoted(out) + " --relations " + quoted(relations) + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("pose graph: "));
  EXPECT_THAT(run.output, HasSubstr("verdict: "));
  for (const char* f : {"corrected.log", "map.png", "loops.json", "relations_error.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json e = read_json(out / "relations_error.json");
  EXPECT_TRUE(e["translation_m"]["mean"].is_number());  // units in the keys: metres and degrees
  EXPECT_TRUE(e["rotation_deg"]["std"].is_number());
  EXPECT_EQ(e["relations"].get<int>(), 1);
  EXPECT_EQ(e["missing"].get<int>(), 0);
  // The corrected log is a log: submaps can be built from it.
  EXPECT_EQ(run_partslam("submaps " + quoted(out / "corrected.log") + " --db " + quoted(dir_ / "c.db")).exit_code, 0);
  EXPECT_NE(run_partslam("slam sim:1 --out " + quoted(out) + " --relations " + quoted(dir_ / "none")).exit_code, 0);
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

TEST_F(CliEvalTest, MatchRanksANewLocalMapFromALog) {
  const fs::path db = dir_ / "q.db", json = dir_ / "ranking.json";
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db)).exit_code, 0);
  // The local map over 10..12 m of travel is, point for point, the stored submap anchored at 10 m.
  const CliRun run = run_partslam("match " + quoted(db) + " --query-log sim:1 --from 10 --to 12 --method dmm --top 3 --json " +
                                  quoted(json));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("local map of sim:1 (10.0 .. 12.0 m of travel, log time "));
  // The dashes of a new local map are explained under the table, as the columns are.
  EXPECT_THAT(run.output, HasSubstr("-: a new local map has no pose in the stored dataset's world frame"));
  EXPECT_THAT(run.output, HasSubstr("dx, dy, dth: where that puts the query"));
  EXPECT_THAT(run.output, HasSubstr("confidence"));
  const nlohmann::json j = read_json(json);
  ASSERT_EQ(j["ranking"].size(), 3u);
  EXPECT_DOUBLE_EQ(j["ranking"][0]["inlier_fraction"].get<double>(), 1.0);
  EXPECT_NEAR(j["ranking"][0]["T_map_query"]["x"].get<double>(), 0.0, 0.1);
  EXPECT_EQ(j["method"], "dmm");
  // Each verified row says how probable the map's best other pose is, and whether that makes its pose
  // ambiguous (as the warning under the table says of the best row).
  for (const nlohmann::json& row : j["ranking"]) {
    const double p = row["probability"].get<double>(), runner_up = row["runner_up_probability"].get<double>();
    EXPECT_LE(runner_up, p);
    EXPECT_EQ(row["pose_ambiguous"].get<bool>(), runner_up >= 0.5 * p);
  }
  EXPECT_EQ(run.output.find("warning: the pose of map") != std::string::npos,
            j["ranking"][0]["pose_ambiguous"].get<bool>());
  // --at: a log time instead of travel.
  EXPECT_EQ(run_partslam("match " + quoted(db) + " --query-log sim:1 --at 30 --method succinct").exit_code, 0);
  for (const std::string& bad : {std::string(" --query 3 --query-log sim:1 --from 1 --to 3"), std::string(" --query-log sim:1"),
                                std::string(" --query-log sim:1 --from-m 1 --to-m 3 --at-m 5"),
                                std::string(" --query-log sim:1 --from-time 5"),
                                std::string(" --query-log sim:1 --from-time 5 --to-time 4"),
                                std::string(" --query-log sim:1 --at-m -1"),
                                std::string(" --query-log sim:1 --from 5 --to 4"),
                                std::string(" --query-log sim:1 --at 1e9"),
                                std::string(" --query-log sim:1 --at 3 --from 1 --to 2"),
                                std::string(" --query-log sim:1 --from 1 --to 3 --method hmm:3")}) {
    const CliRun r = run_partslam("match " + quoted(db) + bad);
    EXPECT_EQ(r.exit_code, 1) << bad << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr("partslam: error:")) << bad;
  }
}

// A stretch by the log's clock or by travel, alike: the same scans give the same local map, and the
// label says which travel and which log time they cover.
TEST_F(CliEvalTest, MatchTakesAStretchByLogTimeOrByTravelAlike) {
  const fs::path db = dir_ / "t.db";
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db)).exit_code, 0);
  const Scans scans = io::load_scan_source("sim:1").scans;
  const std::vector<double> s = travel_distances(scans);
  std::size_t first = 0;
  while (s[first] < 10) ++first;
  std::size_t end = first;
  while (s[end] < 12) ++end;
  char times[120];
  std::snprintf(times, sizeof times, " --from-time %.17g --to-time %.17g", scans[first].timestamp, scans[end].timestamp);
  const std::string common = kNarrowDmm + " --method dmm --top 1 --json ";
  CliRun run = run_partslam("match " + quoted(db) + " --query-log sim:1 --from-m 10 --to-m 12" + common +
                            quoted(dir_ / "m.json"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  run = run_partslam("match " + quoted(db) + " --query-log sim:1" + times + common + quoted(dir_ / "t.json"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr(std::to_string(end - first) + " scans"));
  const nlohmann::json by_m = read_json(dir_ / "m.json"), by_time = read_json(dir_ / "t.json");
  EXPECT_EQ(by_m["ranking"], by_time["ranking"]);
  // One window from a travel (--at-m) or from a log time (--at): the same scans again.
  char at[60], at_m[60];
  std::snprintf(at, sizeof at, " --at %.17g", scans[first].timestamp);
  std::snprintf(at_m, sizeof at_m, " --at-m %.17g", s[first]);
  run = run_partslam("match " + quoted(db) + " --query-log sim:1" + at_m + common + quoted(dir_ / "am.json"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  run = run_partslam("match " + quoted(db) + " --query-log sim:1" + at + common + quoted(dir_ / "at.json"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(read_json(dir_ / "am.json")["ranking"], read_json(dir_ / "at.json")["ranking"]);
  // Outside the log: the error names the option and the log's span on that clock.
  run = run_partslam("match " + quoted(db) + " --query-log sim:1 --from-time 1e9 --to-time 2e9");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.output, HasSubstr("--from-time/--to-time, the log's clock; the log's scans are stamped "));
  // The help says which clock: the scans' own stamps, not seconds since the first scan.
  run = run_partslam("match --help");
  EXPECT_THAT(run.output, HasSubstr("not seconds since the first scan"));
  EXPECT_THAT(run.output, HasSubstr("--from-m"));
  EXPECT_THAT(run.output, HasSubstr("--at-m"));
}

// --scan-match with a stretch runs the front end over the stretch and a margin before it, not the whole log, and
// still finds the stored map of that place.
TEST_F(CliEvalTest, MatchScanMatchesOnlyTheQueryStretch) {
  const fs::path db = dir_ / "sm.db", json = dir_ / "sm.json";
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db)).exit_code, 0);
  const std::size_t log_scans = io::load_scan_source("sim:1").scans.size();
  const CliRun run = run_partslam("match " + quoted(db) + " --query-log sim:1 --from-m 60 --to-m 62 --scan-match "
                                  "--method dmm --top 1 --json " + quoted(json));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string key = "the front end ran over ";
  const std::size_t at = run.output.find(key);
  ASSERT_NE(at, std::string::npos) << run.output;
  const std::size_t matched = std::stoul(run.output.substr(at + key.size()));
  EXPECT_THAT(run.output, HasSubstr("of the log's " + std::to_string(log_scans) + " scans"));
  EXPECT_LT(matched, log_scans / 4) << run.output;
  EXPECT_GT(read_json(json)["ranking"][0]["inlier_fraction"].get<double>(), 0.9);
}

}  // namespace
}  // namespace partslam
