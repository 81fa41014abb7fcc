// Python bindings of global localisation: building maps (GridMap: cells unknown / free / occupied, as ROS map_server
// holds them; ray-cast from posed scans; read and written as map.yaml + PGM), point files, a local map from bare
// points or from a stretch of a log (as `match` and `locate` build one), and the Localizer (a local map's pose in a
// building map, with its confidence). The cells cross as a (height, width) uint8 numpy array of CellState values, row
// 0 the lowest y. Map building and localisation release the GIL.
#include "casters.h"
// (casters.h first: see its header comment)
#include <pybind11/numpy.h>

#include "bindings.h"
#include "core/error.h"
#include "core/maps/grid_map.h"
#include "core/maps/submap.h"
#include "core/matching/localizer.h"
#include "core/matching/tracker.h"
#include "core/slam/log_stretch.h"
#include "io/formats/map_server.h"
#include "io/formats/point_export.h"

namespace partslam::python {

namespace py = pybind11;
using namespace pybind11::literals;
using release_gil = py::call_guard<py::gil_scoped_release>;

namespace {

py::array_t<std::uint8_t> cells_array(const GridMap& m) {
  py::array_t<std::uint8_t> out({m.height, m.width});
  auto v = out.mutable_unchecked<2>();
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c) v(r, c) = static_cast<std::uint8_t>(m.at(c, r));
  return out;
}

void set_cells(GridMap& m, const py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>& a) {
  if (a.ndim() != 2) throw InputError("GridMap.cells: expected a (height, width) array");
  m.height = static_cast<int>(a.shape(0)), m.width = static_cast<int>(a.shape(1));
  m.cells.resize(static_cast<std::size_t>(m.width) * static_cast<std::size_t>(m.height));
  auto v = a.unchecked<2>();
  for (int r = 0; r < m.height; ++r) {
    for (int c = 0; c < m.width; ++c) {
      if (v(r, c) > 2) throw InputError("GridMap.cells: values are 0 (unknown), 1 (free) or 2 (occupied)");
      m.cells[static_cast<std::size_t>(r) * m.width + c] = static_cast<CellState>(v(r, c));
    }
  }
}


void define_log_stretch(py::module_& m) {
  py::class_<ScanMatcherConfig> matcher(m, "ScanMatcherConfig", "Scan matching (core/matching/scan_matcher.h)");
  def_config_fields(matcher);
  def_keyword_init(matcher);
  py::class_<FrontEndConfig> front_end(m, "FrontEndConfig",
                                       "The front end that poses a raw log's scans (core/slam/front_end_config.h)");
  def_config_fields(front_end);
  def_keyword_init(front_end);
  py::class_<StretchSpec> spec(m, "StretchSpec",
                               "A stretch of a log: from_m and to_m, or at_m (travel along the log's own poses "
                               "[m]), or from_time and to_time, or at_time (the log's clock [s]); "
                               "core/slam/log_stretch.h");
  spec.def_readwrite("from_m", &StretchSpec::from_m)
      .def_readwrite("to_m", &StretchSpec::to_m)
      .def_readwrite("at_m", &StretchSpec::at_m, "one window of travel from here")
      .def_readwrite("from_time", &StretchSpec::from_time)
      .def_readwrite("to_time", &StretchSpec::to_time)
      .def_readwrite("at_time", &StretchSpec::at_time, "one window of travel from the first scan stamped then")
      .def("validate", [](const StretchSpec& s) { validate(s); },
           "Raises InputError unless it names exactly one stretch with values in range.");
  def_keyword_init(spec);
  py::class_<LogStretch>(m, "LogStretch", "A log's stretch, as find_log_stretch finds it")
      .def_readonly("scans", &LogStretch::scans, "the log's scans (scan-matched: the margin and the stretch)")
      .def_readonly("stretch", &LogStretch::stretch, "a stretch was given")
      .def_readonly("first", &LogStretch::first, "the stretch is scans[first:end]")
      .def_readonly("end", &LogStretch::end)
      .def_readonly("from_m", &LogStretch::from_m)
      .def_readonly("to_m", &LogStretch::to_m)
      .def_readonly("from_time", &LogStretch::from_time)
      .def_readonly("to_time", &LogStretch::to_time)
      .def_readonly("log_scans", &LogStretch::log_scans)
      .def_readonly("matched_scans", &LogStretch::matched_scans)
      .def_readonly("match_ms", &LogStretch::match_ms);
  m.attr("SCAN_MATCH_MARGIN") = kScanMatchMargin;
  m.def("find_log_stretch", &find_log_stretch, "scans"_a, "spec"_a, "window"_a = SubmapConfig{}.window_length,
        "scan_match"_a = std::optional<FrontEndConfig>{}, "name"_a = "log", release_gil(),
        "The stretch of the log's scans the spec gives (an empty spec: the whole log), as `partslam match` and "
        "`locate` take it; with scan_match (a FrontEndConfig) its scans and SCAN_MATCH_MARGIN of travel before it "
        "are scan-matched. window: the travel of an at_m / at_time stretch [m].");
  m.def("stretch_local_map", &stretch_local_map, "stretch"_a, "config"_a = SubmapConfig{}, "name"_a = "log",
        release_gil(), "The local map of a stretch, built as stored maps are.");
}

}  // namespace

