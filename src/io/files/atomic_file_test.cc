#include "io/files/atomic_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <stdexcept>

#include "core/error.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::read_bytes;
using testing::TempDir;
using testing::write_bytes;

void write_text(const fs::path& path, const std::string& text) {
  write_atomically(path, [&](std::ostream& out) { out << text; });
}

TEST(AtomicFile, ReplacesTheFileAndLeavesNothingBesideIt) {
  TempDir dir;
  write_bytes(dir / "out.json", "old");
  write_text(dir / "out.json", "new");
  EXPECT_EQ(read_bytes(dir / "out.json"), "new");
  // A writer that fails leaves the old file and no temporary file.
  EXPECT_THROW(write_atomically(dir / "out.json",
                                [](std::ostream& out) {
                                  out << "half";
                                  throw InputError("the writer failed");
                                }),
               InputError);
  EXPECT_EQ(read_bytes(dir / "out.json"), "new");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / ""), fs::directory_iterator()), 1);
}

TEST(AtomicFile, WritesThroughASymbolicLinkAndKeepsTheLink) {
  TempDir dir;
  fs::create_directories(dir / "data");
  write_bytes(dir / "data/target.csv", "old");
  fs::create_symlink("data/target.csv", dir / "link.csv");
  write_text(dir / "link.csv", "new");
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_EQ(read_bytes(dir / "data/target.csv"), "new");
  // A dangling link: the file it names is created.
  fs::create_symlink("data/later.csv", dir / "dangling.csv");
  write_text(dir / "dangling.csv", "made");
  EXPECT_TRUE(fs::is_symlink(dir / "dangling.csv"));
  EXPECT_EQ(read_bytes(dir / "data/later.csv"), "made");
  // Commits by name (the PNG and SQLite writers') go through the link too.
  write_bytes(dir / "data/picture.png", "old");
  fs::create_symlink("data/picture.png", dir / "picture.png");
  const fs::path tmp = temporary_sibling(dir / "picture.png");
  EXPECT_EQ(tmp.parent_path(), dir / "data");
  write_bytes(tmp, "png");
  commit_temporary(tmp, dir / "picture.png");
  EXPECT_TRUE(fs::is_symlink(dir / "picture.png"));
  EXPECT_EQ(read_bytes(dir / "data/picture.png"), "png");
}

TEST(AtomicFile, WritesADeviceOrAFifoInPlace) {
  // /dev/null stays a device: the old writer renamed a regular file over it (as root, it could).
  write_text("/dev/null", "discarded");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  const fs::path tmp = temporary_sibling("/dev/null");
  write_bytes(tmp, "png");
  commit_temporary(tmp, "/dev/null");
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_FALSE(fs::exists(tmp));
  // A device that takes no bytes is an error naming it, not a success.
  if (fs::is_character_file("/dev/full")) {
    try {
      write_text("/dev/full", std::string(1 << 16, 'x'));
      ADD_FAILURE() << "no error writing /dev/full";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("/dev/full"));
    }
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
  }
  // A FIFO stays a FIFO (opened for reading and writing here, so that nothing blocks).
  TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  EXPECT_NO_THROW(check_writable(dir / "pipe"));
  EXPECT_TRUE(fs::is_fifo(dir / "pipe"));
}

TEST(AtomicFile, RefusesADashAndAFolder) {
  TempDir dir;
  try {
    write_text("-", "x");
    ADD_FAILURE() << "'-' accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/dev/stdout"));
  }
  EXPECT_FALSE(fs::exists("-"));
  EXPECT_THROW(check_writable(dir / ""), InputError);
  EXPECT_THROW(check_writable(dir / "missing/out.json"), InputError);
}

TEST(AtomicFile, AnOutputThatIsAnInputOrAnotherOutputIsRefusedBeforeAnyWork) {
  TempDir dir;
  write_bytes(dir / "maps.db", "db");
  fs::create_symlink("maps.db", dir / "alias.db");
  const auto refused = [](const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs,
                          const std::string& says) {
    try {
      check_outputs(outputs, inputs);
      ADD_FAILURE() << "accepted; expected: " << says;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(says));
    }
  };
  refused({{"--json", dir / "maps.db"}}, {{"DB", dir / "maps.db"}}, "--json is the file DB reads");
  refused({{"--out", dir / "alias.db"}}, {{"DB", dir / "maps.db"}}, "--out is the file DB reads");
  refused({{"--json", dir / "maps.db"}}, {{"DB", dir / "alias.db"}}, "--json is the file DB reads");
  // Two outputs naming one file, whether it exists yet or not.
  refused({{"--db", dir / "new.db"}, {"--json", dir / "./new.db"}}, {}, "given both as --db and as --json");
  refused({{"--json", dir / "maps.db"}, {"--plot", dir / "alias.db"}}, {},
          "given both as --json and as --plot");
  EXPECT_EQ(read_bytes(dir / "maps.db"), "db");
  // Apart, and the ones not given, are fine.
  EXPECT_NO_THROW(check_outputs({{"--json", dir / "out.json"}, {"--plot", ""}, {"--g2o", dir / "out.g2o"}},
                                {{"DB", dir / "maps.db"}, {"--raw", ""}}));
}

}  // namespace
}  // namespace partslam::io
