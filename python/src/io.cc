// Python bindings of io: reading CARMEN logs, ROS bags and the simulator through the one scan-source entry
// point (load_scan_source: a path or "sim[:SEED]"), and writing CARMEN logs. Both release the GIL.
#include "casters.h"
// (casters.h first: see its header comment)
#include "bindings.h"
#include "io/carmen_log.h"
#include "io/scan_source.h"

namespace partslam::python {

namespace py = pybind11;
using namespace pybind11::literals;
using release_gil = py::call_guard<py::gil_scoped_release>;

namespace {

void define_logs(py::module_& m) {
  py::enum_<io::FlaserSpacing>(m, "FlaserSpacing", "Angle between consecutive FLASER beams")
      .value("CARMEN", io::FlaserSpacing::kCarmen)
      .value("PI_OVER_N", io::FlaserSpacing::kPiOverN)
      .value("PI_OVER_N_MINUS_1", io::FlaserSpacing::kPiOverNMinus1);
  py::class_<io::LogReadOptions> options(m, "LogReadOptions", "How logs are read (io/carmen_log.h)");
  options.def_readwrite("min_range", &io::LogReadOptions::min_range, "[m]")
      .def_readwrite("max_usable_range", &io::LogReadOptions::max_usable_range, "[m]")
      .def_readwrite("no_return_range", &io::LogReadOptions::no_return_range, "[m]")
      .def_readwrite("flaser_spacing", &io::LogReadOptions::flaser_spacing)
      .def_readwrite("max_points", &io::LogReadOptions::max_points, "a log with more valid beams is refused")
      .def("validate", py::overload_cast<const io::LogReadOptions&>(&io::validate),
           "Raises InputError naming the field that is out of range.");
  def_keyword_init(options);

  py::class_<io::OdomReading>(m, "OdomReading", "One ODOM message")
      .def_readonly("timestamp", &io::OdomReading::timestamp)
      .def_readonly("T_world_odom", &io::OdomReading::T_world_odom)
      .def_readonly("tv", &io::OdomReading::tv)
      .def_readonly("rv", &io::OdomReading::rv)
      .def_readonly("accel", &io::OdomReading::accel);
  py::class_<io::CarmenLogStats>(m, "CarmenLogStats", "What a log held, by line and message")
      .def_readonly("lines", &io::CarmenLogStats::lines)
      .def_readonly("flaser", &io::CarmenLogStats::flaser)
      .def_readonly("robotlaser", &io::CarmenLogStats::robotlaser)
      .def_readonly("odom", &io::CarmenLogStats::odom)
      .def_readonly("comments", &io::CarmenLogStats::comments)
      .def_readonly("blank", &io::CarmenLogStats::blank)
      .def_readonly("beams", &io::CarmenLogStats::beams)
      .def_readonly("valid_beams", &io::CarmenLogStats::valid_beams)
      .def_readonly("skipped", &io::CarmenLogStats::skipped, "skipped messages by name");
  py::class_<io::CarmenLog>(m, "CarmenLog", "A whole CARMEN log")
      .def_readonly("scans", &io::CarmenLog::scans)
      .def_readonly("odometry", &io::CarmenLog::odometry)
      .def_readonly("stats", &io::CarmenLog::stats);
  m.def("read_carmen_log", &io::read_carmen_log, "path"_a, "options"_a = io::LogReadOptions{}, release_gil(),
        "Reads a whole CARMEN log (plain or gzip); InputError names the file, line and field of anything "
        "malformed.");
  m.def("write_carmen_log", &io::write_carmen_log, "path"_a, "scans"_a, "header"_a = "", release_gil(),
        "Writes scans as a corrected CARMEN log of FLASER messages (atomically).");

  py::class_<io::ScanSource>(m, "ScanSource", "Scans of a log or of the simulator, with the dataset's name")
      .def_readonly("name", &io::ScanSource::name, "the log's file name without .gz/.log/.clf, or 'sim-SEED'")
      .def_readonly("source", &io::ScanSource::source, "the spec it was loaded from")
      .def_readonly("scans", &io::ScanSource::scans);
  m.def("is_simulator_spec", &io::is_simulator_spec, "spec"_a, "True for 'sim' and 'sim:SEED'.");
  m.def("load_scan_source", &io::load_scan_source, "spec"_a, "options"_a = io::LogReadOptions{},
        release_gil(),
        "Loads a CARMEN log (plain or gzip), a ROS 1 bag (*.bag) or 'sim[:SEED]' (the built-in simulator).");
}

}  // namespace

void define_io(py::module_& m) { define_logs(m); }

}  // namespace partslam::python
