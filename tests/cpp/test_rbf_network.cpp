// RBF network, eq. 30: g_j(x) = exp(-||x_hat - xi_j||^2 / (2 sigma_j^2)),
// y = W g(x), x_hat = (x - offset) .* scale. Checked against a plain loop, at
// the points where the value is known exactly (a centre, one width away), for
// dynamic and compile-time sizes, and for its refusals.
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/control/rbf_network.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using namespace neurov_test;

using MatXd = Eigen::MatrixXd;
using VecXd = Eigen::VectorXd;

NEUROV_SCALAR_SUITE(RbfNetworkTest);

template <typename S>
using DynNet = RbfNetwork<S>;
template <typename S>
using MatX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <typename S>
using VecX = Eigen::Matrix<S, Eigen::Dynamic, 1>;

VecXd plain_basis(const MatXd& centres, const VecXd& widths, const VecXd& x, const VecXd& offset,
                  const VecXd& scale) {
  VecXd g(centres.rows());
  for (int j = 0; j < centres.rows(); ++j) {
    double d2 = 0;
    for (int i = 0; i < centres.cols(); ++i) {
      const double xi = (x(i) - offset(i)) * scale(i);
      d2 += (xi - centres(j, i)) * (xi - centres(j, i));
    }
    g(j) = std::exp(-d2 / (2 * widths(j) * widths(j)));
  }
  return g;
}

template <typename S>
MatXd rounded(Rng& rng, int rows, int cols, double lo, double hi) {
  return rng.matrix(rows, cols, lo, hi).cast<S>().template cast<double>();
}

TYPED_TEST(RbfNetworkTest, BasisAndOutputMatchAPlainLoop) {
  using S = TypeParam;
  Rng rng(301);
  for (int k = 0; k < 50; ++k) {
    const int n_in = 1 + k % 24, n_c = 1 + (7 * k) % 40;
    const VecXd x = rounded<S>(rng, n_in, 1, -3, 3);
    const VecXd offset = rounded<S>(rng, n_in, 1, -0.5, 0.5);
    const VecXd scale = rounded<S>(rng, n_in, 1, 0.5, 2.0);
    // Centres near x_hat so that g spans (0, 1) rather than underflowing.
    MatXd centres(n_c, n_in);
    for (int j = 0; j < n_c; ++j)
      for (int i = 0; i < n_in; ++i)
        centres(j, i) = static_cast<double>(
            static_cast<S>((x(i) - offset(i)) * scale(i) + rng.uniform<double>(-1, 1)));
    const VecXd widths = rounded<S>(rng, n_c, 1, 0.5, 3.0);
    const MatXd w = rounded<S>(rng, 6, n_c, -10, 10);
    DynNet<S> net(centres.cast<S>(), widths.cast<S>(), offset.cast<S>(), scale.cast<S>());
    ASSERT_TRUE(net.set_weights(w.cast<S>()));
    EXPECT_EQ(net.inputs(), n_in);
    EXPECT_EQ(net.centres_count(), n_c);
    EXPECT_EQ(net.outputs(), 6);
    VecX<S> g(n_c);
    Vector6<S> y;
    ASSERT_EQ(net.output(x.cast<S>(), g, y), Status::ok);
    const VecXd g_ref = plain_basis(centres, widths, x, offset, scale);
    Eigen::Matrix<double, 6, 1> y_ref = Eigen::Matrix<double, 6, 1>::Zero();
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < n_c; ++j) y_ref(i) += w(i, j) * g_ref(j);
    // exp amplifies the rounding of its argument (|arg| up to ~50 here).
    EXPECT_TRUE(all_near(g, g_ref, 200 * eps<S>())) << "case " << k;
    EXPECT_TRUE(all_near(y, y_ref, 200 * eps<S>() * (1 + max_abs(w) * n_c)));
    VecX<S> g2(n_c);
    ASSERT_EQ(net.basis(x.cast<S>(), g2), Status::ok);
    EXPECT_TRUE(all_near(g2, g, 0.0));
  }
}

