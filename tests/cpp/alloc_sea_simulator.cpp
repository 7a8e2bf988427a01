// A run in the sea - Gauss-Markov current, 512 wave components and payload
// events - steps and resets without touching the heap, in float and double.
#include "alloc_probe.hpp"
#include "alloc_closed_loop.hpp"

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "held_command.hpp"

namespace {

using namespace neurov;
using alloc_probe::expect_run_does_not_allocate;

/// Station keeping at 8 m in a Gauss-Markov current and spread waves, with a
/// payload picked up and one dropped.
template <typename S>
SimulationConfig<S> sea_config() {
  SimulationConfig<S> c;
  c.duration = S(30);
  c.eta0 << S(0), S(0), S(8), S(0), S(0), S(0);
  c.command = neurov_test::held(c.eta0);
  c.noise_eta.setConstant(S(0.01));
  c.current_model = CurrentModel::gauss_markov;
  c.gauss_markov_current.direction_std = S(5);
  WaveConfig<S> w;
  w.components = 512;
  w.spreading = S(2);
  c.waves = w;
  PayloadEvent<S> pick, drop;
  pick.time = S(5);
  pick.mass = S(10);
  pick.mass_position = Vector3<S>(S(0.2), S(0), S(0.1));
  drop.time = S(20);
  drop.buoyancy = S(-30);
  drop.damping_scale.setConstant(S(1.2));
  c.payload = {pick, drop};
  return c;
}

NEUROV_SCALAR_SUITE(SeaSimulatorAllocTest);

TYPED_TEST(SeaSimulatorAllocTest, StepAndResetDoNotAllocate) {
  using S = TypeParam;
  PDConfig<S> cfg;
  cfg.kp.setConstant(S(50));
  cfg.kd.setConstant(S(80));
  PDController<S> pd;
  ASSERT_TRUE(PDController<S>::create(cfg, pd).ok());
  expect_run_does_not_allocate<S>(pd, sea_config<S>(), 0);  // no sensor fault: nothing to refuse
}

}  // namespace
