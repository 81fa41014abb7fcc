// The fields of every settings struct a settings file sets, listed once: each field's key, where it is and a
// line of help. The YAML reader and writer (config_file.cc: --config, --print-config) and the Python bindings
// (python/src) walk these tables, so a field added here is read, printed and bound alike, and one left out is
// none of these. A table is config_fields(v, std::type_identity<T>{}), which calls, for each field in order,
//   v.field(key, &T::member, help)             a value: bool, int, double or std::string
//   v.field(key, &T::member, &M::part, help)   a value inside a member struct, under a key of its own
//   v.section(key, &T::member, help)           a nested struct (its own table): a nested YAML map
#pragma once

#include <type_traits>

#include "core/evaluation/loop_evaluation.h"
#include "core/maps/submap.h"
#include "core/matching/dmm.h"
#include "core/matching/localizer.h"
#include "core/matching/scan_matcher.h"
#include "core/matching/tracker.h"
#include "core/matching/verification.h"
#include "core/slam/back_end.h"
#include "core/slam/front_end_config.h"
#include "core/slam/loop_closure.h"
#include "core/slam/map_check.h"
#include "core/slam/pose_graph.h"
#include "core/slam/slam.h"
#include "core/slam/submap_graph.h"

namespace partslam::io {

/// What `partslam loops` is set by: the loop closures, which are accepted, and how they are judged (the
/// truth's min_travel_gap is the loops' and has no key of its own).
/// `loops` reports the graph's poses of the consistent hypotheses (LoopClosureConfig::graph_pose).
inline LoopClosureConfig loops_command_defaults() {
  LoopClosureConfig c;
  c.graph_pose = true;
  return c;
}
struct LoopsConfig {
  LoopClosureConfig loops = loops_command_defaults();
  double min_confidence = 0.2;  ///< closures at least this confident are accepted
  LoopTruthConfig truth;
};

/// What `partslam locate` is set by: how the local map is built, how it is located, and how --track follows
/// the robot.
struct LocateConfig {
  SubmapConfig submaps;
  LocalizerConfig localizer;
  TrackerConfig tracker;
};

template <class V>
void config_fields(V& v, std::type_identity<ScanMatcherConfig>) {
  using C = ScanMatcherConfig;
  v.field("resolution", &C::resolution, "");
  v.field("sigma", &C::sigma, "");
  v.field("linear_window", &C::linear_window, "");
  v.field("angular_window", &C::angular_window, "");
  v.field("max_iterations", &C::max_iterations, "");
  v.field("num_threads", &C::num_threads, "");
}

template <class V>
void config_fields(V& v, std::type_identity<FrontEndConfig>) {
  using C = FrontEndConfig;
  v.section("matcher", &C::matcher, "");
  v.field("fine_sigma", &C::fine_sigma, "");
  v.field("max_range", &C::max_range, "");
  v.field("point_resolution", &C::point_resolution, "");
  v.field("local_map_scans", &C::local_map_scans, "");
  v.field("key_translation", &C::key_translation, "");
  v.field("key_rotation", &C::key_rotation, "");
  v.field("min_score", &C::min_score, "");
  v.field("degenerate_ratio", &C::degenerate_ratio, "");
  v.field("half_constrained_ratio", &C::half_constrained_ratio,
          "along a direction fixed below this share, a match moves no further than the odometry's recent error "
          "allows (0: off)");
  v.field("half_constrained_slack", &C::half_constrained_slack, "... times the root mean square of that error");
  v.field("scale_memory", &C::scale_memory,
          "the odometry's scale, learned on scans that fix both directions, over this much travel, predicts a bare "
          "corridor's axis (0: off) [m]");
  v.field("scale_ratio", &C::scale_ratio, "... on scans whose weaker direction holds at least this share");
  v.field("jump_turn", &C::jump_turn, "");
  v.field("second_prediction", &C::second_prediction, "");
  v.field("second_margin", &C::second_margin, "");
  v.field("wide_score", &C::wide_score, "a match scoring below this is searched again over every heading (0: off)");
  v.field("wide_window", &C::wide_window, "... and +- this translation [m]");
  v.field("wide_margin", &C::wide_margin, "... and kept when it scores this much higher");
  v.field("mirror_check", &C::mirror_check,
          "scans that turn against the odometry are matched again mirrored (a laser mounted upside down)");
}

template <class V>
void config_fields(V& v, std::type_identity<SubmapConfig>) {
  using C = SubmapConfig;
  v.field("window_length", &C::window_length, "L: travel covered by one submap [m]");
  v.field("spacing", &C::spacing, "travel between consecutive anchors [m]");
  v.field("resolution", &C::resolution, "downsampling cell [m]");
  v.field("crop_size", &C::crop_size, "side of the square crop around the centroid [m]");
  v.field("max_range", &C::max_range, "beam endpoints farther from the laser are dropped [m]");
  v.field("min_points", &C::min_points, "submaps with fewer points are dropped");
  v.field("align", &C::align, "rotate into the canonical Manhattan frame");
}

template <class V>
void config_fields(V& v, std::type_identity<ClosureConsistencyConfig>) {
  using C = ClosureConsistencyConfig;
  v.field("enabled", &C::enabled, "");
  v.field("offset", &C::offset, "");
  v.field("rate", &C::rate, "");
  v.field("turn", &C::turn, "");
  v.field("turn_rate", &C::turn_rate, "");
  v.field("max_chain", &C::max_chain, "");
  v.field("long_chain", &C::long_chain, "");
  v.field("long_factor", &C::long_factor, "");
  v.field("long_min_confidence", &C::long_min_confidence, "");
  v.field("long_alias_extent", &C::long_alias_extent, "");
}

template <class V>
void config_fields(V& v, std::type_identity<LoopClosureConfig>) {
  using C = LoopClosureConfig;
  v.field("method", &C::method, "");
  v.field("min_travel_gap", &C::min_travel_gap, "");
  v.field("other_place", &C::other_place, &OtherPlace::distance, "");
  v.field("min_score", &C::min_score, "");
  v.field("context", &C::context, "");
  v.field("drift_offset", &C::drift_offset, "");
  v.field("drift_rate", &C::drift_rate, "");
  v.field("drift_turn", &C::drift_turn, "");
  v.field("drift_turn_rate", &C::drift_turn_rate, "");
  v.field("gate_candidates", &C::gate_candidates, "");
  v.section("consistency", &C::consistency, "");
  v.field("graph_check", &C::graph_check, "");
  v.field("graph_pose", &C::graph_pose,
          "a consistent hypothesis reports the optimised graph's relative pose instead of its match's");
  v.field("verify_dmm", &C::verify_dmm, "");
  v.field("num_threads", &C::num_threads, "");
}

template <class V>
void config_fields(V& v, std::type_identity<SubmapGraphWeights>) {
  using C = SubmapGraphWeights;
  v.field("chain_translation", &C::chain_translation, "");
  v.field("chain_rotation", &C::chain_rotation, "");
  v.field("loop_translation", &C::loop_translation, "");
  v.field("loop_rotation", &C::loop_rotation, "");
}

template <class V>
void config_fields(V& v, std::type_identity<PoseGraphConfig>) {
  using C = PoseGraphConfig;
  v.field("robust_scale", &C::robust_scale, "");
  v.field("max_iterations", &C::max_iterations, "");
}

template <class V>
void config_fields(V& v, std::type_identity<BackEndConfig>) {
  using C = BackEndConfig;
  v.section("weights", &C::weights, "");
  v.section("graph", &C::graph, "");
  v.field("max_translation_residual", &C::max_translation_residual, "");
  v.field("max_rotation_residual", &C::max_rotation_residual, "");
  v.field("max_rounds", &C::max_rounds, "");
  v.field("max_rejected_share", &C::max_rejected_share, "");
  v.field("max_chain_translation", &C::max_chain_translation, "");
  v.field("max_chain_rotation", &C::max_chain_rotation, "");
}

template <class V>
void config_fields(V& v, std::type_identity<MapCheckConfig>) {
  using C = MapCheckConfig;
  v.field("resolution", &C::resolution, "");
  v.field("max_range", &C::max_range, "");
  v.field("key_spacing", &C::key_spacing, "");
  v.field("min_gap", &C::min_gap, "");
  v.field("end_margin", &C::end_margin, "");
  v.field("min_hits", &C::min_hits, "");
  v.field("own_cells", &C::own_cells, "");
  v.field("place_size", &C::place_size, "");
  v.field("min_place_beams", &C::min_place_beams, "");
  v.field("max_crossing_share", &C::max_crossing_share, "");
  v.field("max_place_share", &C::max_place_share, "");
  v.field("min_revisiting_beams", &C::min_revisiting_beams, "");
}

template <class V>
void config_fields(V& v, std::type_identity<ClosureRefinementConfig>) {
  using C = ClosureRefinementConfig;
  v.field("enabled", &C::enabled, "");
  v.field("context", &C::context, "");
  v.field("resolution", &C::resolution, "");
  v.field("sigma", &C::sigma, "");
  v.field("max_range", &C::max_range, "");
  v.field("linear_window", &C::linear_window, "");
  v.field("angular_window", &C::angular_window, "");
  v.field("max_points", &C::max_points, "");
  v.field("num_threads", &C::num_threads, "");
}

template <class V>
void config_fields(V& v, std::type_identity<NeighbourRefinementConfig>) {
  using C = NeighbourRefinementConfig;
  v.field("rounds", &C::rounds, "");
  v.field("window", &C::window, "");
  v.field("block", &C::block, "");
  v.field("sigma", &C::sigma, "");
  v.field("max_move", &C::max_move, "");
  v.field("num_threads", &C::num_threads, "");
}

template <class V>
void config_fields(V& v, std::type_identity<SecondOpinionConfig>) {
  using C = SecondOpinionConfig;
  v.field("enabled", &C::enabled, "");
  v.field("fine_sigma", &C::fine_sigma, "");
  v.field("window", &C::window, "");
  v.field("max_turn", &C::max_turn, "");
  v.field("max_shift", &C::max_shift, "");
}

template <class V>
void config_fields(V& v, std::type_identity<SlamConfig>) {
  using C = SlamConfig;
  v.section("front_end", &C::front_end, "");
  v.section("submaps", &C::submaps, "");
  v.section("loops", &C::loops, "");
  v.field("min_confidence", &C::min_confidence, "");
  v.section("refinement", &C::refinement, "");
  v.section("back_end", &C::back_end, "");
  v.section("map_check", &C::map_check, "");
  v.field("max_degenerate_share", &C::max_degenerate_share, "");
  v.section("neighbours", &C::neighbours, "");
  v.field("align_to_walls", &C::align_to_walls, "");
  v.section("second_opinion", &C::second_opinion, "");
}

template <class V>
void config_fields(V& v, std::type_identity<LoopTruthConfig>) {  // min_travel_gap: the loops' (LoopsConfig)
  using C = LoopTruthConfig;
  v.field("radius", &C::radius, "");
  v.field("max_translation_error", &C::max_translation_error, "");
  v.field("max_rotation_error", &C::max_rotation_error, "");
}

template <class V>
void config_fields(V& v, std::type_identity<LoopsConfig>) {
  using C = LoopsConfig;
  v.section("loops", &C::loops, "");
  v.field("min_confidence", &C::min_confidence, "");
  v.section("truth", &C::truth, "");
}

// extra_directions is no settings-file field: the localizer sets it from the building's walls.
template <class V>
void config_fields(V& v, std::type_identity<DmmConfig>) {
  using C = DmmConfig;
  v.field("resolution", &C::resolution, "grid cell and translation step [m]");
  v.field("linear_window", &C::linear_window,
          "translations |t_x|, |t_y| <= this [m]; <= 0: every translation at which the query overlaps the "
          "target");
  v.field("angular_window", &C::angular_window,
          "canonical: residual +- this about each multiple of 90 deg [rad]");
  v.field("angular_step", &C::angular_step, "rotation step [rad]; 0: one cell at the far point");
  v.field("canonical", &C::canonical,
          "both maps are in the canonical frame (turns x residual); false: full circle");
  v.field("canonical_turns", &C::canonical_turns,
          "canonical: rotation families, 4 (multiples of 90 deg) or 8 (of 45 deg)");
  v.field("extra_window", &C::extra_window, "residual about each extra direction [rad]");
  v.field("dilation", &C::dilation, "target cells within this many cells are occupied");
  v.field("search_depth", &C::search_depth, "branch-and-bound depth; 0: automatic");
}

template <class V>
void config_fields(V& v, std::type_identity<VerifyConfig>) {
  using C = VerifyConfig;
  v.field("resolution", &C::resolution, "cell of the free-space grid [m]");
  v.field("dilation", &C::dilation, "occupied cells grown by this many cells [cells]");
  v.field("max_ray", &C::max_ray, "beams longer than this are not cast [m]");
  v.field("refine_window", &C::refine_window, "the refinement searches +- this around the pose [m]");
  v.field("refine_angle", &C::refine_angle, "... and +- this in rotation [rad]");
  v.field("alternatives", &C::alternatives, "next-best distinct poses of Eq. 1 verified besides its optimum");
  v.field("alternative_bar", &C::alternative_bar, "an alternative reaches this share of the optimum's score");
  v.field("alternative_distance", &C::alternative_distance, "distinct: translations this far apart [m]");
  v.field("alternative_angle", &C::alternative_angle, "... or rotations this far apart [rad]");
  v.field("refined", &C::refined, "the most probable this many poses are refined");
  v.field("corner_radius", &C::corner_radius,
          "a point's cornerness is read off its neighbours within this [m]");
  v.field("keep_along_ratio", &C::keep_along_ratio,
          "the refinement keeps the translation along a direction the query's walls do not fix (weaker / stronger "
          "below this; 0: off) ...");
  v.field("keep_along_slack", &C::keep_along_slack, "... within this of the input pose's [m]");
}

template <class V>
void config_fields(V& v, std::type_identity<LocalizerConfig>) {
  using C = LocalizerConfig;
  v.section("dmm", &C::dmm, "the global search");
  v.section("verify", &C::verify, "the verification of the best candidates");
  v.field("elsewhere_distance", &C::elsewhere, &OtherPlace::distance,
          "the confidence's other place: the local map's centre at least this far away [m] ...");
  v.field("elsewhere_angle", &C::elsewhere, &OtherPlace::angle, "... or turned by more than this [rad]");
  v.field("candidate_distance", &C::candidate_distance,
          "the search's candidates lie at least this far apart [m], at most elsewhere_distance");
  v.field("candidates", &C::candidates, "distinct poses examined");
  v.field("free_weight", &C::free_weight, "inliers a point on the map's free space costs");
  v.field("neighbourhood", &C::neighbourhood,
          "the verification's map: the local map's box grown by this [m]");
  v.field("wall_direction_share", &C::wall_direction_share,
          "wall directions off the axes holding this share of the walls are searched too; 0: none");
  v.field("wall_direction_length", &C::wall_direction_length, "... and at least this length of wall [m]");
  v.field("verified", &C::verified,
          "the best-scoring candidates verified; the most probable of them is the answer");
  v.field("restart_distance", &C::restart_distance,
          "the answer is verified again from starts this far from it along each axis [m]; 0: not");
}

template <class V>
void config_fields(V& v, std::type_identity<TrackerConfig>) {
  using C = TrackerConfig;
  v.field("hypotheses", &C::hypotheses, "the global search's distinct poses taken per search");
  v.field("search_verified", &C::search_verified, "the global search's best candidates verified to find them");
  v.field("max_hypotheses", &C::max_hypotheses, "hypotheses kept at most");
  v.field("track_window", &C::track_window, "a carried hypothesis is refined within +- this [m] ...");
  v.field("track_angle", &C::track_angle, "... and +- this [rad]");
  v.field("merge_distance", &C::merge_distance, "hypotheses this close [m] ...");
  v.field("merge_angle", &C::merge_angle, "... and turned by no more than this are one [rad]");
  v.field("floor_probability", &C::floor_probability, "a step weighs a hypothesis by its probability, at least this");
  v.field("other_probability", &C::other_probability, "the none-of-these weight's factor per step");
  v.field("declare_share", &C::declare_share, "share of the weight that declares a hypothesis ...");
  v.field("declare_steps", &C::declare_steps, "... on this many consecutive steps");
  v.field("lost_probability", &C::lost_probability, "the declared one's probability below this ...");
  v.field("lost_steps", &C::lost_steps, "... on this many consecutive steps: lost");
  v.field("drop_share", &C::drop_share, "hypotheses below this share of the heaviest are dropped");
  v.field("min_seen", &C::min_seen, "a hypothesis is weighed when the map saw this share of the local map there");
  v.field("move_gain", &C::move_gain,
          "a match moving a hypothesis beyond claim_shift is taken only when this many times as probable");
  v.field("declare_probability", &C::declare_probability,
          "a hypothesis counts towards being declared only on steps with this probability");
  v.field("search_every", &C::search_every, "while not localised, the global search runs every this many steps");
  v.field("search_budget", &C::search_budget,
          "the global search's work per step (DmmSearch::next's budget, about a millisecond per million); a "
          "longer search goes on over the next steps; 0: each search within its step");
  v.field("search_min_share", &C::search_min_share,
          "the global search looks for candidates with more than this share of the best one's inliers only");
  v.field("min_none_share", &C::min_none_share, "the none weight's share never falls below this");
  v.field("weighed_back", &C::weighed_back,
          "a newborn hypothesis is also weighed on this many earlier local maps (against the rivals carried then)");
  v.field("corridor_ratio", &C::corridor_ratio,
          "a carried hypothesis's match moves it at most corridor_slack along a direction the local map's walls do "
          "not fix (weaker / stronger below this; 0: off)");
  v.field("corridor_slack", &C::corridor_slack, "... [m]");
  v.field("claim_shift_distance", &C::claim_shift, &PoseTolerance::translation,
          "no claim on a step whose match moved the declared pose further than this from the odometry's [m] ...");
  v.field("claim_shift_angle", &C::claim_shift, &PoseTolerance::rotation, "... or turned it more than this [rad]");
}

template <class V>
void config_fields(V& v, std::type_identity<LocateConfig>) {
  using C = LocateConfig;
  v.section("submaps", &C::submaps, "");
  v.section("localizer", &C::localizer, "");
  v.section("tracker", &C::tracker, "locate --track");
}

}  // namespace partslam::io
