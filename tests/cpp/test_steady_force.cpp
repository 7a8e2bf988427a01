// The steady force (sim/disturbances/steady_force.hpp): a force fixed in the
// earth frame acting at a body point from its start on, in body axes with its
// moment, and its fields checked by their description.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "neurov/neurov.hpp"
#include "held_command.hpp"

namespace {

using namespace neurov;

template <typename Scalar>
SimulationConfig<Scalar> facing_east(Scalar start) {
  SimulationConfig<Scalar> c;
  c.dt = Scalar(0.2);
  c.duration = Scalar(1);
  c.eta0 << 0, 0, 10, 0, 0, Scalar(M_PI / 2);
  c.command = neurov_test::held(c.eta0);
  SteadyForceConfig<Scalar> f;
  f.force << 100, 0, 0;  // northward
  f.point << Scalar(0.5), 0, 0;
  f.start = start;
  c.steady_force = f;
  return c;
}

template <typename Scalar>
SimulationResult<Scalar> run_still(const SimulationConfig<Scalar>& c) {
  Vehicle<Scalar> v;
  EXPECT_TRUE(Vehicle<Scalar>::create(nerov_parameters<Scalar>(), v).ok());
  Simulator<Scalar> sim;
  EXPECT_TRUE(Simulator<Scalar>::create(v, c, sim).ok());
  while (!sim.done()) sim.step(Vector6<Scalar>::Zero(), ControllerReport<Scalar>{});
  SimulationResult<Scalar> r;
  sim.release_result(r);
  return r;
}

TEST(SteadyForce, ActsInBodyAxesWithItsMomentAtThePoint) {
  // Facing east, a northward force pushes the vehicle to its left (body -y),
  // and at 0.5 m ahead of the origin it yaws it to the left: r x F = (0, 0, -50).
  const auto r = run_still(facing_east<double>(0.0));
  const Vector6<double> expected = (Vector6<double>() << 0, -100, 0, 0, 0, -50).finished();
  EXPECT_LT((r.disturbance.row(0).transpose() - expected).norm(), 1e-9);
  // float: the same law.
  const auto rf = run_still(facing_east<float>(0.0f));
  EXPECT_LT((rf.disturbance.row(0).transpose().cast<double>() - expected).norm(), 1e-3);
}

TEST(SteadyForce, NothingBeforeItsStart) {
  const auto r = run_still(facing_east<double>(0.5));
  EXPECT_EQ(r.disturbance.row(0).norm(), 0.0);  // t = 0
  EXPECT_EQ(r.disturbance.row(2).norm(), 0.0);  // t = 0.4
  EXPECT_GT(r.disturbance.row(3).norm(), 99.0);  // t = 0.6
}

TEST(SteadyForce, BadFieldsAreRefusedByName) {
  SimulationConfig<double> c = facing_east<double>(0.0);
  c.steady_force->force(1) = std::numeric_limits<double>::quiet_NaN();
  ValidationError e = validate(c);
  ASSERT_TRUE(e);
  EXPECT_STREQ(e.field, "force");
  EXPECT_EQ(e.index, 1);
  c = facing_east<double>(-1.0);
  e = validate(c);
  ASSERT_TRUE(e);
  EXPECT_STREQ(e.field, "start");
  EXPECT_STREQ(e.expected, ">= 0 and finite");
  c.steady_force.reset();  // absent: no force, nothing to check
  EXPECT_FALSE(validate(c));
}

}  // namespace
