// Dormand-Prince 8(5,3), "DOP853" (Hairer, Norsett & Wanner, Solving
// Ordinary Differential Equations I, 2nd ed., Springer 1993, II.10 and its
// code dop853): an explicit Runge-Kutta pair of order 8 with 12 stages (the
// first the derivative at the step's start, which the caller evaluates at
// the end of the step before: DenseHighOrder does), its error estimated
// from an order-5 and an order-3 embedded
// solution combined as err5^2 / sqrt(err5^2 + 0.01 err3^2), which tracks
// the order-8 solution's own error more closely than Fehlberg's 7(8)
// estimate (the difference of the 7th- and 8th-order solutions, which
// vanishes on pure quadratures: Fehlberg's known blind spot), so it takes
// larger steps for the same error.
//
// Boost.Odeint ships no pair of this class (its 8th-order stepper is
// Fehlberg's 7(8)), so this is the method as the book states it, with the
// book's step-size controller (safety 0.9, factor in [1/3, 6], no increase
// right after a rejection, beta = 0) and error norm (RMS over components of
// err_i / (atol + rtol max(|x_i|, |x1_i|))). The coefficients are the
// tableau's as published with dop853; test_dop853.cpp checks them (row
// sums, quadrature order 8, the convergence order on a nonlinear problem).
// The dense output is not the book's (3 more stages): DenseHighOrder's
// Hermite interpolation (dense_high_order.hpp) with 2.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <utility>

