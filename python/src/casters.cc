// The conversions of casters.h: numpy point arrays and pose / box tuples.
#include "casters.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace pybind11::detail {
namespace {

std::string shape_text(const array& a) {
  std::string text = "(";
  for (ssize_t d = 0; d < a.ndim(); ++d) text += (d > 0 ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

std::string number_text(double v) { return pybind11::str(pybind11::float_(v)); }

// A sequence of exactly n numbers, as doubles; false when src is not one.
template <std::size_t n>
bool load_numbers(handle src, bool convert, double (&out)[n]) {
  if (!isinstance<sequence>(src) || isinstance<str>(src) || isinstance<bytes>(src)) return false;
  const auto items = reinterpret_borrow<sequence>(src);
  if (items.size() != n) return false;
  for (std::size_t i = 0; i < n; ++i) {
    make_caster<double> number;
    if (!number.load(items[i], convert)) return false;
    out[i] = cast_op<double>(number);
  }
  return true;
}

}  // namespace

bool type_caster<partslam::Points2>::load(handle src, bool convert) {
  if (!convert && !array_t<double>::check_(src)) return false;
  const auto a = array_t<double, array::c_style | array::forcecast>::ensure(src);
  if (!a) return false;  // not array-like (ensure has cleared the Python error)
  if (a.ndim() != 2 || a.shape(1) != 2) {
    throw partslam::InputError("points: expected an array of shape (n, 2), got shape " + shape_text(a));
  }
  const auto rows = a.unchecked<2>();
  value.clear();
  value.reserve(static_cast<std::size_t>(rows.shape(0)));
  for (ssize_t i = 0; i < rows.shape(0); ++i) {
    if (!std::isfinite(rows(i, 0)) || !std::isfinite(rows(i, 1))) {
      throw partslam::InputError("points: row " + std::to_string(i) + " is not finite (" +
                                 number_text(rows(i, 0)) + ", " + number_text(rows(i, 1)) + ")");
    }
    value.emplace_back(rows(i, 0), rows(i, 1));
  }
  return true;
}

handle type_caster<partslam::Points2>::cast(const partslam::Points2& points, return_value_policy, handle) {
  array_t<double> out({static_cast<ssize_t>(points.size()), ssize_t{2}});
  auto rows = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    rows(static_cast<ssize_t>(i), 0) = points[i].x();
    rows(static_cast<ssize_t>(i), 1) = points[i].y();
  }
  return out.release();
}

// Three (four) numbers that are not all finite are the right type with a bad value: InputError naming them
// (a NaN pose would otherwise flow through compose, transform and matching as NaN results).
template <std::size_t n>
void check_finite(const char* what, const char* layout, const double (&v)[n]) {
  for (double x : v) {
    if (std::isfinite(x)) continue;
    std::string text;
    for (double y : v) text += (text.empty() ? "" : ", ") + number_text(y);
    throw partslam::InputError(std::string(what) + ": " + layout + " must be finite, got (" + text + ")");
  }
}

bool type_caster<partslam::Pose2>::load(handle src, bool convert) {
  double v[3];
  if (!load_numbers(src, convert, v)) return false;
  check_finite("pose", "(x, y, theta)", v);
  value = {v[0], v[1], v[2]};
  return true;
}

handle type_caster<partslam::Pose2>::cast(const partslam::Pose2& pose, return_value_policy, handle) {
  return make_tuple(pose.x, pose.y, pose.theta).release();
}

bool type_caster<partslam::Box2>::load(handle src, bool convert) {
  double v[4];
  if (!load_numbers(src, convert, v)) return false;
  check_finite("box", "(x_min, x_max, y_min, y_max)", v);
  value = {v[0], v[1], v[2], v[3]};
  return true;
}

handle type_caster<partslam::Box2>::cast(const partslam::Box2& box, return_value_policy, handle) {
  return make_tuple(box.x_min, box.x_max, box.y_min, box.y_max).release();
}

}  // namespace pybind11::detail

namespace partslam::python {

pybind11::array_t<double> to_array(const std::vector<double>& values) {
  return pybind11::array_t<double>(static_cast<pybind11::ssize_t>(values.size()), values.data());
}

pybind11::tuple to_tuple(const Vec2& v) { return pybind11::make_tuple(v.x(), v.y()); }

}  // namespace partslam::python
