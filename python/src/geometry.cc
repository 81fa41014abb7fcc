// Python bindings of core/types.h: the shared lattice constants and the few pose and point-set operations
// that callers need to read the library's frames (compose T_world_map with T_map_query, move points into a
// frame).
#include "casters.h"
// (casters.h first: see its header comment)
#include "bindings.h"
#include "core/types.h"

namespace partslam::python {

namespace py = pybind11;
using namespace pybind11::literals;

void define_geometry(py::module_& m) {
  m.attr("MAP_RESOLUTION") = kMapResolution;
  m.attr("CROP_SIZE") = kCropSize;
  m.attr("DEFAULT_MAX_RANGE") = kDefaultMaxRange;

  m.def("transform", &transform, "T"_a, "points"_a,
        "The points mapped by the pose T = (x, y, theta): rotation by theta, then translation by (x, y).");
  m.def(
      "compose", [](const Pose2& T_a_b, const Pose2& T_b_c) { return T_a_b * T_b_c; }, "T_a_b"_a, "T_b_c"_a,
      "T_a_c = T_a_b * T_b_c (angles wrapped to (-pi, pi]).");
  m.def(
      "inverse", [](const Pose2& T) { return T.inverse(); }, "T"_a, "The inverse pose: T_b_a from T_a_b.");
  m.def("wrap_angle", &wrap_angle, "angle"_a, "The angle wrapped to (-pi, pi] [rad].");
  m.def(
      "centroid", [](const Points2& points) { return to_tuple(centroid(points)); }, "points"_a,
      "Mean (x, y) of the points; (0, 0) for none.");
  m.def("bounding_box", &bounding_box, "points"_a,
        "(x_min, x_max, y_min, y_max) of the points; all 0 for none.");
}

}  // namespace partslam::python
