// The desired trajectory at one instant, as every controller takes it.
#pragma once

#include "neurov/core/types.hpp"

namespace neurov {

/// eta_d and its first two time derivatives, in the earth frame.
template <typename Scalar>
struct DesiredState {
  Vector6<Scalar> eta_d = Vector6<Scalar>::Zero();
  Vector6<Scalar> eta_d_dot = Vector6<Scalar>::Zero();
  Vector6<Scalar> eta_d_ddot = Vector6<Scalar>::Zero();
};

}  // namespace neurov
