// partslam render DB --map ID --out FILE.png: the paper's Fig. E for one stored map. Top panel: the map with
// the keypoint boxes of its best K parts; with --dict, a second panel: the dictionary with the matching
// descriptor boxes in the same colours. Parts come from the stored descriptors when `describe` has run (the
// stored P-part list when there is one, since it keeps the appearance scores), else from CPD on the fly.
// Tested by: apps/cli_parts_test.cc
#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "apps/commands.h"
#include "apps/cpd_options.h"
#include "apps/db_hints.h"
#include "core/error.h"
#include "core/parts/cpd.h"
#include "io/files/atomic_file.h"
#include "io/store/descriptor_store.h"
#include "io/store/map_database.h"
#include "plot/render.h"

namespace partslam::apps {
namespace {

struct RenderOptions {
  std::string db;
  std::int64_t map_id = -1;
  std::string dictionary;
  int parts = 5;
  std::string out;
  bool fresh = false;
  CpdConfig cpd;
  plot::RenderConfig render;
};

// The map's parts for the figure: the stored part list, or the stored K-part descriptor, or (--fresh, or neither
// stored) CPD on the fly. Returns where they came from.
std::string add_parts(const io::MapDatabase& db, const io::Dictionary& dictionary, const Submap& submap,
                      const RenderOptions& o, plot::PartsFigure& figure) {
  std::string source;
  if (!o.fresh) {
    if (const int p = io::query_list_parts(db, dictionary.name, o.map_id); p > 0) {
      figure.parts = select_top_parts(io::load_descriptor(db, dictionary.name, p, o.map_id)->parts, o.parts).parts;
      source = "the stored " + std::to_string(p) + "-part list";
    } else if (auto d = io::load_descriptor(db, dictionary.name, o.parts, o.map_id)) {
      figure.parts = d->parts;
      figure.show_scores = false;  // stored K-part descriptors keep no appearance score
      source = "the stored K=" + std::to_string(o.parts) + " descriptor";
    }
  }
  if (figure.parts.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    const PreparedDictionary prepared = prepare_dictionary(dictionary.points, o.cpd);
    const CpdResult cpd =
        discover_parts(submap.points, prepared, o.cpd, static_cast<std::uint64_t>(o.map_id));
    figure.parts = select_top_parts(cpd.parts, o.parts).parts;
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    source = "CPD on the fly (" + std::to_string(static_cast<long>(ms)) + " ms, " +
             std::to_string(cpd.parts.size()) + " parts found)";
  }
  return source;
}

void run_render(RenderOptions o) {
  if (o.parts < 1 || o.parts > 100)
    throw InputError("--parts must be in [1, 100], got " + std::to_string(o.parts));
  validate(o.cpd);
  validate(o.render);
  if (std::filesystem::path(o.out).extension() != ".png")
    throw InputError("--out: expected a .png file, got '" + o.out + "'");
  io::check_outputs({{"--out", o.out}}, {{"DB", o.db}});
  const io::MapDatabase db = io::MapDatabase::open(o.db, io::MapDatabase::Mode::kReadOnly);
  const io::MapLocation where = with_hint([&] { return db.locate(o.map_id); }, info_hint(o.db));
  const Submap submap = db.load_submap(o.map_id);

  plot::PartsFigure figure;
  figure.map_points = submap.points;
  std::optional<io::Dictionary> dictionary;
  if (!o.dictionary.empty())
    dictionary = io::resolve_dictionary(db, o.dictionary);
  else if (!db.dictionaries().empty())
    dictionary = with_hint([&] { return io::resolve_dictionary(db, ""); }, "--dict NAME chooses one");
  std::string source = "no dictionary in the database: no parts";
  if (!dictionary)
    std::cerr
        << "warning: " << o.db
        << " holds no dictionary: the map is drawn without parts (store one with `partslam dictionary`)\n";
  if (dictionary) {
    source = add_parts(db, *dictionary, submap, o, figure);
    source += ", dictionary '" + dictionary->name + "'";
  }
  figure.map_title = "map " + std::to_string(o.map_id) + " (" + where.dataset_name + ", submap " +
                     std::to_string(where.index) + "): keypoint boxes of " +
                     std::to_string(figure.parts.size()) + " parts";
  if (!o.dictionary.empty()) {
    figure.show_dictionary = true;
    figure.dictionary_title =
        "dictionary '" + dictionary->name + "': descriptor boxes, crops carried onto them";
    figure.dictionary_points = dictionary->points;
  }
  plot::write_parts_figure(o.out, figure, o.render);
  std::cout << "map " << o.map_id << " (dataset '" << where.dataset_name << "', submap " << where.index
            << "): " << figure.parts.size() << " parts from " << source << "; wrote " << o.out << " ("
            << std::filesystem::file_size(o.out) / 1024 << " KiB)\n";
}

}  // namespace

void register_render(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd =
      app.add_subcommand("render", "Draw a stored map's parts and their descriptor boxes (Fig. E) as PNG");
  cmd->add_option("db", o->db, "map database file")->required();
  cmd->add_option("--map", o->map_id, "global map id (see 'partslam info')")->required();
  cmd->add_option("--dict", o->dictionary,
                  "dictionary to describe against and to draw (default: the only one, parts only)");
  cmd->add_option("--parts", o->parts, "K: parts drawn, best appearance score first")->capture_default_str();
  cmd->add_option("--out", o->out, "PNG file to write (atomically)")->required();
  cmd->add_flag("--fresh", o->fresh, "run CPD even when descriptors are stored");
  cmd->add_option("--cpd-parts", o->cpd.max_parts, "CPD on the fly: parts searched (as describe --parts)")
      ->capture_default_str();
  add_cpd_options(*cmd, o->cpd, "");  // CPD on the fly, as describe
  cmd->add_option("--width", o->render.width, "image width [px]")->capture_default_str();
  cmd->callback([o] { run_render(*o); });
}

}  // namespace partslam::apps
