// The command of most test runs: one pose held from t = 0 to the end.
#pragma once

#include "neurov/core/types.hpp"
#include "neurov/sim/config.hpp"

namespace neurov_test {

template <typename S>
neurov::Command<S> held(const neurov::Vector6<S>& pose) {
  neurov::Command<S> c;
  c.times.setZero(1);
  c.poses = pose.transpose();
  return c;
}

}  // namespace neurov_test
