// Shared helpers for the neurov C++ tests: the typed suites of scalar_suite.hpp,
// a seeded random source, tolerances that scale with the scalar's epsilon
// and random but physically valid vehicles.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/core/types.hpp"
#include "neurov/model/vehicle.hpp"
#include "scalar_suite.hpp"

namespace neurov_test {

template <typename S>
constexpr S eps() {
  return std::numeric_limits<S>::epsilon();
}

constexpr double kPi = 3.14159265358979323846;

/// Random points per property test.
constexpr int kPoints = 200;

/// Draws in double and casts, so the float and double instantiations of a
/// typed test visit the same points (up to rounding) for the same seed.
/// (std::uniform_real_distribution is implementation-defined, so another
/// standard library visits other points; the tests are properties that must
/// hold at any point, and the controller tests are tuned to this sequence.)
class Rng {
 public:
  explicit Rng(std::uint32_t seed) : gen_(seed) {}

  template <typename S>
  S uniform(double lo, double hi) {
    return static_cast<S>(std::uniform_real_distribution<double>(lo, hi)(gen_));
  }

  template <typename S>
  neurov::Vector3<S> vec3(double lo, double hi) {
    neurov::Vector3<S> v;
    for (int i = 0; i < 3; ++i) v(i) = uniform<S>(lo, hi);
    return v;
  }

  template <typename S>
  neurov::Vector6<S> vec6(double lo, double hi) {
    neurov::Vector6<S> v;
    for (int i = 0; i < 6; ++i) v(i) = uniform<S>(lo, hi);
    return v;
  }

  /// A pose with |theta| <= max_pitch, so 1/cos(theta) stays bounded.
  template <typename S>
  neurov::Vector6<S> pose(double max_pitch = 1.3) {
    neurov::Vector6<S> eta;
    eta.template head<3>() = vec3<S>(-10.0, 10.0);
    eta(3) = uniform<S>(-kPi, kPi);
    eta(4) = uniform<S>(-max_pitch, max_pitch);
    eta(5) = uniform<S>(-kPi, kPi);
    return eta;
  }

  /// Body velocity of the size an ROV sees: about 1 m/s and 1 rad/s.
  template <typename S>
  neurov::Vector6<S> velocity() {
    return vec6<S>(-1.0, 1.0);
  }

  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic> matrix(int rows, int cols, double lo,
                                                               double hi) {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic> m(rows, cols);
    for (int j = 0; j < cols; ++j)
      for (int i = 0; i < rows; ++i) m(i, j) = uniform<double>(lo, hi);
    return m;
  }

  /// The underlying engine, for draws from other distributions.
  std::mt19937& engine() { return gen_; }

 private:
  std::mt19937 gen_;
};

/// A vehicle that exercises every term the NEROV numbers leave at zero: r_g
/// off the origin, a full (non-diagonal) added-mass matrix, W != B and r_b
/// off r_g. Built in double and cast, so the float copy is just as valid.
template <typename S>
neurov::VehicleParameters<S> random_vehicle_parameters(Rng& rng, neurov::CoriolisForm form) {
  neurov::VehicleParameters<double> p;
  p.mass = rng.uniform<double>(50.0, 200.0);
  p.centre_of_gravity = rng.vec3<double>(-0.1, 0.1);
  // I_o = I_c + m S(r_g)^T S(r_g) (parallel axes) keeps M_RB positive definite.
  const Eigen::Matrix3d a = rng.matrix(3, 3, -1.0, 1.0);
  const Eigen::Matrix3d s = neurov::skew<double>(p.centre_of_gravity);
  Eigen::Matrix3d inertia =
      a * a.transpose() + 10.0 * Eigen::Matrix3d::Identity() + p.mass * s.transpose() * s;
  p.inertia = 0.5 * (inertia + inertia.transpose());  // exactly symmetric
  const Eigen::Matrix<double, 6, 6> b = rng.matrix(6, 6, -3.0, 3.0);
  Eigen::Matrix<double, 6, 6> added = b * b.transpose();
  added.diagonal().array() += 5.0;
  p.added_mass = 0.5 * (added + added.transpose());
  p.weight = p.mass * 9.81;
  p.buoyancy = p.weight * rng.uniform<double>(0.9, 1.1);
  p.centre_of_buoyancy = p.centre_of_gravity + rng.vec3<double>(-0.05, 0.05);
  p.linear_damping = rng.vec6<double>(10.0, 100.0);
  p.quadratic_damping = rng.vec6<double>(10.0, 200.0);
  p.coriolis_form = form;
  return p.template cast<S>();
}

/// NEROV with the restoring forces switched off: W = B and r_b = r_g = 0.
template <typename S>
neurov::VehicleParameters<S> nerov_without_restoring() {
  auto p = neurov::nerov_parameters<S>();
  p.centre_of_buoyancy.setZero();
  return p;
}

/// Largest absolute entry of a - b, with both matrices printed on failure.
template <typename A, typename B>
::testing::AssertionResult all_near(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b,
                                    double tol) {
  const auto ad = a.template cast<double>().eval();
  const auto bd = b.template cast<double>().eval();
  if (ad.rows() != bd.rows() || ad.cols() != bd.cols())
    return ::testing::AssertionFailure() << "shape mismatch";
  const double err = (ad - bd).cwiseAbs().maxCoeff();
  if (err <= tol) return ::testing::AssertionSuccess();
  std::ostringstream os;
  os << "max |a - b| = " << err << " > tol " << tol << "\na =\n" << ad << "\nb =\n" << bd;
  return ::testing::AssertionFailure() << os.str();
}

/// A case of a validation test: a change that makes a valid Config invalid,
/// and the field the refusal must name.
template <typename Config>
struct BadField {
  const char* field;
  void (*mutate)(Config&);
};

/// The same bits, NaN payloads and signed zeros included: "nothing changed"
/// for a refused step, "the same arithmetic" for two paths.
template <typename S, int R, int C>
bool same_bits(const Eigen::Matrix<S, R, C>& a, const Eigen::Matrix<S, R, C>& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), sizeof(S) * static_cast<std::size_t>(a.size())) == 0;
}

/// Stores a measured number (error, drift, ratio) in the XML report, so the
/// margin to a tolerance can be read from `--gtest_output=xml`.
inline void record(const std::string& key, double value) {
  std::ostringstream os;
  os.precision(3);
  os << std::scientific << value;
  ::testing::Test::RecordProperty(key, os.str());
}

/// Max-abs of a matrix in double, used to scale relative tolerances.
template <typename A>
double max_abs(const Eigen::MatrixBase<A>& a) {
  return a.template cast<double>().cwiseAbs().maxCoeff();
}

/// A vehicle from valid parameters (a failure names the field).
template <typename S>
neurov::Vehicle<S> make_vehicle(const neurov::VehicleParameters<S>& p) {
  neurov::Vehicle<S> v;
  const neurov::ValidationError e = neurov::Vehicle<S>::create(p, v);
  EXPECT_TRUE(e.ok()) << (e.field ? e.field : "");
  return v;
}

}  // namespace neurov_test
