// Descriptor matcher (paper §"Descriptor Matcher", Eqs. 3-6; docs/DESIGN.md "DM"): the likelihood that a local
// (query) map and a global (stored) map show the same place, from their descriptor boxes on the dictionary:
//   f_RS(Bl, Bg) = area(Bl ∩ Bg) / sqrt(area(Bl) area(Bg))                       (region similarity, Eq. 3)
//   Max-Max            F_MM  = max_i max_j f_RS(Bl_i, Bg_j)                          (Eq. 4)
//   Sum-Max            F_SM  = sum_i max_j f_RS(Bl_i, Bg_j)                          (Eq. 5)
//   Sum-Max-Weighted   F_SMW = sum_i max_j f_RS(Bl_i, Bg_j) * AS(Bl_i)               (Eq. 6)
// i runs over the query's parts, j over the stored map's parts; AS is the query part's appearance score.
// Origin gate (ours, not the paper's; origin_gate = 0 turns it off): a pair of parts counts only when the two
// parts put their maps' frame origins within origin_gate of each other on the dictionary (|dx|, |dy| <=
// origin_gate, see dictionary_origin in part.h). Maps of the same place have nearby frames (their centroids),
// so true part matches pass; chance overlaps of descriptor boxes mostly imply a far-off frame and are dropped.
// This file holds the reference (double precision, one pair at a time); descriptor_database.h scores a whole
// database with the same definitions on integer boxes, in blocks of maps.
#pragma once

#include <string_view>

#include "core/parts/part.h"

namespace partslam {

enum class Matcher { kMaxMax, kSumMax, kSumMaxWeighted };

/// The origin gate the CLI and the evaluation use unless told otherwise [m]: the relevant-pair radius R of the
/// protocol (docs/DESIGN.md). The library functions default to 0 (no gate, the paper's matcher).
inline constexpr double kDefaultOriginGate = 2.0;

/// "max-max", "sum-max" or "sum-max-weighted".
const char* to_string(Matcher matcher);
/// Inverse of to_string (also accepts "mm", "sm", "smw"); throws InputError naming the value otherwise.
Matcher matcher_from_string(std::string_view name);

/// f_RS (Eq. 3), in [0, 1]; 0 when either box is empty.
double region_similarity(const Box2& a, const Box2& b);

/// F_MM, F_SM or F_SMW between a query and a stored descriptor (Eqs. 4-6); 0 when either has no parts.
/// origin_gate [m]: see above; 0 = no gate (the paper's matcher).
double match_score(const MapDescriptor& query, const MapDescriptor& stored, Matcher matcher,
                   double origin_gate = 0.0);

/// True when origin_gate is 0 or the parts' dictionary origins are within origin_gate on both axes.
bool passes_origin_gate(const Part& query, const Part& stored, double origin_gate);

}  // namespace partslam
