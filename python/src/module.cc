// The Python module `partslam`: the library's version, partslam.InputError (a ValueError, raised for every
// partslam::InputError with its message intact: bad input and bad parameters), and each area's bindings.
#include "casters.h"
// (casters.h first: see its header comment)
#include "bindings.h"
#include "core/error.h"

PYBIND11_MODULE(partslam, m) {
  m.doc() =
      "PartSLAM: fast, succinct 1-to-N matching of 2D laser maps (read logs, build submaps, dMM with the "
      "relative pose, CPD parts and descriptors, ranking, the map database). Points are numpy float64 arrays "
      "of shape (n, 2), poses tuples (x, y, theta), boxes tuples (x_min, x_max, y_min, y_max).";
  m.attr("__version__") = PARTSLAM_VERSION;
  pybind11::register_exception<partslam::InputError>(m, "InputError", PyExc_ValueError);
  partslam::python::define_geometry(m);
  partslam::python::define_maps(m);
  partslam::python::define_matching(m);
  partslam::python::define_parts(m);
  partslam::python::define_io(m);
  partslam::python::define_localization(m);
}
