// What the binding files share: one define_<area>() per area of the library, called by module.cc in this
// order, and the keyword construction of config and record structs (SubmapConfig(window_length=3.0,
// spacing=1.0)).
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <type_traits>

#include "io/formats/config_fields.h"

namespace partslam::python {

// core/types.h: the lattice constants, poses and point transforms
void define_geometry(pybind11::module_& m);
// core/maps: scans, submaps, Manhattan alignment
void define_maps(pybind11::module_& m);
// core/matching: dMM, method specs, ranking
void define_matching(pybind11::module_& m);
// core/parts and the dictionary map: CPD, codec, descriptor matching
void define_parts(pybind11::module_& m);
// io: logs, scan sources, the map database, stored descriptors
void define_io(pybind11::module_& m);
// building maps (core/maps/grid_map.h, io/formats/map_server.h), point files, global localisation
// (core/matching/localizer.h)
void define_localization(pybind11::module_& m);

/// Gives a class whose fields are bound as read-write properties a keyword form: __init__(**fields) starts
/// from the C++ defaults and sets each field given (an unknown name raises TypeError), and, unless the class
/// has its own, __repr__ prints that form back: SubmapConfig(window_length=2.0, ...).
template <typename T, typename... Options>
void def_keyword_init(pybind11::class_<T, Options...>& cls) {
  namespace py = pybind11;
  const std::string name = cls.attr("__name__").template cast<std::string>();
  cls.def(py::init([name](const py::kwargs& fields) {
            py::object object = py::cast(T{});
            for (const auto& [key, value] : fields) {
              if (!py::hasattr(object, key)) {
                throw py::type_error(name + "() got an unexpected keyword argument '" +
                                     py::str(key).template cast<std::string>() + "'");
              }
              py::setattr(object, key, value);
            }
            return object.template cast<T>();
          }),
          ("A " + name + " with the library's defaults, changed by any fields given as keywords.").c_str());
  if (cls.attr("__dict__").contains("__repr__")) return;
  cls.def("__repr__", [name](const py::object& self) {
    const py::object property = py::module_::import("builtins").attr("property");
    std::string text = name + "(";
    for (const auto& [key, value] : py::dict(py::type::of(self).attr("__dict__"))) {
      if (!py::isinstance(value, property)) continue;
      text += (text.back() == '(' ? "" : ", ") + py::str(key).template cast<std::string>() + "=" +
              py::repr(self.attr(key)).template cast<std::string>();
    }
    return text + ")";
  });
}

/// The walker of a settings table (io/formats/config_fields.h) that binds each field as a read-write property.
template <typename Class, typename T>
struct ConfigFieldBinder {
  Class& cls;
  template <class M>
  void field(const char* key, M T::*member, const char* help) {
    cls.def_readwrite(key, member, help);
  }
  template <class M, class P>
  void field(const char* key, M T::*member, P M::*part, const char* help) {
    cls.def_property(
        key, [member, part](const T& t) { return (t.*member).*part; },
        [member, part](T& t, P value) { (t.*member).*part = value; }, help);
  }
  template <class S>
  void section(const char* key, S T::*member, const char* help) {
    cls.def_readwrite(key, member, help);
  }
};

/// Binds every field of T's settings table (io/formats/config_fields.h, the one the settings files are read and
/// printed with) as a read-write property of cls, with its help: a nested struct (its class bound first) as one
/// property, a value inside a member struct under its own key.
template <typename T, typename... Options>
void def_config_fields(pybind11::class_<T, Options...>& cls) {
  ConfigFieldBinder<pybind11::class_<T, Options...>, T> binder{cls};
  io::config_fields(binder, std::type_identity<T>{});
}

}  // namespace partslam::python
