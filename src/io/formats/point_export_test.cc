#include "io/formats/point_export.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The error reading a file of this content gives (at most 10 points), or "no error".
std::string read_error(const testing::TempDir& dir, const std::string& name, const std::string& content) {
  testing::write_bytes(dir / name, content);
  try {
    read_point_file(dir / name, 10);
  } catch (const InputError& e) {
    return std::string(e.what());
  }
  return std::string("no error");
}

TEST(PointExport, WritesCsvAndPly) {
  const auto dir = std::filesystem::temp_directory_path();
  const Points2 pts{{1.0, 2.0}, {-0.5, 0.25}};
  write_points(dir / "pe.csv", pts, PointFormat::kCsv);
  EXPECT_EQ(slurp(dir / "pe.csv"), "x,y\n1.000000,2.000000\n-0.500000,0.250000\n");
  write_points(dir / "pe.ply", pts, PointFormat::kPly);
  const std::string ply = slurp(dir / "pe.ply");
  EXPECT_NE(ply.find("element vertex 2"), std::string::npos);
  EXPECT_NE(ply.find("-0.500000 0.250000 0"), std::string::npos);
}

TEST(PointExport, RejectsUnknownFormatAndUnwritablePath) {
  try {
    parse_point_format("xyz");
    ADD_FAILURE() << "no error for format xyz";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "point format: expected ply or csv, got 'xyz'");  // the library's words, no CLI flag
  }
  EXPECT_THROW(write_points("/nonexistent-dir/x.csv", {}, PointFormat::kCsv), InputError);
}

TEST(PointFiles, ReadBackWhatWasWritten) {
  testing::TempDir dir;
  const Points2 pts{{1.0, 2.0}, {-0.5, 0.25}, {3.125, -7.5}};
  for (const char* name : {"p.csv", "p.ply"}) {
    write_points(dir / name, pts, std::string(name).ends_with(".ply") ? PointFormat::kPly : PointFormat::kCsv);
    EXPECT_EQ(read_points(dir / name), pts) << name;
  }
  // Another tool's PLY: other properties first, comments, CRLF-free; and a CSV without header, extra columns.
  testing::write_bytes(dir / "o.ply", "ply\nformat ascii 1.0\ncomment x\nelement vertex 2\nproperty float intensity\n"
                                      "property float x\nproperty float y\nend_header\n9 1 2\n9 3 4\n");
  EXPECT_EQ(read_points(dir / "o.ply"), (Points2{{1.0, 2.0}, {3.0, 4.0}}));
  testing::write_bytes(dir / "o.csv", "1,2,7\n3, 4 ,8\n");
  EXPECT_EQ(read_points(dir / "o.csv"), (Points2{{1.0, 2.0}, {3.0, 4.0}}));
}

// A file written in a map frame names that frame's pose in the world frame, to every digit, in either format;
// a file without it has none. A CSV header may follow comment lines.
TEST(PointFiles, TheFramesPoseRoundTrips) {
  testing::TempDir dir;
  const Points2 pts{{1.0, 2.0}, {-0.5, 0.25}};
  const Pose2 T{12.345678901234567, -0.1, 0.7853981633974483};
  for (const char* name : {"f.csv", "f.ply"}) {
    write_points(dir / name, pts, std::string(name).ends_with(".ply") ? PointFormat::kPly : PointFormat::kCsv, T);
    const PointFile file = read_point_file(dir / name);
    EXPECT_EQ(file.points, pts) << name;
    ASSERT_TRUE(file.T_world_points) << name;
    EXPECT_EQ(file.T_world_points->x, T.x) << name;
    EXPECT_EQ(file.T_world_points->y, T.y) << name;
    EXPECT_EQ(file.T_world_points->theta, T.theta) << name;
    EXPECT_EQ(read_points(dir / name), pts) << name;
  }
  write_points(dir / "n.csv", pts, PointFormat::kCsv);
  EXPECT_FALSE(read_point_file(dir / "n.csv").T_world_points);
  testing::write_bytes(dir / "h.csv", "# a comment\n\nx,y\n1,2\n");
  EXPECT_EQ(read_points(dir / "h.csv"), (Points2{{1.0, 2.0}}));
  testing::write_bytes(dir / "bad.csv", "# T_world_points 1 2\nx,y\n1,2\n");
  EXPECT_THROW(read_point_file(dir / "bad.csv"), InputError);
  testing::write_bytes(dir / "bad.ply", "ply\nformat ascii 1.0\ncomment T_world_points 1 nan 0\nelement vertex 1\n"
                                        "property float x\nproperty float y\nend_header\n1 2\n");
  EXPECT_THROW(read_point_file(dir / "bad.ply"), InputError);
}

