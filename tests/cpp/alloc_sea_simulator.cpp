// A run in the sea - Gauss-Markov current, 512 wave components and payload
// events - steps and resets without touching the heap, in float and double.
#include "alloc_probe.hpp"

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"
#include "held_command.hpp"

namespace {

using namespace neurov;
using alloc_probe::watch;
using alloc_probe::Window;

NEUROV_SCALAR_SUITE(SeaSimulatorAllocTest);

TYPED_TEST(SeaSimulatorAllocTest, StepAndResetDoNotAllocate) {
  using S = TypeParam;
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
  PDConfig<S> cfg;
  cfg.kp.setConstant(S(50));
  cfg.kd.setConstant(S(80));
  PDController<S> pd;
  ASSERT_TRUE(PDController<S>::create(cfg, pd).ok());
  const Vehicle<S> vehicle(nerov_parameters<S>());
  Simulator<S> sim;
  ASSERT_TRUE(Simulator<S>::create(vehicle, c, sim).ok());
  Vector6<S> tau;
  Status worst_plant = Status::ok;
  const Window win = watch([&] {
    for (int run = 0; run < 2; ++run) {
      while (!sim.done()) {
        const Observation<S>& o = sim.observation();
        const Status cs = pd.step(o.eta, o.nu, o.desired, tau);
        ControllerReport<S> report;
        report.status = cs;
        worst_plant = worst(worst_plant, sim.step(tau, report));
      }
      sim.reset(static_cast<std::uint64_t>(run + 5));
      pd.reset();
    }
  });
  EXPECT_EQ(win.new_calls, 0);
  EXPECT_EQ(win.eigen_failures, 0);
  EXPECT_EQ(worst_plant, Status::ok);
}

}  // namespace