namespace rotor_rub::core {

struct Dop853Tableau {
  static constexpr double c2 = 0.526001519587677318785587544488e-1;
  static constexpr double c3 = 0.789002279381515978178381316732e-1;
  static constexpr double c4 = 0.118350341907227396726757197510;
  static constexpr double c5 = 0.281649658092772603273242802490;
  static constexpr double c6 = 0.333333333333333333333333333333;
  static constexpr double c7 = 0.25;
  static constexpr double c8 = 0.307692307692307692307692307692;
  static constexpr double c9 = 0.651282051282051282051282051282;
  static constexpr double c10 = 0.6;
  static constexpr double c11 = 0.857142857142857142857142857142;
  static constexpr double a21 = 5.26001519587677318785587544488e-2;
  static constexpr double a31 = 1.97250569845378994544595329183e-2;
  static constexpr double a32 = 5.91751709536136983633785987549e-2;
  static constexpr double a41 = 2.95875854768068491816892993775e-2;
  static constexpr double a43 = 8.87627564304205475450678981324e-2;
  static constexpr double a51 = 2.41365134159266685502369798665e-1;
  static constexpr double a53 = -8.84549479328286085344864962717e-1;
  static constexpr double a54 = 9.24834003261792003115737966543e-1;
  static constexpr double a61 = 3.7037037037037037037037037037e-2;
  static constexpr double a64 = 1.70828608729473871279604482173e-1;
  static constexpr double a65 = 1.25467687566822425016691814123e-1;
  static constexpr double a71 = 3.7109375e-2;
  static constexpr double a74 = 1.70252211019544039314978060272e-1;
  static constexpr double a75 = 6.02165389804559606850219397283e-2;
  static constexpr double a76 = -1.7578125e-2;
  static constexpr double a81 = 3.70920001185047927108779319836e-2;
  static constexpr double a84 = 1.70383925712239993810214054705e-1;
  static constexpr double a85 = 1.07262030446373284651809199168e-1;
  static constexpr double a86 = -1.53194377486244017527936158236e-2;
  static constexpr double a87 = 8.27378916381402288758473766002e-3;
  static constexpr double a91 = 6.24110958716075717114429577812e-1;
  static constexpr double a94 = -3.36089262944694129406857109825e0;
  static constexpr double a95 = -8.68219346841726006818189891453e-1;
  static constexpr double a96 = 2.75920996994467083049415600797e1;
  static constexpr double a97 = 2.01540675504778934086186788979e1;
  static constexpr double a98 = -4.34898841810699588477366255144e1;
  static constexpr double a101 = 4.77662536438264365890433908527e-1;
  static constexpr double a104 = -2.48811461997166764192642586468e0;
  static constexpr double a105 = -5.90290826836842996371446475743e-1;
  static constexpr double a106 = 2.12300514481811942347288949897e1;
  static constexpr double a107 = 1.52792336328824235832596922938e1;
  static constexpr double a108 = -3.32882109689848629194453265587e1;
  static constexpr double a109 = -2.03312017085086261358222928593e-2;
  static constexpr double a111 = -9.3714243008598732571704021658e-1;
  static constexpr double a114 = 5.18637242884406370830023853209e0;
  static constexpr double a115 = 1.09143734899672957818500254654e0;
  static constexpr double a116 = -8.14978701074692612513997267357e0;
  static constexpr double a117 = -1.85200656599969598641566180701e1;
  static constexpr double a118 = 2.27394870993505042818970056734e1;
  static constexpr double a119 = 2.49360555267965238987089396762e0;
  static constexpr double a1110 = -3.0467644718982195003823669022e0;
  static constexpr double a121 = 2.27331014751653820792359768449e0;
  static constexpr double a124 = -1.05344954667372501984066689879e1;
  static constexpr double a125 = -2.00087205822486249909675718444e0;
  static constexpr double a126 = -1.79589318631187989172765950534e1;
  static constexpr double a127 = 2.79488845294199600508499808837e1;
  static constexpr double a128 = -2.85899827713502369474065508674e0;
  static constexpr double a129 = -8.87285693353062954433549289258e0;
  static constexpr double a1210 = 1.23605671757943030647266201528e1;
  static constexpr double a1211 = 6.43392746015763530355970484046e-1;
  static constexpr double b1 = 5.42937341165687622380535766363e-2;
  static constexpr double b6 = 4.45031289275240888144113950566;
  static constexpr double b7 = 1.89151789931450038304281599044;
  static constexpr double b8 = -5.8012039600105847814672114227;
  static constexpr double b9 = 3.1116436695781989440891606237e-1;
  static constexpr double b10 = -1.52160949662516078556178806805e-1;
  static constexpr double b11 = 2.01365400804030348374776537501e-1;
  static constexpr double b12 = 4.47106157277725905176885569043e-2;
  static constexpr double bhh1 = 0.244094488188976377952755905512;
  static constexpr double bhh2 = 0.733846688281611857341361741547;
  static constexpr double bhh3 = 0.220588235294117647058823529412e-1;
  static constexpr double er1 = 0.1312004499419488073250102996e-1;
  static constexpr double er6 = -0.1225156446376204440720569753e1;
  static constexpr double er7 = -0.4957589496572501915214079952;
  static constexpr double er8 = 0.1664377182454986536961530415e1;
  static constexpr double er9 = -0.3503288487499736816886487290;
  static constexpr double er10 = 0.3341791187130174790297318841;
  static constexpr double er11 = 0.8192320648511571246570742613e-1;
  static constexpr double er12 = -0.2235530786388629525884427845e-1;
};

// The controlled stepper: the contract of odeint's controlled_runge_kutta
// try_step(sys, x, dxdt, t, x_out, dt) (true: accepted, t advanced and dt
// the next step's proposal; false: rejected, dt reduced).
template <class State>
class Dop853 {
 public:
  // Derivative evaluations per attempt: 11, the first stage being the
  // derivative at the step's start (given: the last step's end).
  static constexpr int kStagesPerAttempt = 11;
  // The book's controller and error combination (dop853's defaults).
  static constexpr double kSafety = 0.9;
  static constexpr double kMinFactor = 1.0 / 3.0;  // h_new / h bounds
  static constexpr double kMaxFactor = 6.0;
  static constexpr double kErr3Weight = 0.01;     // err5^2 / sqrt(err5^2 + 0.01 err3^2)
  static constexpr double kExponent = 1.0 / 8.0;  // h ~ err^(-1/8): the order-8 solution's error

  Dop853(double atol, double rtol) : atol_(atol), rtol_(rtol) {}

