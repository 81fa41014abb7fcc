// Loop closures accepted as a consistent group (pairwise consistency maximisation, PCM: Mangelson et al.,
// ICRA 2018). Two closures a (query i in match j's frame) and b (query k in match l's frame) close a cycle
// through the front end's chain: Z_a^-1 * C(j, l) * Z_b * C(k, i), where C(u, v) is the stored relative pose
// of submaps u and v (locally consistent, drifting with the travel between them). When both closures are
// right the cycle is the identity up to the chain's drift; a wrong closure (an alias, a match slid along a
// corridor) breaks the cycle with every right closure near it. The largest set of closures that agree
// pairwise is kept: the complement of the consistency graph is sparse (far-apart closures cannot contradict
// each other through a long, loose chain), so the closure with the most disagreements is dropped until none
// disagree (a greedy vertex cover of the disagreements; ties drop the less confident closure). Then the same
// over the long cycles of the group kept, with a tolerance measured on them, dropping only what sees one place as
// another (long_chain).
#pragma once

#include <vector>

#include "core/maps/submap.h"
#include "core/slam/submap_graph.h"

namespace partslam {

struct ClosureConsistencyConfig {
  bool enabled = true;
  /// Two closures agree when their cycle's error is within offset + rate * chain [m] and turn + turn_rate *
  /// chain [rad], chain = the travel along the two chain segments of the cycle [m].
  double offset = 0.5;
  double rate = 0.01;
  double turn = 0.08;
  double turn_rate = 0.001;
  /// Cycles whose chain segments are longer than this are not tested (their tolerance covers any alias) [m].
  double max_chain = 100.0;
  /// Then the long cycles of the group kept (chain segments longer than max_chain, up to long_chain [m]) between
  /// its confident closures (at least long_min_confidence: those `slam` offers its back end) are tested with a rate
  /// measured on them: long_factor times the median of their translation errors per metre of chain, at least
  /// `rate`. A group of wrong closures that agree with each other (one alias seen from several submaps) breaks only
  /// long cycles with the right ones, by many times the front end's usual drift; a front end that drifts more than
  /// `rate` along a long corridor raises the rate with it. What that drops is kept again unless it sees one place:
  /// the dropped closures in stretches of their queries' travel (a gap over long_alias_extent [m] starts a new
  /// one), a stretch staying dropped only when its matches lie within long_alias_extent of each other. A stretch
  /// whose matches are spread over the building disagrees with every place it revisits: the front end's chain
  /// broken where no short cycle reaches (a heading lost in a spin), which the graph mends, not an alias
  /// (docs/NOTES.md, "Long cycles that drop only one place"). long_chain <= max_chain turns the long cycles off.
  double long_chain = 1000.0;
  double long_factor = 10.0;
  double long_min_confidence = 0.2;
  double long_alias_extent = 20.0;
};

/// Throws InputError naming the offending field when a value is out of range.
void validate(const ClosureConsistencyConfig& config);

/// True when closures a and b agree through the chain of `maps`' stored frames.
bool closures_agree(const Submaps& maps, const LoopClosure& a, const LoopClosure& b,
                    const ClosureConsistencyConfig& config = {});

/// Per closure: in the largest pairwise-consistent set found (greedy; the same answer for the same input).
/// The cycles are tested on num_threads; the answer does not depend on it.
std::vector<bool> consistent_closures(const Submaps& maps, const std::vector<LoopClosure>& closures,
                                      const ClosureConsistencyConfig& config = {}, int num_threads = 1);

}  // namespace partslam
