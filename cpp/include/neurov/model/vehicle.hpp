// 6-DOF vehicle dynamics in Fossen's form, eq. 1 of the paper:
//   M nu_dot + C(nu) nu + D(nu) nu + g(eta) = tau.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "neurov/core/config.hpp"
#include "neurov/core/field_spec.hpp"
#include "neurov/model/kinematics.hpp"
#include "neurov/model/plant_kernel.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/symmetric_matrix.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

namespace neurov {

/// Which skew-symmetric C(nu) the vehicle uses. Both give the same C(nu) nu,
/// so the plant moves identically; they differ in C(nu) v for v != nu, which
/// is what a controller's C(nu) nu_r sees.
enum class CoriolisForm : std::uint8_t {
  /// Fossen's linear-velocity-independent C_RB plus C_A from M_A: the paper's
  /// eq. 39 for a vehicle with r_g = 0 and diagonal M_A. The default.
  velocity_independent = 0,
  /// Both C_RB and C_A from the 6x6 mass matrices (Fossen's "m2c" form).
  kirchhoff = 1,
};

/// The form's name, as vehicle files and Python give it.
constexpr const char* to_string(CoriolisForm f) noexcept {
  return f == CoriolisForm::kirchhoff ? "kirchhoff" : "velocity_independent";
}

template <typename Scalar>
struct VehicleParameters {
  Scalar mass = Scalar(0);                          ///< m [kg]
  Matrix3<Scalar> inertia = Matrix3<Scalar>::Zero();  ///< I_o about the body origin [kg m^2]
  Vector3<Scalar> centre_of_gravity = Vector3<Scalar>::Zero();   ///< r_g [m], body axes
  Vector3<Scalar> centre_of_buoyancy = Vector3<Scalar>::Zero();  ///< r_b [m], body axes (z down)
  Scalar weight = Scalar(0);                        ///< W = m g [N]
  Scalar buoyancy = Scalar(0);                      ///< B [N]
  /// M_A, positive definite (M_A = -diag(X_udot, ..., N_rdot) for a diagonal one).
  Matrix6<Scalar> added_mass = Matrix6<Scalar>::Zero();
  /// D(nu) = diag(linear_damping + quadratic_damping .* |nu|).
  Vector6<Scalar> linear_damping = Vector6<Scalar>::Zero();
  Vector6<Scalar> quadratic_damping = Vector6<Scalar>::Zero();
  CoriolisForm coriolis_form = CoriolisForm::velocity_independent;

