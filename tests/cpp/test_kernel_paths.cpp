// The copies of the RBF loops (rbf_kernels.hpp: the build's own "generic"
// loops, AVX2+FMA, AVX-512) agree to a stated tolerance, and NEUROV_KERNEL
// pins the one in use. Each path runs here only where the CPU has it; on a
// build without runtime dispatch every request gives the build's loops.
#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/control/nn_controller.hpp"
#include "neurov/control/rbf_kernels.hpp"
#include "test_support.hpp"

namespace {

using neurov::NNAdaptiveConfig;
using neurov::NNAdaptiveController;
using neurov::Status;
using neurov::Vector6;
using neurov::detail::KernelIsa;

/// Restores the process-wide choice when a test ends.
struct KernelGuard {
  KernelIsa saved = neurov::detail::kernel_isa();
  ~KernelGuard() { neurov::detail::set_kernel_isa(saved); }
};

/// The paths this CPU (and build) can run, generic first.
std::vector<KernelIsa> available_paths() {
  std::vector<KernelIsa> out;
  for (KernelIsa isa : {KernelIsa::build, KernelIsa::avx2, KernelIsa::avx512})
    if (neurov::detail::set_kernel_isa(isa) == isa) out.push_back(isa);
  return out;
}

/// Relative agreement the paths promise (docs/studies.md): per basis value and
/// per tau of a step, over 400 adaptive steps. FMA and sums split over other
/// lane counts round differently; the difference stays at rounding level.
template <typename S>
double path_tolerance() {
  return std::is_same<S, float>::value ? 1e-4 : 1e-12;
}

/// tau of 400 NN steps (N centres, sigma-modification) along a smooth
/// trajectory, with the path `isa`; and every g(x) of the network on the way.
template <typename S, int N>
std::vector<double> run_path(KernelIsa isa, int n, std::vector<double>& basis) {
  neurov::detail::set_kernel_isa(isa);
  neurov_test::Rng rng(7);
  using Ctl = NNAdaptiveController<S, N>;
  typename Ctl::Network::CentreMatrix centres(n, neurov::kNNInputs);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < neurov::kNNInputs; ++i) centres(j, i) = rng.uniform<S>(-2.0, 2.0);
  typename Ctl::Network::BasisVector widths(n);
  widths.setConstant(S(2.5));
  NNAdaptiveConfig<S> cfg;
  cfg.kd.setConstant(S(20));
  cfg.modification = neurov::RobustModification::sigma;
  cfg.sigma_m = S(0.05);
  Ctl ctl;
  EXPECT_FALSE(Ctl::create(centres, widths, Ctl::Network::InputVector::Zero(),
                           Ctl::Network::InputVector::Ones(), cfg, ctl));
  std::vector<double> taus;
  basis.clear();
  Vector6<S> tau;
  for (int k = 0; k < 400; ++k) {
    const double t = 0.2 * k;
    Vector6<S> eta, nu, eta_d, eta_d_dot, eta_d_ddot;
    for (int i = 0; i < 6; ++i) {
      const double w = 0.05 * (i + 1);
      eta_d(i) = static_cast<S>(std::sin(w * t));
      eta_d_dot(i) = static_cast<S>(w * std::cos(w * t));
      eta_d_ddot(i) = static_cast<S>(-w * w * std::sin(w * t));
      eta(i) = static_cast<S>(std::sin(w * t - 0.3) * 1.1);
      nu(i) = static_cast<S>(0.9 * w * std::cos(w * t - 0.3));
    }
    EXPECT_EQ(ctl.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot, tau), Status::ok);
    for (int i = 0; i < 6; ++i) taus.push_back(static_cast<double>(tau(i)));
    for (int j = 0; j < n; ++j) basis.push_back(static_cast<double>(ctl.basis()(j)));
  }
  return taus;
}

/// max |a - b| / max |b| over the sequence.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return diff / scale;
}

template <typename S, int N>
void expect_paths_agree(int n) {
  KernelGuard guard;
  const std::vector<KernelIsa> paths = available_paths();
  std::vector<double> g_generic, g_other;
  const std::vector<double> generic = run_path<S, N>(KernelIsa::build, n, g_generic);
  for (KernelIsa isa : paths) {
    const std::vector<double> other = run_path<S, N>(isa, n, g_other);
    SCOPED_TRACE(::testing::Message() << "path " << neurov::detail::kernel_isa_name()
                                      << ", N = " << n);
    ASSERT_EQ(other.size(), generic.size());
    EXPECT_LE(relative_difference(other, generic), path_tolerance<S>());
    for (std::size_t i = 0; i < g_other.size(); ++i)
      ASSERT_NEAR(g_other[i], g_generic[i], path_tolerance<S>()) << "g entry " << i;
  }
}

NEUROV_SCALAR_SUITE(KernelPathsTest);