// A stored map's laser origins go with its points, in either format and frame; another tool's PLY with more
// elements (faces) is read for its vertices; a malformed or truncated origin names the line.
TEST(PointFiles, LaserOriginsRoundTrip) {
  testing::TempDir dir;
  const Points2 pts{{1.0, 2.0}, {-0.5, 0.25}}, origins{{0.5, -1.25}, {0.75, -1.0}, {1.0, -0.75}};
  const Pose2 T{3.0, -4.0, 0.5};
  for (const char* name : {"o.csv", "o.ply"}) {
    write_points(dir / name, pts, std::string(name).ends_with(".ply") ? PointFormat::kPly : PointFormat::kCsv,
                 T, origins);
    const PointFile file = read_point_file(dir / name);
    EXPECT_EQ(file.points, pts) << name;
    EXPECT_EQ(file.laser_origins, origins) << name;
    ASSERT_TRUE(file.T_world_points) << name;
    EXPECT_EQ(file.T_world_points->x, T.x) << name;
  }
  write_points(dir / "bare.csv", pts, PointFormat::kCsv);
  EXPECT_TRUE(read_point_file(dir / "bare.csv").laser_origins.empty());
  testing::write_bytes(dir / "faces.ply",
                       "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                       "element face 1\nproperty list uchar int vertex_indices\n"
                       "element laser_origin 1\nproperty float x\nproperty float y\nend_header\n"
                       "1 2\n3 4\n2 0 1\n5 6\n");
  const PointFile faces = read_point_file(dir / "faces.ply");
  EXPECT_EQ(faces.points, (Points2{{1.0, 2.0}, {3.0, 4.0}}));
  EXPECT_EQ(faces.laser_origins, (Points2{{5.0, 6.0}}));
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n";
  const std::vector<std::array<std::string, 3>> bad = {
      // file, content, what the error says
      {"a.csv", "# laser_origin 1\n1,2\n", "a.csv:1: laser_origin: expected x y"},
      {"b.csv", "# laser_origin 1 inf\n1,2\n", "b.csv:1: laser_origin y: not finite"},
      {"c.ply", ply + "element laser_origin 2\nproperty float x\nproperty float y\nend_header\n1 2\n3 4\n",
       "c.ply:11: truncated: 1 of 2 laser_origin rows"},
      {"d.ply", ply + "element laser_origin 1\nproperty float x\nend_header\n1 2\n3\n", "lacks x or y"},
      {"e.ply", ply + "element laser_origin 11\nproperty float x\nproperty float y\nend_header\n1 2\n",
       "11 laser origins is more than 10"}};
  for (const auto& [name, content, what] : bad)
    EXPECT_THAT(read_error(dir, name, content), ::testing::HasSubstr(what)) << name;
}

TEST(PointFiles, BadFilesNameTheFileAndLine) {
  testing::TempDir dir;
  const auto error = [&](const std::string& name, const std::string& content) {
    return read_error(dir, name, content);
  };
  EXPECT_NE(error("a.csv", "x,y\n").find("a.csv: no points"), std::string::npos);
  EXPECT_NE(error("b.csv", "x,y\n1,2\nnan,3\n").find("b.csv:3: x: not finite"), std::string::npos);
  EXPECT_NE(error("c.csv", "1,2\n1;2\n").find("c.csv:2: expected x,y"), std::string::npos);
  EXPECT_NE(error("d.csv", std::string(11 * 4, ' ').replace(0, 44, "1,1\n1,1\n1,1\n1,1\n1,1\n1,1\n1,1\n1,1\n1,1\n1,1\n1,1\n"))
                .find("more than 10 points"), std::string::npos);
  EXPECT_NE(error("e.ply", "ply\nformat binary_little_endian 1.0\n").find("e.ply:2: only ASCII"), std::string::npos);
  EXPECT_NE(error("f.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n1 2\n")
                .find("truncated: 1 of 3"), std::string::npos);
  EXPECT_NE(error("g.ply", "ply\nformat ascii 1.0\nelement vertex 1\n").find("no end_header"), std::string::npos);
  EXPECT_NE(error("h.txt", "1,2\n").find("unknown point file type"), std::string::npos);
  // Vertex counts that are not whole numbers (fuzz_points: 1e300 was cast to long, undefined behaviour).
  for (const char* bad : {"1e300", "-1e300", "2.5", "-3", "nan", "99999999999999999999"}) {
    EXPECT_NE(error("i.ply", std::string("ply\nformat ascii 1.0\nelement vertex ") + bad +
                                 "\nproperty float x\nproperty float y\nend_header\n1 2\n")
                  .find("i.ply:3: element vertex: not a whole number"),
              std::string::npos)
        << bad;
  }
  EXPECT_NE(error("j.ply", "ply\nformat ascii 1.0\nelement vertex 4611686018427387904\nproperty float x\n"
                           "property float y\nend_header\n")
                .find("vertices is more than 10"),
            std::string::npos);
  EXPECT_THROW(read_points(dir / "missing.csv"), InputError);
}

}  // namespace
}  // namespace partslam::io