  template <typename Other>
  VehicleParameters<Other> cast() const {
    VehicleParameters<Other> p;
    p.mass = static_cast<Other>(mass);
    p.inertia = inertia.template cast<Other>();
    p.centre_of_gravity = centre_of_gravity.template cast<Other>();
    p.centre_of_buoyancy = centre_of_buoyancy.template cast<Other>();
    p.weight = static_cast<Other>(weight);
    p.buoyancy = static_cast<Other>(buoyancy);
    p.added_mass = added_mass.template cast<Other>();
    p.linear_damping = linear_damping.template cast<Other>();
    p.quadratic_damping = quadratic_damping.template cast<Other>();
    p.coriolis_form = coriolis_form;
    return p;
  }
};

/// The parameters described once: the Python class VehicleParameters, the
/// keyword arguments and properties of Vehicle, the vehicle files' keys and
/// the simple part of validate() come from this list.
template <typename Scalar>
auto config_fields(const VehicleParameters<Scalar>*) noexcept {
  using P = VehicleParameters<Scalar>;
  return std::make_tuple(
      field_spec<P>("mass", &P::mass, "kg", Check::positive, "m", kRequired),
      field_spec<P>("inertia", &P::inertia, "kg m^2", Check::finite,
                    "I_o about the body origin (3, 3), or its diagonal (3,); symmetric positive "
                    "definite",
                    kRequired | kDiagonal),
      field_spec<P>("centre_of_gravity", &P::centre_of_gravity, "m", Check::finite,
                    "r_g (3,), body axes"),
      field_spec<P>("centre_of_buoyancy", &P::centre_of_buoyancy, "m", Check::finite,
                    "r_b (3,), body axes (z down)"),
      field_spec<P>("weight", &P::weight, "N", Check::non_negative, "W = m g", kRequired),
      field_spec<P>("buoyancy", &P::buoyancy, "N", Check::non_negative, "B", kRequired),
      field_spec<P>("added_mass", &P::added_mass, "kg, kg m, kg m^2", Check::finite,
                    "M_A (6, 6), or its diagonal (6,); symmetric positive semidefinite "
                    "(M_A = -diag(X_udot, ..., N_rdot) for a diagonal one)",
                    kRequired | kDiagonal),
      field_spec<P>("linear_damping", &P::linear_damping, "N s/m, N m s", Check::non_negative,
                    "D_L (6,), the constant part of D(nu)'s diagonal", kRequired),
      field_spec<P>("quadratic_damping", &P::quadratic_damping, "N s^2/m^2, N m s^2",
                    Check::non_negative, "D_Q (6,), the part of D(nu)'s diagonal times abs(nu)",
                    kRequired),
      field_spec<P>("coriolis_form", &P::coriolis_form,
                    "'velocity_independent' (the paper's eq. 39, the default) or 'kirchhoff'"));
}

/// M_RB = [[m I, -m S(r_g)], [m S(r_g), I_o]].
template <typename Scalar>
inline Matrix6<Scalar> rigid_body_mass_matrix(const VehicleParameters<Scalar>& p) noexcept {
  Matrix6<Scalar> m;
  const Matrix3<Scalar> s = skew<Scalar>(p.centre_of_gravity);
  m.template topLeftCorner<3, 3>() = p.mass * Matrix3<Scalar>::Identity();
  m.template topRightCorner<3, 3>() = -p.mass * s;
  m.template bottomLeftCorner<3, 3>() = p.mass * s;
  m.template bottomRightCorner<3, 3>() = p.inertia;
  return m;
}

/// Checks a parameter set: each field's rule (config_fields: finite numbers,
/// mass > 0, W and B >= 0, damping >= 0), then what ties fields together:
/// symmetric inertia and added mass, and M = M_RB + M_A positive definite.
template <typename Scalar>
inline ValidationError validate(const VehicleParameters<Scalar>& p) noexcept {
  using detail::invalid;
  if (auto e = check_fields(p)) return e;
  if (p.coriolis_form != CoriolisForm::velocity_independent &&
      p.coriolis_form != CoriolisForm::kirchhoff)
    return invalid("coriolis_form", -1, static_cast<double>(p.coriolis_form),
                   "velocity_independent or kirchhoff");

  if (auto e = detail::check_symmetric("inertia", p.inertia)) return e;
  if (auto e = detail::check_symmetric("added_mass", p.added_mass)) return e;
  // Each part must be physical on its own: a negative moment of inertia can
  // hide behind a large added inertia in the sum M.
  if (Matrix3<Scalar> l; !detail::cholesky(p.inertia, l))
    return detail::invalid("inertia", -1, std::nan(""), "positive definite");
  {
    const Scalar min_eig = detail::min_eigenvalue(p.added_mass);
    const Scalar tol = Scalar(64) * Eigen::NumTraits<Scalar>::epsilon() *
                       std::max(Scalar(1), p.added_mass.cwiseAbs().maxCoeff());
    if (min_eig < -tol)
      return detail::invalid("added_mass", -1, static_cast<double>(min_eig),
                             "positive semidefinite (value is its smallest eigenvalue)");
  }
  const Matrix6<Scalar> m = rigid_body_mass_matrix(p) + p.added_mass;
  if (Matrix6<Scalar> l; !detail::cholesky(m, l))
    return invalid("mass_matrix", -1, std::nan(""),
                   "M = M_RB + M_A (from mass, inertia, centre_of_gravity, added_mass) "
                   "positive definite");
  return {};
}

/// A vehicle: validated parameters plus what is derived from them once
/// (M and its inverse), so that the hot path only multiplies.
template <typename ScalarT>
class Vehicle {
 public:
  using Scalar = ScalarT;
  using Vec3 = Vector3<Scalar>;
  using Vec6 = Vector6<Scalar>;
  using Mat6 = Matrix6<Scalar>;

