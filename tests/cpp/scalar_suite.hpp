// The scalar types the typed tests run over, and NEUROV_SCALAR_SUITE, which
// declares a suite on them. Apart from test_support.hpp so that the
// allocation tests can use it without the helpers' heavier includes (they
// must include alloc_probe.hpp before any Eigen header).
#pragma once

#include <string>
#include <type_traits>

#include <gtest/gtest.h>

namespace neurov_test {

// A build may leave float out (NEUROV_TEST_FLOAT=OFF): the sanitised CI build
// does, since its time is the instantiations' and float's memory is checked
// by valgrind on the Release build.
#ifdef NEUROV_TEST_DOUBLE_ONLY
using Scalars = ::testing::Types<double>;
#else
using Scalars = ::testing::Types<float, double>;
#endif

/// The fixture of every test typed on the scalar (NEUROV_SCALAR_SUITE).
template <typename S>
class ScalarTest : public ::testing::Test {};

/// Readable test names in ctest ("KinematicsTest/float.Foo" rather than "/0").
struct ScalarName {
  template <typename T>
  static std::string GetName(int) {
    return std::is_same<T, float>::value ? "float" : "double";
  }
};

}  // namespace neurov_test

/// Declares the test suite `Name`, typed on float and double, with readable
/// names ("Name/float.Test").
#define NEUROV_SCALAR_SUITE(Name)            \
  template <typename S>                      \
  using Name = ::neurov_test::ScalarTest<S>; \
  TYPED_TEST_SUITE(Name, ::neurov_test::Scalars, ::neurov_test::ScalarName)
