// How the library's value types cross into Python, for every binding file. Include it first in each of them:
// the casters and the opaque Scans must look the same to every translation unit of the module.
//   Points2 (std::vector<Vec2>)  <->  numpy float64 array of shape (n, 2), copied both ways; anything numpy
//   can
//                                     turn into float64 is accepted, a wrong shape or a non-finite coordinate
//                                     raises partslam.InputError (a ValueError) naming the row
//   Pose2                        <->  tuple (x, y, theta) [m, m, rad]; a non-finite one raises InputError
//   Box2                         <->  tuple (x_min, x_max, y_min, y_max) [m]; a non-finite one raises InputError
//   Scans                        opaque: partslam.Scans, a list-like held in C++ (a log is not copied per
//   call) std::filesystem::path        <->  str or os.PathLike
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <pybind11/stl_bind.h>

#include <vector>

#include "core/maps/scan.h"
#include "core/types.h"

PYBIND11_MAKE_OPAQUE(partslam::Scans)

namespace pybind11::detail {

template <>
struct type_caster<partslam::Points2> {
  PYBIND11_TYPE_CASTER(partslam::Points2, const_name("numpy.ndarray[float64[n, 2]]"));
  /// Without convert only float64 arrays are taken (so overloads on other types are tried first).
  bool load(handle src, bool convert);
  static handle cast(const partslam::Points2& points, return_value_policy policy, handle parent);
};

template <>
struct type_caster<partslam::Pose2> {
  PYBIND11_TYPE_CASTER(partslam::Pose2, const_name("Tuple[float, float, float]"));
  bool load(handle src, bool convert);
  static handle cast(const partslam::Pose2& pose, return_value_policy policy, handle parent);
};

template <>
struct type_caster<partslam::Box2> {
  PYBIND11_TYPE_CASTER(partslam::Box2, const_name("Tuple[float, float, float, float]"));
  bool load(handle src, bool convert);
  static handle cast(const partslam::Box2& box, return_value_policy policy, handle parent);
};

}  // namespace pybind11::detail

namespace partslam::python {

/// A 1-D float64 numpy array holding a copy of the values (timestamps, travel, scores).
pybind11::array_t<double> to_array(const std::vector<double>& values);

/// (x, y) of a 2D vector.
pybind11::tuple to_tuple(const Vec2& v);

}  // namespace partslam::python
