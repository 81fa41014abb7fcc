#include "core/slam/back_end.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"

namespace partslam {
namespace {

// |translation| and |rotation| of the error between a measured relative pose and the solved frames'.
std::pair<double, double> residual(const Pose2& measured, const Pose2& from, const Pose2& to) {
  const Pose2 E = measured.inverse() * (from.inverse() * to);
  return {E.translation().norm(), std::abs(wrap_angle(E.theta))};
}

}  // namespace

void validate(const BackEndConfig& c) {
  validate_nested("back end config", "weights", [&] { validate(c.weights); });
  validate_nested("back end config", "graph", [&] { validate(c.graph); });
  const std::pair<double, const char*> positive[] = {
      {c.max_translation_residual, "max_translation_residual"}, {c.max_rotation_residual, "max_rotation_residual"},
      {c.max_chain_translation, "max_chain_translation"},       {c.max_chain_rotation, "max_chain_rotation"}};
  for (const auto& [v, name] : positive)
    if (!(v > 0) || !std::isfinite(v)) throw InputError(std::string("back end config: ") + name + " must be positive");
  if (c.max_rounds < 1 || c.max_rounds > 100) throw InputError("back end config: max_rounds must be in [1, 100]");
  if (!(c.max_rejected_share >= 0 && c.max_rejected_share <= 1))
    throw InputError("back end config: max_rejected_share must be in [0, 1]");
}

BackEndResult solve_back_end(const Submaps& maps, const std::vector<LoopClosure>& closures, const BackEndConfig& c) {
  validate(c);
  BackEndResult r;
  r.used.assign(closures.size(), true);
  const auto selected = [&] {
    std::vector<LoopClosure> out;
    for (std::size_t k = 0; k < closures.size(); ++k)
      if (r.used[k]) out.push_back(closures[k]);
    return out;
  };
  const double factors[] = {4, 2, 1};
  for (int round = 0; round < c.max_rounds; ++round) {
    r.frames = optimize_submap_graph(maps, selected(), c.weights, c.graph, &r.graph);
    r.rounds = round + 1;
    const double f = factors[std::min<std::size_t>(static_cast<std::size_t>(round), 2)];
    bool changed = false;
    for (std::size_t k = 0; k < closures.size(); ++k) {
      const LoopClosure& l = closures[k];
      const auto [t, a] = residual(l.T_match_query, r.frames[l.match], r.frames[l.query]);
      const bool agrees = t <= f * c.max_translation_residual && a <= f * c.max_rotation_residual;
      if (agrees != r.used[k]) changed = true;
      r.used[k] = agrees;
    }
    if (!changed && round >= 2) break;
  }
  // The last solve may predate the last change of sides: solve once more with the final set.
  r.frames = optimize_submap_graph(maps, selected(), c.weights, c.graph, &r.graph);
  r.used_count = static_cast<std::size_t>(std::count(r.used.begin(), r.used.end(), true));
  r.rejected = closures.size() - r.used_count;

  for (std::size_t i = 1; i < maps.size(); ++i) {
    const Pose2 chain = maps[i - 1].T_world_map.inverse() * maps[i].T_world_map;
    const auto [t, a] = residual(chain, r.frames[i - 1], r.frames[i]);
    r.max_chain_translation = std::max(r.max_chain_translation, t);
    r.max_chain_rotation = std::max(r.max_chain_rotation, a);
    r.chain_bends += t > c.max_chain_translation || a > c.max_chain_rotation;
  }
  std::ostringstream why;
  if (r.used_count == 0) {
    // Nothing closed (none accepted, or none agreed): the front end's frames.
    for (std::size_t i = 0; i < maps.size(); ++i) r.frames[i] = maps[i].T_world_map;
    r.chain_bends = 0, r.max_chain_translation = 0, r.max_chain_rotation = 0;
    r.verdict = closures.empty() ? "open" : "front end";
    if (!closures.empty()) why << "none of the " << closures.size() << " closures agreed with the others";
  } else if (static_cast<double>(r.rejected) > c.max_rejected_share * static_cast<double>(closures.size())) {
    r.verdict = "doubtful";
    why << r.rejected << " of " << closures.size() << " closures disagreed with the solution";
  } else if (r.chain_bends > 0) {
    r.verdict = "doubtful";
    why << "the closures bend the front end's trajectory at " << r.chain_bends << " place(s), by up to "
        << r.max_chain_translation << " m / " << r.max_chain_rotation << " rad between consecutive submaps";
  } else {
    r.verdict = "closed";
  }
  // What the closures say is doubted: the front end's chain, which they could not be made to agree with, is the
  // map to vouch for (on the bench, every run whose closures were doubted this way had a better front end than
  // solution: docs/NOTES.md, "The front end's chain when the closures are doubted").
  if (r.verdict != "closed" && r.verdict != "open") {
    r.front_end_written = true;
    for (std::size_t i = 0; i < maps.size(); ++i) r.frames[i] = maps[i].T_world_map;
  }
  r.reason = why.str();
  return r;
}

}  // namespace partslam
