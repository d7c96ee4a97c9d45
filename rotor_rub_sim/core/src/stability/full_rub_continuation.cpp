#include "rotor_rub_sim/core/full_rub_continuation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "regula_falsi.hpp"

namespace rotor_rub::core {
namespace {

// The corrector's residual bound: every acceleration below 1e-12 of w^2
// times its coordinate's scale (linearised_full_rub's own bound, so that
// its Newton accepts the point as it is).
constexpr double kResidual = 1e-12;
// The difference step in scaled units: the accelerations are linear in every
// coordinate but the contact angle and the speed, whose central difference's
// error at 1e-6 is of order 1e-12 of their curvature.
constexpr double kDifference = 1e-6;
// The corrector's iterations before a step is halved, and the smallest step.
constexpr int kMaxCorrections = 12;
constexpr double kMinStep = 1e-9;
// A fold's or a stability change's regula falsi stops on a bracket this
// fraction of the step (the speed at a fold is stationary in the arclength:
// its error is of the bracket's square).
constexpr double kLocateFraction = 1e-10;
// A step whose tangent turns by more than this angle's cosine (18 deg) is
// taken again at half the length: two folds or two changes of stability
// inside one step would cancel in their sign tests, and a turn beyond 90 deg
// would reverse the trace.
constexpr double kMinTurnCosine = 0.95;
// linearised_full_rub polishes a point by Newton at its speed: the point it
// linearises must be the traced one, to this fraction of each scale.
constexpr double kSamePoint = 1e-6;

// The rest point's equations in scaled unknowns y = (q / scale_q, w / scale_w).
class RestPoint {
 public:
  RestPoint(const TurningRotor& rotor, const StationStator& stator, double C, double f, const PenaltyContact* penalty,
            const Eigen::VectorXd& q0, double w0)
      : rotor_(rotor), stator_(stator), C_(C), f_(f), penalty_(penalty), nq_(static_cast<int>(q0.size())) {
    scale_.resize(nq_ + 1);
    for (int j = 0; j < nq_; ++j) {
      const bool angle = penalty == nullptr && j == nq_ - 1;  // the rigid contact's theta
      scale_(j) = angle ? 1.0 : std::max(std::abs(q0(j)), C);
    }
    scale_(nq_) = w0;
  }
  int size() const { return nq_; }
  double speed(const Eigen::VectorXd& y) const { return y(nq_) * scale_(nq_); }
  Eigen::VectorXd positions(const Eigen::VectorXd& y) const { return y.head(nq_).cwiseProduct(scale_.head(nq_)); }
  Eigen::VectorXd scaled(const Eigen::VectorXd& q, double w) const {
    Eigen::VectorXd y(nq_ + 1);
    y.head(nq_) = q.cwiseQuotient(scale_.head(nq_));
    y(nq_) = w / scale_(nq_);
    return y;
  }
  // Each acceleration over w^2 times its coordinate's scale.
  Eigen::VectorXd residual(const Eigen::VectorXd& y) const {
    const double w = speed(y);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * nq_);
    x.head(nq_) = positions(y);
    const Eigen::VectorXd acc = full_rub_rates(rotor_, stator_, C_, f_, w, x, nullptr, penalty_).tail(nq_);
    return acc.cwiseQuotient(w * w * scale_.head(nq_));
  }
  // d residual / dy, nq x (nq + 1).
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& y) const {
    Eigen::MatrixXd j(nq_, nq_ + 1);
    for (int c = 0; c <= nq_; ++c) {
      Eigen::VectorXd up = y, down = y;
      up(c) += kDifference;
      down(c) -= kDifference;
      j.col(c) = (residual(up) - residual(down)) / (2.0 * kDifference);
    }
    return j;
  }
  // The unit tangent at y on the side of `previous` (its last row fixes the
  // null vector's size and sign: t . previous = 1 before normalising).
  Eigen::VectorXd tangent(const Eigen::VectorXd& y, const Eigen::VectorXd& previous) const {
    Eigen::MatrixXd a(nq_ + 1, nq_ + 1);
    a.topRows(nq_) = jacobian(y);
    a.row(nq_) = previous.transpose();
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nq_ + 1);
    rhs(nq_) = 1.0;
    return a.fullPivLu().solve(rhs).normalized();
  }
  // Newton from the predictor y_pred on the hyperplane t . (y - y_pred) = 0;
  // false when it does not converge.
  bool correct(const Eigen::VectorXd& y_pred, const Eigen::VectorXd& t, Eigen::VectorXd& y, int& iterations) const {
    y = y_pred;
    for (iterations = 0; iterations < kMaxCorrections; ++iterations) {
      const Eigen::VectorXd r = residual(y);
      if (!r.allFinite()) return false;
      if (r.cwiseAbs().maxCoeff() < kResidual) return true;
      Eigen::MatrixXd a(nq_ + 1, nq_ + 1);
      a.topRows(nq_) = jacobian(y);
      a.row(nq_) = t.transpose();
      Eigen::VectorXd rhs(nq_ + 1);
      rhs.head(nq_) = -r;
      rhs(nq_) = -t.dot(y - y_pred);
      const Eigen::VectorXd dy = a.fullPivLu().solve(rhs);
      y += dy;
      // A stiff mode's acceleration keeps the rounding of k/m times its
      // coordinate (linearised_full_rub stops there too).
      if (dy.cwiseAbs().maxCoeff() < kResidual) return residual(y).cwiseAbs().maxCoeff() < 1e3 * kResidual;
    }
    return false;
  }
  // The point linearised; throws std::runtime_error where linearised_full_rub's
  // own Newton moved it off the traced point (near a fold, onto the other root).
  FullRubStability linearise(const Eigen::VectorXd& y) const {
    Eigen::VectorXd guess = Eigen::VectorXd::Zero(2 * nq_);
    guess.head(nq_) = positions(y);
    FullRubStability rub = linearised_full_rub(rotor_, stator_, C_, f_, speed(y), guess, penalty_);
    if ((rub.state.head(nq_) - guess.head(nq_)).cwiseQuotient(scale_.head(nq_)).cwiseAbs().maxCoeff() > kSamePoint) {
      throw std::runtime_error("the linearisation's Newton left the traced point at " + std::to_string(speed(y)) +
                               " rad/s");
    }
    return rub;
  }

 private:
  const TurningRotor& rotor_;
  const StationStator& stator_;
  double C_, f_;
  const PenaltyContact* penalty_;
  int nq_;
  Eigen::VectorXd scale_;
};

}  // namespace

