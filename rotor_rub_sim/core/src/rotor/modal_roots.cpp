#include "rotor/modal_roots.hpp"

#include <Spectra/GenEigsSolver.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rotor_rub::core::modal {

// The first-order matrix [[0, I], [-L^-1 K L^-T, -L^-1 (C + Omega G) L^-T]]
// in mass-normalised coordinates y = L^T q (M = L L^T): there the stiffness
// of a symmetric K is symmetric, and the matrix far better scaled than with
// M^-1 K (a rotor's masses and inertias span 1e4 and more). L written to l.
Eigen::MatrixXd first_order_matrix(const RotorMatrices& m, double speed_rad_per_s, Eigen::MatrixXd& l) {
  const int n = static_cast<int>(m.M.rows());
  const Eigen::LLT<Eigen::MatrixXd> mass(m.M);
  if (mass.info() != Eigen::Success) {
    throw std::invalid_argument("rotor: the mass matrix is not positive definite (a node without mass or inertia?)");
  }
  l = mass.matrixL();
  auto congruent = [&](const Eigen::MatrixXd& x) {
    const Eigen::MatrixXd left = l.triangularView<Eigen::Lower>().solve(x);
    return Eigen::MatrixXd(l.triangularView<Eigen::Lower>().solve(left.transpose()).transpose());
  };
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -congruent(m.K);
  a.bottomRightCorner(n, n) = -congruent(m.C + speed_rad_per_s * m.G);
  return a;
}

// A decaying root is oscillatory (a mode) when it completes a cycle before
// decaying below double rounding: its amplitude falls by exp(2 pi |Re| / Im)
// in a period 2 pi / Im, so Im > 2 pi / ln(1 / eps) (-Re) = 0.174 (-Re), a
// damping ratio below 0.985. Above that no oscillation can be seen: an
// overdamped pair's two real roots, turned into a complex pair by the
// gyroscopic coupling at speed (ROSS's damped rig,
// config/rotors/ross_rub_rig.yaml, whose stiffness-proportional damping
// overdamps its highest shaft modes: at 1000 rad/s they are pairs at 23
// rad/s with a damping ratio of 1 - 3e-8, below every shaft mode), and a
// real root that leaves the QR with a small imaginary part (about eps times
// the largest eigenvalue for a simple root, sqrt(eps) = 1.5e-8 of itself
// for a double one). A root that does not decay (Re >= 0: undamped, or
// growing, an instability) is a mode when Im > 1e-6 |lambda|, the same
// rounding's bound, and, as a decaying one, when it completes a cycle before
// growing by 1 / eps. No root below 1 rpm is a mode (kRigidBodyBelow_rad_per_s).
// So every mode has |lambda| < kModulusPerImag Im, which bounds the search
// for the lowest ones (lowest_mode_roots). (test_fe_rotor,
// RayleighShaftDampingGivesEachModeItsClosedFormRatio,
// NearlyCriticalPairsAreNoModes, OverdampedPairsTurnedByTheSpinAreNoModes;
// RotorSupports.AFreePedestalIsRigidBodyMotionNotADivergence.)
namespace {
const double kCycleBound = 2.0 * M_PI / std::log(1.0 / std::numeric_limits<double>::epsilon());
const double kModulusPerImag = std::sqrt(1.0 + 1.0 / (kCycleBound * kCycleBound));  // 5.82
}  // namespace

bool oscillatory(std::complex<double> lambda) {
  if (!(std::abs(lambda) > kRigidBodyBelow_rad_per_s)) return false;
  if (lambda.real() < 0.0) return lambda.imag() > kCycleBound * -lambda.real();
  return lambda.imag() > std::max(kCycleBound * lambda.real(), 1e-6 * std::abs(lambda));
}

// The oscillatory roots of the first-order matrix a by damped frequency, from
// its eigenvalues alone (the QR without vectors: half its cost).
std::vector<std::complex<double>> mode_roots(const Eigen::MatrixXd& a) {
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(a, false);
  if (eig.info() != Eigen::Success) throw std::runtime_error("modes: the eigenvalue solver did not converge");
  std::vector<std::complex<double>> roots;
  for (int i = 0; i < a.rows(); ++i) {
    if (oscillatory(eig.eigenvalues()(i))) roots.push_back(eig.eigenvalues()(i));
  }
  std::sort(roots.begin(), roots.end(), [](auto p, auto q) { return p.imag() < q.imag(); });
  return roots;
}

