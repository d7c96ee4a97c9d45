// The iteration method's contact forces (iteration_method_impl.hpp): each
// a one-dimensional root of the contact's accelerations, found by TOMS 748
// from the last root. Private to the method's units (an unnamed namespace:
// each unit its own copy, as the method's class template).
#pragma once

#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/run_types.hpp"
#include "rotor_rub_sim/core/station_model.hpp"

namespace rotor_rub::core {
namespace {

// A root of an increasing function r(F) of one force [N], by TOMS 748 on a
// bracket grown from the last root (the warm start): the model is a black box
// to the root finder, as a large FE model would be.
class ForceRoot {
 public:
  ForceRoot(double rtol, int max_iterations, const char* name)
      : rtol_(rtol), max_iterations_(max_iterations), name_(name) {}

  // r must increase with F; finds F in [lo, inf) with r(F) = 0 given r(lo) < 0,
  // to rtol of max(|F|, scale_N): a root at zero's rounding (a stick force
  // the state hardly needs) is found to rtol of its scale, not of itself,
  // which no bracket from zero reaches. A bracket no wider than resolution_N
  // (where r is its own rounding: resolution_N()) is a root too once the
  // budget is spent: TOMS 748 can spend it narrowing a bracket on which r
  // only steps by its rounding (ForceRoot.*, test_force_root.cpp).
  template <class R>
  double solve(R&& r, double lo, double r_lo, double t_s, long& iterations, double scale_N = 0.0,
               double resolution_N = 0.0) const {
    double step = std::max(std::abs(last_N_) * 2.0, 1e-3);
    double hi = std::max(lo, last_N_) + step;
    double r_hi = r(hi);
    ++iterations;
    for (int i = 0; r_hi < 0.0; ++i) {
      if (i > 200) throw MethodFailure(FailureClass::kNotConverged, t_s, std::string(name_) + " not bracketed");
      lo = hi;
      r_lo = r_hi;
      step *= 4.0;
      hi += step;
      r_hi = r(hi);
      ++iterations;
    }
    if (r_hi == 0.0) return last_N_ = hi;
    std::uintmax_t it = static_cast<std::uintmax_t>(max_iterations_);
    const double rtol = rtol_;
    auto tol = [rtol, scale_N](double a, double b) {
      return std::abs(b - a) <= rtol * std::max({std::abs(a), std::abs(b), scale_N});
    };
    const auto br = boost::math::tools::toms748_solve(r, lo, hi, r_lo, r_hi, tol, it);
    iterations += static_cast<long>(it);
    if (static_cast<int>(it) >= max_iterations_ && !tol(br.first, br.second) && br.second - br.first > resolution_N) {
      throw MethodFailure(FailureClass::kNotConverged, t_s, std::string(name_) + " iteration did not converge");
    }
    last_N_ = 0.5 * (br.first + br.second);
    return last_N_;
  }

 private:
  double rtol_;
  int max_iterations_;
  const char* name_;
  mutable double last_N_ = 1.0;
};

struct ContactForces {
  double normal_N = 0.0;
  double tangential_N = 0.0;  // F_t applied (slip: -f F_n s; stick: the stick force)
  double stick_N = 0.0;       // the F_t that holds v_slide' = 0
};

// Finds the contact forces of an engaged contact: F_n >= 0 that makes the
// distance's acceleration delta'' vanish (0 when none is needed), and in
// stick the F_t that makes the sliding acceleration v_slide' vanish. F_n and
// F_t act along n and t, so each root is one-dimensional.
class ContactForceSolver {
 public:
  using Loads = FreeLoads;
  ContactForceSolver(const StationModel* m, double rtol, int max_iterations)
      : model_(m), normal_(rtol, max_iterations, "normal force"), tangential_(rtol, max_iterations, "stick force") {}

  // free: the state's free loads (model.hpp), the same for every trial force.
  double distance_acceleration(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const Loads& free,
                               double fn, double ft) const {
    return StationModel::distance_acceleration(k, g, model_->accelerations(d, g, free, fn, ft));
  }
  double sliding_acceleration(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const Loads& free,
                              double fn, double ft) const {
    return model_->sliding_acceleration(k, g, model_->accelerations(d, g, free, fn, ft));
  }

  // The F_t that makes v_slide' vanish at normal force fn, to rtol of the
  // cone's scale fn where it is smaller (ForceRoot).
  double stick_force(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const Loads& free, double fn,
                     double t_s, long& iterations) const {
    const double s0 = sliding_acceleration(k, d, g, free, fn, 0.0);
    ++iterations;
    // v_slide' rises with F_t: solve from the side where it is negative.
    if (s0 == 0.0) return 0.0;
    if (s0 < 0.0) {
      return tangential_.solve([&](double ft) { return sliding_acceleration(k, d, g, free, fn, ft); }, 0.0, s0, t_s,
                               iterations, fn, resolution_N(free));
    }
    return -tangential_.solve([&](double ft) { return -sliding_acceleration(k, d, g, free, fn, -ft); }, 0.0, -s0, t_s,
                              iterations, fn, resolution_N(free));
  }

