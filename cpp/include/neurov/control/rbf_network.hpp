// Radial-basis-function network, eq. 30 of the paper:
//   g_j(x) = exp(-||x_hat - xi_j||^2 / (2 sigma_j^2)),  f_hat(x) = W g(x),
// with x_hat = (x - input_offset) .* input_scale (identity by default, as in
// the paper) so inputs of different units can share one width.
//
// Sizes are template parameters: Eigen::Dynamic (the default) sizes the
// network at create() time, which is the only time it allocates; a fixed
// number of centres gives firmware a network with no heap at all.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <type_traits>

#include "neurov/core/cache_line_array.hpp"
#include "neurov/core/config.hpp"
#include "neurov/control/rbf_kernels.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

namespace neurov {

/// The most centres a network takes (2^16). It bounds what a count read from
/// a file can allocate before anything runs: an NN controller of 65536
/// centres of 24 inputs holds 77 MB and takes 8.6 ms a step (measured from
/// Python, docs/reliability.md), 16 times the largest network benchmarked
/// (4096) and a thousand times the paper's 64; a count beyond it is a typo
/// whose network would not fit in memory (10^8 centres: 24 GB).
inline constexpr int kMaxCentres = 65536;
static_assert(kMaxCentres == 65536, "create()'s centres message names the maximum");

template <typename ScalarT, int InputsT = Eigen::Dynamic, int CentresT = Eigen::Dynamic,
          int OutputsT = 6>
class RbfNetwork {
 public:
  using Scalar = ScalarT;
  static constexpr int kInputs = InputsT;
  static constexpr int kCentres = CentresT;
  static constexpr int kOutputs = OutputsT;
  /// Row j is centre xi_j. Column-major, so each input's coordinates over all
  /// centres are contiguous and the distance loop vectorises across centres.
  using CentreMatrix = Eigen::Matrix<Scalar, CentresT, InputsT>;
  using InputVector = Eigen::Matrix<Scalar, InputsT, 1>;
  using BasisVector = Eigen::Matrix<Scalar, CentresT, 1>;
  using OutputVector = Eigen::Matrix<Scalar, OutputsT, 1>;
  using WeightMatrix = Eigen::Matrix<Scalar, OutputsT, CentresT>;
  /// A network sized at run time also holds its centres packed in
  /// cache-line panels for the basis loop (rbf_kernel_loops.hpp): N x n_in
  /// more numbers, for 1.2-2.3x at N >= 256. A network of fixed N
  /// (firmware, the C interface) is stored once and reads the column-major
  /// matrix.
  /// The packed copy starts on a cache line, so the kernels' vector loads
  /// never straddle two, wherever the heap put it.
  static constexpr bool kPacked = CentresT == Eigen::Dynamic;
  using PackedCentres = std::conditional_t<kPacked, detail::CacheLineArray<Scalar>,
                                           Eigen::Matrix<Scalar, 0, 1>>;

  RbfNetwork() = default;

#if NEUROV_HAS_EXCEPTIONS
  RbfNetwork(const CentreMatrix& centres, const BasisVector& widths) {
    throw_if_invalid(create(centres, widths, *this), "RBF network");
  }
  RbfNetwork(const CentreMatrix& centres, const BasisVector& widths, const InputVector& input_offset,
             const InputVector& input_scale) {
    throw_if_invalid(create(centres, widths, input_offset, input_scale, *this), "RBF network");
  }
#endif

  /// Centres (N x n_in) and one width per centre (N), identity input scaling,
  /// zero weights. `out` is untouched on failure.
  static ValidationError create(const CentreMatrix& centres, const BasisVector& widths,
                                RbfNetwork& out) {
    return create(centres, widths, InputVector::Zero(centres.cols()),
                  InputVector::Ones(centres.cols()), out);
  }

