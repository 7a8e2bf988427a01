// The exceptions neurov._core raises for a refused configuration. They are
// Python classes made here, not in the package, because the compiled module
// never imports the package; neurov.errors re-exports them and derives every
// other neurov error from NeurovError.
#pragma once

#include <pybind11/pybind11.h>

#include "neurov/core/validation.hpp"

namespace neurov::bindings {

/// Raises neurov._core.ValidationError for `e` (a no-op when e is ok): the
/// message "`what`: <e.format()>", and the exception's attributes `field`,
/// `index` (-1: the whole field), `value` and `expected` are e's, so callers
/// name the field without reading the message.
void raise_validation_error(const ValidationError& e, const char* what);

}  // namespace neurov::bindings
