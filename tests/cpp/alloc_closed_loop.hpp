// A whole closed loop watched for allocations: what the simulator's
// allocation tests (alloc_simulator.cpp, alloc_sea_simulator.cpp) run on
// their configurations.
#pragma once

#include "alloc_probe.hpp"

#include <cstdint>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"

namespace alloc_probe {

/// Runs a whole closed loop (controller, report, simulator step), a rejected
/// step and a reset, twice, in the watch window: nothing allocates, the plant
/// steps without fault and the controller refuses at least min_refused steps.
template <typename S, typename Controller>
void expect_run_does_not_allocate(Controller& controller, const neurov::SimulationConfig<S>& config,
                                  long min_refused) {
  using namespace neurov;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  Eigen::Matrix<S, 1, kMaxLoggedParameters> parameters;
  const int logged = controller_report<S>(controller, Status::ok, parameters).parameter_count;
  Simulator<S> sim;
  ASSERT_TRUE(Simulator<S>::create(vehicle, config, sim, logged).ok());
  Vector6<S> tau;
  long refused = 0;
  Status worst_plant = Status::ok;
  const Window w = watch([&] {
    for (int run = 0; run < 2; ++run) {
      while (!sim.done()) {
        const Observation<S>& o = sim.observation();
        const Status cs = controller.step(o.eta, o.nu, o.desired, tau);
        refused += cs != Status::ok;
        worst_plant = worst(worst_plant, sim.step(tau, controller_report<S>(controller, cs, parameters)));
      }
      // Rejected calls change nothing and allocate nothing either.
      worst_plant = worst(worst_plant, sim.step(tau, ControllerReport<S>{}) == Status::invalid_argument
                                           ? Status::ok
                                           : Status::non_finite_output);
      sim.reset(static_cast<std::uint64_t>(run + 5));
      controller.reset();
    }
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
  EXPECT_EQ(worst_plant, Status::ok);
  EXPECT_GE(refused, min_refused);
}

}  // namespace alloc_probe
