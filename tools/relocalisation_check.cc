// relocalisation_check CORRECTED_LOG OUT_DIR [NAME=VALUE ...]: the relocalisation floors (core/evaluation/relocalisation.h).
// Maps the first visit of each place (scans before the first revisit) as a map_server map, writes it to
// OUT_DIR/first_visit.yaml + .pgm and reads it back (the round trip a user makes), then locates local maps of
// every later stretch of the log in it and prints: the share of queries with true overlap >= 30 % whose pose is
// within 0.3 m / 3 deg, the time per query (median, p95; one core), and how often a confident answer is wrong or a
// query outside the map is reported confidently.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "core/evaluation/relocalisation.h"
#include "io/formats/map_server.h"
#include "io/logs/scan_source.h"

using namespace partslam;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: relocalisation_check CORRECTED_LOG OUT_DIR [candidates=K turns=4|8 free_weight=W "
                 "elsewhere=M distinct=M restart=M window=M full_circle verified=K wall_share=S "
                 "refine_window=M confidence=C "
                 "probability=P]\n");
    return 2;
  }
  try {
    const Scans scans = io::load_scan_source(argv[1]).scans;
    RelocalisationConfig config;
    // Ablation settings (docs/NOTES.md, "Locate"): NAME=VALUE after the log.
    for (int a = 3; a < argc; ++a) {
      const std::string arg = argv[a];
      const std::size_t eq = arg.find('=');
      const std::string name = arg.substr(0, eq);
      const double value = eq == std::string::npos ? 0.0 : std::atof(arg.c_str() + eq + 1);
      if (name == "candidates") config.localizer.candidates = static_cast<int>(value);
      else if (name == "turns") config.localizer.dmm.canonical_turns = static_cast<int>(value);
      else if (name == "free_weight") config.localizer.free_weight = value;
      else if (name == "neighbourhood") config.localizer.neighbourhood = value;
      else if (name == "confidence") config.confident_rule.min_margin = value;
      else if (name == "probability") config.confident_rule.min_probability = value;
      else if (name == "elsewhere") config.localizer.elsewhere.distance = value;
      else if (name == "window") config.submap.window_length = value;
      else if (name == "full_circle") config.localizer.dmm.canonical = false;
      else if (name == "restart")
        config.localizer.restart_distance = value;
      else if (name == "distinct")
        config.localizer.candidate_distance = value;
      else if (name == "verified") config.localizer.verified = static_cast<int>(value);
      else if (name == "wall_share") config.localizer.wall_direction_share = value;
      else if (name == "refine_window") config.localizer.verify.refine_window = value;
      else throw std::runtime_error("unknown setting '" + arg + "'");
    }
    const std::size_t split = first_revisit(scans, config.revisit_radius, config.revisit_gap);
    const std::vector<double> travel = travel_distances(scans);
    const std::filesystem::path dir = argv[2];
    const std::filesystem::path yaml = dir / "first_visit.yaml";
    io::write_map_yaml(yaml, build_grid_map(Scans(scans.begin(), scans.begin() + static_cast<std::ptrdiff_t>(split))));
    const GridMap map = io::read_map_yaml(yaml);
    std::printf("%s: map of scans [0, %zu) (%.0f of %.0f m of travel), %d x %d cells at %.2f m -> %s\n", argv[1], split,
                travel[split == scans.size() ? split - 1 : split], travel.back(), map.width, map.height, map.resolution,
                yaml.c_str());
    const RelocalisationReport r = evaluate_relocalisation(map, scans, split, config);
    std::printf("wing directions searched beside the axes:");
    for (const double d : r.wing_directions) std::printf(" %+.0f deg", d * kDegreesPerRadian);
    std::printf("%s\n", r.wing_directions.empty() ? " none" : "");
    const auto share = [](std::size_t a, std::size_t b) { return b ? 100.0 * a / b : 0.0; };
    std::printf("queries: %zu (every %.1f m of travel after the split)\n", r.outcomes.size(), config.query_spacing);
    std::printf("in the map (overlap >= %.0f %%): %zu, pose within %.2f m / %.0f deg: %zu (%.1f %%)\n",
                100 * config.min_overlap, r.in_map, config.correct.translation,
                config.correct.rotation * kDegreesPerRadian, r.in_map_correct, share(r.in_map_correct, r.in_map));
    std::printf("confident (>= %.2f, probability >= %.3f): %zu, wrong among them: %zu (%.1f %%)\n",
                config.confident_rule.min_margin, config.confident_rule.min_probability, r.confident,
                r.confident_wrong, share(r.confident_wrong, r.confident));
    std::printf("outside the map (overlap < %.0f %%): %zu, reported confidently: %zu (%.1f %%)\n",
                100 * config.min_overlap, r.outside, r.outside_confident, share(r.outside_confident, r.outside));
    std::printf("time per query (one core): median %.1f ms, p95 %.1f ms\n", r.median_ms, r.p95_ms);
    for (const RelocalisationOutcome& o : r.outcomes) {
      const MatchTerms& t = o.result.terms;
      std::printf("  %7.1f m  overlap %.2f  conf %.3f  score %.3f  inl %.3f  free %d  else %.3f  p %.3f  qo %.3f "
                  "qf %.3f qs %.3f mo %.3f mf %.3f ms %.3f  err %.2f m %.1f deg  %.1f ms  truth: score %.3f p %.3f%s\n",
                  o.travel, o.overlap, o.result.confidence, o.result.score, o.result.inlier_fraction,
                  o.result.free_conflicts, o.result.elsewhere_score, o.result.probability, t.query.occupied, t.query.free, t.query.seen, t.map.occupied, t.map.free,
                  t.map.seen,
                  o.translation_error, o.rotation_error * kDegreesPerRadian, o.result.time_ms,
                  o.truth_score, o.truth_verified.probability, o.correct ? "" : "  WRONG");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "relocalisation_check: %s\n", e.what());
    return 1;
  }
  return 0;
}
