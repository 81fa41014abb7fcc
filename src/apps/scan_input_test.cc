// apps/scan_input.h through the built binary: every command reading a log takes --skip-damaged and prints the
// reader's warnings as "warning: ..." (a recording cut short), and `submaps` refuses a corrected log with a scan
// moved kilometres, naming the line, unless --skip-damaged.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli_testing.h"

namespace partslam {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::CliRun;
using testing::quoted;
using testing::run_partslam;

std::string gunzip(const fs::path& path) {
  gzFile gz = gzopen(path.c_str(), "rb");
  std::string text;
  char buffer[1 << 16];
  for (int n; gz != nullptr && (n = gzread(gz, buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<std::size_t>(n));
  if (gz != nullptr) gzclose(gz);
  return text;
}

class ScanInput : public ::testing::Test {
 protected:
  void SetUp() override {
    const fs::path source = fs::path(PARTSLAM_SHARED_DATA) / "corrected" / "orebro-corrected.log.gz";
    if (!fs::exists(source)) GTEST_SKIP() << source << " is absent";
    dir_ = fs::temp_directory_path() / ("partslam_scan_input_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    text_ = gunzip(source);
    ASSERT_GT(text_.size(), 100000u);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return dir_ / name;
  }

  fs::path dir_;
  std::string text_;
};

TEST_F(ScanInput, ALogCutShortIsReadWithAWarning) {
  const fs::path cut = write("cut.log", text_.substr(0, text_.size() * 2 / 3));
  const CliRun run = run_partslam("export-map " + quoted(cut) + " --out " + quoted(dir_ / "map.yaml"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("warning: " + cut.string() + ": the file ends mid-record after byte "));
  EXPECT_TRUE(fs::exists(dir_ / "map.yaml"));
  const CliRun whole = run_partslam("export-map " + quoted(write("whole.log", text_)) + " --out " +
                                    quoted(dir_ / "whole.yaml"));
  EXPECT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_THAT(whole.output, Not(HasSubstr("warning:")));
}

TEST_F(ScanInput, SubmapsRefusesAScanMovedThreeKilometresUnlessSkipDamaged) {
  // The 100th FLASER line moved 3 km in both pose slots: "FLASER n r1..rn x y theta odom_x odom_y odom_theta ...".
  std::size_t at = 0;
  for (int k = 0; k < 100; ++k) at = text_.find("\nFLASER ", at + 1);
  ASSERT_NE(at, std::string::npos);
  const std::size_t line = static_cast<std::size_t>(std::count(text_.begin(), text_.begin() + static_cast<long>(at), '\n')) + 2;
  const std::size_t end = text_.find('\n', at + 1);
  std::istringstream fields(text_.substr(at + 1, end - at - 1));
  std::vector<std::string> t;
  for (std::string f; fields >> f;) t.push_back(f);
  const std::size_t n = std::stoul(t[1]);
  t[2 + n] = std::to_string(std::stod(t[2 + n]) + 3000.0);
  t[5 + n] = std::to_string(std::stod(t[5 + n]) + 3000.0);
  std::string moved;
  for (const std::string& f : t) moved += (moved.empty() ? "" : " ") + f;
  const fs::path log = write("moved.log", text_.substr(0, at + 1) + moved + text_.substr(end));

  const CliRun refused = run_partslam("submaps " + quoted(log) + " --db " + quoted(dir_ / "maps.db"));
  EXPECT_NE(refused.exit_code, 0) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr(log.string() + ":" + std::to_string(line) + ": the scan's pose"));
  // The reader names LogReadOptions::skip_damaged; the command line names the flag that sets it.
  EXPECT_THAT(refused.output, HasSubstr("--skip-damaged skips such scans"));
  EXPECT_THAT(refused.output, Not(HasSubstr("skip_damaged")));

  const CliRun skipped = run_partslam("submaps " + quoted(log) + " --skip-damaged --db " + quoted(dir_ / "maps.db"));
  EXPECT_EQ(skipped.exit_code, 0) << skipped.output;
  EXPECT_THAT(skipped.output,
              HasSubstr("warning: " + log.string() + ": skipped 1 scan(s) whose pose jumps (--skip-damaged); the first"));
}

}  // namespace
}  // namespace partslam
