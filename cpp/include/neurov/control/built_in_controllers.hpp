// The one list of the built-in controllers. From it come the Python classes
// and their configurations, the all-C++ closed loop's dispatch
// (run_closed_loop), neurov._core.BUILT_IN_CONTROLLERS (type name -> class)
// and so the Python registry, and the typed contract suite of the C++ tests.
// A controller joins with its header (with NEUROV_CONTROLLER_NAMES and, for
// the generic bindings, config_fields) and one line here.
#pragma once

#include <cstddef>
#include <utility>

#include "neurov/control/ardusub_controller.hpp"
#include "neurov/control/computed_torque_controller.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/nn_controller.hpp"
#include "neurov/control/pd_controller.hpp"
#include "neurov/control/pid_controller.hpp"
#include "neurov/control/sliding_mode_controller.hpp"
#include "neurov/control/super_twisting_controller.hpp"

namespace neurov {

template <typename... Ts>
struct TypeList {
  static constexpr std::size_t size = sizeof...(Ts);
};

/// The built-in controllers in Scalar, in the order the bindings register them.
template <typename Scalar>
using BuiltInControllers =
    TypeList<NNAdaptiveController<Scalar>, LinearAdaptiveController<Scalar>, PDController<Scalar>,
             PIDController<Scalar>, SlidingModeController<Scalar>,
             ComputedTorqueController<Scalar>, SuperTwistingController<Scalar>,
             ArduSubController<Scalar>>;

/// A type carried as a value, for for_each_type's function.
template <typename T>
struct TypeTag {
  using type = T;
};

/// f(TypeTag<T>{}) for each T of the list, in order.
template <typename... Ts, typename F>
void for_each_type(TypeList<Ts...>, F&& f) {
  (f(TypeTag<Ts>{}), ...);
}

}  // namespace neurov
