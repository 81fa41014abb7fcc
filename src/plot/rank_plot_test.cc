#include "plot/rank_plot.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"

namespace partslam::plot {
namespace {

TEST(RankPlot, WritesAPng) {
  const auto path = std::filesystem::temp_directory_path() / "rank_plot_test.png";
  std::filesystem::remove(path);
  write_rank_plot(path, "test", {{"a", {0.01, 0.2, 0.5}}, {"b", {0.3, 0.9}}});
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
}

TEST(RankPlot, UnwritablePathThrowsAndLeavesNothing) {
  EXPECT_THROW(write_rank_plot("/nonexistent-dir/plot.png", "t", {}), InputError);
}

}  // namespace
}  // namespace partslam::plot
