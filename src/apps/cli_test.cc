// Runs the built partslam binary (PARTSLAM_BINARY) on a map database made here with hand-built submaps.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "apps/cli_testing.h"
#include "apps/log_inputs.h"
#include "io/files/sqlite.h"
#include "io/store/map_database.h"

namespace partslam {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::CliRun;
using testing::quoted;
using testing::run_partslam;

int count_lines(const fs::path& p) {
  std::ifstream in(p);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  return lines;
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("partslam_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    db_ = dir_ / "maps.db";
    io::MapDatabase db = io::MapDatabase::open(db_, io::MapDatabase::Mode::kCreate);
    Submaps submaps(7);
    for (std::size_t i = 0; i < submaps.size(); ++i) {
      submaps[i].T_world_map = Pose2{10.0 * static_cast<double>(i), 0.0, 0.0};
      for (std::size_t j = 0; j < 20 + i; ++j) submaps[i].points.emplace_back(0.1 * j, -0.2 * j);
    }
    db.store_dataset({"sim-loop", "simulator", io::DatasetKind::kSubmaps, {}}, submaps);
    db.store_dataset({"sim-other", "simulator", io::DatasetKind::kSubmaps, {}}, Submaps(2));
    CodecConfig codec;  // 42 bits per part
    codec.dictionary_extent = {-20.0, 30.0, -5.0, 45.0};
    codec.rotation_bits = 0;
    db.put_descriptor(3, "fr079", 3, codec, {std::vector<std::uint8_t>(16, 0x5a), 126});
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  fs::path db_;
};

TEST_F(CliTest, InfoCountsSubmaps) {
  const CliRun run = run_partslam("info " + quoted(db_));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("sim-loop: 7 submaps, mean 23.0 points, map ids 1..7"));
  EXPECT_THAT(run.output, HasSubstr("sim-other: 2 submaps"));
  EXPECT_THAT(run.output, HasSubstr("total: 9 submaps, 161 points"));
  EXPECT_THAT(run.output, HasSubstr("dictionary fr079, K=3: 1 maps, mean 126.0 bits"));

  const CliRun json = run_partslam("info --json --check " + quoted(db_));
  EXPECT_EQ(json.exit_code, 0) << json.output;
  EXPECT_THAT(json.output, HasSubstr("\"submaps\": 9"));

  // A name that is not UTF-8 (stored before names were checked) does not break --json.
  io::sqlite::Connection::open(db_, io::sqlite::Connection::Access::kReadWrite)
      .exec("UPDATE datasets SET name = CAST(X'626164ff' AS TEXT) WHERE name = 'sim-other'");
  const CliRun odd = run_partslam("info --json " + quoted(db_));
  EXPECT_EQ(odd.exit_code, 0) << odd.output;
  EXPECT_THAT(odd.output, HasSubstr("bad\xef\xbf\xbd"));  // U+FFFD
}

TEST_F(CliTest, InfoOnSchemaVersionTwoCountsFromTheRowsAndUpgradeMigrates) {
  // What partslam wrote before schema version 3: no counts tables or triggers (nor version 4's origins).
  io::sqlite::Connection::open(db_, io::sqlite::Connection::Access::kReadWrite)
      .exec("ALTER TABLE submaps DROP COLUMN origins; DROP TRIGGER dataset_counted; DROP TRIGGER submap_added; DROP TRIGGER submap_removed;"
            " DROP TRIGGER submap_changed; DROP TRIGGER descriptor_added; DROP TRIGGER descriptor_removed;"
            " DROP TRIGGER descriptor_changed; DROP TABLE dataset_counts; DROP TABLE descriptor_counts;"
            " PRAGMA user_version = 2");
  const std::array<std::string, 3> upgrade = {"", " --upgrade", ""};
  for (std::size_t i = 0; i < upgrade.size(); ++i) {
    const CliRun run = run_partslam("info " + quoted(db_) + upgrade[i]);
    const bool old = i == 0;  // only the first run sees version 2: --upgrade migrated it
    EXPECT_THAT(run.output, HasSubstr(old ? std::string("schema version 2,")
                                           : "schema version " + std::to_string(io::kMapDatabaseSchemaVersion) + ","));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_THAT(run.output, HasSubstr("sim-loop: 7 submaps, mean 23.0 points, map ids 1..7"));
    EXPECT_THAT(run.output, HasSubstr("total: 9 submaps, 161 points"));
    EXPECT_THAT(run.output, HasSubstr("dictionary fr079, K=3: 1 maps, mean 126.0 bits"));
    EXPECT_EQ(run.output.find("keeps no counts") != std::string::npos, old) << run.output;
  }
}

TEST_F(CliTest, ExportWritesCsvAndPly) {
  const fs::path csv = dir_ / "map5.csv";
  const CliRun run = run_partslam("export " + quoted(db_) + " --map 5 --format csv --out " + quoted(csv));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(count_lines(csv), 2 + 24);  // the frame's pose, the header + map 5 (index 4) has 24 points
  {
    std::ifstream in(csv);
    std::string first;
    std::getline(in, first);
    EXPECT_EQ(first.rfind("# T_world_points ", 0), 0u) << first;  // the map frame names its pose in the world
  }
  EXPECT_THAT(run.output, HasSubstr("wrote 24 points of map 5 (dataset 'sim-loop', submap 4)"));

  const fs::path ply = dir_ / "map1.ply";
  const CliRun world = run_partslam("export " + quoted(db_) + " --map 2 --frame world --out " + quoted(ply));
  EXPECT_EQ(world.exit_code, 0) << world.output;
  EXPECT_EQ(count_lines(ply), 8 + 21);  // PLY header + points
  std::ifstream in(ply);
  std::string line;
  for (int i = 0; i < 9; ++i) std::getline(in, line);
  EXPECT_EQ(line, "10.000000 0.000000 0");  // first point (0, 0) moved by T_world_map
}

TEST_F(CliTest, BadMapIdExitsNonZeroWithMessage) {
  const fs::path out = dir_ / "missing.csv";
  const CliRun run = run_partslam("export " + quoted(db_) + " --map 99 --format csv --out " + quoted(out));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.output, HasSubstr("partslam: error:"));
  EXPECT_THAT(run.output, HasSubstr("no map with id 99"));
  EXPECT_FALSE(fs::exists(out));

