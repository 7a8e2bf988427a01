// The sea models' per-step calls (and their create functions) must not touch
// the heap: the current's advance, the waves' direct and recursive
// evaluation, and a payload event applied mid-run. The counting operator new
// is defined in alloc_foundation.cpp.
#include "alloc_probe.hpp"

#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "neurov/model/vehicle.hpp"
#include "neurov/sim/gauss_markov_current.hpp"
#include "neurov/sim/payload.hpp"
#include "neurov/sim/waves.hpp"

namespace {

using namespace neurov;
using alloc_probe::watch;
using alloc_probe::Window;

NEUROV_SCALAR_SUITE(SeaAllocTest);

TYPED_TEST(SeaAllocTest, CurrentWavesAndPayloadDoNotAllocate) {
  using S = TypeParam;
  GaussMarkovCurrentConfig<S> cc;
  cc.direction_std = S(5);
  cc.vertical_angle_std = S(1);
  WaveConfig<S> wc;
  wc.spreading = S(2);
  // The wave field is about 90 kB: on the heap, made before the window.
  auto waves = std::make_unique<Waves<S>>();
  GaussMarkovCurrent<S> current;
  const Vehicle<S> vehicle(nerov_parameters<S>());
  Vehicle<S> loaded;
  PayloadEvent<S> event;
  event.mass = S(10);
  event.mass_position = Vector3<S>(S(0.1), S(0), S(0.05));
  event.buoyancy = S(-20);
  ValidationError errors[3];
  Status worst_status = Status::ok;
  volatile double sink = 0;

  const Window w = watch([&] {
    errors[0] = GaussMarkovCurrent<S>::create(cc, 7, current);
    errors[1] = Waves<S>::create(wc, 7, *waves);
    Vector3<S> p(S(0), S(0), S(10));
    worst_status = worst(worst_status, waves->start(0.0, p, S(0.02)));
    WaveKinematics<S> direct;
    for (int i = 0; i < 3000; ++i) {  // 60 s at 0.02 s, three resyncs
      p.x() += S(0.02);
      p.z() += S(0.001);
      worst_status = worst(worst_status, current.advance(S(0.02)));
      worst_status = worst(worst_status, waves->advance(p));
      sink = sink + static_cast<double>(current.velocity().sum() + waves->kinematics().velocity.sum() +
                                        waves->kinematics().acceleration.sum());
    }
    worst_status = worst(worst_status, waves->evaluate(waves->time(), p, direct));
    sink = sink + static_cast<double>(direct.elevation);
    errors[2] = apply_payload(event, vehicle, loaded);
  });

  EXPECT_EQ(w.new_calls, 0) << "operator new was called";
  EXPECT_EQ(w.eigen_failures, 0) << "Eigen allocated (or asserted)";
  for (const auto& e : errors) EXPECT_TRUE(e.ok()) << (e.field ? e.field : "");
  EXPECT_EQ(worst_status, Status::ok);
  EXPECT_TRUE(loaded.valid());
  EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
}

}  // namespace