// The QR's roots within this of each other, relative, are a cluster
// (refined_mode_roots).
constexpr double kQrClusterRadius = 1e-6;
// A refined root and its vector solve Q(lambda) x = 0 to this backward
// error, |Q(lambda) x| relative to |lambda|^2 |M x| + |lambda| |D x| + |K x|:
// at most 8e-10 measured on the tests' rotors, 0.24 for an iterate drawn off
// its root (test_fe_rotor).
constexpr double kBackwardError = 1e-6;

namespace {

// The unit vector x orthogonal to the orthonormal `basis` that makes |q x|
// least: q's smallest singular vector on the basis's complement.
Eigen::VectorXcd least_null_vector(const Eigen::MatrixXcd& q, const std::vector<Eigen::VectorXcd>& basis) {
  const Eigen::Index n = q.cols(), k = static_cast<Eigen::Index>(basis.size());
  Eigen::MatrixXcd complement = Eigen::MatrixXcd::Identity(n, n - k);
  if (k > 0) {
    Eigen::MatrixXcd b(n, k);
    for (Eigen::Index j = 0; j < k; ++j) b.col(j) = basis[static_cast<std::size_t>(j)];
    complement =
        Eigen::HouseholderQR<Eigen::MatrixXcd>(b).householderQ() * Eigen::MatrixXcd::Identity(n, n).rightCols(n - k);
  }
  const Eigen::BDCSVD<Eigen::MatrixXcd> svd(q * complement, Eigen::ComputeThinV);
  return (complement * svd.matrixV().col(svd.matrixV().cols() - 1)).normalized();
}

}  // namespace

