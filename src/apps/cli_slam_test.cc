// CLI tests of `partslam slam`: what it writes, the verdict, the map usable by `locate`, relation errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "apps/cli_testing.h"
#include "core/sim/simulator.h"
#include "io/logs/carmen_log.h"
#include "io/testing/test_files.h"

namespace partslam {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::CliRun;
using testing::quoted;
using testing::run_partslam;

// The simulated building's raw log (drifting odometry): every output is written, slam.json says how many
// closures were used and the verdict, the map is a map_server map that `locate` reads, and a relations file that
// names no scan of the log says so instead of printing an error of 0.
TEST(CliSlam, WritesTheMapTheVerdictAndSaysWhenNoRelationMatched) {
  const io::testing::TempDir dir;
  const fs::path out = dir / "out", relations = dir / "other.relations";
  std::ofstream(relations) << "1.0 2.0 0.5 0 0 0 0 0.1\n";
  const CliRun run = run_partslam("slam sim:2 --out " + quoted(out) + " --relations " + quoted(relations) +
                                  " --compare --threads 2 --quiet --picture-side 300");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("verdict: "));
  EXPECT_THAT(run.output, HasSubstr("; checked: "));  // what the verdict looked at, in one sentence
  EXPECT_THAT(run.output, HasSubstr("no relation matched"));
  EXPECT_THAT(run.output, HasSubstr("no relation names a scan of"));
  EXPECT_THAT(run.output, HasSubstr("how to carry relations onto a re-timed recording"));
  EXPECT_THAT(run.output, HasSubstr("checked before the run"));
  for (const char* name : {"corrected.log", "map.yaml", "map.pgm", "map.png", "loops.json", "slam.json"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  {  // --picture-side bounds map.png (two maps side by side, a title row above): its IHDR width and height
    std::ifstream png(out / "map.png", std::ios::binary);
    unsigned char header[24] = {};
    png.read(reinterpret_cast<char*>(header), sizeof header);
    const auto be32 = [&](int at) { return header[at] << 24 | header[at + 1] << 16 | header[at + 2] << 8 | header[at + 3]; };
    EXPECT_LE(be32(16), 300);
    EXPECT_GT(be32(16), 100);
    EXPECT_LE(be32(20), 300 + 40);
  }
  EXPECT_NE(run_partslam("slam sim:2 --out " + quoted(dir / "x") + " --picture-side 5").exit_code, 0);
  std::ifstream in(out / "slam.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const std::string verdict = j["verdict"].get<std::string>();
  EXPECT_THAT(j["verdict_checks"].get<std::string>(), HasSubstr("closures offered agree with the solution"));
  EXPECT_TRUE(verdict == "closed" || verdict == "open" || verdict == "doubtful" || verdict == "front end") << verdict;
  EXPECT_EQ(verdict, "closed");  // the simulated building closes its loops
  EXPECT_TRUE(j["trusted"].get<bool>());
  EXPECT_TRUE(j["map_check"]["judged"].get<bool>());  // the building is driven twice
  EXPECT_TRUE(j["map_check"]["passed"].get<bool>());
  EXPECT_GT(j["closures"]["used"].get<int>(), 10);
  EXPECT_LE(j["closures"]["used"].get<int>(), j["closures"]["offered"].get<int>());
  EXPECT_LE(j["closures"]["outside_consistent_group"].get<int>(), j["closures"]["hypotheses"].get<int>());
  EXPECT_LE(j["closures"]["at_odds_with_graph"].get<int>(), j["closures"]["hypotheses"].get<int>());
  EXPECT_EQ(j["relations"]["slam"]["relations"].get<int>(), 0);
  EXPECT_FALSE(j["relations"]["slam"].contains("translation_m"));
  EXPECT_GT(j["front_end"]["turn_slope"].get<double>(), 0.8);  // the scans turn with the wheels
  EXPECT_GT(j["front_end"]["turning_steps"].get<int>(), 20);
  EXPECT_FALSE(j["front_end"]["mirrored"].get<bool>());
  EXPECT_LT(std::abs(j["front_end"]["wall_axis_deg"].get<double>()), 2.0);  // the simulated walls lie along its axes
  EXPECT_THAT(run.output, Not(HasSubstr("read mirrored")));
  EXPECT_THAT(run.output, HasSubstr(" deg to the log's axes (mapped turned onto them"));
  const CliRun located = run_partslam("locate --map " + quoted(out / "map.yaml") + " --query-log " +
                                      quoted(out / "corrected.log") + " --from 30 --to 32");
  EXPECT_EQ(located.exit_code, 0) << located.output;
  EXPECT_THAT(located.output, HasSubstr("robot in the map"));
}

// A map the program cannot vouch for is still written, with a warning, the verdict in slam.json and exit status 3
// (docs/USAGE.md, "Exit status"). Forced here by a map check that tolerates no crossing beam at all: the simulated
// building's map has a few (beams past a door's edge), so its check fails.
TEST(CliSlam, AMapThatFailsItsCheckIsWrittenButExitsWithStatus3) {
  const io::testing::TempDir dir;
  std::ofstream(dir / "strict.yaml") << "map_check:\n  max_crossing_share: 0\n  min_revisiting_beams: 1\n";
  const fs::path out = dir / "out";
  const CliRun run = run_partslam("slam sim:2 --quiet --out " + quoted(out) + " --config " + quoted(dir / "strict.yaml"));
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_THAT(run.output, HasSubstr("verdict: doubtful ("));
  EXPECT_THAT(run.output, HasSubstr("cross a wall another visit saw"));
  EXPECT_THAT(run.output, HasSubstr("partslam: warning: "));
  EXPECT_THAT(run.output, HasSubstr(": the map written is not trusted, verdict doubtful ("));
  for (const char* name : {"corrected.log", "map.yaml", "map.pgm", "map.png", "loops.json", "slam.json"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  std::ifstream in(out / "slam.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["verdict"], "doubtful");
  EXPECT_FALSE(j["trusted"].get<bool>());
  EXPECT_GT(j["map_check"]["crossing_beams"].get<int>(), 0);
  EXPECT_FALSE(j["map_check"]["passed"].get<bool>());
  // The second opinion is in slam.json whatever the verdict: here the closures tie the windows of travel, and
  // nothing the front ends do there fails it.
  EXPECT_TRUE(j["second_opinion"]["passed"].get<bool>());
  EXPECT_GT(j["second_opinion"]["windows"].get<int>() + j["second_opinion"]["pinned_windows"].get<int>(), 0);
  EXPECT_LT(j["second_opinion"]["max_turn_deg"].get<double>(), j["second_opinion"]["limit_turn_deg"].get<double>());
  EXPECT_TRUE(j["map_check"].contains("worst_place"));
}

// A second front end that parts from the first (forced here by limits no two settings meet, over a map no
// closure ties: none is used) leaves a map the verdict does not trust: exit status 3, the reason in the verdict
// and the warning, the window in slam.json.
TEST(CliSlam, ASecondFrontEndThatPartsFromTheFirstExitsWithStatus3) {
  const io::testing::TempDir dir;
  std::ofstream(dir / "strict.yaml")
      << "min_confidence: 1.0e9\nsecond_opinion:\n  max_turn: 1.0e-9\n  max_shift: 1.0e-9\n"
      << "map_check:\n  max_crossing_share: 1\n  max_place_share: 1\n";  // the front end's map: a wing twice
  const fs::path out = dir / "out";
  const CliRun run = run_partslam("slam sim:2 --quiet --threads 2 --out " + quoted(out) + " --config " +
                                  quoted(dir / "strict.yaml"));
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_THAT(run.output, HasSubstr("verdict: doubtful (a second front end (fine field 0.03 m) parts from the first"));
  EXPECT_THAT(run.output, HasSubstr(": the map written is not trusted, verdict doubtful (a second front end"));
  std::ifstream in(out / "slam.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_FALSE(j["second_opinion"]["passed"].get<bool>());
  const nlohmann::json& w = j["second_opinion"]["worst_window"];
  EXPECT_LT(w["from_time"].get<double>(), w["to_time"].get<double>());
  EXPECT_GT(j["seconds"]["second_opinion"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(out / "map.png"));
}

// A ROS 2 bag wherever a log is accepted: the shared MCAP (fr079, odometry poses) cut to its first tenth (30 m of
// travel), so slam and match run in seconds and say the recording was cut short; export-map, locate and match
// read it too.
TEST(CliSlam, Ros2BagsAreLogsLikeAnyOther) {
  const io::testing::TempDir dir;
  const fs::path mcap = io::testing::shared_data() / "bags" / "fr079.mcap";
  ASSERT_TRUE(fs::exists(mcap)) << mcap;
  const fs::path cut = dir / "fr079-cut.mcap";
  {
    std::ifstream in(mcap, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 10));
  }
  CliRun run = run_partslam("slam " + quoted(cut) + " --out " + quoted(dir / "out") + " --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("warning: "));
  EXPECT_THAT(run.output, HasSubstr("fr079-cut.mcap: the recording is cut short"));
  EXPECT_TRUE(fs::exists(dir / "out" / "map.yaml"));
  {  // the JSON says so too, so a batch run can tell
    std::ifstream in(dir / "out" / "slam.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_EQ(j["warnings"].size(), 1u);
    EXPECT_THAT(j["warnings"][0].get<std::string>(), HasSubstr("the recording is cut short"));
  }
  run = run_partslam("export-map " + quoted(mcap) + " --until 60 --out " + quoted(dir / "first.yaml"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  run = run_partslam("locate --map " + quoted(dir / "first.yaml") + " --query-log " + quoted(mcap) +
                     " --from 20 --to 22");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("robot in the map"));
  ASSERT_EQ(run_partslam("submaps " + quoted(cut) + " --db " + quoted(dir / "m.db") + " --quiet --json " +
                         quoted(dir / "submaps.json")).exit_code, 0);
  {
    std::ifstream in(dir / "submaps.json");
    EXPECT_EQ(nlohmann::json::parse(in)["warnings"].size(), 1u);
  }
  run = run_partslam("match " + quoted(dir / "m.db") + " --query-log " + quoted(mcap) + " --from 20 --to 22");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("fr079-cut"));  // the dataset, named after the file
  // A rosbag2 folder's metadata.yaml is a log, though a map_server map is a .yaml too.
  fs::create_directories(dir / "bag2");
  fs::copy_file(mcap, dir / "bag2" / "fr079_0.mcap");
  std::ofstream(dir / "bag2" / "metadata.yaml")
      << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: mcap\n"
         "  relative_file_paths:\n    - fr079_0.mcap\n";
  run = run_partslam("dictionary " + quoted(dir / "bag2" / "metadata.yaml") + " --db " + quoted(dir / "d.db") +
                     " --name bag2");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("dictionary 'bag2': "));
}

TEST(CliSlam, RefusesAbsurdThreadCounts) {
  const io::testing::TempDir dir;
  const CliRun run = run_partslam("slam sim:2 --out " + quoted(dir / "x") + " --threads 0");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("--threads"));
}

// A run that fails leaves no empty output folder of its own making; a file where the folder should be is
// named.
TEST(CliSlam, AFailedRunLeavesNoFolderBehind) {
  const io::testing::TempDir dir;
  io::testing::write_bytes(dir / "not_a_log.log", "\x89PNG\r\n");
  const CliRun bad = run_partslam("slam " + quoted(dir / "not_a_log.log") + " --out " + quoted(dir / "out"));
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::create_directories(dir / "mine");  // a folder the user made stays
  EXPECT_EQ(
      run_partslam("slam " + quoted(dir / "not_a_log.log") + " --out " + quoted(dir / "mine")).exit_code, 1);
  EXPECT_TRUE(fs::is_directory(dir / "mine"));
  const CliRun file = run_partslam("slam sim:2 --out " + quoted(dir / "not_a_log.log"));
  EXPECT_EQ(file.exit_code, 1);
  EXPECT_THAT(file.output, HasSubstr("exists and is not a folder"));
}

// --print-config writes every setting; --config reads that file back, flags given override it, and a file with an
// unknown key or a bad value is refused naming the file and the key (slam, loops and locate alike). The runs read
// the simulated building's first 400 scans, written as a log: what is checked is which settings slam ran with,
// and the whole building would cost the sanitizer build half a minute a run.
TEST(CliSlam, SettingsFilesReadBackAndFlagsOverrideThem) {
  const io::testing::TempDir dir;
  Scans scans = simulate().scans;
  scans.resize(400);
  const fs::path log = dir / "short.log";
  io::write_carmen_log(log, scans);
  const CliRun printed = run_partslam("slam --print-config");
  ASSERT_EQ(printed.exit_code, 0) << printed.output;
  EXPECT_THAT(printed.output, HasSubstr("\nback_end:\n  weights:\n"));
  std::string text = printed.output;
  const std::size_t at = text.find("\nmin_confidence: 0.2\n");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, 21, "\nmin_confidence: 0.35\n");
  std::ofstream(dir / "slam.yaml") << text;
  const CliRun from_file = run_partslam("slam " + quoted(log) + " --quiet --out " + quoted(dir / "a") +
                                        " --config " + quoted(dir / "slam.yaml"));
  ASSERT_EQ(from_file.exit_code, 0) << from_file.output;
  EXPECT_THAT(from_file.output, HasSubstr("offered (confidence >= 0.35)"));
  const CliRun flag = run_partslam("slam " + quoted(log) + " --quiet --out " + quoted(dir / "b") +
                                   " --config " + quoted(dir / "slam.yaml") + " --min-confidence 0.25");
  ASSERT_EQ(flag.exit_code, 0) << flag.output;
  EXPECT_THAT(flag.output, HasSubstr("offered (confidence >= 0.25)"));

  std::ofstream(dir / "bad.yaml") << "loops:\n  context: 4\n  contxt: 2\n";
  for (const std::string& command : {"slam sim:2 --out " + quoted(dir / "c"), "loops " + quoted(dir / "none.db"),
                                    "locate --map " + quoted(dir / "none.yaml") + " --query-log sim --at-m 3"}) {
    const CliRun bad = run_partslam(command + " --config " + quoted(dir / "bad.yaml"));
    EXPECT_EQ(bad.exit_code, 1) << command;
    EXPECT_THAT(bad.output, HasSubstr("bad.yaml: line ")) << command;
    EXPECT_THAT(bad.output, HasSubstr("unknown key '")) << command;
  }
  std::ofstream(dir / "range.yaml") << "back_end:\n  graph:\n    robust_scale: -1\n";
  const CliRun range = run_partslam("slam sim:2 --out " + quoted(dir / "d") + " --config " + quoted(dir / "range.yaml"));
  EXPECT_EQ(range.exit_code, 1);
  EXPECT_THAT(range.output, HasSubstr("range.yaml: slam config: back_end.graph.robust_scale must be finite and > 0"));
  for (const char* command : {"loops --print-config", "locate --print-config"}) {
    const CliRun defaults = run_partslam(command);
    EXPECT_EQ(defaults.exit_code, 0) << command;
    EXPECT_THAT(defaults.output, HasSubstr(" --config: every setting")) << command;
  }
}

}  // namespace
}  // namespace partslam