  // The forces for the state's free loads (the rotor model's); want_stick_force:
  // compute stick_N even when sliding (to decide a transition).
  ContactForces solve(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const Loads& free,
                      const FrictionMode& mode, bool want_stick_force, double t_s, long& iterations) const {
    ContactForces f;
    const double r0 = distance_acceleration(k, d, g, free, 0.0, 0.0);
    ++iterations;
    if (!(r0 > 0.0)) {
      // Separating without help: released, no force. The stick force keeps
      // its meaning, what rolling would need with F_n = 0: at a lift-off in
      // stick it need not vanish, and the breakaway's function |F_t,stick| -
      // f F_n must read it there, not a clamped zero, for a breakaway just
      // before the lift-off to be bracketed (test_transitions.cpp).
      if ((mode.stick || want_stick_force) && !model_->motor()) {
        f.stick_N = stick_force(k, d, g, free, 0.0, t_s, iterations);
      }
      return f;
    }
    if (model_->motor()) return solve_with_spin(k, d, g, free, mode, want_stick_force, t_s, iterations);
    // delta'' falls as F_n grows: solve -delta''(F_n) = 0 from F_n = 0.
    f.normal_N = normal_.solve([&](double fn) { return -distance_acceleration(k, d, g, free, fn, 0.0); }, 0.0, -r0, t_s,
                               iterations, normal_scale_N(free), resolution_N(free));
    if (mode.stick || want_stick_force) f.stick_N = stick_force(k, d, g, free, f.normal_N, t_s, iterations);
    if (mode.stick) {
      f.tangential_N = f.stick_N;
    } else if (model_->has_friction()) {
      f.tangential_N = -model_->parameters().friction_coefficient * f.normal_N * mode.slip_sign;
    }
    return f;
  }

 private:
  // Under a motor drive the spin couples the normal and the tangential
  // force (model.hpp: the compliance W): the normal root is taken with the
  // tangential force that goes with each trial F_n, -f s F_n in slip and the
  // stick force (an inner root) in stick. delta'' still falls as F_n grows:
  // its slope is -(W_nn + f s W_nt) in slip and the Schur complement
  // -(W_nn - W_nt^2 / W_tt) in stick, both < 0 (validate_scene's bound).
  ContactForces solve_with_spin(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const Loads& free,
                                const FrictionMode& mode, bool want_stick_force, double t_s, long& iterations) const {
    ContactForces f;
    const double friction = model_->has_friction() ? model_->parameters().friction_coefficient : 0.0;
    auto tangential_at = [&](double fn) {
      return mode.stick ? stick_force(k, d, g, free, fn, t_s, iterations) : -friction * fn * mode.slip_sign;
    };
    auto residual = [&](double fn) { return -distance_acceleration(k, d, g, free, fn, tangential_at(fn)); };
    const double r_lo = residual(0.0);
    ++iterations;
    if (r_lo < 0.0) {
      f.normal_N = normal_.solve(residual, 0.0, r_lo, t_s, iterations, normal_scale_N(free), resolution_N(free));
    }
    f.tangential_N = tangential_at(f.normal_N);
    if (mode.stick) {
      f.stick_N = f.tangential_N;
    } else if (want_stick_force) {
      f.stick_N = stick_force(k, d, g, free, f.normal_N, t_s, iterations);
    }
    return f;
  }

  // The scale a normal force is found to rtol of where it is smaller: 1e-6
  // of the free loads it balances. At a lift-off it falls through zero, and
  // to rtol of itself a root near 1e-20 N took a bracket from zero past the
  // iteration budget (not_converged at a lift-off under other last bits,
  // rtol 1e-11); at 1e-6 of the loads it converges, and away from zero
  // nothing moves (at the loads themselves, on dop853, the Jeffcott and its
  // rotor-file twin drifted 1.2e-9 m apart where they had agreed to
  // 2.6e-10 m: test_flexible_rotor_runs).
  static double normal_scale_N(const Loads& free) { return 1e-6 * (free.rotor_N.norm() + free.stator_N.norm()); }
  // How finely a contact force is defined by its residual: the accelerations'
  // rounding (eps of the loads over a mass) over the residual's slope (one
  // over a mass no larger), so about eps of the loads; 64 of them for the
  // sums of terms as large.
  static double resolution_N(const Loads& free) {
    return 64.0 * std::numeric_limits<double>::epsilon() * (free.rotor_N.norm() + free.stator_N.norm());
  }

  const StationModel* model_;
  ForceRoot normal_, tangential_;
};

}  // namespace
}  // namespace rotor_rub::core