// The packed centres start on a cache line in the network, in every copy
// and after a move, and hold the same numbers: the basis is the same bit for
// bit wherever the heap put the copy. The copies are kept, with a spacer of
// 16 more bytes before each, so that they land at different offsets from a
// cache line (with glibc they do; a copy freed at once would come back to
// the same place).
TYPED_TEST(RbfNetworkTest, CopiesAndMovesKeepThePackedCentresOnACacheLine) {
  using S = TypeParam;
  Rng rng(302);
  const int n_in = 24, n_c = 37;
  DynNet<S> net(rng.matrix(n_c, n_in, -1, 1).cast<S>(), VecX<S>::Constant(n_c, S(0.8)));
  const VecX<S> x = rng.matrix(n_in, 1, -1, 1).cast<S>();
  VecX<S> g(n_c), g_copy(n_c);
  ASSERT_EQ(net.basis(x, g), Status::ok);
  const auto expect_same_basis = [&](const DynNet<S>& other, const char* how, int shift) {
    ASSERT_EQ(other.basis(x, g_copy), Status::ok);
    EXPECT_TRUE(same_bits(g_copy, g)) << how << ", heap shift " << shift;
  };
  std::vector<std::vector<char>> kept;
  std::vector<DynNet<S>> copies;
  copies.reserve(8);
  DynNet<S> assigned(MatX<S>::Ones(1, 1), VecX<S>::Ones(1));
  for (int shift = 0; shift < 8; ++shift) {
    kept.emplace_back(16 * shift + 8);
    const DynNet<S>& copy = copies.emplace_back(net);
    expect_same_basis(copy, "copy", shift);
    assigned = copy;
    expect_same_basis(assigned, "copy-assigned", shift);
    DynNet<S> moved(std::move(assigned));
    expect_same_basis(moved, "moved", shift);
    assigned = std::move(moved);
    expect_same_basis(assigned, "move-assigned", shift);
  }

  detail::CacheLineArray<S> a;
  a.resize(n_c);
  for (int j = 0; j < n_c; ++j) a.data()[j] = S(j);
  std::vector<detail::CacheLineArray<S>> array_copies;
  array_copies.reserve(8);
  for (int shift = 0; shift < 8; ++shift) {
    kept.emplace_back(16 * shift + 8);
    const detail::CacheLineArray<S>& b = array_copies.emplace_back(a);
    ASSERT_EQ(b.size(), n_c);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % 64, 0u) << "shift " << shift;
    for (int j = 0; j < n_c; ++j) ASSERT_EQ(b.data()[j], S(j)) << "shift " << shift;
  }
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(a.data()) % 64, 0u);
}

TYPED_TEST(RbfNetworkTest, BasisIsOneAtTheCentreAndExpMinusHalfOneWidthAway) {
  using S = TypeParam;
  MatX<S> centres(3, 4);
  centres << S(0), S(1), S(2), S(3),  //
      S(-1), S(0), S(0.5), S(2),      //
      S(4), S(4), S(4), S(4);
  VecX<S> widths(3);
  widths << S(0.5), S(2), S(30);
  DynNet<S> net(centres, widths);
  VecX<S> g(3);
  // At centre 0.
  ASSERT_EQ(net.basis(centres.row(0).transpose(), g), Status::ok);
  EXPECT_EQ(g(0), S(1));
  // One width of centre 1 away from centre 1 along one input.
  VecX<S> x = centres.row(1).transpose();
  x(2) += widths(1);
  ASSERT_EQ(net.basis(x, g), Status::ok);
  EXPECT_NEAR(static_cast<double>(g(1)), std::exp(-0.5), 4 * eps<S>());
  // Widths are per centre: the wide one barely notices a distance of 4.
  x = centres.row(2).transpose();
  x(0) += S(4);
  ASSERT_EQ(net.basis(x, g), Status::ok);
  EXPECT_NEAR(static_cast<double>(g(2)), std::exp(-16.0 / (2 * 900)), 4 * eps<S>());
}

TYPED_TEST(RbfNetworkTest, CompileTimeSizesGiveTheSameNumbers) {
  using S = TypeParam;
  Rng rng(302);
  const MatXd centres = rounded<S>(rng, 8, 24, -1, 1);
  const VecXd widths = rounded<S>(rng, 8, 1, 1, 3);
  const MatXd w = rounded<S>(rng, 6, 8, -5, 5);
  DynNet<S> dyn(centres.cast<S>(), widths.cast<S>());
  RbfNetwork<S, 24, 8, 6> fixed(centres.cast<S>(), widths.cast<S>());
  ASSERT_TRUE(dyn.set_weights(w.cast<S>()));
  ASSERT_TRUE(fixed.set_weights(w.cast<S>()));
  for (int k = 0; k < 20; ++k) {
    const VecXd x = rounded<S>(rng, 24, 1, -1, 1);
    VecX<S> g_d(8);
    Eigen::Matrix<S, 8, 1> g_f;
    Vector6<S> y_d, y_f;
    ASSERT_EQ(dyn.output(x.cast<S>(), g_d, y_d), Status::ok);
    ASSERT_EQ(fixed.output(x.cast<S>(), g_f, y_f), Status::ok);
    EXPECT_TRUE(all_near(g_f, g_d, 8 * eps<S>()));
    EXPECT_TRUE(all_near(y_f, y_d, 64 * eps<S>() * (1 + max_abs(y_d))));
  }
}

