// CLI tests of `partslam slam`: what it writes, the verdict, the map usable by `locate`, relation errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "apps/cli_testing.h"
#include "io/test_files.h"

namespace partslam {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
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
                                  " --compare --threads 2 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("verdict: "));
  EXPECT_THAT(run.output, HasSubstr("no relation matched"));
  EXPECT_THAT(run.output, HasSubstr("no relation names a scan of"));
  for (const char* name : {"corrected.log", "map.yaml", "map.pgm", "map.png", "loops.json", "slam.json"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  std::ifstream in(out / "slam.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  const std::string verdict = j["verdict"].get<std::string>();
  EXPECT_TRUE(verdict == "closed" || verdict == "open" || verdict == "doubtful" || verdict == "front end") << verdict;
  EXPECT_EQ(verdict, "closed");  // the simulated building closes its loops
  EXPECT_TRUE(j["trusted"].get<bool>());
  EXPECT_GT(j["closures"]["used"].get<int>(), 10);
  EXPECT_LE(j["closures"]["used"].get<int>(), j["closures"]["offered"].get<int>());
  EXPECT_EQ(j["relations"]["slam"]["relations"].get<int>(), 0);
  EXPECT_FALSE(j["relations"]["slam"].contains("translation_m"));
  const CliRun located = run_partslam("locate --map " + quoted(out / "map.yaml") + " --query-log " +
                                      quoted(out / "corrected.log") + " --from 30 --to 32");
  EXPECT_EQ(located.exit_code, 0) << located.output;
  EXPECT_THAT(located.output, HasSubstr("robot in the map"));
}

// A ROS 2 bag wherever a log is accepted: the shared MCAP (fr079, odometry poses) cut to its first fifth, so slam
// runs in seconds and says the recording was cut short; export-map, locate and match read it too.
TEST(CliSlam, Ros2BagsAreLogsLikeAnyOther) {
  const io::testing::TempDir dir;
  const fs::path mcap = io::testing::shared_data() / "bags" / "fr079.mcap";
  ASSERT_TRUE(fs::exists(mcap)) << mcap;
  const fs::path cut = dir / "fr079-cut.mcap";
  {
    std::ifstream in(mcap, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 5));
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
}

TEST(CliSlam, RefusesAbsurdThreadCounts) {
  const io::testing::TempDir dir;
  const CliRun run = run_partslam("slam sim:2 --out " + quoted(dir / "x") + " --threads 0");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("--threads"));
}

}  // namespace
}  // namespace partslam