  /// An empty vehicle: valid() is false and acceleration() returns
  /// invalid_argument until create() has filled it.
  Vehicle() = default;

#if NEUROV_HAS_EXCEPTIONS
  /// Validates and builds; throws std::invalid_argument naming the field.
  explicit Vehicle(const VehicleParameters<Scalar>& p) {
    throw_if_invalid(create(p, *this), "vehicle parameter");
  }
#endif

  /// Validates p and, if valid, builds `out` from it; `out` is untouched
  /// otherwise. Never throws, never allocates.
  static ValidationError create(const VehicleParameters<Scalar>& p, Vehicle& out) noexcept {
    const ValidationError e = validate(p);
    if (e) return e;
    out.params_ = p;
    out.m_ = rigid_body_mass_matrix(p) + p.added_mass;
    // Symmetrise away rounding so M and M^-1 are exactly symmetric.
    out.m_ = (Scalar(0.5) * (out.m_ + out.m_.transpose())).eval();
    // validate() has shown M positive definite, so the inverse exists.
    (void)detail::spd_inverse(out.m_, out.m_inv_);
    // The common structure (NEROV, BlueROV2): r_g = 0 and diagonal inertia
    // and added mass, so M^-1 is diagonal too and the plant's 6x6 products
    // are elementwise. The same sums with the zero terms left out: the same
    // numbers as the general path.
    const auto off_diagonal_zero = [](const auto& m) {
      for (Eigen::Index j = 0; j < m.cols(); ++j)
        for (Eigen::Index i = 0; i < m.rows(); ++i)
          if (i != j && m(i, j) != Scalar(0)) return false;
      return true;
    };
    out.diagonal_ = p.centre_of_gravity.isZero(Scalar(0)) && off_diagonal_zero(p.inertia) &&
                    off_diagonal_zero(p.added_mass) && off_diagonal_zero(out.m_inv_);
    namespace pc = detail::plant_coef;
    Scalar* c = out.coefficients_;
    c[pc::mass] = p.mass;
    for (int i = 0; i < 3; ++i) c[pc::inertia + i] = p.inertia(i, i);
    for (int i = 0; i < 6; ++i) {
      c[pc::added_mass + i] = p.added_mass(i, i);
      c[pc::m_inv + i] = out.m_inv_(i, i);
      c[pc::linear + i] = p.linear_damping(i);
      c[pc::quadratic + i] = p.quadratic_damping(i);
    }
    const Vec3& rg = p.centre_of_gravity;
    const Vec3& rb = p.centre_of_buoyancy;
    c[pc::net_weight] = p.weight - p.buoyancy;
    c[pc::moment_x] = rg.x() * p.weight - rb.x() * p.buoyancy;
    c[pc::moment_y] = rg.y() * p.weight - rb.y() * p.buoyancy;
    c[pc::moment_z] = rg.z() * p.weight - rb.z() * p.buoyancy;
    out.valid_ = true;
    return {};
  }

  bool valid() const noexcept { return valid_; }
  /// r_g = 0 and diagonal inertia, added mass and M^-1: the plant's
  /// products are elementwise and its RK4 step runs in model/plant_kernel.hpp
  /// (one run, or many in SIMD lanes).
  bool diagonal() const noexcept { return diagonal_; }
  /// The numbers plant_kernel.hpp reads (detail::plant_coef's order);
  /// meaningful where diagonal().
  const Scalar* plant_coefficients() const noexcept { return coefficients_; }
  const VehicleParameters<Scalar>& parameters() const noexcept { return params_; }
  /// M = M_RB + M_A.
  const Mat6& mass_matrix() const noexcept { return m_; }
  const Mat6& mass_matrix_inverse() const noexcept { return m_inv_; }