  template <class System>
  bool try_step(System& sys, const State& x, const State& k1, double& t, State& x_out, double& dt) {
    using T = Dop853Tableau;
    const double h = dt;
    sys(State(x + h * T::a21 * k1), k2_, t + T::c2 * h);
    sys(State(x + h * (T::a31 * k1 + T::a32 * k2_)), k3_, t + T::c3 * h);
    sys(State(x + h * (T::a41 * k1 + T::a43 * k3_)), k4_, t + T::c4 * h);
    sys(State(x + h * (T::a51 * k1 + T::a53 * k3_ + T::a54 * k4_)), k5_, t + T::c5 * h);
    sys(State(x + h * (T::a61 * k1 + T::a64 * k4_ + T::a65 * k5_)), k6_, t + T::c6 * h);
    sys(State(x + h * (T::a71 * k1 + T::a74 * k4_ + T::a75 * k5_ + T::a76 * k6_)), k7_, t + T::c7 * h);
    sys(State(x + h * (T::a81 * k1 + T::a84 * k4_ + T::a85 * k5_ + T::a86 * k6_ + T::a87 * k7_)), k8_, t + T::c8 * h);
    sys(State(x + h * (T::a91 * k1 + T::a94 * k4_ + T::a95 * k5_ + T::a96 * k6_ + T::a97 * k7_ + T::a98 * k8_)), k9_,
        t + T::c9 * h);
    sys(State(x + h * (T::a101 * k1 + T::a104 * k4_ + T::a105 * k5_ + T::a106 * k6_ + T::a107 * k7_ + T::a108 * k8_ +
                       T::a109 * k9_)),
        k10_, t + T::c10 * h);
    sys(State(x + h * (T::a111 * k1 + T::a114 * k4_ + T::a115 * k5_ + T::a116 * k6_ + T::a117 * k7_ + T::a118 * k8_ +
                       T::a119 * k9_ + T::a1110 * k10_)),
        k11_, t + T::c11 * h);
    const double t_end = t + h;
    y12_ = x + h * (T::a121 * k1 + T::a124 * k4_ + T::a125 * k5_ + T::a126 * k6_ + T::a127 * k7_ + T::a128 * k8_ +
                    T::a129 * k9_ + T::a1210 * k10_ + T::a1211 * k11_);
    sys(y12_, k12_, t_end);
    const State slope = T::b1 * k1 + T::b6 * k6_ + T::b7 * k7_ + T::b8 * k8_ + T::b9 * k9_ + T::b10 * k10_ +
                        T::b11 * k11_ + T::b12 * k12_;
    x_out = x + h * slope;

    // The book's error: err5^2 / sqrt(err5^2 + 0.01 err3^2), RMS-scaled.
    const auto scale = atol_ + rtol_ * x.array().abs().max(x_out.array().abs());
    const double err3 = ((slope - T::bhh1 * k1 - T::bhh2 * k9_ - T::bhh3 * k12_).array() / scale).square().sum();
    const double err5 = ((T::er1 * k1 + T::er6 * k6_ + T::er7 * k7_ + T::er8 * k8_ + T::er9 * k9_ + T::er10 * k10_ +
                          T::er11 * k11_ + T::er12 * k12_)
                             .array() /
                         scale)
                            .square()
                            .sum();
    double denominator = err5 + kErr3Weight * err3;
    if (!(denominator > 0.0)) denominator = 1.0;
    const double err = std::abs(h) * err5 / std::sqrt(denominator * static_cast<double>(x.size()));

    // A non-finite end or error rejects at the smallest factor (the dense
    // integrator cuts a non-finite trial further and reports a collapse to
    // min_step_s as divergence: StepEnds::rejected_as_non_finite).
    if (!std::isfinite(err) || !x_out.allFinite()) {
      rejected_ = true;
      dt = h * kMinFactor;
      return false;
    }
    // The step-size factor h_new / h = 0.9 err^(-1/8), bounded.
    // err^(1/8) as three square roots: about half the price of std::pow and
    // within 1 ulp of it (10^6 values from 1e-12 up).
    static_assert(kExponent == 0.125, "the square roots below take the eighth root");
    const double shrink = std::sqrt(std::sqrt(std::sqrt(err)));
    if (err <= 1.0) {
      double factor = std::clamp(kSafety / shrink, kMinFactor, kMaxFactor);
      if (rejected_) factor = std::min(factor, 1.0);
      rejected_ = false;
      t = t_end;
      dt = h * factor;
      return true;
    }
    rejected_ = true;
    dt = h * std::max(kMinFactor, kSafety / shrink);
    return false;
  }

  // Hairer's stiffness test (dop853's HLAMB): h times the Lipschitz
  // quotient |f(x1) - f(y12)| / |x1 - y12| of the accepted step h, taken
  // between its end x1 and its last stage's argument y12 (both at t + h),
  // with f1 = f(x1): an estimate of h rho(J) along the direction the step's
  // error grows in. Near or above dop853's stability boundary (about 6 from
  // the negative real axis to the imaginary one) the step is bound by
  // stability, not by the tolerance (DenseStiffnessSwitch).
  double h_rho(const State& x1, const State& f1, double h) const {
    const double den = (x1 - y12_).squaredNorm();
    return den > 0.0 ? std::abs(h) * std::sqrt((f1 - k12_).squaredNorm() / den) : 0.0;
  }

 private:
  double atol_, rtol_;
  bool rejected_ = false;
  State k2_, k3_, k4_, k5_, k6_, k7_, k8_, k9_, k10_, k11_, k12_, y12_;
};

}  // namespace rotor_rub::core