// A root of the quadratic eigenproblem Q(mu) q = (mu^2 M + mu D + K) q = 0
// refined from the QR's value lambda, in the physical coordinates (an n x n
// complex LU per step, an eighth of the first-order matrix's): inverse
// iteration for the right and left vectors x and y, and the two-sided
// Rayleigh functional, the root of y^H Q(mu) x = 0 nearest the last value
// (second order in the vectors' errors). The starts are generic (unit
// entries at phases a golden angle apart: no symmetry of the rotor's
// leaves a direction out), and an orthonormal basis of the vectors of
// earlier roots of a cluster (a double root: an isotropic rotor at rest, or
// its translation at any speed) is projected out of each iterate, so that a
// cluster's roots keep independent shapes
// (FeRotor.PureTiltWhirlsAsItsSlopes). A shift that is a root to the last
// bit makes Q singular: it is nudged by a relative 1e-13, then 1e-10, and
// where no nudge gives finite vectors the refinement throws.
std::complex<double> refined_qep_root(const Eigen::MatrixXcd& mass, const Eigen::MatrixXcd& damping,
                                      const Eigen::MatrixXcd& stiffness, std::complex<double> lambda,
                                      const std::vector<const QepVectors*>& cluster, QepVectors& v) {
  using Complex = std::complex<double>;
  using Basis = std::vector<Eigen::VectorXcd>;
  const Eigen::Index n = mass.rows();
  Basis right_basis, left_basis;
  auto extend = [](Basis& basis, const Eigen::VectorXcd& u) {
    Eigen::VectorXcd w = u;
    for (const Eigen::VectorXcd& e : basis) w -= e.dot(w) * e;
    if (w.norm() > 1e-8 * u.norm()) basis.push_back(w.normalized());  // a dependent vector adds nothing
  };
  for (const QepVectors* c : cluster) {
    extend(right_basis, c->right);
    extend(left_basis, c->left);
  }
  // u with the basis projected out (twice: the second pass takes what the
  // first's rounding left), as a unit vector; false where nothing is left.
  auto apart = [](const Basis& basis, Eigen::VectorXcd& u) {
    for (int pass = 0; pass < 2; ++pass) {
      for (const Eigen::VectorXcd& e : basis) u -= e.dot(u) * e;
    }
    const double norm = u.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) return false;
    u /= norm;
    return true;
  };
  const Complex start = lambda;
  // y^H Q(mu) x = a mu^2 + b mu + c for v's vectors: its finite root nearest
  // `near` (the pair without cancellation).
  auto rayleigh_root = [&](Complex near) {
    const Complex a = v.left.dot(mass * v.right), b = v.left.dot(damping * v.right),
                  c = v.left.dot(stiffness * v.right);
    const Complex root = std::sqrt(b * b - 4.0 * a * c);
    const Complex big = -0.5 * (std::real(std::conj(b) * root) >= 0.0 ? b + root : b - root);
    Complex refined = near;
    double nearest = std::numeric_limits<double>::infinity();
    for (const Complex candidate : {big / a, c / big}) {
      const double distance = std::abs(candidate - near);
      if (std::isfinite(candidate.real()) && std::isfinite(candidate.imag()) && distance < nearest) {
        nearest = distance;
        refined = candidate;
      }
    }
    return refined;
  };
  // The backward error of (mu, x): |Q(mu) x| relative to its terms' sizes.
  auto residual = [&](Complex mu, const Eigen::VectorXcd& x) {
    const Eigen::VectorXcd mx = mass * x, dx = damping * x, kx = stiffness * x;
    return (mu * mu * mx + mu * dx + kx).norm() / (std::norm(mu) * mx.norm() + std::abs(mu) * dx.norm() + kx.norm());
  };
  constexpr double kGoldenAngle_rad = 2.399963229728653;
  v.right.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) v.right(k) = std::polar(1.0, kGoldenAngle_rad * static_cast<double>(k));
  v.left = v.right.conjugate();
  if (!apart(right_basis, v.right) || !apart(left_basis, v.left)) {
    throw std::runtime_error("modes: a cluster of roots spans the whole space");
  }
  for (int step = 0; step < 3; ++step) {
    bool solved = false;
    for (const double nudge : {0.0, 1e-13, 1e-10}) {
      const Complex shift = lambda * (1.0 + nudge);
      const Eigen::PartialPivLU<Eigen::MatrixXcd> q(shift * shift * mass + shift * damping + stiffness);
      QepVectors next = v;
      solved = true;
      for (int pass = 0; pass < (step == 0 ? 2 : 1) && solved; ++pass) {  // from the generic starts: twice
        next.right = q.solve(next.right);
        next.left = q.adjoint().solve(next.left);
        solved = apart(right_basis, next.right) && apart(left_basis, next.left);
      }
      if (solved) {
        v = std::move(next);
        break;
      }
    }
    if (!solved) throw std::runtime_error("modes: inverse iteration found no finite vector at a root");
    lambda = rayleigh_root(lambda);
  }
  // A refinement whose root and right vector do not solve Q(lambda) x = 0
  // (kBackwardError) had its iterates drawn off the QR's root: the third copy
  // of a fourfold root did, onto no root at all, where its left and right
  // iterates paired badly (y^H Q'(lambda) x about 0:
  // FeRotor.AFourfoldRootKeepsItsFourModes). Then the vectors are those that
  // make |Q(start) x| and |Q(start)^H y| least apart from the cluster's (the
  // smallest singular vectors of Q restricted to the complement), one
  // Rayleigh step refines the QR's root, and where that step does not solve
  // Q x = 0 either the QR's root stays; a root whose vector solves neither is
  // refused.
  v.refined = residual(lambda, v.right) <= kBackwardError;
  if (v.refined) return lambda;
  v.right = least_null_vector(start * start * mass + start * damping + stiffness, right_basis);
  v.left = least_null_vector((start * start * mass + start * damping + stiffness).adjoint(), left_basis);
  const Complex rayleigh = rayleigh_root(start);
  if (residual(rayleigh, v.right) <= kBackwardError) return rayleigh;
  if (!(residual(start, v.right) <= kBackwardError)) {
    throw std::runtime_error("modes: no vector solves the quadratic problem at the root (" +
                             std::to_string(start.real()) + ", " + std::to_string(start.imag()) + ") 1/s");
  }
  return start;
}