  /// C_RB(nu) in the configured form.
  Mat6 coriolis_rigid_body(const Vec6& nu) const noexcept {
    const Vec3 v = nu.template head<3>(), w = nu.template tail<3>();
    const Scalar m = params_.mass;
    const Vec3& rg = params_.centre_of_gravity;
    Mat6 c;
    if (params_.coriolis_form == CoriolisForm::velocity_independent) {
      const Matrix3<Scalar> sw = skew<Scalar>(w);
      c.template topLeftCorner<3, 3>() = m * sw;
      c.template topRightCorner<3, 3>() = -m * sw * skew<Scalar>(rg);
      c.template bottomLeftCorner<3, 3>() = m * skew<Scalar>(rg) * sw;
      c.template bottomRightCorner<3, 3>() = -skew<Scalar>(params_.inertia * w);
    } else {
      const Vec3 b1 = m * v + m * w.cross(rg);
      const Vec3 b2 = m * rg.cross(v) + params_.inertia * w;
      c.template topLeftCorner<3, 3>().setZero();
      c.template topRightCorner<3, 3>() = -skew<Scalar>(b1);
      c.template bottomLeftCorner<3, 3>() = -skew<Scalar>(b1);
      c.template bottomRightCorner<3, 3>() = -skew<Scalar>(b2);
    }
    return c;
  }

  /// C_A(nu) = [[0, -S(a1)], [-S(a1), -S(a2)]], [a1; a2] = M_A nu.
  Mat6 coriolis_added_mass(const Vec6& nu) const noexcept {
    const Vec6 a = params_.added_mass * nu;
    const Matrix3<Scalar> s1 = skew<Scalar>(a.template head<3>());
    Mat6 c;
    c.template topLeftCorner<3, 3>().setZero();
    c.template topRightCorner<3, 3>() = -s1;
    c.template bottomLeftCorner<3, 3>() = -s1;
    c.template bottomRightCorner<3, 3>() = -skew<Scalar>(a.template tail<3>());
    return c;
  }

  /// C(nu) = C_RB(nu) + C_A(nu); skew-symmetric.
  Mat6 coriolis(const Vec6& nu) const noexcept {
    return coriolis_rigid_body(nu) + coriolis_added_mass(nu);
  }

  /// C(nu) nu without forming C. The same in both forms:
  ///   [w x (m v + m w x r_g) + w x a1;  m r_g x (w x v) + w x I w + v x a1 + w x a2].
  Vec6 coriolis_force(const Vec6& nu) const noexcept {
    const Vec3 v = nu.template head<3>(), w = nu.template tail<3>();
    const Scalar m = params_.mass;
    const Vec3& rg = params_.centre_of_gravity;
    const Vec6 a = params_.added_mass * nu;
    const Vec3 a1 = a.template head<3>(), a2 = a.template tail<3>();
    Vec6 f;
    f.template head<3>() = w.cross(Vec3(m * v + m * w.cross(rg) + a1));
    f.template tail<3>() = m * rg.cross(w.cross(v)) + w.cross(Vec3(params_.inertia * w + a2)) +
                           v.cross(a1);
    return f;
  }

  /// Diagonal of D(nu).
  Vec6 damping_diagonal(const Vec6& nu) const noexcept {
    return params_.linear_damping + params_.quadratic_damping.cwiseProduct(nu.cwiseAbs());
  }
  /// D(nu) = diag(D_L + D_Q |nu|).
  Mat6 damping(const Vec6& nu) const noexcept { return damping_diagonal(nu).asDiagonal(); }

  /// g(eta): Fossen's restoring forces for weight W at r_g and buoyancy B at r_b.
  Vec6 restoring(const Vec6& eta) const noexcept {
    // The same sin/cos as EulerTrig, so acceleration() and derivative() agree.
    Scalar sf, cf, st, ct;
    detail::sincos(eta(3), sf, cf);
    detail::sincos(eta(4), st, ct);
    return restoring(sf, cf, st, ct);
  }

