// tracking_check CORRECTED_LOG OUT_DIR [noise=mild|harsh seed=N NAME=VALUE ...]: the tracking bench
// (core/evaluation/tracking.h). The building map of the first visit as relocalisation_check makes it
// (OUT_DIR/first_visit.yaml, read back), then runs of the tracker from every 10 m after it, motion from a drifted
// twin's odometry, one kidnapping per run. Prints one summary line (`summary: ...`, the fields of the tracking
// table that scripts/relocalisation_tables.py reads) and a line per run.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "core/evaluation/tracking.h"
#include "io/formats/map_server.h"
#include "io/logs/carmen_log.h"
#include "io/logs/scan_source.h"

using namespace partslam;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: tracking_check CORRECTED_LOG OUT_DIR [noise=mild|harsh seed=N twin_out=FILE max_starts=K hypotheses=K "
                 "declare_share=S declare_steps=K other_probability=P lost_probability=P lost_steps=K "
                 "track_window=M min_seen=S search_budget=W search_min_share=S weighed_back=K candidates=K ...]\n");
    return 2;
  }
  try {
    const Scans scans = io::load_scan_source(argv[1]).scans;
    TrackingBenchConfig config;
    std::string twin_out;  // twin_out=FILE: the drifted twin as a CARMEN log, for a peer on the same odometry
    for (int a = 3; a < argc; ++a) {
      const std::string arg = argv[a];
      const std::size_t eq = arg.find('=');
      const std::string name = arg.substr(0, eq), text = eq == std::string::npos ? "" : arg.substr(eq + 1);
      const double value = std::atof(text.c_str());
      if (name == "noise") config.noise = text;
      else if (name == "seed") config.seed = static_cast<std::uint64_t>(value);
      else if (name == "max_starts") config.max_starts = static_cast<int>(value);
      else if (name == "hypotheses") config.tracker.hypotheses = static_cast<int>(value);
      else if (name == "declare_share") config.tracker.declare_share = value;
      else if (name == "declare_steps") config.tracker.declare_steps = static_cast<int>(value);
      else if (name == "other_probability") config.tracker.other_probability = value;
      else if (name == "floor_probability") config.tracker.floor_probability = value;
      else if (name == "merge_distance") config.tracker.merge_distance = value;
      else if (name == "lost_probability") config.tracker.lost_probability = value;
      else if (name == "lost_steps") config.tracker.lost_steps = static_cast<int>(value);
      else if (name == "track_window") config.tracker.track_window = value;
      else if (name == "min_seen") config.tracker.min_seen = value;
      else if (name == "min_none") config.tracker.min_none_share = value;
      else if (name == "twin_out") twin_out = text;
      else if (name == "move_gain") config.tracker.move_gain = value;
      else if (name == "corridor_ratio") config.tracker.corridor_ratio = value;
      else if (name == "corridor_slack") config.tracker.corridor_slack = value;
      else if (name == "declare_probability") config.tracker.declare_probability = value;
      else if (name == "search_every") config.tracker.search_every = static_cast<int>(value);
      else if (name == "search_budget") config.tracker.search_budget = static_cast<int>(value);
      else if (name == "search_min_share") config.tracker.search_min_share = value;
      else if (name == "weighed_back") config.tracker.weighed_back = static_cast<int>(value);
      else if (name == "verified") config.localizer.verified = static_cast<int>(value);
      else if (name == "candidates") config.localizer.candidates = static_cast<int>(value);
      else if (name == "search_verified") config.tracker.search_verified = static_cast<int>(value);
      else if (name == "claim_m") config.tracker.claim_shift.translation = value;
      else if (name == "claim_deg") config.tracker.claim_shift.rotation = value * std::numbers::pi / 180;
      else throw std::runtime_error("unknown setting '" + arg + "'");
    }
    const RelocalisationConfig reloc;
    const std::size_t split = first_revisit(scans, reloc.revisit_radius, reloc.revisit_gap);
    const std::filesystem::path yaml = std::filesystem::path(argv[2]) / "first_visit.yaml";
    io::write_map_yaml(yaml, build_grid_map(Scans(scans.begin(), scans.begin() + static_cast<std::ptrdiff_t>(split))));
    const GridMap map = io::read_map_yaml(yaml);
    if (!twin_out.empty()) {
      io::write_carmen_log(twin_out, drifted_twin(scans, odometry_noise(config.noise), config.seed),
                           "drifted twin (" + config.noise + ", seed " + std::to_string(config.seed) + ") of " + argv[1]);
      std::printf("wrote %s (the drifted twin; the first visit ends at scan %zu)\n", twin_out.c_str(), split);
    }
    const TrackingReport r = evaluate_tracking(map, scans, split, config);
    std::size_t eligible = 0, converged = 0, single = 0, truth_first = 0, wrong = 0, wrong_in_map = 0, steps = 0;
    std::size_t kidnaps = 0, noticed = 0, recovered = 0, in_map = 0, in_map_localised = 0;
    std::vector<double> to_converge;
    for (const TrackingRun& run : r.runs) {
      steps += run.steps.size();
      for (const TrackedStep& t : run.steps) {
        const bool in = t.overlap >= config.min_overlap;
        in_map += in;
        in_map_localised += in && t.step.status == TrackStatus::kLocalised && t.right;
      }
      wrong += static_cast<std::size_t>(run.declared_wrong);
      wrong_in_map += static_cast<std::size_t>(run.declared_wrong_in_map);
      if (run.eligible) {
        ++eligible;
        single += run.single_shot_right;
        truth_first += run.truth_among_first;
        if (run.converged >= 0 && run.converged <= config.converge_within && run.converged_right) ++converged;
        if (run.converged >= 0) to_converge.push_back(run.converged);
      }
      if (run.localised_at_jump && run.jump_in_map) {
        ++kidnaps;
        noticed += run.noticed >= 0;
        recovered += run.recovered >= 0 && run.recovered <= config.recover_within;
      }
    }
    const auto pct = [](std::size_t a, std::size_t b) { return b ? 100.0 * static_cast<double>(a) / static_cast<double>(b) : 0.0; };
    std::printf("%s (%s odometry, seed %llu): map of scans [0, %zu); %zu runs, %zu steps\n", argv[1], config.noise.c_str(),
                static_cast<unsigned long long>(config.seed), split, r.runs.size(), steps);
    std::printf("summary: noise %s | runs %zu | eligible %zu | localised within %.0f m %zu (%.1f %%) | single-shot %zu (%.1f %%) "
                "| truth among first hypotheses %zu (%.1f %%) | travel to converge median %.0f m p90 %.0f m "
                "| declared wrong %zu of %zu steps (in the map %zu) | kidnappings %zu noticed %zu recovered %zu (%.1f %%) "
                "| in-map steps localised %zu of %zu (%.1f %%) | step median %.1f ms p95 %.1f ms\n",
                config.noise.c_str(), r.runs.size(), eligible, config.converge_within, converged, pct(converged, eligible),
                single, pct(single, eligible), truth_first, pct(truth_first, eligible), percentile(to_converge, 0.5),
                percentile(to_converge, 0.9), wrong, steps, wrong_in_map, kidnaps, noticed, recovered,
                pct(recovered, kidnaps), in_map_localised, in_map, pct(in_map_localised, in_map), r.median_ms, r.p95_ms);
    for (const TrackingRun& run : r.runs) {
      std::printf("  start %7.1f m  jump to %7.1f m  %s  converged %5.0f m%s  single %d  first %d  at jump %d  "
                  "jump in map %d  noticed %4.0f m  recovered %4.0f m  wrong %d (in map %d)\n",
                  run.start, run.jump_to, run.eligible ? "eligible" : "partly out", run.converged,
                  run.converged >= 0 && !run.converged_right ? " WRONG" : "", run.single_shot_right,
                  run.truth_among_first, run.localised_at_jump, run.jump_in_map, run.noticed, run.recovered,
                  run.declared_wrong, run.declared_wrong_in_map);
      if (std::getenv("TRACK_STEPS") == nullptr) continue;  // the steps too, for a closer look
      for (const TrackedStep& t : run.steps)
        std::printf("    %5.1f m%s  overlap %.2f  %-9s  %s %5.2f m %5.1f deg  share %.3f  p %.3f  none %.3f  hyps %zu  %.1f ms%s%s\n", t.travel,
                    t.after_jump ? " (jumped)" : "", t.overlap, to_string(t.step.status), t.right ? "right" : "off  ", t.translation_error,
                    t.rotation_error * kDegreesPerRadian,
                    t.step.best.share, t.step.best.probability, t.step.none_share, t.step.hypotheses.size(), t.step.time_ms,
                    t.step.evidence ? "" : "  no evidence", t.step.searched ? "  searched" : "");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tracking_check: %s\n", e.what());
    return 1;
  }
  return 0;
}