void define_localization(py::module_& m) {
  py::enum_<CellState>(m, "CellState")
      .value("UNKNOWN", CellState::kUnknown)
      .value("FREE", CellState::kFree)
      .value("OCCUPIED", CellState::kOccupied);
  py::class_<GridMap> grid(m, "GridMap", "A building map as map_server holds one (core/maps/grid_map.h)");
  grid.def_readwrite("resolution", &GridMap::resolution, "cell side [m]")
      .def_readwrite("origin", &GridMap::origin, "pose of cell (0, 0)'s lower-left corner (x, y, theta)")
      .def_readonly("width", &GridMap::width)
      .def_readonly("height", &GridMap::height)
      .def_property("cells", &cells_array, &set_cells,
                    "(height, width) uint8 array of CellState values, row 0 the lowest y (a copy)")
      .def("validate", py::overload_cast<const GridMap&>(&validate), "Raises InputError when inconsistent.")
      .def("__repr__", [](const GridMap& g) {
        return "<partslam.GridMap " + std::to_string(g.width) + " x " + std::to_string(g.height) + " at " +
               std::to_string(g.resolution) + " m>";
      });
  grid.def(py::init<>());
  py::class_<GridMapConfig> grid_config(m, "GridMapConfig", "How build_grid_map ray-casts scans");
  grid_config.def_readwrite("resolution", &GridMapConfig::resolution, "[m]")
      .def_readwrite("max_range", &GridMapConfig::max_range, "[m]")
      .def_readwrite("occupied_ratio", &GridMapConfig::occupied_ratio)
      .def_readwrite("margin", &GridMapConfig::margin, "[m]");
  def_keyword_init(grid_config);
  m.def("build_grid_map", &build_grid_map, "scans"_a, "config"_a = GridMapConfig{}, release_gil(),
        "The map of scans with known poses (a corrected log), by ray casting.");
  m.def("occupied_points", &occupied_points, "map"_a, "Centres of the occupied cells in the map frame.");
  m.def("read_map_yaml", &io::read_map_yaml, "path"_a, release_gil(), "A ROS map_server map (map.yaml + PGM).");
  m.def("write_map_yaml", &io::write_map_yaml, "path"_a, "map"_a, release_gil(),
        "Writes map.yaml and map.pgm beside it, atomically.");
  m.def(
      "read_points", [](const std::string& path) { return io::read_points(path); }, "path"_a, release_gil(),
      "A point file (.ply ASCII or .csv) as an (n, 2) array, in the file's own frame.");
  m.def(
      "read_point_file",
      [](const std::string& path) {
        io::PointFile file = io::read_point_file(path);
        return py::make_tuple(py::cast(std::move(file.points)), py::cast(file.T_world_points),
                              py::cast(std::move(file.laser_origins)));
      },
      "path"_a,
      "(points, T_world_points, laser_origins): the file's points; when its header names it (partslam export "
      "--frame map), the pose of their frame in the world frame, else None; the laser origins it carries, in the "
      "points' frame ((0, 2) when none). Take both into the world frame with transform() before "
      "local_map_from_points to build the local map the world-frame file gives.");
  m.def("local_map_from_points", &local_map_from_points, "points"_a, "config"_a = SubmapConfig{},
        "origins"_a = Points2{}, release_gil(),
        "A local map shaped as submaps are (one point per cell, centred, canonical, cropped) from points and, "
        "when given, the laser origins they were seen from (in the points' frame), which let its free space be "
        "verified.");

  define_log_stretch(m);

  py::class_<VerifyConfig> verify(m, "VerifyConfig",
                                   "How a candidate pose is verified (core/matching/verification.h)");
  def_config_fields(verify);
  verify.def("validate", py::overload_cast<const VerifyConfig&>(&validate),
             "Raises InputError naming the field that is out of range.");
  def_keyword_init(verify);
  py::class_<LocalizerConfig> config(m, "LocalizerConfig", "How the Localizer searches (core/matching/localizer.h)");
  def_config_fields(config);
  def_keyword_init(config);
  py::class_<Localization>(m, "Localization", "Where a local map lies in the building map, and how surely")
      .def_readonly("T_map_query", &Localization::T_map_query)
      .def_readonly("inliers", &Localization::inliers)
      .def_readonly("inlier_fraction", &Localization::inlier_fraction)
      .def_readonly("T_map_lattice", &Localization::T_map_lattice)
      .def_readonly("free_conflicts", &Localization::free_conflicts)
      .def_readonly("score", &Localization::score)
      .def_readonly("elsewhere_score", &Localization::elsewhere_score)
      .def_readonly("probability", &Localization::probability, "verified same-place probability at T_map_query")
      .def_readonly("calibrated", &Localization::calibrated)
      .def_readonly("T_map_elsewhere", &Localization::T_map_elsewhere)
      .def_readonly("confidence", &Localization::confidence)
      .def_property_readonly(
          "confident", [](const Localization& l) { return is_confident(l); },
          "reported as found: confidence >= 0.2 and, when calibrated, probability >= 0.025 (as `partslam locate`)")
      .def_readonly("candidates", &Localization::candidates)
      .def_readonly("time_ms", &Localization::time_ms)
      .def("__repr__", [](const Localization& l) {
        return "<partslam.Localization x=" + std::to_string(l.T_map_query.x) + " y=" + std::to_string(l.T_map_query.y) +
               " confidence=" + std::to_string(l.confidence) + ">";
      });
  py::class_<Verified>(m, "Verified", "A pose verified against the map (core/matching/verification.h)")
      .def_readonly("T_map_query", &Verified::T_map_query, "the refined pose")
      .def_readonly("probability", &Verified::probability, "the same-place probability there")
      .def_property_readonly("query_seen", [](const Verified& v) { return v.terms.query.seen; },
                             "share of the local map's points on cells the map saw");
  py::class_<Localizer>(m, "Localizer", "A building map prepared once for global localisation")
      .def(py::init<const GridMap&, const LocalizerConfig&>(), "map"_a, "config"_a = LocalizerConfig{}, release_gil())
      .def(py::init<const Points2&, const LocalizerConfig&>(), "points"_a, "config"_a = LocalizerConfig{},
           release_gil())
      .def("locate", &Localizer::locate, "query_points"_a, "query_origins"_a = Points2{}, release_gil(),
           "The local map's pose in the map frame (its points in their canonical frame, as build_local_map gives; "
           "query_origins: its laser positions, Submap.origins, for a calibrated probability).")
      .def("hypotheses",
           static_cast<std::vector<Verified> (Localizer::*)(const Points2&, const Points2&, int, int, double)
                           const>(&Localizer::hypotheses),
           "query_points"_a, "query_origins"_a = Points2{}, "count"_a = 8,
           "verified"_a = 0, "min_share"_a = 0.0, release_gil(),
           "The global search's distinct verified poses (Verified), most probable first: what a tracker starts "
           "from (min_share: candidates with no more than this share of the best one's inliers are not searched "
           "for).")
      .def_property_readonly("prepare_ms", &Localizer::prepare_ms)
      .def_property_readonly("alignment_angle", &Localizer::alignment_angle)
      .def_property_readonly("wing_directions", &Localizer::wing_directions,
                             "wall directions searched beside the axes, in the canonical frame [rad]");

  py::class_<TrackerConfig> tracker_config(m, "TrackerConfig",
                                           "How the Tracker keeps and declares hypotheses (core/matching/tracker.h)");
  def_config_fields(tracker_config);
  tracker_config.def("validate", py::overload_cast<const TrackerConfig&>(&validate),
                     "Raises InputError naming the field that is out of range.");
  def_keyword_init(tracker_config);
  py::class_<TrackHypothesis>(m, "TrackHypothesis", "One place the robot may be")
      .def_readonly("T_map_query", &TrackHypothesis::T_map_query)
      .def_readonly("probability", &TrackHypothesis::probability, "this step's same-place probability there")
      .def_readonly("share", &TrackHypothesis::share, "its share of the weight (the none weight included)")
      .def_readonly("age", &TrackHypothesis::age, "steps it has been carried");
  py::class_<TrackStep>(m, "TrackStep", "What one local map told the tracker")
      .def_property_readonly("status", [](const TrackStep& s) { return std::string(to_string(s.status)); },
                             "'searching', 'localised' or 'lost'")
      .def_property_readonly(
          "pose", [](const TrackStep& s) { return s.has_pose ? py::cast(s.best) : py::none(); },
          "the declared hypothesis (localised) or the heaviest (TrackHypothesis), None when there is none")
      .def_readonly("hypotheses", &TrackStep::hypotheses, "heaviest first")
      .def_readonly("none_share", &TrackStep::none_share)
      .def_readonly("searched", &TrackStep::searched)
      .def_readonly("evidence", &TrackStep::evidence)
      .def_readonly("time_ms", &TrackStep::time_ms)
      .def("__repr__", [](const TrackStep& s) {
        return std::string("<partslam.TrackStep ") + to_string(s.status) + " hypotheses=" +
               std::to_string(s.hypotheses.size()) + ">";
      });
  py::class_<Tracker>(m, "Tracker",
                      "Global localisation over travel: hypotheses carried by the robot's motion until one "
                      "dominates (core/matching/tracker.h)")
      .def(py::init<const Localizer&, const TrackerConfig&>(), "localizer"_a, "config"_a = TrackerConfig{},
           py::keep_alive<1, 2>())
      .def("step", &Tracker::step, "points"_a, "origins"_a, "T_odom_map"_a, release_gil(),
           "One local map (its points and laser origins in its own frame, Submap.points / .origins) and its frame "
           "in the odometry's frame (Submap.T_world_map of a map built from the log's poses).")
      .def("reset", &Tracker::reset);
}

}  // namespace partslam::python