// N = 64 (the C interface's), 37 (a tail shorter than a vector) and N fixed.
TYPED_TEST(KernelPathsTest, EveryPathGivesTheSameStepsToTheStatedTolerance) {
  expect_paths_agree<TypeParam, Eigen::Dynamic>(64);
  expect_paths_agree<TypeParam, Eigen::Dynamic>(37);
  expect_paths_agree<TypeParam, 64>(64);
}

// The packed centres take the loops with the panel width as a compile-time
// constant; the column-major matrix (one panel of N) the run-time width. Both
// sum each centre's inputs in the same order, so on every path the centres in
// whole vectors get the same g bit for bit (N = 203 runs blocks of 8, 4, 2
// and 1 vectors). The last N mod L centres are one padded vector in the
// packed copy but scalar code on the matrix, which on the FMA paths rounds
// differently: those agree to the paths' tolerance.
TYPED_TEST(KernelPathsTest, PackedAndColumnMajorCentresGiveTheSameBasisBitForBit) {
  using S = TypeParam;
  using neurov::detail::CentrePanels;
  using neurov::detail::Index;
  KernelGuard guard;
  constexpr Index n = 203, n_in = neurov::kNNInputs;
  neurov_test::Rng rng(11);
  std::vector<S> centres(n * n_in), inv(n), x(n_in);
  for (S& c : centres) c = rng.uniform<S>(-2.0, 2.0);
  for (S& v : inv) v = rng.uniform<S>(0.05, 0.2);
  for (S& v : x) v = rng.uniform<S>(-2.0, 2.0);
  std::vector<S> packed(neurov::detail::packed_centres_size<S>(n, n_in));
  neurov::detail::pack_centres<S>(centres.data(), n, n, n_in, packed.data());
  for (KernelIsa isa : available_paths()) {
    neurov::detail::set_kernel_isa(isa);
    SCOPED_TRACE(::testing::Message() << "path " << neurov::detail::kernel_isa_name());
    std::vector<S> g_packed(n), g_plain(n);
    const CentrePanels<S> panels{packed.data(), neurov::detail::panel_width<S>(), true};
    const CentrePanels<S> column_major{centres.data(), n, false};
    neurov::detail::rbf_basis<S>(panels, n, n_in, x.data(), inv.data(), g_packed.data());
    neurov::detail::rbf_basis<S>(column_major, n, n_in, x.data(), inv.data(), g_plain.data());
    const Index whole = n - n % 16;  // 16: the most lanes of any path
    for (Index j = 0; j < n; ++j) {
      ASSERT_GT(g_plain[j], S(0)) << "centre " << j;  // a basis value, not an underflow
      if (j < whole)
        ASSERT_EQ(g_packed[j], g_plain[j]) << "centre " << j;
      else
        ASSERT_NEAR(g_packed[j], g_plain[j], path_tolerance<S>() * g_plain[j]) << "centre " << j;
    }
  }
}

TEST(KernelPathsTest, NeurovKernelPinsThePathCappedAtTheCpu) {
  using neurov::detail::requested_kernel_isa;
#if NEUROV_RUNTIME_DISPATCH
  for (KernelIsa cpu : {KernelIsa::build, KernelIsa::avx2, KernelIsa::avx512}) {
    EXPECT_EQ(requested_kernel_isa("generic", cpu), KernelIsa::build);
    EXPECT_EQ(requested_kernel_isa("avx2", cpu), cpu < KernelIsa::avx2 ? cpu : KernelIsa::avx2);
    EXPECT_EQ(requested_kernel_isa("avx512", cpu), cpu);
    EXPECT_EQ(requested_kernel_isa("auto", cpu), cpu);
    EXPECT_EQ(requested_kernel_isa("", cpu), cpu);
    EXPECT_EQ(requested_kernel_isa(nullptr, cpu), cpu);
  }
  // The choice is read from the environment at the first call after a reset.
  KernelGuard guard;
  const char* before = std::getenv("NEUROV_KERNEL");
  const std::string saved = before != nullptr ? before : "";
  ::setenv("NEUROV_KERNEL", "generic", 1);
  neurov::detail::kernel_isa_choice.store(neurov::detail::kKernelIsaUnset);
  EXPECT_EQ(neurov::detail::kernel_isa(), KernelIsa::build);
  EXPECT_STRNE(neurov::detail::kernel_isa_name(), "avx2");
  EXPECT_STRNE(neurov::detail::kernel_isa_name(), "avx512");
  ::setenv("NEUROV_KERNEL", "avx512", 1);  // read once: no effect now
  EXPECT_EQ(neurov::detail::kernel_isa(), KernelIsa::build);
  if (before != nullptr)
    ::setenv("NEUROV_KERNEL", saved.c_str(), 1);
  else
    ::unsetenv("NEUROV_KERNEL");
#else
  EXPECT_EQ(neurov::detail::set_kernel_isa(KernelIsa::avx512), KernelIsa::build);
#endif
}

}  // namespace