  Vec6 restoring(Scalar sin_phi, Scalar cos_phi, Scalar sin_theta,
                 Scalar cos_theta) const noexcept {
    const Scalar w = params_.weight, b = params_.buoyancy;
    const Vec3& rg = params_.centre_of_gravity;
    const Vec3& rb = params_.centre_of_buoyancy;
    const Scalar wb = w - b;
    const Scalar xm = rg.x() * w - rb.x() * b;
    const Scalar ym = rg.y() * w - rb.y() * b;
    const Scalar zm = rg.z() * w - rb.z() * b;
    const Scalar ctcf = cos_theta * cos_phi, ctsf = cos_theta * sin_phi;
    Vec6 g;
    g << wb * sin_theta, -wb * ctsf, -wb * ctcf,  //
        -ym * ctcf + zm * ctsf,                   //
        zm * sin_theta + xm * ctcf,               //
        -xm * ctsf - ym * sin_theta;
    return g;
  }

  /// nu_dot = M^-1 (tau - C(nu) nu - D(nu) nu - g(eta)), with the relative
  /// velocity nu - nu_c in the hydrodynamic terms when a current is given.
  /// Returns non_finite_input (nu_dot = 0) for NaN/Inf inputs,
  /// invalid_argument (nu_dot = 0) for an empty vehicle, non_finite_output
  /// (nu_dot = 0) on overflow.
  Status acceleration(const Vec6& eta, const Vec6& nu, const Vec6& tau,
                      Vec6& nu_dot) const noexcept {
    if (!valid_) {
      nu_dot.setZero();
      return Status::invalid_argument;
    }
    if (!detail::all_finite(eta, nu, tau)) {
      nu_dot.setZero();
      return Status::non_finite_input;
    }
    nu_dot.noalias() = m_inv_ * (tau - forces(eta, nu));
    return finite_or_zero(nu_dot);
  }

  /// As above in an ocean current that is constant and irrotational in the
  /// earth frame (NED velocity current_ned). With the velocity-independent
  /// C_RB, M_RB nu_dot + C_RB(nu) nu = M_RB nu_r_dot + C_RB(nu_r) nu_r
  /// (Fossen 2011, Property 8.1), so the whole model runs on the relative
  /// velocity nu_r = nu - nu_c, and nu_dot = nu_r_dot + nu_c_dot with
  /// nu_c_dot = [-w x v_c; 0] as the body turns in the current.
  Status acceleration(const Vec6& eta, const Vec6& nu, const Vec6& tau, const Vec3& current_ned,
                      Vec6& nu_dot) const noexcept {
    Vec6 eta_dot;
    const Status s = derivative(eta, nu, tau, current_ned, eta_dot, nu_dot);
    return s == Status::near_singularity ? Status::ok : s;  // nu_dot needs no 1/cos(theta)
  }

  /// The whole 12-state plant: eta_dot = J(eta) nu and nu_dot as in
  /// acceleration(), sharing one evaluation of the Euler-angle trigonometry.
  /// near_singularity means eta_dot used a clamped cos(theta).
  Status derivative(const Vec6& eta, const Vec6& nu, const Vec6& tau, const Vec3& current_ned,
                    Vec6& eta_dot, Vec6& nu_dot) const noexcept {
    return derivative(EulerTrig<Scalar>::from_pose(eta), eta, nu, tau, current_ned, eta_dot,
                      nu_dot);
  }