std::vector<ModeRoot> refined_mode_roots(const RotorMatrices& m, double speed_rad_per_s, const Eigen::MatrixXd& a,
                                         int count) {
  using Complex = std::complex<double>;
  const std::vector<Complex> roots = mode_roots(a);  // by damped frequency
  const Eigen::MatrixXcd mass = m.M.cast<Complex>(), stiffness = m.K.cast<Complex>(),
                         damping = (m.C + speed_rad_per_s * m.G).cast<Complex>();
  std::vector<ModeRoot> out;
  std::vector<Complex> qr_values;
  std::vector<QepVectors> vectors;
  vectors.reserve(roots.size());  // the cluster's pointers stay valid
  for (const Complex qr_value : roots) {
    if (static_cast<int>(out.size()) == count) break;
    // The QR's eigenvalues carry an error of eps times the largest, which
    // the lowest modes feel: refined (refined_qep_root). Earlier roots
    // within kQrClusterRadius of this one are its cluster.
    std::vector<const QepVectors*> cluster;
    for (std::size_t j = 0; j < qr_values.size(); ++j) {
      if (std::abs(qr_values[j] - qr_value) <= kQrClusterRadius * std::abs(qr_value)) cluster.push_back(&vectors[j]);
    }
    QepVectors v;
    const Complex lambda = refined_qep_root(mass, damping, stiffness, qr_value, cluster, v);
    qr_values.push_back(qr_value);
    vectors.push_back(v);
    if (oscillatory(lambda)) out.push_back({lambda, v.right});
  }
  std::sort(out.begin(), out.end(),
            [](const ModeRoot& x, const ModeRoot& y) { return x.lambda.imag() < y.lambda.imag(); });
  return out;
}

namespace {

// Spectra's operator: (A - sigma I)^-1 x, and with an orthonormal basis Q of
// roots already found, P (A - sigma I)^-1 P x with P = I - Q Q^T, whose
// eigenvalues are the other roots' (the found invariant subspace deflated).
class ShiftInverted {
 public:
  using Scalar = double;
  ShiftInverted(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu, const Eigen::MatrixXd* deflated)
      : lu_(lu), deflated_(deflated) {}
  Eigen::Index rows() const { return lu_.rows(); }
  Eigen::Index cols() const { return lu_.cols(); }
  void perform_op(const double* x_in, double* y_out) const {
    const Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    if (deflated_ == nullptr) {
      y = lu_.solve(x);
      return;
    }
    const Eigen::MatrixXd& q = *deflated_;
    y = lu_.solve(Eigen::VectorXd(x - q * (q.transpose() * x)));
    y -= q * (q.transpose() * y);
  }

 private:
  const Eigen::PartialPivLU<Eigen::MatrixXd>& lu_;
  const Eigen::MatrixXd* deflated_;
};

// The shift [1/s]: off zero, where a free rotor's rigid-body roots are.
constexpr double kShift = -1.0;
// The Ritz values' tolerance (Spectra: the residual relative to the
// transformed root 1 / (lambda - sigma)); the roots then agree with the
// dense path's refined ones to 6.7e-11 on the anisotropic rig
// (ModalRoots.ArnoldiFindsTheDenseQrsLowestModes).
constexpr double kRitzTolerance = 1e-12;
// Roots this close (relative) are one multiple root's copies: Arnoldi's
// copies of test_modal_roots' double and twelve-fold roots agree to 1e-12.
constexpr double kClusterWithin = 1e-9;
// The found vectors' span is taken as invariant when (A - sigma I)^-1 maps
// it into itself to this much of its largest root (Ritz vectors converged
// to 1e-12 of theirs), and as of full rank when its columns, each of unit
// length, keep this much of a dimension apart.
constexpr double kInvariantTo = 1e-9;
constexpr double kIndependentTo = 1e-8;
// The deflated run's tolerance: only the size of its largest root counts,
// and the radius is taken this much shorter than it says.
constexpr double kRadiusTolerance = 1e-6;
constexpr double kRadiusMargin = 1e-5;

}  // namespace

