// Runs the built partslam binary (PARTSLAM_BINARY) through the parts workflow on the simulator, so no data is
// needed: submaps sim:1 + dictionary sim:2 -> describe -> match (dMM, hMM) -> render, and its error messages.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "core/evaluation/tasks.h"
#include "apps/cli_testing.h"
#include "io/store/map_database.h"

namespace partslam {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

using testing::CliRun;
using testing::quoted;
using testing::run_partslam;

// The fields of the ranking row of the given rank ("    1     72 ...").
std::vector<std::string> ranking_row(const std::string& output, int rank) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string s; fields >> s;) f.push_back(s);
    if (f.size() >= 3 && f[0] == std::to_string(rank)) return f;
  }
  return {};
}

// One database per test binary run (simulated loop, 2 m between submaps, and another building as dictionary);
// every test works on its own copy.
class CliPartsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    base_dir_ = fs::temp_directory_path() / ("partslam_cli_parts_" + std::to_string(::getpid()));
    fs::remove_all(base_dir_);
    fs::create_directories(base_dir_);
    const fs::path db = base_dir_ / "base.db";
    const CliRun submaps = run_partslam("submaps sim:1 --spacing 2 --db " + quoted(db));
    ASSERT_EQ(submaps.exit_code, 0) << submaps.output;
    const CliRun dictionary = run_partslam("dictionary sim:2 --name d --db " + quoted(db));
    ASSERT_EQ(dictionary.exit_code, 0) << dictionary.output;
  }
  static void TearDownTestSuite() { fs::remove_all(base_dir_); }

  void SetUp() override {
    db_ = base_dir_ / (std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".db");
    fs::copy_file(base_dir_ / "base.db", db_, fs::copy_options::overwrite_existing);
  }

  CliRun describe() {
    return run_partslam("describe " + quoted(db_) + " --dict d --parts 20 --k 1,3 --threads 2");
  }

  static fs::path base_dir_;
  fs::path db_;
};

fs::path CliPartsTest::base_dir_;

TEST_F(CliPartsTest, DescribeStoresEveryK) {
  const CliRun run = describe();
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("P = 20 parts, K = 1 3 20"));
  EXPECT_THAT(run.output, HasSubstr("CPD: "));
  EXPECT_THAT(run.output, HasSubstr("(hMM query list, with AS)"));
  const io::MapDatabase db = io::MapDatabase::open(db_, io::MapDatabase::Mode::kReadOnly);
  const std::size_t maps = db.load_submaps(db.datasets().front().id).size();
  const CliRun info = run_partslam("info " + quoted(db_));
  for (int k : {1, 3, 20}) {
    EXPECT_THAT(info.output,
                HasSubstr("dictionary d, K=" + std::to_string(k) + ": " + std::to_string(maps) + " maps"));
  }
  // Stored K-part descriptors cost 44 bits per part; the query list 52 (8 bits of AS).
  for (const io::DescriptorRecord& r : db.load_descriptors("d", 3)) {
    EXPECT_EQ(r.descriptor.bits % 44, 0);
    EXPECT_LE(r.descriptor.bits, 3 * 44);
  }
  for (const io::DescriptorRecord& r : db.load_descriptors("d", 20)) EXPECT_EQ(r.descriptor.bits % 52, 0);

  // One thread gives the same descriptors as two (CPD is seeded by the map id).
  const fs::path serial = base_dir_ / "serial.db";
  fs::copy_file(base_dir_ / "base.db", serial, fs::copy_options::overwrite_existing);
  ASSERT_EQ(run_partslam("describe " + quoted(serial) + " --dict d --parts 20 --k 3 --threads 1").exit_code,
            0);
  const auto one = io::MapDatabase::open(serial, io::MapDatabase::Mode::kReadOnly).load_descriptors("d", 3);
  const auto two = db.load_descriptors("d", 3);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].map_id, two[i].map_id);
    EXPECT_EQ(one[i].descriptor.bytes, two[i].descriptor.bytes);
  }
}

