// Scan Context's ranker, for callers that set a ScanContextConfig field no spec names (e.g. the shortlist).
#pragma once

#include <memory>

#include "core/matching/scan_context.h"
#include "core/ranking/ranking.h"

namespace partslam {

/// The ranker of a configuration (what `sc` and `sc:128` make): score = -(column-shift distance) over the
/// ring-key shortlist, and kScanContextShortlistOut minus the ring-key distance for every candidate outside it
/// (below the shortlist, in ring-key order: a ranking orders every map, as rerank does below its top R).
std::unique_ptr<Ranker> make_scan_context_ranker(const ScanContextConfig& config);

}  // namespace partslam
