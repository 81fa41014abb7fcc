// Python bindings of core/maps: scans (one Scan, and Scans, the list-like a log is held in), submaps and
// their config, a query's local map, travel distances, voxel downsampling and the Manhattan alignment angle.
// Submap building and alignment release the GIL.
#include "casters.h"
// (casters.h first: see its header comment)
#include "bindings.h"
#include "core/maps/manhattan.h"
#include "core/maps/scan.h"
#include "core/maps/submap.h"

namespace partslam::python {

namespace py = pybind11;
using namespace pybind11::literals;
using release_gil = py::call_guard<py::gil_scoped_release>;

namespace {

void define_scans(py::module_& m) {
  py::class_<Scan> scan(
      m, "Scan",
      "One laser scan: timestamp [s], laser pose and odometry pose (x, y, theta) in the log's "
      "world frame, and the endpoints of its valid beams in the laser frame [m].");
  scan.def_readwrite("timestamp", &Scan::timestamp)
      .def_readwrite("T_world_laser", &Scan::T_world_laser)
      .def_readwrite("T_world_odom", &Scan::T_world_odom)
      .def_readwrite("points_laser", &Scan::points_laser,
                     "(n, 2) array, a copy: assign a new array to change it")
      .def_readwrite("num_beams", &Scan::num_beams, "beams in the message, valid or not")
      .def(
          "points_world",
          [](const Scan& s, std::optional<double> max_range) {
            return max_range ? points_world(s, *max_range) : points_world(s);
          },
          "max_range"_a = py::none(),
          "The endpoints in the world frame, those within max_range [m] when given.")
      .def("__repr__", [](const Scan& s) {
        return "<partslam.Scan t=" + std::to_string(s.timestamp) +
               " points=" + std::to_string(s.points_laser.size()) + ">";
      });
  def_keyword_init(scan);

  py::bind_vector<Scans>(m, "Scans",
                         "Scans of one log, held in C++ (a list of Scan; build it from any iterable)");
  py::implicitly_convertible<py::list, Scans>();
  py::implicitly_convertible<py::tuple, Scans>();
}

void define_submaps(py::module_& m) {
  py::class_<SubmapConfig> config(m, "SubmapConfig", "How submaps are built (core/maps/submap.h)");
  def_config_fields(config);
  config.def("validate", py::overload_cast<const SubmapConfig&>(&validate),
           "Raises InputError naming the field that is out of range.");
  def_keyword_init(config);

  py::class_<Submap> submap(
      m, "Submap",
      "A submap: its points in the map frame (centroid, canonical axes) and where that frame "
      "lies in the log's world frame (T_world_map).");
  submap.def_readwrite("id", &Submap::id, "index within its dataset (the global map id once stored)")
      .def_readwrite("anchor_scan", &Submap::anchor_scan, "index of the anchor scan in the scan stream")
      .def_readwrite("anchor_timestamp", &Submap::anchor_timestamp, "[s]")
      .def_readwrite("travel", &Submap::travel, "distance travelled up to the anchor scan [m]")
      .def_readwrite("alignment_angle", &Submap::alignment_angle,
                     "rotation applied to enter the canonical frame [rad]")
      .def_readwrite("T_world_map", &Submap::T_world_map)
      .def_readwrite("points", &Submap::points, "(n, 2) array in the map frame [m], a copy")
      .def_readwrite("origins", &Submap::origins,
                     "(k, 2) array: where the laser was, one position per 0.25 m of travel, in the map frame [m]")
      .def_property(
          "scan_timestamps", [](const Submap& s) { return to_array(s.scan_timestamps); },
          [](Submap& s, std::vector<double> t) { s.scan_timestamps = std::move(t); },
          "timestamps of the scans that built it [s], a copy")
      .def("__repr__", [](const Submap& s) {
        return "<partslam.Submap id=" + std::to_string(s.id) + " points=" + std::to_string(s.points.size()) +
               " travel=" + std::to_string(s.travel) + ">";
      });
  def_keyword_init(submap);

  m.def(
      "travel_distances", [](const Scans& scans) { return to_array(travel_distances(scans)); }, "scans"_a,
      "Cumulative travel of the laser along the scans [m], one per scan.");
  m.def("build_submaps", &build_submaps, "scans"_a, "config"_a = SubmapConfig{}, release_gil(),
        "Every submap of a scan stream (list of Submap).");
  m.def(
      "build_local_map", &build_local_map, "scans"_a, "from_"_a, "to"_a, "config"_a = SubmapConfig{},
      release_gil(),
      "A query's local map, built as build_submaps builds a stored one, over the scans whose travel lies in "
      "[from_, to) [m].");
  m.def("voxel_downsample", &voxel_downsample, "points"_a, "resolution"_a = kMapResolution, release_gil(),
        "One point per occupied cell (the mean of its points).");
}

void define_manhattan(py::module_& m) {
  py::class_<ManhattanConfig> config(m, "ManhattanConfig",
                                     "The Manhattan alignment search (core/maps/manhattan.h)");
  config.def_readwrite("bin_size", &ManhattanConfig::bin_size, "histogram bin [m]")
      .def_readwrite("coarse_step", &ManhattanConfig::coarse_step, "first sweep over [0, pi/2) [rad]")
      .def_readwrite("fine_step", &ManhattanConfig::fine_step, "refinement step [rad]");
  def_keyword_init(config);
  m.def("manhattan_angle", &manhattan_angle, "points"_a, "config"_a = ManhattanConfig{}, release_gil(),
        "The angle in [0, pi/2) by which to rotate the points about the origin into the canonical frame "
        "[rad].");
  m.def("axis_entropy", &axis_entropy, "points"_a, "angle"_a, "bin_size"_a = kMapResolution,
        "Summed entropy of the x and y histograms of the points rotated by angle [nats].");
}

}  // namespace

void define_maps(py::module_& m) {
  define_scans(m);
  define_submaps(m);
  define_manhattan(m);
}

}  // namespace partslam::python
