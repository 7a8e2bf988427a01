// Wave spectra of a fully developed or fetch-limited sea, as one-sided
// spectral densities S(omega) [m^2 s / rad] of the surface elevation in the
// circular frequency omega [rad/s]; both have the zeroth moment
// m0 = integral S = Hs^2 / 16 (Hs = 4 sqrt(m0)).
//
//  * Two-parameter Pierson-Moskowitz (Bretschneider) in the peak period:
//      S(w) = 5/16 Hs^2 wp^4 w^-5 exp(-5/4 (wp / w)^4),  wp = 2 pi / Tp,
//    which is the ITTC two-parameter spectrum 173 Hs^2 T1^-4 w^-5
//    exp(-691 T1^-4 w^-4) with T1 = 0.772 Tp.
//  * JONSWAP (Hasselmann et al. 1973), the same with the peak enhanced:
//      S(w) = C(gamma) S_PM(w) gamma^exp(-(w - wp)^2 / (2 sigma^2 wp^2)),
//    sigma = 0.07 for w <= wp and 0.09 above, and C(gamma) computed so that
//    m0 is Hs^2 / 16 exactly (rather than the usual fit 1 - 0.287 ln gamma).
#pragma once

#include <cmath>
#include <cstdint>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/validation.hpp"

namespace neurov {

enum class WaveSpectrum : std::uint8_t {
  jonswap = 0,
  pierson_moskowitz = 1,
};

/// The fields and units of the scenario file's [waves] table (the direction
/// in degrees, as the file has it).
template <typename Scalar>
struct WaveConfig {
  WaveSpectrum spectrum = WaveSpectrum::jonswap;
  Scalar hs = Scalar(2);      ///< significant wave height [m]
  Scalar tp = Scalar(8);      ///< peak period [s]
  Scalar gamma = Scalar(3.3); ///< JONSWAP peak enhancement (not used by pierson_moskowitz)
  Scalar direction = Scalar(0);  ///< direction the waves travel toward [deg from north]
  /// n of the directional spreading D(theta) ~ cos^n(theta - direction),
  /// |theta - direction| < 90 deg (n = 2 to 4 for a wind sea); 0 gives
  /// long-crested waves that all travel toward `direction`.
  Scalar spreading = Scalar(0);
  int components = 200;  ///< number of sinusoidal components realising the spectrum
};

/// The capacity of the simulator's wave field (Waves' default): the most
/// components a run's waves take. 200 (the default) already realise the
/// spectrum's statistics (docs/disturbances.md); each component costs about
/// 200 bytes, held inline, and a pass per step.
inline constexpr int kMaxWaveComponents = 512;
static_assert(kMaxWaveComponents == 512, "validate()'s components message names the maximum");

template <typename Scalar>
auto config_fields(const WaveConfig<Scalar>*) noexcept {
  using C = WaveConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("spectrum", &C::spectrum, "A WaveSpectrum."),
      field_spec<C>("hs", &C::hs, "m", Check::positive, "Significant wave height"),
      field_spec<C>("tp", &C::tp, "s", Check::positive, "Peak period"),
      field_spec<C>("gamma", &C::gamma, "", Check::none, "JONSWAP peak enhancement, >= 1"),
      field_spec<C>("direction", &C::direction, "deg from north", Check::finite,
                    "Direction the waves travel toward"),
      field_spec<C>("spreading", &C::spreading, "", Check::non_negative,
                    "n of the cos^n directional spreading; 0: long-crested"),
      field_spec<C>("components", &C::components, "", Check::none, "Number of components")
          .within(1, kMaxWaveComponents));
}