TEST_F(CliPartsTest, DmmRanksARevisitFirstWithItsPose) {
  const io::MapDatabase db = io::MapDatabase::open(db_, io::MapDatabase::Mode::kReadOnly);
  const Submaps maps = db.load_submaps(db.datasets().front().id);
  TaskConfig near;
  near.radius = 4.0;  // the same place: with the 8 m range cap, centroids of one place spread more than 2 m
  const std::vector<RelevantPair> pairs = relevant_pairs(maps, near);
  ASSERT_FALSE(pairs.empty());
  const Submap& query = maps[pairs.front().query];
  std::set<std::int64_t> revisits;
  for (const RelevantPair& p : pairs)
    if (p.query == pairs.front().query) revisits.insert(maps[p.global].id);

  const CliRun run = run_partslam("match " + quoted(db_) + " --query " + std::to_string(query.id) +
                                  " --method dmm --min-gap 20 --top 3");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("dMM over"));
  EXPECT_THAT(run.output, HasSubstr("th [deg]"));
  const std::vector<std::string> first = ranking_row(run.output, 1);
  ASSERT_EQ(first.size(), 12u) << run.output;  // rank map prob inliers inl% x y th dx dy dth dist
  EXPECT_TRUE(revisits.count(std::stoll(first[1]))) << run.output;
  EXPECT_GT(std::stod(first[2]), 0.0) << run.output;  // the verified probability
  EXPECT_LE(std::stod(first[2]), 1.0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("prob: the probability that the query and the map show the same place"));
  EXPECT_THAT(run.output, HasSubstr("confidence")) << run.output;
  // The match puts the query where its own (exact, simulated) pose says it is.
  EXPECT_LT(std::abs(std::stod(first[8])), 0.3) << run.output;
  EXPECT_LT(std::abs(std::stod(first[9])), 0.3) << run.output;
  EXPECT_LT(std::abs(std::stod(first[10])), 3.0) << run.output;
}

TEST_F(CliPartsTest, SuccinctAndItsRerankNeedNoDescribe) {
  const CliRun succinct = run_partslam("match " + quoted(db_) + " --query 40 --method succinct --top 3");
  ASSERT_EQ(succinct.exit_code, 0) << succinct.output;
  EXPECT_THAT(succinct.output, HasSubstr("succinct over"));
  EXPECT_THAT(succinct.output, HasSubstr("succinct score"));
  EXPECT_THAT(succinct.output, Not(HasSubstr("inliers")));
  EXPECT_EQ(ranking_row(succinct.output, 3).size(), 4u) << succinct.output;  // rank map score dist
  const CliRun rerank = run_partslam("match " + quoted(db_) + " --query 40 --method rerank:5 --top 6");
  ASSERT_EQ(rerank.exit_code, 0) << rerank.output;
  EXPECT_THAT(rerank.output, HasSubstr("rerank5 succinct over"));
  // The top 5 carry a verified dMM pose (rank map score prob inliers inl% x y th dx dy dth dist), the sixth
  // does not.
  ASSERT_EQ(ranking_row(rerank.output, 5).size(), 13u) << rerank.output;
  ASSERT_EQ(ranking_row(rerank.output, 6).size(), 13u) << rerank.output;
  EXPECT_NE(ranking_row(rerank.output, 5).at(3), "-") << rerank.output;
  EXPECT_NE(ranking_row(rerank.output, 5).at(4), "-") << rerank.output;
  EXPECT_EQ(ranking_row(rerank.output, 6).at(3), "-") << rerank.output;
  EXPECT_EQ(ranking_row(rerank.output, 6).at(4), "-") << rerank.output;
}

TEST_F(CliPartsTest, HmmNeedsDescribeFirst) {
  const std::string match = "match " + quoted(db_) + " --query 40 --method hmm:3 --top 5";
  const CliRun before = run_partslam(match);
  EXPECT_EQ(before.exit_code, 1);
  EXPECT_THAT(before.output, HasSubstr("no descriptors stored"));
  EXPECT_THAT(before.output, HasSubstr("'partslam describe"));
  EXPECT_THAT(before.output, Not(HasSubstr("query map")));  // fails before printing a ranking

  ASSERT_EQ(describe().exit_code, 0);
  const CliRun after = run_partslam(match);
  ASSERT_EQ(after.exit_code, 0) << after.output;
  EXPECT_THAT(after.output, HasSubstr("hMM cpd:3 over"));
  EXPECT_THAT(after.output, HasSubstr("hMM score"));
  EXPECT_THAT(after.output, HasSubstr("(K=20)"));                      // the query list
  EXPECT_EQ(ranking_row(after.output, 5).size(), 4u) << after.output;  // rank map score dist

  // A K that describe did not store names the missing set.
  const CliRun k4 = run_partslam("match " + quoted(db_) + " --query 40 --method imm:4");
  EXPECT_EQ(k4.exit_code, 1);
  EXPECT_THAT(k4.output, HasSubstr("no K=4 descriptor for dictionary 'd'"));
  EXPECT_THAT(k4.output, HasSubstr("with K = 4 first"));
  EXPECT_THAT(k4.output, HasSubstr("'partslam describe"));

  const CliRun rerank = run_partslam("match " + quoted(db_) + " --query 40 --method rerank:5:3 --top 6");
  ASSERT_EQ(rerank.exit_code, 0) << rerank.output;
  EXPECT_EQ(ranking_row(rerank.output, 5).size(), 13u) << rerank.output;  // reranked: with a pose
  EXPECT_EQ(ranking_row(rerank.output, 6).size(), 13u) << rerank.output;  // below the top R: dashes
  EXPECT_THAT(ranking_row(rerank.output, 6)[3], "-");
}

