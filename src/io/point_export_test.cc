#include "io/point_export.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.h"

namespace partslam::io {
namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
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
  EXPECT_THROW(parse_point_format("xyz"), InputError);
  EXPECT_THROW(write_points("/nonexistent-dir/x.csv", {}, PointFormat::kCsv), InputError);
}

}  // namespace
}  // namespace partslam::io
