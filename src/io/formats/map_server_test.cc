#include "io/formats/map_server.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

using testing::TempDir;
using testing::write_bytes;


// The error message of f(), or "" when it did not throw InputError.
template <typename F>
std::string error_of(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

GridMap small_map() {
  GridMap m;
  m.resolution = 0.05;
  m.origin = {-1.25, 3.5, 0.0};
  m.width = 3, m.height = 2;
  m.cells = {CellState::kOccupied, CellState::kFree, CellState::kUnknown,  // bottom row
             CellState::kFree, CellState::kFree, CellState::kOccupied};
  return m;
}

TEST(MapServer, WriteThenReadGivesTheSameMap) {
  TempDir dir;
  write_map_yaml(dir / "map.yaml", small_map());
  EXPECT_TRUE(std::filesystem::exists(dir / "map.pgm"));
  const GridMap m = read_map_yaml(dir / "map.yaml");
  EXPECT_EQ(m.width, 3);
  EXPECT_EQ(m.height, 2);
  EXPECT_DOUBLE_EQ(m.resolution, 0.05);
  EXPECT_DOUBLE_EQ(m.origin.x, -1.25);
  EXPECT_DOUBLE_EQ(m.origin.y, 3.5);
  EXPECT_EQ(m.cells, small_map().cells);
}

// The image's name is quoted in map.yaml: a plain scalar would read "m: 2 #1.pgm" as a map and "#1.pgm" as a
// comment.
TEST(MapServer, NamesThatArePlainYamlElsewhereReadBack) {
  TempDir dir;
  for (const char* name : {"m: 2 #1.yaml", "#1.yaml", "a\"b\\c.yaml", "[x].yaml"}) {
    write_map_yaml(dir / name, small_map());
    EXPECT_EQ(read_map_yaml(dir / name).cells, small_map().cells) << name;
  }
}

// The image's first row is the top of the map; thresholds, negate and an ASCII PGM are honoured.
TEST(MapServer, ReadsThresholdsNegateAndAsciiPgm) {
  TempDir dir;
  write_bytes(dir / "m.pgm", "P2\n# comment\n3 2\n255\n0 128 255\n10 210 100\n");
  write_bytes(dir / "m.yaml", "image: m.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
                             "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  GridMap m = read_map_yaml(dir / "m.yaml");
  // Top row (0 128 255) is row 1: occupancy 1.0, 0.498, 0.0.
  EXPECT_EQ(m.at(0, 1), CellState::kOccupied);
  EXPECT_EQ(m.at(1, 1), CellState::kUnknown);
  EXPECT_EQ(m.at(2, 1), CellState::kFree);
  EXPECT_EQ(m.at(0, 0), CellState::kOccupied);  // 10: occupancy 0.96
  EXPECT_EQ(m.at(1, 0), CellState::kFree);      // 210: occupancy 0.18
  EXPECT_EQ(m.at(2, 0), CellState::kUnknown);   // 100: occupancy 0.61
  write_bytes(dir / "m.yaml", "image: m.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 1\n");
  m = read_map_yaml(dir / "m.yaml");
  EXPECT_EQ(m.at(0, 1), CellState::kFree);
  EXPECT_EQ(m.at(2, 1), CellState::kOccupied);
}

TEST(MapServer, BadInputNamesTheFileAndField) {
  TempDir dir;
  write_map_yaml(dir / "map.yaml", small_map());
  const auto yaml = dir / "bad.yaml";
  write_bytes(yaml, "image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("bad.yaml: field 'image'"), std::string::npos);
  write_bytes(yaml, "image: map.pgm\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("missing field 'resolution'"), std::string::npos);
  write_bytes(yaml, "image: map.pgm\nresolution: 0.05\norigin: [0, nan]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("'origin'"), std::string::npos);
  write_bytes(yaml, "image: map.pgm\nresolution: [1, 2]\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("line 2: field 'resolution'"), std::string::npos);
  write_bytes(yaml, "image: map.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n  : : bad\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("bad.yaml: line"), std::string::npos);
  EXPECT_NE(error_of([&] { read_map_yaml(dir / "none.yaml"); }).find("none.yaml: cannot open"), std::string::npos);
  // A PGM whose pixels stop short of its header's size, and one that is not a PGM at all.
  write_bytes(dir / "short.pgm", "P5\n10 10\n255\n" + std::string(42, '\0'));
  write_bytes(yaml, "image: short.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("short.pgm: truncated PGM"), std::string::npos);
  write_bytes(dir / "map.png", "\x89PNG\r\n");
  write_bytes(yaml, "image: map.png\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("not a PGM"), std::string::npos);
  // The image itself given as the map: said so, its bytes not printed.
  write_bytes(dir / "real.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16));
  EXPECT_NE(error_of([&] { read_map_yaml(dir / "real.png"); }).find("real.png: binary data, not a map YAML file"),
            std::string::npos);
  // Headers claiming far more pixels than the file holds are refused before the pixels are allocated (16384 x 16384
  // 16-bit pixels allocated 1.5 GB); an image that is not a regular file (a FIFO or /dev/zero would never end).
  write_bytes(dir / "huge.pgm", "P5 16384 16384 65535\n\x01\x02");
  write_bytes(yaml, "image: huge.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("huge.pgm: truncated PGM: the header says 16384 x 16384 pixels "
                                                        "(at least 536870913 bytes) but 3 bytes follow"),
            std::string::npos);
  write_bytes(dir / "huge2.pgm", "P2 16384 16384 255\n1 2 3\n");
  write_bytes(yaml, "image: huge2.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("huge2.pgm: truncated PGM"), std::string::npos);
  // A path the file system refuses is bad input too (a filesystem_error escaped: fuzz_map_server_yaml).
  write_bytes(yaml, "image: " + std::string(5000, 'a') + ".pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("File name too long"), std::string::npos);
  write_bytes(yaml, "image: /dev/zero\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("/dev/zero is not a regular file"), std::string::npos);
  // A map bigger than the extent limit.
  write_bytes(dir / "wide.pgm", "P5\n30000 1\n255\n" + std::string(30000, '\xfe'));
  write_bytes(yaml, "image: wide.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { read_map_yaml(yaml); }).find("spans more than"), std::string::npos);
}

TEST(MapServer, AFailedWriteLeavesNothingBehind) {
  TempDir dir;
  std::filesystem::create_directories(dir / "map.pgm");  // the image's name is taken by a folder
  EXPECT_THROW(write_map_yaml(dir / "map.yaml", small_map()), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "map.yaml"));
}

}  // namespace
}  // namespace partslam::io