TEST_F(CliPartsTest, RenderWritesAPng) {
  const fs::path png = base_dir_ / "fig_e.png";
  const CliRun run =
      run_partslam("render " + quoted(db_) + " --map 40 --dict d --parts 3 --out " + quoted(png));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("CPD on the fly"));
  std::ifstream in(png, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");

  ASSERT_EQ(describe().exit_code, 0);
  const CliRun stored = run_partslam("render " + quoted(db_) + " --map 40 --out " + quoted(png));
  ASSERT_EQ(stored.exit_code, 0) << stored.output;
  EXPECT_THAT(stored.output, HasSubstr("from the stored 20-part list"));
}

// Without --dict, render draws the parts of the database's only dictionary; it names the dictionaries when
// there are several, and says so when there is none instead of drawing a bare map as if it were the figure.
TEST_F(CliPartsTest, RenderWithoutDictSaysWhichDictionaryOrThatThereIsNone) {
  const fs::path png =
      base_dir_ / (std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".png");
  ASSERT_EQ(run_partslam("dictionary sim:3 --name e --db " + quoted(db_)).exit_code, 0);
  const CliRun two = run_partslam("render " + quoted(db_) + " --map 40 --out " + quoted(png));
  EXPECT_EQ(two.exit_code, 1) << two.output;
  EXPECT_THAT(two.output, HasSubstr("several dictionaries (d, e)"));
  EXPECT_THAT(two.output, HasSubstr("--dict NAME chooses one"));
  EXPECT_FALSE(fs::exists(png));

  const fs::path bare = base_dir_ / "bare.db";
  ASSERT_EQ(run_partslam("submaps sim:1 --spacing 2 --db " + quoted(bare)).exit_code, 0);
  const CliRun none = run_partslam("render " + quoted(bare) + " --map 40 --out " + quoted(png));
  ASSERT_EQ(none.exit_code, 0) << none.output;
  EXPECT_THAT(none.output, HasSubstr("warning: " + bare.string() + " holds no dictionary"));
  EXPECT_THAT(none.output, HasSubstr(": 0 parts from no dictionary in the database"));
  EXPECT_TRUE(fs::exists(png));
  fs::remove(png);
  fs::remove(bare);
}

TEST_F(CliPartsTest, BadInputsExitNonZeroWithAMessage) {
  const std::string db = quoted(db_);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"match " + db + " --query 9999", "no map with id 9999"},
      {"match " + db + " --query 40 --method hmm", "method 'hmm'"},
      {"match " + db + " --query 40 --method fast", "method 'fast'"},
      {"match " + db + " --query 40 --method imm:3 --dict nope", "no dictionary named 'nope'"},
      {"describe " + db + " --dict nope", "no dictionary named 'nope'"},
      {"describe " + db + " --dict d --parts 3 --k 5", "--k: every K must be in [1, P = 3]"},
      {"describe " + db + " --dict d --dataset nope", "no dataset named 'nope'"},
      {"describe " + db + " --dict d --mc most", "--mc: expected point or inlier, got 'most'"},
      {"describe " + db + " --dict d --tsize 2", "--tsize: must be in [0,1], got 2"},
      {"describe " + db + " --dict d --candidates corners --box-sizes 1,0.1",
       "--box-sizes: must be in [0.2,100], got 0.1"},
      {"render " + db + " --map 9999 --out x.png", "no map with id 9999"},
      {"render " + db + " --map 40 --dict nope --out x.png", "no dictionary named 'nope'"},
      {"render " + db + " --map 40 --out x.txt", "--out: expected a .png file"},
  };
  for (const auto& [args, message] : cases) {
    const CliRun run = run_partslam(args);
    EXPECT_EQ(run.exit_code, 1) << args << "\n" << run.output;
    EXPECT_THAT(run.output, HasSubstr("partslam: error: ")) << args;
    EXPECT_THAT(run.output, HasSubstr(message)) << args;
  }
  EXPECT_FALSE(fs::exists("x.png"));
}

}  // namespace
}  // namespace partslam