std::optional<double> complete_within(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu, const Eigen::MatrixXcd& vectors,
                                      Eigen::Index found) {
  const Eigen::Index size = lu.rows();
  Eigen::MatrixXd span(size, 2 * vectors.cols());
  span << vectors.real(), vectors.imag();
  for (Eigen::Index j = 0; j < span.cols(); ++j) {
    if (span.col(j).norm() > 0.0) span.col(j).normalize();  // a real root's zero imaginary part stays zero
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(span.rows(), span.cols());
  qr.setThreshold(kIndependentTo);
  qr.compute(span);
  if (qr.rank() != found || size - found < 4) return std::nullopt;  // dependent vectors; or no room to look
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(size, found);
  // Invariant: B Q = Q (Q^T B Q), B = (A - sigma I)^-1, else P B P has
  // other roots than those left out.
  const Eigen::MatrixXd bq = lu.solve(q);
  const double largest_found = bq.norm();  // >= the largest |theta| found
  if (!((bq - q * (q.transpose() * bq)).norm() <= kInvariantTo * largest_found)) return std::nullopt;
  ShiftInverted rest_op(lu, &q);
  Spectra::GenEigsSolver<ShiftInverted> rest(rest_op, 1, std::min<Eigen::Index>(size - found, 20));
  // Its own start: from the first run's, P B P's Krylov space would be the
  // projection of B's, which holds no copy of a multiple root that B's
  // missed (exactly, but for rounding). Unit entries at phases a golden
  // angle apart, real parts: generic, and the same in every thread.
  constexpr double kGoldenAngle_rad = 2.399963229728653;
  Eigen::VectorXd start(size);
  for (Eigen::Index k = 0; k < size; ++k) start(k) = std::cos(kGoldenAngle_rad * static_cast<double>(k));
  start -= q * (q.transpose() * start);
  rest.init(start.data());
  rest.compute(Spectra::SortRule::LargestMagn, 1000, kRadiusTolerance);
  if (rest.info() != Spectra::CompInfo::Successful) return std::nullopt;
  const double largest = std::abs(rest.eigenvalues()(0));
  if (!(largest > 0.0) || !std::isfinite(largest)) return std::nullopt;
  return (1.0 - kRadiusMargin) / largest;
}

namespace {

// The displacements q of a mode from its first-order vector y = [L^T q;
// lambda L^T q]: from the velocity half over lambda when |lambda| > 1, whose
// error is the vector's over |lambda|, and q = L^-T (.) in either case.
Eigen::VectorXcd displacements(const Eigen::MatrixXd& l, std::complex<double> lambda, const Eigen::VectorXcd& y) {
  const Eigen::Index n = l.rows();
  const Eigen::VectorXcd z =
      std::abs(lambda) > 1.0 ? Eigen::VectorXcd(y.tail(n) / lambda) : Eigen::VectorXcd(y.head(n));
  Eigen::MatrixXd parts(n, 2);
  parts << z.real(), z.imag();
  l.transpose().triangularView<Eigen::Upper>().solveInPlace(parts);
  return parts.col(0).cast<std::complex<double>>() +
         std::complex<double>(0.0, 1.0) * parts.col(1).cast<std::complex<double>>();
}

}  // namespace

// Shift-invert Arnoldi finds the roots nearest the shift, ever more of them
// until the modes found include the `count` lowest: with every root within
// a distance R of the shift found (complete_within), a mode left out has
// |lambda| >= R - |sigma|, so Im lambda > (R - |sigma|) / kModulusPerImag
// (oscillatory): when that is above the count-th mode's Im, none lower is
// missing. A double root (an isotropic rotor at rest) whose second copy the
// Arnoldi missed is the deflated operator's largest root, and R stops short
// of it. Past a quarter of the roots the dense QR is as cheap: nothing.
std::optional<std::vector<ModeRoot>> lowest_mode_roots(const Eigen::MatrixXd& a, const Eigen::MatrixXd& l, int count) {
  using Complex = std::complex<double>;
  const Eigen::Index size = a.rows();
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a - kShift * Eigen::MatrixXd::Identity(size, size));
  if (!(lu.rcond() > std::numeric_limits<double>::epsilon())) return std::nullopt;  // the shift is a root
  if (count < 1) return std::vector<ModeRoot>{};
  ShiftInverted op(lu, nullptr);
  for (Eigen::Index nev = 2 * count + 8; 4 * nev <= size; nev *= 2) {
    Spectra::GenEigsSolver<ShiftInverted> eigs(op, nev, std::min(size, 2 * nev + 1));
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestMagn, 1000, kRitzTolerance);
    if (eigs.info() != Spectra::CompInfo::Successful) return std::nullopt;
    const Eigen::VectorXcd theta = eigs.eigenvalues();
    const Eigen::MatrixXcd vectors = eigs.eigenvectors();
    if (!theta.allFinite() || !vectors.allFinite()) return std::nullopt;
    // A real matrix's roots come in conjugate pairs (exact ones, from the
    // Ritz values' real Schur form); a pair is one mode, and one root of
    // the pair found stands for both (its vector's real span holds both).
    std::vector<ModeRoot> found;
    Eigen::Index dimensions = 0;  // of the found roots' invariant subspace
    for (Eigen::Index i = 0; i < theta.size(); ++i) {
      const bool real = theta(i).imag() == 0.0;
      const bool paired = !real && (theta.array() == std::conj(theta(i))).any();
      dimensions += real || paired ? 1 : 2;
      Complex lambda = kShift + 1.0 / theta(i);
      Eigen::VectorXcd y = vectors.col(i);
      if (lambda.imag() < 0.0) {
        if (paired) continue;  // its conjugate is listed
        lambda = std::conj(lambda);
        y = y.conjugate().eval();
      }
      if (oscillatory(lambda)) found.push_back({lambda, displacements(l, lambda, y)});
    }
    std::sort(found.begin(), found.end(),
              [](const ModeRoot& x, const ModeRoot& y) { return x.lambda.imag() < y.lambda.imag(); });
    if (static_cast<int>(found.size()) < count) continue;
    const std::optional<double> radius = complete_within(lu, vectors, dimensions);
    if (!radius) return std::nullopt;
    if ((*radius - std::abs(kShift)) / kModulusPerImag <= found[static_cast<std::size_t>(count) - 1].lambda.imag()) {
      continue;
    }
    found.resize(static_cast<std::size_t>(count));
    // A multiple root's vectors span its shapes: made orthonormal, as the
    // dense path's are (FeRotor.PureTiltWhirlsAsItsSlopes); copies that
    // leave nothing apart are refused.
    for (std::size_t i = 0; i < found.size(); ++i) {
      found[i].shape.normalize();
      for (std::size_t j = 0; j < i; ++j) {
        if (std::abs(found[j].lambda - found[i].lambda) <= kClusterWithin * std::abs(found[i].lambda)) {
          found[i].shape -= found[j].shape.dot(found[i].shape) * found[j].shape;
        }
      }
      const double left = found[i].shape.norm();
      if (!(left > kIndependentTo)) return std::nullopt;
      found[i].shape /= left;
    }
    return found;
  }
  return std::nullopt;
}

std::vector<std::complex<double>> mode_roots_below(const Eigen::MatrixXd& a, const Eigen::MatrixXd& l,
                                                   double w_max_rad_per_s) {
  std::vector<std::complex<double>> out;
  for (int count = 8;; count *= 2) {
    const std::optional<std::vector<ModeRoot>> lowest = lowest_mode_roots(a, l, count);
    if (!lowest) break;
    if (lowest->back().lambda.imag() <= w_max_rad_per_s) continue;  // some may lie above it
    for (const ModeRoot& r : *lowest) {
      if (r.lambda.imag() <= w_max_rad_per_s) out.push_back(r.lambda);
    }
    return out;
  }
  for (const std::complex<double>& lambda : mode_roots(a)) {
    if (lambda.imag() <= w_max_rad_per_s) out.push_back(lambda);
  }
  return out;
}

}  // namespace rotor_rub::core::modal
