// What the binding files share: one define_<area>() per area of the library, called by module.cc in this
// order, and the keyword construction of config and record structs (SubmapConfig(window_length=3.0,
// spacing=1.0)).
#pragma once

#include <pybind11/pybind11.h>

#include <string>

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

/// Adds __init__(**fields) to a class whose fields are bound as read-write properties: starts from the C++
/// defaults and sets each field given; an unknown name raises TypeError.
template <typename T, typename... Options>
void def_keyword_init(pybind11::class_<T, Options...>& cls) {
  const std::string name = cls.attr("__name__").template cast<std::string>();
  cls.def(pybind11::init([name](const pybind11::kwargs& fields) {
            pybind11::object object = pybind11::cast(T{});
            for (const auto& [key, value] : fields) {
              if (!pybind11::hasattr(object, key)) {
                throw pybind11::type_error(name + "() got an unexpected keyword argument '" +
                                           pybind11::str(key).template cast<std::string>() + "'");
              }
              pybind11::setattr(object, key, value);
            }
            return object.template cast<T>();
          }),
          ("A " + name + " with the library's defaults, changed by any fields given as keywords.").c_str());
}

}  // namespace partslam::python
