// The paper's Fig. E as a PNG (cairo): what a map's parts are. Top panel: the map's points (canonical frame)
// with the keypoint box of every part, one colour per part. Optional bottom panel: the dictionary map's
// points with the matching descriptor boxes in the same colours, and each part's cropped points carried onto
// its descriptor box (turned by the part's quarter turns about the box centre), so the fit can be judged by
// eye. Parts are numbered best appearance score (AS, Eq. 2) first; the label gives the AS.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/parts/part.h"

namespace partslam::plot {

struct PartsFigure {
  std::string map_title;    ///< caption of the top panel
  Points2 map_points;       ///< the map's points, map frame [m]
  std::vector<Part> parts;  ///< keypoint boxes in the map frame, descriptor boxes in the dictionary frame
  bool show_scores = true;  ///< label the parts with their AS (false when the AS is not known)
  bool show_dictionary = false;  ///< draw the bottom panel
  std::string dictionary_title;  ///< caption of the bottom panel
  Points2 dictionary_points;     ///< the dictionary's points, dictionary frame [m]
};

struct RenderConfig {
  int width = 1000;                 ///< image width [px]
  int map_panel_height = 620;       ///< height of the top panel [px]
  int max_dictionary_height = 900;  ///< the bottom panel keeps the dictionary's aspect up to this height [px]
  double point_radius = 1.6;        ///< radius of a drawn point [px]
  double box_line_width = 2.5;      ///< [px]
};

/// Throws InputError naming the offending field.
void validate(const RenderConfig& config);

/// Writes the figure atomically (temporary sibling, then rename); throws InputError naming the path when it
/// cannot be written, leaving nothing behind.
void write_parts_figure(const std::filesystem::path& path, const PartsFigure& figure,
                        const RenderConfig& config = {});

}  // namespace partslam::plot
