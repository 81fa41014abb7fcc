// The grid descriptors' ranker, for callers that set a GridConfig field no spec names (e.g. index_min_maps).
#pragma once

#include <memory>

#include "core/matching/grid_descriptor.h"
#include "core/ranking/ranking.h"

namespace partslam {

/// The ranker of a configuration (what `grid` and `succinct` make through make_ranker).
std::unique_ptr<Ranker> make_grid_ranker(const GridConfig& config);

}  // namespace partslam
