// The paper's Fig. D: cumulative histogram of the normalised rank, one curve per method, as a PNG (cairo).
// x: normalised rank [%] (0..100), y: share of tasks whose normalised rank is at most x.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace partslam::plot {

struct RankCurve {
  std::string label;
  std::vector<double> normalized_ranks;  ///< per task, in [0, 1]
};

/// Writes the plot atomically; throws InputError naming the path when it cannot be written.
void write_rank_plot(const std::filesystem::path& path, const std::string& title, const std::vector<RankCurve>& curves);

}  // namespace partslam::plot
