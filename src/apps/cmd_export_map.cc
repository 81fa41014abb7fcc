// partslam export-map LOG --out map.yaml: a log's map as ROS map_server writes one (map.yaml + map.pgm, trinary:
// occupied, free, unknown), by ray casting its scans at their poses (core/maps/grid_map.h) — a corrected log, a
// raw one with --scan-match, or the corrected.log of `partslam slam`. --until M keeps the scans before M m of
// travel (a map of the first visit, to localise the rest of the log in). A PNG preview (map.png) goes beside them.
// All files are written atomically.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "apps/commands.h"
#include "apps/log_inputs.h"
#include "core/error.h"
#include "core/maps/grid_map.h"
#include "core/maps/submap.h"
#include "core/slam/front_end.h"
#include "core/timing.h"
#include "io/files/atomic_file.h"
#include "io/formats/map_server.h"
#include "io/logs/scan_source.h"
#include "apps/scan_input.h"
#include "plot/grid_map_image.h"

namespace partslam::apps {
namespace {

struct ExportMapOptions {
  std::string log;
  io::LogReadOptions read;
  std::string out;
  GridMapConfig grid;
  std::optional<double> until;  ///< --until M: given or not
  bool scan_match = false;
};

void run_export_map(const ExportMapOptions& o) {
  validate(o.grid);
  if (o.until && !(std::isfinite(*o.until) && *o.until >= 0))
    throw InputError("--until must be a finite travel >= 0 [m], got " + std::to_string(*o.until));
  if (o.out.empty() || std::filesystem::path(o.out).extension() != ".yaml")
    throw InputError("--out must name the map's YAML file (e.g. map.yaml; the image goes beside it as .pgm)");
  std::filesystem::path image(o.out);
  image.replace_extension(".pgm");
  std::filesystem::path preview(o.out);
  preview.replace_extension(".png");
  io::check_outputs({{"--out", o.out}, {"--out's image", image}, {"--out's preview", preview}},
                    {{"LOG", o.log}});
  const auto t0 = Clock::now();
  Scans scans = load_scans(o.log, o.read).scans;
  if (o.scan_match) scans = scan_match_log(scans).scans;
  if (o.until) {
    const std::vector<double> s = travel_distances(scans);
    std::size_t end = 0;
    while (end < scans.size() && s[end] < *o.until) ++end;
    if (end == 0) throw InputError("--until " + std::to_string(*o.until) + ": no scan before that travel");
    scans.resize(end);
  }
  const GridMap map = build_grid_map(scans, o.grid);
  io::write_map_yaml(o.out, map);
  char title[200];
  std::snprintf(title, sizeof title, "%s: %d x %d cells at %.3g m", std::filesystem::path(o.log).filename().c_str(),
                map.width, map.height, map.resolution);
  plot::write_grid_maps_png(preview, {{&map, title, {}, {}, {}}});
  std::size_t occupied = 0, free = 0;
  for (const CellState c : map.cells) occupied += c == CellState::kOccupied, free += c == CellState::kFree;
  std::cout << "wrote " << o.out << ", " << image.string() << " and " << preview.string() << " (preview): " << map.width << " x " << map.height
            << " cells at " << map.resolution << " m (" << occupied << " occupied, " << free << " free) from "
            << scans.size() << " scans in " << static_cast<long>(ms_since(t0)) << " ms\n";
}

}  // namespace

void register_export_map(CLI::App& app) {
  auto o = std::make_shared<ExportMapOptions>();
  CLI::App* cmd = app.add_subcommand("export-map", "Write a log's map as a ROS map_server map (map.yaml + PGM)");
  cmd->add_option("log", o->log, "a log with good poses (corrected; raw with --scan-match): " + kLogInputs)->required();
  cmd->add_option("--out", o->out, "the map's YAML file; the PGM and a PNG preview are written beside it")->required();
  cmd->add_option("--resolution", o->grid.resolution, "cell side [m]")->capture_default_str();
  cmd->add_option("--max-range", o->grid.max_range, "beams longer than this are not used [m]")->capture_default_str();
  cmd->add_option("--until", o->until, "use only the scans before this travel along the log [m]");
  cmd->add_flag("--scan-match", o->scan_match, "poses from scan matching (raw logs)");
  add_log_read_options(*cmd, o->read);
  cmd->callback([o] { run_export_map(*o); });
}

}  // namespace partslam::apps