TYPED_TEST(RbfNetworkTest, BadInputGivesZeroOutputAndAStatus) {
  using S = TypeParam;
  Rng rng(303);
  DynNet<S> net(rng.matrix(5, 3, -1, 1).cast<S>(), VecX<S>::Ones(5));
  ASSERT_TRUE(net.set_weights(MatX<S>::Ones(6, 5)));
  VecX<S> g = VecX<S>::Constant(5, S(7));
  Vector6<S> y = Vector6<S>::Constant(S(7));
  for (const S bad : {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity()}) {
    VecX<S> x = VecX<S>::Zero(3);
    x(1) = bad;
    EXPECT_EQ(net.output(x, g, y), Status::non_finite_input);
    EXPECT_TRUE((g.array() == S(0)).all());
    EXPECT_TRUE((y.array() == S(0)).all());
  }
  g.setConstant(S(7));
  EXPECT_EQ(net.basis(VecX<S>::Zero(4), g), Status::invalid_argument);  // wrong input size
  EXPECT_TRUE((g.array() == S(0)).all());
  VecX<S> g_short(4);
  EXPECT_EQ(net.basis(VecX<S>::Zero(3), g_short), Status::invalid_argument);
  DynNet<S> unconfigured;
  EXPECT_FALSE(unconfigured.configured());
  EXPECT_EQ(unconfigured.basis(VecX<S>::Zero(3), g), Status::invalid_argument);
}

TYPED_TEST(RbfNetworkTest, SetWeightsRefusesBadMatricesAndKeepsTheOldOnes) {
  using S = TypeParam;
  DynNet<S> net(MatX<S>::Zero(4, 2), VecX<S>::Ones(4));
  const MatX<S> w = MatX<S>::Constant(6, 4, S(2));
  ASSERT_TRUE(net.set_weights(w));
  MatX<S> nan = w;
  nan(3, 1) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_FALSE(net.set_weights(nan));
  EXPECT_FALSE(net.set_weights(MatX<S>::Ones(6, 5)));
  // (A dynamic matrix with other than 6 rows cannot be tried here: the
  // conversion to the 6-row WeightMatrix at the call site is already out of
  // Eigen's contract, undefined behaviour in a release build.)
  EXPECT_TRUE(all_near(net.weights(), w, 0.0));
}

TYPED_TEST(RbfNetworkTest, InvalidConfigurationNamesTheField) {
  using S = TypeParam;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  const MatX<S> good_c = MatX<S>::Zero(3, 2);
  const VecX<S> good_w = VecX<S>::Ones(3);
  struct Case {
    const char* field;
    MatX<S> centres;
    VecX<S> widths;
    VecX<S> offset;
    VecX<S> scale;
  };
  MatX<S> nan_c = good_c;
  nan_c(1, 1) = nan;
  MatX<S> inf_c = good_c;
  inf_c(2, 0) = std::numeric_limits<S>::infinity();
  VecX<S> zero_w = good_w, neg_w = good_w, nan_w = good_w;
  zero_w(1) = S(0);
  neg_w(2) = S(-1);
  nan_w(0) = nan;
  VecX<S> tiny_w = good_w;
  tiny_w(0) = std::numeric_limits<S>::min();  // 1 / (2 sigma^2) overflows
  const VecX<S> z2 = VecX<S>::Zero(2), o2 = VecX<S>::Ones(2);
  VecX<S> zero_scale = o2;
  zero_scale(0) = S(0);
  VecX<S> nan_offset = z2;
  nan_offset(1) = nan;
  const Case cases[] = {
      {"centres", MatX<S>::Zero(0, 2), VecX<S>::Ones(0), z2, o2},
      {"centres", MatX<S>::Zero(3, 0), good_w, VecX<S>::Zero(0), VecX<S>::Ones(0)},
      {"centres", nan_c, good_w, z2, o2},
      {"centres", inf_c, good_w, z2, o2},
      {"widths", good_c, VecX<S>::Ones(2), z2, o2},
      {"widths", good_c, VecX<S>::Ones(4), z2, o2},
      {"widths", good_c, zero_w, z2, o2},
      {"widths", good_c, neg_w, z2, o2},
      {"widths", good_c, nan_w, z2, o2},
      {"widths", good_c, tiny_w, z2, o2},
      {"input_offset", good_c, good_w, VecX<S>::Zero(3), o2},
      {"input_offset", good_c, good_w, nan_offset, o2},
      {"input_scale", good_c, good_w, z2, VecX<S>::Ones(1)},
      {"input_scale", good_c, good_w, z2, zero_scale},
  };
  for (const Case& c : cases) {
    DynNet<S> out(MatX<S>::Ones(1, 1), VecX<S>::Ones(1));
    const ValidationError e = DynNet<S>::create(c.centres, c.widths, c.offset, c.scale, out);
    ASSERT_FALSE(e.ok()) << c.field;
    // "widths (1 / (2 sigma^2) overflows)" starts with the field's name.
    EXPECT_EQ(std::string(e.field).rfind(c.field, 0), 0u) << e.field << " vs " << c.field;
    EXPECT_EQ(out.centres_count(), 1) << "create() wrote into `out` on failure";
    try {
      DynNet<S> thrown(c.centres, c.widths, c.offset, c.scale);
      ADD_FAILURE() << "no exception for a bad " << c.field;
    } catch (const std::invalid_argument& ex) {
      EXPECT_NE(std::string(ex.what()).find(c.field), std::string::npos) << ex.what();
    }
  }
}

}  // namespace