  const CliRun format = run_partslam("export " + quoted(db_) + " --map 1 --format xyz");
  EXPECT_EQ(format.exit_code, 1);
  EXPECT_THAT(format.output, HasSubstr("--format: expected ply or csv, got 'xyz'"));
  const CliRun neither = run_partslam("export " + quoted(db_));
  EXPECT_EQ(neither.exit_code, 1);
  EXPECT_THAT(neither.output, HasSubstr("--map ID or --dictionary NAME"));
}

// An output named as one of the command's inputs is refused before any work: the database outlives the typo.
TEST_F(CliTest, AnOutputThatIsTheInputIsRefusedAndTheInputKept) {
  const auto size = fs::file_size(db_);
  for (const std::string& args : {"export " + quoted(db_) + " --map 1 --out " + quoted(db_),
                                  "match " + quoted(db_) + " --query 1 --json " + quoted(db_),
                                  "loops " + quoted(db_) + " --json " + quoted(db_),
                                  "render " + quoted(db_) + " --map 1 --out " + quoted(db_)}) {
    const CliRun run = run_partslam(args);
    EXPECT_EQ(run.exit_code, 1) << args << "\n" << run.output;
    EXPECT_THAT(run.output, HasSubstr("partslam: error: ")) << args;
  }
  EXPECT_EQ(fs::file_size(db_), size);
  EXPECT_EQ(run_partslam("info " + quoted(db_)).exit_code, 0);
  const CliRun both = run_partslam("loops " + quoted(db_) + " --json " + quoted(dir_ / "x.json") + " --g2o " +
                                   quoted(dir_ / "x.json"));
  EXPECT_EQ(both.exit_code, 1);
  EXPECT_THAT(both.output, HasSubstr("given both as --json and as --g2o"));
  const CliRun disagree =
      run_partslam("export " + quoted(db_) + " --map 1 --format csv --out " + quoted(dir_ / "m.ply"));
  EXPECT_EQ(disagree.exit_code, 1);
  EXPECT_THAT(disagree.output, HasSubstr("--format csv and --out"));
  EXPECT_FALSE(fs::exists(dir_ / "m.ply"));
}

// Command-line errors (unknown option, a number that is not one, a missing argument) exit 1 with the same
// prefix as bad input; --help and --version still exit 0.
TEST_F(CliTest, ParseErrorsExitOneWithThePrefix) {
  for (const std::string& args : {std::string("eval --input sim --dict sim --tasks many"),
                                  std::string("info --no-such-option ") + quoted(db_), std::string("match"),
                                  std::string("frobnicate")}) {
    const CliRun run = run_partslam(args);
    EXPECT_EQ(run.exit_code, 1) << args << "\n" << run.output;
    EXPECT_THAT(run.output, HasSubstr("partslam: error: ")) << args;
  }
  for (const std::string& args :
       {std::string("eval --input sim --dict sim --seed -1"), std::string("describe ") + quoted(db_) + " --dict d --seed -3",
        std::string("match ") + quoted(db_) + " --query 1 --min-gap nan",
        std::string("match ") + quoted(db_) + " --query 1 --query-parts -5"}) {
    const CliRun run = run_partslam(args);
    EXPECT_EQ(run.exit_code, 1) << args << "\n" << run.output;
    EXPECT_THAT(run.output, HasSubstr("partslam: error: ")) << args;
  }
  // Writing onto a folder names the folder, not "Success".
  const CliRun onto = run_partslam("export " + quoted(db_) + " --map 1 --format csv --out " + quoted(dir_));
  EXPECT_EQ(onto.exit_code, 1) << onto.output;
  EXPECT_THAT(onto.output, HasSubstr("is a directory"));
  EXPECT_EQ(run_partslam("--help").exit_code, 0);
  EXPECT_EQ(run_partslam("eval --help").exit_code, 0);
  EXPECT_EQ(run_partslam("--version").exit_code, 0);
}

TEST_F(CliTest, InfoRefusesNonDatabase) {
  const fs::path text = dir_ / "notes.txt";
  std::ofstream(text) << "hello\n";
  const CliRun run = run_partslam("info " + quoted(text));
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.output, HasSubstr("not an SQLite database"));
  const CliRun missing = run_partslam("info " + quoted(dir_ / "nope.db"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_THAT(missing.output, HasSubstr("no such file"));
}

// Every command that reads a log names every input the readers take, in the one wording (not CARMEN logs and sim
// only). CLI11 wraps nothing, so the wording appears whole.
TEST(CliHelp, EveryLogReadingCommandNamesEveryInput) {
  for (const char* command : {"submaps", "slam", "dictionary", "export-map", "eval", "match", "locate"}) {
    const CliRun run = run_partslam(std::string(command) + " --help");
    EXPECT_EQ(run.exit_code, 0) << command;
    EXPECT_THAT(run.output, HasSubstr(apps::kLogInputs)) << command << ":\n" << run.output;
  }
}

}  // namespace
}  // namespace partslam
