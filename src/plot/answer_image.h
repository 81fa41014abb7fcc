// Pictures of an answer, for a person to judge at a glance: panels side by side, each a building map (an
// occupancy grid, drawn in its own frame; optional) with point sets and a path drawn over it in the same frame,
// north up, one scale per panel, a title above. `locate --plot` draws the query's points where they were found in
// the building map (or the located trajectory, with --every); `match --plot` draws each of the best stored maps
// with the query's points at the found pose.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/maps/grid_map.h"
#include "core/types.h"

namespace partslam::plot {

struct Rgb {
  double r = 0, g = 0, b = 0;
};

inline constexpr Rgb kMapGrey{0.35, 0.35, 0.35};  ///< a stored map's points
inline constexpr Rgb kGood{0.0, 0.62, 0.25};       ///< a confident answer
inline constexpr Rgb kDoubtful{0.90, 0.35, 0.0};   ///< an answer below the confidence threshold

struct PointLayer {
  Points2 points;  ///< in the panel's frame [m]
  Rgb colour;
  double radius = 1.5;  ///< [px]
};

struct Panel {
  std::string title;
  const GridMap* map = nullptr;  ///< drawn first when set (its frame is the panel's)
  std::vector<PointLayer> layers;
  std::vector<Vec2> path;         ///< a trajectory in the panel's frame, drawn as a line through dots
  std::vector<Rgb> path_colours;  ///< one per path point (the dot's colour); empty: kGood
  std::string legend;             ///< a line of small text at the panel's bottom right (what the colours mean)
  /// one per path point: whether a line joins it to the point before (the first's is ignored); empty: all joined
  std::vector<bool> path_joined;
};

/// Writes the panels side by side as a PNG, atomically, each panel_side pixels on its longer side and as its
/// drawing's aspect asks on the other (all as high as the highest), under its title. Throws
/// InputError for no panel, an invalid map, path_colours or path_joined of another length than path, a panel with
/// nothing to draw, or a PNG that cannot be written.
void write_panels_png(const std::filesystem::path& path, const std::vector<Panel>& panels, int panel_side = 800);

/// The points moved by T (e.g. a query's points into the map frame by T_map_query).
Points2 transformed(const Points2& points, const Pose2& T);

}  // namespace partslam::plot