/// Checks a configuration; the error names the field. max_components is the
/// capacity of the wave field that will hold it.
template <typename Scalar>
inline ValidationError validate(const WaveConfig<Scalar>& c, int max_components) noexcept {
  using detail::invalid;
  const auto d = [](Scalar v) { return static_cast<double>(v); };
  if (c.spectrum != WaveSpectrum::jonswap && c.spectrum != WaveSpectrum::pierson_moskowitz)
    return invalid("spectrum", -1, static_cast<double>(c.spectrum), "jonswap or pierson_moskowitz");
  if (auto e = detail::check_positive_scalar("hs", d(c.hs))) return e;
  if (auto e = detail::check_positive_scalar("tp", d(c.tp))) return e;
  if (c.spectrum == WaveSpectrum::jonswap && !(std::isfinite(d(c.gamma)) && c.gamma >= Scalar(1)))
    return invalid("gamma", -1, d(c.gamma), ">= 1 and finite");
  if (!std::isfinite(d(c.direction))) return invalid("direction", -1, d(c.direction), "finite");
  if (auto e = detail::check_non_negative_scalar("spreading", d(c.spreading))) return e;
  if (c.components < 1 || c.components > max_components)
    return invalid("components", -1, static_cast<double>(c.components),
                   max_components == kMaxWaveComponents
                       ? "within [1, 512] (neurov::kMaxWaveComponents, the wave field's "
                         "capacity)"
                       : max_components > 1 ? "within [1, the wave field's capacity]" : "1");
  return {};
}

namespace detail {

/// 5 x^-5 exp(-5/4 x^-4): the Pierson-Moskowitz shape in x = w / wp, with
/// unit area over x in (0, inf).
inline double pierson_moskowitz_shape(double x) noexcept {
  if (!(x > 0.0)) return 0.0;
  const double x4 = x * x * x * x;
  return 5.0 / (x4 * x) * std::exp(-1.25 / x4);
}

inline double jonswap_peak_factor(double x, double gamma) noexcept {
  const double sigma = x <= 1.0 ? 0.07 : 0.09;
  const double r = (x - 1.0) / sigma;
  return std::pow(gamma, std::exp(-0.5 * r * r));
}

/// C(gamma) = 1 / integral of shape * gamma^r: 1 + the integral of
/// shape * (gamma^r - 1), which vanishes outside 1 -+ 12 sigma, by Simpson's
/// rule on 4000 panels (converged to rounding: the integrand is smooth).
inline double jonswap_normalisation(double gamma) noexcept {
  if (gamma == 1.0) return 1.0;
  const double lo = 1.0 - 12.0 * 0.07, hi = 1.0 + 12.0 * 0.09;
  const int n = 4000;
  const double h = (hi - lo) / n;
  const auto f = [gamma](double x) {
    return pierson_moskowitz_shape(x) * (jonswap_peak_factor(x, gamma) - 1.0);
  };
  double sum = f(lo) + f(hi);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(lo + i * h);
  return 1.0 / (1.0 + sum * h / 3.0);
}

}  // namespace detail

/// A spectrum with its parameters and normalisation fixed: S(omega) is then
/// one exp (and a pow for JONSWAP) per call.
struct SpectralDensity {
  WaveSpectrum spectrum = WaveSpectrum::pierson_moskowitz;
  double hs = 0.0, peak_frequency = 0.0, gamma = 1.0;
  double normalisation = 1.0;  ///< C(gamma); 1 for pierson_moskowitz

  template <typename Scalar>
  static SpectralDensity from(const WaveConfig<Scalar>& c) noexcept {
    SpectralDensity s;
    s.spectrum = c.spectrum;
    s.hs = static_cast<double>(c.hs);
    s.peak_frequency = 6.283185307179586 / static_cast<double>(c.tp);
    s.gamma = c.spectrum == WaveSpectrum::jonswap ? static_cast<double>(c.gamma) : 1.0;
    s.normalisation = detail::jonswap_normalisation(s.gamma);
    return s;
  }

  /// S(omega) [m^2 s / rad] for omega [rad/s]; 0 for omega <= 0.
  double operator()(double omega) const noexcept {
    const double x = omega / peak_frequency;
    double s = hs * hs / 16.0 / peak_frequency * detail::pierson_moskowitz_shape(x);
    if (spectrum == WaveSpectrum::jonswap) s *= normalisation * detail::jonswap_peak_factor(x, gamma);
    return s;
  }
};

}  // namespace neurov
