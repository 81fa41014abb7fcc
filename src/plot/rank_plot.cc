#include "plot/rank_plot.h"

#include <algorithm>

#include "plot/line_plot.h"

namespace partslam::plot {

void write_rank_plot(const std::filesystem::path& path, const std::string& title, const std::vector<RankCurve>& curves) {
  std::vector<Curve> steps;
  for (const RankCurve& c : curves) {  // one step curve per method: the cumulative histogram
    std::vector<double> r = c.normalized_ranks;
    std::sort(r.begin(), r.end());
    Curve s{c.label, {{0.0, 0.0}}};
    const double n = static_cast<double>(r.size());
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double x = std::clamp(r[i], 0.0, 1.0);
      s.points.emplace_back(x, i / n);
      s.points.emplace_back(x, (i + 1) / n);
    }
    if (!r.empty()) s.points.emplace_back(1.0, 1.0);
    steps.push_back(std::move(s));
  }
  write_line_plot(path, {title, "normalised rank [%]", "share of tasks", 100.0, 0}, steps);
}

}  // namespace partslam::plot