  static ValidationError create(const CentreMatrix& centres, const BasisVector& widths,
                                const InputVector& input_offset, const InputVector& input_scale,
                                RbfNetwork& out) {
    if (centres.rows() < 1 || centres.cols() < 1)
      return detail::invalid("centres", -1, static_cast<double>(centres.rows()),
                             "at least one centre with at least one input");
    if (centres.rows() > kMaxCentres)
      return detail::invalid("centres", -1, static_cast<double>(centres.rows()),
                             "at most 65536 centres (neurov::kMaxCentres)");
    if (widths.size() != centres.rows())
      return detail::invalid("widths", -1, static_cast<double>(widths.size()),
                             "one width per centre");
    if (input_offset.size() != centres.cols())
      return detail::invalid("input_offset", -1, static_cast<double>(input_offset.size()),
                             "one offset per input");
    if (input_scale.size() != centres.cols())
      return detail::invalid("input_scale", -1, static_cast<double>(input_scale.size()),
                             "one scale per input");
    if (auto e = detail::check_finite("centres", centres)) return e;
    if (auto e = detail::check_positive("widths", widths)) return e;
    if (auto e = detail::check_finite("input_offset", input_offset)) return e;
    if (auto e = detail::check_positive("input_scale", input_scale)) return e;
    const BasisVector inv = (Scalar(2) * widths.array().square()).inverse().matrix();
    if (auto e = detail::check_positive("widths (1 / (2 sigma^2) overflows)", inv)) return e;
    out.centres_ = centres;
    if constexpr (kPacked) {
      out.packed_.resize(detail::packed_centres_size<Scalar>(centres.rows(), centres.cols()));
      detail::pack_centres<Scalar>(out.centres_.data(), out.centres_.rows(), out.centres_.rows(),
                                   out.centres_.cols(), out.packed_.data());
    }
    out.inv_two_sigma_sq_ = inv;
    out.widths_ = widths;
    out.input_offset_ = input_offset;
    out.input_scale_ = input_scale;
    out.weights_ = WeightMatrix::Zero(OutputsT == Eigen::Dynamic ? 6 : OutputsT, centres.rows());
    out.configured_ = true;
    return {};
  }

  /// False until create() succeeded; an unconfigured network refuses to run.
  bool configured() const noexcept { return configured_; }
  int inputs() const noexcept { return static_cast<int>(centres_.cols()); }
  int centres_count() const noexcept { return static_cast<int>(centres_.rows()); }
  int outputs() const noexcept { return static_cast<int>(weights_.rows()); }

  /// g(x) into caller storage of size N. Returns non_finite_input for a
  /// NaN/Inf x (g = 0) and invalid_argument for a wrong input size.
  Status basis(const InputVector& x, BasisVector& g) const noexcept {
    if (!configured_ || x.size() != centres_.cols() || g.size() != centres_.rows()) {
      g.setZero();
      return Status::invalid_argument;
    }
    if (!detail::all_finite(x)) {
      g.setZero();
      return Status::non_finite_input;
    }
    const Eigen::Index n_in = centres_.cols();
    if (n_in <= kMaxStackInputs) {
      Scalar x_hat[kMaxStackInputs];
      for (Eigen::Index i = 0; i < n_in; ++i) x_hat[i] = (x(i) - input_offset_(i)) * input_scale_(i);
      detail::rbf_basis<Scalar>(panels(), centres_.rows(), n_in, x_hat, inv_two_sigma_sq_.data(),
                                g.data());
      return Status::ok;
    }
    // More inputs than the stack buffer: squared distances accumulated input
    // by input over the centres, with g as the accumulator.
    g.setZero();
    for (Eigen::Index i = 0; i < n_in; ++i) {
      const Scalar xi = (x(i) - input_offset_(i)) * input_scale_(i);
      g.array() += (centres_.col(i).array() - xi).square();
    }
    g.array() = (-g.array() * inv_two_sigma_sq_.array()).exp();
    return Status::ok;
  }

  /// y = W g(x); g is caller workspace of size N, left holding g(x).
  Status output(const InputVector& x, BasisVector& g, OutputVector& y) const noexcept {
    const Status s = basis(x, g);
    if (s != Status::ok) {
      y.setZero();
      return s;
    }
    y.noalias() = weights_ * g;
    return Status::ok;
  }

  const CentreMatrix& centres() const noexcept { return centres_; }
  const BasisVector& widths() const noexcept { return widths_; }
  const InputVector& input_offset() const noexcept { return input_offset_; }
  const InputVector& input_scale() const noexcept { return input_scale_; }
  const WeightMatrix& weights() const noexcept { return weights_; }
  /// Mutable weights, for the adaptive law and for warm starts.
  WeightMatrix& weights() noexcept { return weights_; }

  /// Replaces the weights; false (unchanged) on a wrong size or a NaN/Inf.
  bool set_weights(const WeightMatrix& w) noexcept {
    if (!configured_ || w.rows() != weights_.rows() || w.cols() != weights_.cols() ||
        !w.allFinite())
      return false;
    weights_ = w;
    return true;
  }

 private:
  detail::CentrePanels<Scalar> panels() const noexcept {
    if constexpr (kPacked)
      return {packed_.data(), detail::panel_width<Scalar>(), true};
    else
      return {centres_.data(), centres_.rows(), false};  // column-major: one panel of N
  }

  /// Inputs of x_hat held on the stack in basis() (exactly n_in when it is
  /// fixed, so firmware stacks stay small); more take a slower loop.
  static constexpr Eigen::Index kMaxStackInputs = InputsT == Eigen::Dynamic ? 256 : InputsT;

  CentreMatrix centres_;
  PackedCentres packed_;
  BasisVector inv_two_sigma_sq_;
  BasisVector widths_;
  InputVector input_offset_;
  InputVector input_scale_;
  WeightMatrix weights_;
  bool configured_ = false;
};

}  // namespace neurov