FullRubBranch continue_full_rub(const TurningRotor& rotor, const StationStator& stator, double C, double f,
                                const FullRubStability& start, double w0, const ContinuationSettings& settings,
                                const PenaltyContact* penalty) {
  if (!(settings.min_speed_rad_per_s < settings.max_speed_rad_per_s) || !(w0 > 0.0) ||
      !(w0 >= settings.min_speed_rad_per_s) || !(w0 <= settings.max_speed_rad_per_s)) {
    throw std::invalid_argument(
        "full rub continuation: the start's speed must be above 0 and lie in a speed range of some width");
  }
  const int nq = static_cast<int>(start.state.size()) / 2;
  const RestPoint g(rotor, stator, C, f, penalty, start.state.head(nq), w0);
  FullRubBranch branch;
  Eigen::VectorXd y = g.scaled(start.state.head(nq), w0);
  Eigen::VectorXd direction = Eigen::VectorXd::Zero(nq + 1);
  direction(nq) = settings.increasing_speed ? 1.0 : -1.0;
  Eigen::VectorXd t = g.tangent(y, direction);
  branch.points.push_back({w0, start});
  double ds = settings.step;
  while (true) {
    if (static_cast<int>(branch.points.size()) >= settings.max_points) {
      branch.end = "max_points (" + std::to_string(settings.max_points) + ")";
      break;
    }
    Eigen::VectorXd y_new;
    int iterations = 0;
    if (!g.correct(y + ds * t, t, y_new, iterations)) {
      ds *= 0.5;
      if (ds < kMinStep) {
        branch.end = "the corrector's failure at the smallest step";
        break;
      }
      continue;
    }
    const Eigen::VectorXd t_new = g.tangent(y_new, t);
    if (t.dot(t_new) < kMinTurnCosine) {
      ds *= 0.5;
      if (ds < kMinStep) {
        branch.end = "a turn of the tangent at the smallest step";
        break;
      }
      continue;
    }
    const double w_new = g.speed(y_new);
    // A point at arclength s along t from y, corrected (the fold's and the
    // stability change's regula falsi); y_new itself at s = ds.
    auto point_at = [&](double s) {
      Eigen::VectorXd ys;
      int its = 0;
      if (!g.correct(y + s * t, t, ys, its)) {
        throw std::runtime_error("the corrector failed inside a step at " + std::to_string(g.speed(y)) + " rad/s");
      }
      return ys;
    };
    FullRubStability rub;
    try {
      if (t(nq) * t_new(nq) < 0.0) {  // dw/ds changes sign: a fold
        const double s = regula_falsi([&](double si) { return g.tangent(point_at(si), t)(nq); }, t(nq), ds, t_new(nq),
                                      kLocateFraction);
        branch.folds_rad_per_s.push_back(g.speed(point_at(s)));
      }
      rub = g.linearise(y_new);
      if (!(rub.normal_force_N > 0.0)) {
        branch.end = "the normal force's fall to 0 near " + std::to_string(w_new) +
                     " rad/s (the branch meets the free orbit: the contact ends)";
        break;
      }
      const FullRubStability& last = branch.points.back().rub;
      if (last.stable() != rub.stable()) {
        const double growth0 = last.eigenvalues.front().real(), growth1 = rub.eigenvalues.front().real();
        const double s = regula_falsi([&](double si) { return g.linearise(point_at(si)).eigenvalues.front().real(); },
                                      growth0, ds, growth1, kLocateFraction);
        branch.stability_changes_rad_per_s.push_back(g.speed(point_at(s)));
      }
    } catch (const std::runtime_error& e) {
      branch.end = std::string("a failure: ") + e.what();  // the points so far stand
      break;
    }
    if (w_new < settings.min_speed_rad_per_s || w_new > settings.max_speed_rad_per_s) {
      branch.end = "the speed range's end";
      break;
    }
    branch.points.push_back({w_new, std::move(rub)});
    y = y_new;
    t = t_new;
    if (iterations <= 3) ds = std::min(1.5 * ds, settings.max_step);
  }
  return branch;
}

}  // namespace rotor_rub::core
