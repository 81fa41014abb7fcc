// partslam match on a small database: a stored submap moved by a known pose must rank its original first
// with that relative pose, for dmm, dmm-exhaustive and dmm-ransac; bad options fail with a clear message.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "core/testing/synthetic_maps.h"
#include "io/map_database.h"

namespace partslam {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

struct CliRun {
  int exit_code = -1;
  std::string output;
};

CliRun run_cli(const std::string& args) {
  const std::string command = std::string("'") + PARTSLAM_BINARY + "' " + args + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) run.output += buffer.data();
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

class MatchCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("partslam_match_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    db_ = dir_ / "maps.db";
    std::mt19937_64 rng(12);
    const testing::SyntheticWorld world = testing::random_world(rng, 40.0, 60);
    Submaps places;
    for (int k = 0; k < 5; ++k) {
      const testing::SyntheticPair pair = testing::make_pair(world, rng, {-14.0 + 7.0 * k, 0.0}, {0, 0}, 0.0, 8.0);
      Submap m;
      m.points = pair.map;
      m.T_world_map = Pose2{-14.0 + 7.0 * k, 0.0, 0.0};
      places.push_back(m);
    }
    // The query: place 2's points in a frame turned by 90 deg + 1 deg and shifted (T_map_query below).
    Submap query;
    query.points = transform(kTruth.inverse(), places[2].points);
    query.T_world_map = places[2].T_world_map * kTruth;
    io::MapDatabase db = io::MapDatabase::open(db_, io::MapDatabase::Mode::kCreate);
    db.store_dataset({"places", "synthetic", io::DatasetKind::kSubmaps, {}}, places);  // map ids 1..5
    db.store_dataset({"queries", "synthetic", io::DatasetKind::kSubmaps, {}}, {query});  // map id 6
  }
  void TearDown() override { fs::remove_all(dir_); }

  static constexpr Pose2 kTruth{0.7, -0.4, 1.5882496193148399};  // 91 deg
  fs::path dir_, db_;
};

TEST_F(MatchCli, RanksTheMovedMapFirstWithItsPose) {
  for (const std::string method : {"dmm", "dmm-exhaustive", "dmm-ransac --ransac-iterations 3000"}) {
    const CliRun run = run_cli("match '" + db_.string() + "' --query 6 --top 3 --method " + method);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_THAT(run.output, HasSubstr("query: map 6 (dataset 'queries', submap 0)"));
    EXPECT_THAT(run.output, HasSubstr("5 maps"));
    // First result row: rank 1, map 3 of dataset places, pose close to the truth.
    std::istringstream lines(run.output);
    std::string line;
    while (std::getline(lines, line) && line.rfind("rank", 0) != 0) {
    }
    ASSERT_TRUE(std::getline(lines, line)) << run.output;
    std::istringstream row(line);
    int rank = 0, index = 0, inliers = 0;
    long long map_id = 0;
    std::string dataset, world;
    double fraction = 0, x = 0, y = 0, theta = 0;
    row >> rank >> map_id >> dataset >> index >> inliers >> fraction >> x >> y >> theta >> world;
    EXPECT_EQ(rank, 1);
    EXPECT_EQ(map_id, 3) << method << "\n" << run.output;
    EXPECT_EQ(dataset, "places");
    EXPECT_GT(fraction, 0.8) << method;
    EXPECT_NEAR(x, kTruth.x, 0.15) << method;
    EXPECT_NEAR(y, kTruth.y, 0.15) << method;
    EXPECT_NEAR(theta, 91.0, 1.5) << method;
    EXPECT_EQ(world, "-");  // another dataset: world frames are not comparable
  }
}

TEST_F(MatchCli, AllRankedExactlyAndJson) {
  const fs::path json = dir_ / "ranking.json";
  const CliRun run = run_cli("match '" + db_.string() + "' --query 3 --top 0 --threads 2 --json '" + json.string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("   1        6 queries"));  // the moved copy of map 3 ranks first
  std::ifstream in(json);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("\"results\""));
  EXPECT_THAT(text, HasSubstr("\"T_map_query\""));
  EXPECT_EQ(std::count(text.begin(), text.end(), '{'), 2 + 2 * 5);  // top, query, 5 results with a pose each
}

TEST_F(MatchCli, BadOptionsFailWithAMessage) {
  const CliRun imm = run_cli("match '" + db_.string() + "' --query 6 --method imm:3");
  EXPECT_EQ(imm.exit_code, 1);
  EXPECT_THAT(imm.output, HasSubstr("match supports dmm, dmm-ransac and dmm-exhaustive"));
  const CliRun dataset = run_cli("match '" + db_.string() + "' --query 6 --dataset nope");
  EXPECT_EQ(dataset.exit_code, 1);
  EXPECT_THAT(dataset.output, HasSubstr("no submap dataset named 'nope'"));
  const CliRun top = run_cli("match '" + db_.string() + "' --query 6 --top -1");
  EXPECT_EQ(top.exit_code, 1);
  EXPECT_THAT(top.output, HasSubstr("--top"));
  const CliRun missing = run_cli("match '" + db_.string() + "' --query 99");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_THAT(missing.output, HasSubstr("99"));
  const CliRun window = run_cli("match '" + db_.string() + "' --query 6 --angular-window 60");
  EXPECT_EQ(window.exit_code, 1);
  EXPECT_THAT(window.output, HasSubstr("angular_window"));
}

}  // namespace
}  // namespace partslam
