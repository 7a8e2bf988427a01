// neurov._core: the compiled part of neurov. The Python package re-exports it.
// The binding files mirror the C++ layers: core/, model/, control/, sim.
#include <pybind11/pybind11.h>

#include "bindings.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  // The stub generated from this module (tools/generate_stubs.py) carries this text.
  m.doc() =
      "neurov's C++ core: vehicle dynamics, Euler-angle kinematics, integrator, reference "
      "model, controllers and closed-loop simulation (double precision). Import from "
      "``neurov``, not from here.\n\n"
      "Every array argument accepts anything ``numpy.asarray`` turns into a real (float or "
      "integer) array of the stated shape: lists, integer arrays, non-contiguous and read-only "
      "arrays. A wrong shape, NaN or Inf raises ``ValueError`` and a wrong dtype (str, complex, "
      "object, bool) or ``None`` raises ``TypeError``; both name the argument. Scalars are real "
      "numbers (not ``bool``). Every returned array is a new, writeable ``float64`` array.";
  m.attr("__version__") = NEUROV_VERSION_INFO;

#define NEUROV_CALL_BINDING(name) neurov::bindings::bind_##name(m);
  NEUROV_BINDINGS(NEUROV_CALL_BINDING)
#undef NEUROV_CALL_BINDING
}