  /// The same with the trigonometry of eta's angles given (a caller that
  /// needs it too computes it once: the sines and cosines are much of the
  /// cost of a step). Forced inline: called through the overload above, it
  /// was not, and a calm run's RK4 stages cost a fifth more.
  NEUROV_ALWAYS_INLINE Status derivative(const EulerTrig<Scalar>& trig, const Vec6& eta, const Vec6& nu,
                    const Vec6& tau, const Vec3& current_ned, Vec6& eta_dot,
                    Vec6& nu_dot) const noexcept {
    if (!valid_) {
      eta_dot.setZero();
      nu_dot.setZero();
      return Status::invalid_argument;
    }
    if (!detail::all_finite(eta, nu, tau, current_ned)) {
      eta_dot.setZero();
      nu_dot.setZero();
      return Status::non_finite_input;
    }
    if (diagonal_) {
      // The inputs were checked above; finite_or_zero tells which output overflowed.
      detail::PlantMasks<Scalar> unused;
      detail::plant_derivative<false>(coefficients_, detail::trig_lanes(trig), eta.data(), nu.data(),
                               tau.data(), current_ned.data(), eta_dot.data(), nu_dot.data(), unused);
      const Status out = worst(finite_or_zero(nu_dot), finite_or_zero(eta_dot));
      return worst(out, trig.status);
    }
    const Matrix3<Scalar> r = rotation(trig);
    const Vec3 w = nu.template tail<3>();
    eta_dot.template head<3>().noalias() = r * nu.template head<3>();
    eta_dot.template tail<3>().noalias() = attitude_transform(trig) * w;

    Vec6 nu_r = nu;
    Vec3 vc = Vec3::Zero();
    const bool has_current = !current_ned.isZero(Scalar(0));
    if (has_current) {
      vc.noalias() = r.transpose() * current_ned;  // v_c in body axes
      nu_r.template head<3>() -= vc;
    }
    const Vec6 g = restoring(trig.sin_phi, trig.cos_phi, trig.sin_theta, trig.cos_theta);
    nu_dot.noalias() =
        m_inv_ * (tau - coriolis_force(nu_r) - damping_diagonal(nu_r).cwiseProduct(nu_r) - g);
    if (has_current) nu_dot.template head<3>() -= w.cross(vc);
    const Status out = worst(finite_or_zero(nu_dot), finite_or_zero(eta_dot));
    return worst(out, trig.status);
  }

  /// C(nu) nu + D(nu) nu + g(eta): everything but inertia.
  Vec6 forces(const Vec6& eta, const Vec6& nu) const noexcept {
    return coriolis_force(nu) + damping_diagonal(nu).cwiseProduct(nu) + restoring(eta);
  }

 private:
  static Status finite_or_zero(Vec6& x) noexcept {
    if (detail::all_finite(x)) return Status::ok;
    x.setZero();
    return Status::non_finite_output;
  }

  VehicleParameters<Scalar> params_{};
  Mat6 m_ = Mat6::Zero();
  Mat6 m_inv_ = Mat6::Zero();
  Scalar coefficients_[detail::plant_coef::count] = {};  ///< see plant_coefficients()
  bool diagonal_ = false;  ///< see create()
  bool valid_ = false;
};

/// NEROV, the paper's vehicle (section 5; numbers in docs/model.md).
template <typename Scalar>
inline VehicleParameters<Scalar> nerov_parameters() noexcept {
  VehicleParameters<Scalar> p;
  p.mass = Scalar(185);
  p.inertia = Vector3<Scalar>(Scalar(25), Scalar(50), Scalar(50)).asDiagonal();
  p.centre_of_gravity.setZero();
  // Buoyancy 0.02 m above the centre of gravity: z is down in body axes.
  p.centre_of_buoyancy = Vector3<Scalar>(Scalar(0), Scalar(0), Scalar(-0.02));
  p.weight = Scalar(1800);
  p.buoyancy = Scalar(1800);
  Vector6<Scalar> added;
  added << Scalar(30), Scalar(80), Scalar(80), Scalar(15), Scalar(30), Scalar(30);
  p.added_mass = added.asDiagonal();
  p.linear_damping << Scalar(70), Scalar(100), Scalar(100), Scalar(30), Scalar(50), Scalar(50);
  p.quadratic_damping << Scalar(100), Scalar(200), Scalar(200), Scalar(50), Scalar(100),
      Scalar(100);
  p.coriolis_form = CoriolisForm::velocity_independent;
  return p;
}

}  // namespace neurov
