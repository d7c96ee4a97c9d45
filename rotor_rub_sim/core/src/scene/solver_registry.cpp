#include "rotor_rub_sim/core/solver_registry.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "methods/iteration_method.hpp"
#include "methods/penalty_method.hpp"
#include "methods/switching_method.hpp"

namespace rotor_rub::core {

// auto: the fastest integrator of each method at the requested tolerance
// that is as accurate as dopri5 there (the paper run-up's work-precision
// sweep, docs/benchmarks.md). dop853's error norm is an RMS over the state
// where dopri5's takes the largest component, so at the same rtol its error
// is larger, by far at rtol 1e-3; from rtol 1e-4 down it is faster than
// dopri5 at the same rtol and at equal error. So switching and iteration run
// dop853 up to rtol 1e-4 and dopri5 above. Penalty runs rosenbrock4 at every
// rtol (faster than dopri5 on the stiff contact spring, at equal or better
// accuracy). The figures: docs/benchmarks.md, "Timings the other pages rest
// on".
// Switching and iteration on rosenbrock4 take RODASP in free flight only,
// dop853 in contact (neither the constrained dynamics nor the iterated force
// has a closed-form Jacobian): a flexible rotor's highest mode kept bounds
// the explicit schemes' steps, not RODASP's (docs/rotors.md, "Speed at many
// modes"). Neither is the faster on every rotor (RODASP is the slower below
// about 8 planar modes and where the modes kept are rung: the seal run-up
// from 12, the 204-DOF anisotropic rig up to 16), so on a flexible rotor
// auto takes dop853_rosenbrock4 up to rtol 1e-4: dop853, and RODASP in free
// flight where dop853's steps are bound by stability and a probe finds
// RODASP's longer by its cost (dense_stiffness_switch.hpp). On the Jeffcott
// auto stays dop853: its free flight has the rotor's and the stator's two
// modes, not stiff on the paper's scene
// (SolverRegistry.EveryRowRunsThePaperScenesFirstContact); a scene with a far
// stiffer stator may name dop853_rosenbrock4.
// Why the other pairs are not offered: the rigid methods locate events on a
// dense output of their own (dopri5's, RODASP's, or the Hermite one of rkf78
// and dop853); iteration on rkf78 let a slow graze with gravity pass beyond the
// bore before lift-offs were located inside a step, and is not offered; the
// penalty contact is stiff, so the explicit high-order schemes only waste
// steps there.
// On a flexible rotor (a rotor_file) the penalty method's choice is the
// Jeffcott's: its rosenbrock4 has the reduced rotor's Jacobian in closed
// form and the pressed contact in polar coordinates there too; its steps do
// not grow with the modes kept, dopri5's do (docs/rotors.md, "The penalty
// method on rosenbrock4": where dopri5 is the faster, by up to 2.3 times,
// and where rosenbrock4 is, by up to 68).
constexpr double kHighOrderUpToRtol = 1e-4;
constexpr double kAnyRtol = 1.0;  // rtol's largest accepted value

const std::vector<SolverEntry>& solver_registry() {
  using I = Integrator;
  using M = Method;
  static const std::vector<SolverEntry> table{
      // method, integrator, auto up to rtol {Jeffcott, flexible}, factories {Jeffcott, flexible}, note
      {M::kPenalty,
       I::kRosenbrock4,
       {kAnyRtol, kAnyRtol},
       {&make_penalty_jeffcott<I::kRosenbrock4>, &make_penalty_flexible<I::kRosenbrock4>},
       "RODASP, linearly implicit 4(3) on an analytic Jacobian: the stiff contact spring at any k_c"},
      {M::kPenalty,
       I::kDopri5,
       {0.0, 0.0},
       {&make_penalty_jeffcott<I::kDopri5>, &make_penalty_flexible<I::kDopri5>},
       "explicit 5(4): steps limited by the contact spring's stability, slow for a stiff k_c"},
      {M::kPenalty,
       I::kRk4,
       {0.0, 0.0},
       {&make_penalty_jeffcott<I::kRk4>, &make_penalty_flexible<I::kRk4>},
       "classic RK4 at the fixed step fixed_step_s (below its stability bound, checked): the paper's fixed-step runs"},
      {M::kSwitching,
       I::kDop853Rosenbrock4,
       {0.0, kHighOrderUpToRtol},
       {&make_switching_jeffcott<I::kDop853Rosenbrock4>, &make_switching_flexible<I::kDop853Rosenbrock4>},
       "dop853, and RODASP in free flight where dop853's steps there are stiff and RODASP's pay for their cost: a "
       "flexible rotor"},
      {M::kSwitching,
       I::kDop853,
       {kHighOrderUpToRtol, kHighOrderUpToRtol},
       {&make_switching_jeffcott<I::kDop853>, &make_switching_flexible<I::kDop853>},
       "explicit 8(5,3), Hermite dense output, RMS error norm: the fastest at tight tolerances"},
      {M::kSwitching,
       I::kDopri5,
       {kAnyRtol, kAnyRtol},
       {&make_switching_jeffcott<I::kDopri5>, &make_switching_flexible<I::kDopri5>},
       "explicit 5(4) with its own dense output, ode45's scheme (the paper's): loose tolerances"},
      {M::kSwitching,
       I::kRkf78,
       {0.0, 0.0},
       {&make_switching_jeffcott<I::kRkf78>, &make_switching_flexible<I::kRkf78>},
       "explicit 7(8), Hermite dense output: an independent high-order check"},
      {M::kSwitching,
       I::kRosenbrock4,
       {0.0, 0.0},
       {&make_switching_jeffcott<I::kRosenbrock4>, &make_switching_flexible<I::kRosenbrock4>},
       "RODASP in free flight (its Jacobian in closed form but under a motor), dop853 in contact: a flexible rotor "
       "with many modes"},
      {M::kIteration,
       I::kDop853Rosenbrock4,
       {0.0, kHighOrderUpToRtol},
       {&make_iteration_jeffcott<I::kDop853Rosenbrock4>, &make_iteration_flexible<I::kDop853Rosenbrock4>},
       "dop853, and RODASP in free flight where dop853's steps there are stiff and RODASP's pay for their cost: a "
       "flexible rotor"},
      {M::kIteration,
       I::kDop853,
       {kHighOrderUpToRtol, kHighOrderUpToRtol},
       {&make_iteration_jeffcott<I::kDop853>, &make_iteration_flexible<I::kDop853>},
       "explicit 8(5,3), Hermite dense output, RMS error norm: the fastest at tight tolerances"},
      {M::kIteration,
       I::kDopri5,
       {kAnyRtol, kAnyRtol},
       {&make_iteration_jeffcott<I::kDopri5>, &make_iteration_flexible<I::kDopri5>},
       "explicit 5(4) with its own dense output, ode45's scheme (the paper's): loose tolerances"},
      {M::kIteration,
       I::kRosenbrock4,
       {0.0, 0.0},
       {&make_iteration_jeffcott<I::kRosenbrock4>, &make_iteration_flexible<I::kRosenbrock4>},
       "RODASP in free flight (its Jacobian in closed form but under a motor), dop853 engaged: a flexible rotor with "
       "many modes"},
  };
  return table;
}

const SolverEntry* find_solver(Method method, Integrator integrator) {
  for (const SolverEntry& e : solver_registry()) {
    if (e.method == method && e.integrator == integrator) return &e;
  }
  return nullptr;
}

Integrator auto_integrator(Method method, double rtol, RotorKind rotor) {
  const auto r = static_cast<std::size_t>(rotor);
  for (const SolverEntry& e : solver_registry()) {
    if (e.method == method && rtol <= e.auto_up_to_rtol[r]) return e.integrator;
  }
  throw std::logic_error(std::string("solver registry: no auto integrator for method ") + to_string(method) +
                         " on the " + to_string(rotor) + " rotor");
}

Integrator effective_integrator(const SolverSettings& solver, RotorKind rotor) {
  return solver.integrator == Integrator::kAuto ? auto_integrator(solver.method, solver.rtol, rotor)
                                                : solver.integrator;
}

Integrator effective_integrator(const Scene& scene) { return effective_integrator(scene.solver, rotor_kind(scene)); }

namespace {

// 1e-4, not 0.0001: how the docs and the template write a tolerance.
std::string rtol_text(double rtol) {
  const long exponent = std::lround(std::log10(rtol));
  if (rtol < 1.0 && rtol == std::pow(10.0, static_cast<double>(exponent))) return "1e" + std::to_string(exponent);
  std::ostringstream os;
  os << rtol;
  return os.str();
}

// "dop853 up to rtol 1e-4, dopri5 above": what auto picks for a method on a rotor.
std::string auto_picks(Method m, RotorKind rotor) {
  const auto r = static_cast<std::size_t>(rotor);
  std::string picks;
  double auto_from = 0.0;  // as auto_integrator: the method's rows in order
  for (const SolverEntry& e : solver_registry()) {
    if (e.method != m || e.auto_up_to_rtol[r] <= auto_from) continue;
    picks += std::string(picks.empty() ? "" : ", ") + to_string(e.integrator);
    if (e.auto_up_to_rtol[r] < kAnyRtol) {
      picks += " up to rtol " + rtol_text(e.auto_up_to_rtol[r]);
    } else if (auto_from > 0.0) {
      picks += " above";
    }
    auto_from = e.auto_up_to_rtol[r];
  }
  return picks;
}

// Every method's picks on one kind of rotor: "penalty rosenbrock4; switching ...".
std::string auto_integrator_text_for(RotorKind rotor) {
  std::string text;
  for (const Method m : kAllMethods)
    text += std::string(text.empty() ? "" : "; ") + to_string(m) + " " + auto_picks(m, rotor);
  return text;
}

}  // namespace

std::string auto_integrator_text() {
  std::string text;
  for (const Method m : kAllMethods) {
    std::string picks = auto_picks(m, RotorKind::kJeffcott);
    const std::string flexible = auto_picks(m, RotorKind::kFlexible);
    if (flexible != picks) picks += ", " + flexible + " with a rotor_file";
    text += std::string(text.empty() ? "" : "; ") + to_string(m) + " " + picks;
  }
  return text;
}

std::string integrators_of(Method method) {
  std::string names;
  for (const SolverEntry& e : solver_registry()) {
    if (e.method == method) names += (names.empty() ? "" : ", ") + std::string(to_string(e.integrator));
  }
  return names;
}

std::string solver_table_text() {
  std::ostringstream os;
  auto pad = [](std::string text, std::size_t width) {
    return text + std::string(text.size() < width ? width - text.size() : 1, ' ');
  };
  double auto_from = 0.0;  // the auto range's lower end within the method
  Method method = solver_registry().front().method;
  for (const SolverEntry& e : solver_registry()) {
    if (e.method != method) auto_from = 0.0;
    method = e.method;
    std::string when = "-";
    const double up_to = e.auto_up_to_rtol[static_cast<std::size_t>(RotorKind::kJeffcott)];
    if (up_to > auto_from) {
      if (auto_from == 0.0 && up_to >= kAnyRtol) {
        when = "any rtol";
      } else if (auto_from == 0.0) {
        when = "rtol <= " + rtol_text(up_to);
      } else {
        when = "rtol > " + rtol_text(auto_from);
      }
      auto_from = up_to;
    }
    os << "  " << pad(to_string(e.method), 11) << pad(to_string(e.integrator), 20) << pad(when, 15) << e.note << '\n';
  }
  os << "  with a rotor_file (a flexible rotor): auto picks " << auto_integrator_text_for(RotorKind::kFlexible)
     << ";\n    penalty on rk4 with fixed_step_s below the rotor's own stability bound (from its eigenvalues in "
        "contact)\n";
  return os.str();
}

}  // namespace rotor_rub::core
