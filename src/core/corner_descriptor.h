// Corner constellations as a succinct map descriptor (ours; docs/NOTES.md, "The succinct matcher"). A stored
// map keeps the positions of its C strongest corners (core/cpd.h find_corners: where walls meet) in its
// canonical frame, 7 + 7 bits each at 0.1 m inside the 12.8 m crop: C = 9 is 126 bits. A query keeps all its
// corners at full precision (the local map is at hand). Two maps of the same place see the same corners up
// to a quarter turn and a translation, so the score of a pair is the largest number of stored corners that
// one (turn, translation) puts within `tolerance` of a query corner; the translation hypotheses come from
// pairing a query corner with a stored one (|t| <= max_translation).
#pragma once

#include <vector>

#include "core/types.h"

namespace partslam {

struct CornerConfig {
  int stored_corners = 9;        ///< C: corners kept per stored map (14 bits each)
  int query_corners = 24;        ///< corners of the query
  double corner_radius = 0.8;    ///< neighbourhood of the corner response [m] (find_corners)
  double corner_spacing = 1.0;   ///< kept corners are at least this far apart [m]
  double tolerance = 0.3;        ///< a stored corner matches a query corner this close [m]
  double max_translation = 3.0;  ///< translation hypotheses up to this long [m]
  double quantum = 0.1;          ///< stored corner coordinates are snapped to this step [m]
};

/// Throws InputError naming the offending field.
void validate(const CornerConfig& config);

/// The stored corners of a map (quantised), strongest first.
Points2 stored_corners(const Points2& points, const CornerConfig& config);

/// The query's corners, strongest first.
Points2 query_corners(const Points2& points, const CornerConfig& config);

/// Largest number of stored corners matched under one quarter turn and translation of the query corners.
int match_corners(const Points2& query, const Points2& stored, const CornerConfig& config);

}  // namespace partslam
