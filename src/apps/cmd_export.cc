// partslam export FILE (--map ID | --dictionary NAME): writes one stored map's points as PLY or CSV,
// atomically, in the map frame (as stored; the header names the frame's pose in the world frame) or the
// source log's world frame, with the map's laser origins. Either file gives the same local map to match /
// locate --query-points.
// Tested by: apps/cli_test.cc, apps/cli_locate_test.cc
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>
#include <optional>

#include "apps/commands.h"
#include "apps/db_hints.h"
#include "core/error.h"
#include "io/files/atomic_file.h"
#include "io/store/map_database.h"
#include "io/formats/point_export.h"

namespace partslam::apps {
namespace {

struct ExportOptions {
  std::string file;
  bool has_map = false;
  std::int64_t map_id = -1;
  std::string dictionary;
  std::string format;  // empty: from --out's extension, else csv
  std::string out;     // empty: map_<ID>.<format> or dictionary_<NAME>.<format>
  std::string frame = "map";
};

io::PointFormat resolve_format(const ExportOptions& options) {
  if (!options.format.empty()) {
    io::PointFormat format;
    try {
      format = io::parse_point_format(options.format);
    } catch (const InputError&) {
      throw InputError("--format: expected ply or csv, got '" + options.format + "'");
    }
    // A file named .ply holding CSV (or the other way round) is read back by nothing, --query-points
    // included.
    const std::string extension = std::filesystem::path(options.out).extension().string();
    if ((extension == ".ply" || extension == ".csv") && extension != "." + options.format)
      throw InputError("--format " + options.format + " and --out '" + options.out + "' disagree");
    return format;
  }
  return std::filesystem::path(options.out).extension() == ".ply" ? io::PointFormat::kPly
                                                                  : io::PointFormat::kCsv;
}

void run_export(const ExportOptions& options, std::ostream& log) {
  const bool by_map = options.has_map;
  if (by_map == !options.dictionary.empty()) {
    throw InputError("export: give exactly one of --map ID or --dictionary NAME");
  }
  if (options.frame != "map" && options.frame != "world") {
    throw InputError("--frame: expected map or world, got '" + options.frame + "'");
  }
  const io::PointFormat format = resolve_format(options);
  const std::string extension = format == io::PointFormat::kPly ? ".ply" : ".csv";
  const io::MapDatabase db = io::MapDatabase::open(options.file, io::MapDatabase::Mode::kReadOnly);

  Points2 points, origins;  // a stored map's laser origins go with it (a dictionary has none)
  Pose2 T_world_map;
  std::string what;
  std::string out = options.out;
  if (by_map) {
    const io::MapLocation where = with_hint([&] { return db.locate(options.map_id); }, info_hint(options.file));
    Submap submap = db.load_submap(options.map_id);
    points = std::move(submap.points);
    origins = std::move(submap.origins);
    T_world_map = submap.T_world_map;
    what = "map " + std::to_string(options.map_id) + " (dataset '" + where.dataset_name + "', submap " +
           std::to_string(where.index) + ")";
    if (out.empty()) out = "map_" + std::to_string(options.map_id) + extension;
  } else {
    io::Dictionary dictionary = db.load_dictionary(options.dictionary);
    points = std::move(dictionary.points);
    T_world_map = dictionary.T_world_dict;
    what = "dictionary '" + options.dictionary + "'";
    if (out.empty()) out = "dictionary_" + options.dictionary + extension;
  }
  // In the map frame the header names the frame's pose (T_world_points = T_world_map): a local map built from the
  // file (match / locate --query-points) takes the points back into the world frame first, so it is the world-frame
  // file's (without it, the re-gridding of rotated points merged cells: 141 of 180 points, -1.7 deg).
  std::optional<Pose2> T_world_points;
  if (options.frame == "world") {
    points = transform(T_world_map, points);
    origins = transform(T_world_map, origins);
  } else {
    T_world_points = T_world_map;
  }
  io::check_outputs({{"--out", out}}, {{"DB", options.file}});
  io::write_points(out, points, format, T_world_points, origins);
  log << "wrote " << points.size() << " points";
  if (!origins.empty()) log << " and " << origins.size() << " laser origins";
  log << " of " << what << " in the " << options.frame << " frame to " << out << "\n";
}

}  // namespace

void register_export(CLI::App& app) {
  auto options = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand("export", "Write one stored map's points as PLY or CSV");
  cmd->add_option("file", options->file, "map database file")->required();
  auto* map = cmd->add_option("--map", options->map_id, "global map id (see 'partslam info')");
  auto* dictionary = cmd->add_option("--dictionary", options->dictionary, "export a dictionary map instead");
  map->excludes(dictionary);
  cmd->add_option("--format", options->format, "ply or csv (default: from --out's extension, else csv)");
  cmd->add_option("--out", options->out, "output path (default: map_<ID>.<format> in the current folder)");
  cmd->add_option("--frame", options->frame,
                  "map (as stored, centred and aligned; the header names its pose in the log's frame) or world (the "
                  "log's frame); either reads back as the same local map (--query-points)")
      ->capture_default_str();
  cmd->callback([options, map] {
    options->has_map = map->count() > 0;
    run_export(*options, std::cout);
  });
}

}  // namespace partslam::apps
