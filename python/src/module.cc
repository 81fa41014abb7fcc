// The Python module `partslam`: the library's version, partslam.InputError (a ValueError, raised for every
// partslam::InputError with its message intact: bad input and bad parameters), and each area's bindings.
#include "casters.h"
// (casters.h first: see its header comment)
#include "bindings.h"
#include "core/error.h"

#include <exception>
#include <string>

PYBIND11_MODULE(partslam, m) {
  m.doc() =
      "PartSLAM: fast, succinct 1-to-N matching of 2D laser maps (read logs, build submaps, dMM with the "
      "relative pose, CPD parts and descriptors, ranking, the map database). Points are numpy float64 arrays "
      "of shape (n, 2), poses tuples (x, y, theta), boxes tuples (x_min, x_max, y_min, y_max).";
  m.attr("__version__") = PARTSLAM_VERSION;
  // The translator register_exception installs passes what() to PyErr_SetString, which drops the message (an
  // InputError() with no text) when it is not valid UTF-8 (a message quoting a binary file's bytes, e.g. a PNG
  // read as a log). This one decodes it with backslashreplace, so every message arrives.
  static pybind11::exception<partslam::InputError> input_error(m, "InputError", PyExc_ValueError);
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const partslam::InputError& e) {
      const std::string what = e.what();
      PyObject* text = PyUnicode_DecodeUTF8(what.data(), static_cast<Py_ssize_t>(what.size()), "backslashreplace");
      if (!text) {  // cannot happen with backslashreplace; keep the error it raised rather than none
        return;
      }
      PyErr_SetObject(input_error.ptr(), text);
      Py_DECREF(text);
    }
  });
  partslam::python::define_geometry(m);
  partslam::python::define_maps(m);
  partslam::python::define_matching(m);
  partslam::python::define_parts(m);
  partslam::python::define_io(m);
  partslam::python::define_localization(m);
}
