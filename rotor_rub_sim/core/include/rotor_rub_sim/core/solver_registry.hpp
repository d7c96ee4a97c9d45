/// @file
/// The one table of contact methods and the time integrators each runs on,
/// with a factory and auto's choice per kind of rotor (RotorKind).
/// Validation (validate_scene), the factory (make_contact_method),
/// rotor_rub_run --list-solvers, the tests' solver lists (test_support.hpp)
/// and the bench's rows all read it: adding an integrator to a method is a
/// row here and an explicit instantiation of the method's factory
/// (docs/architecture.md).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

class ContactMethod;
struct Scene;

/// Builds a contact method for a scene whose method and integrator are the row's.
using ContactMethodFactory = std::unique_ptr<ContactMethod> (*)(const Scene&);

/// One method on one integrator, for each kind of rotor (indexed by RotorKind).
struct SolverEntry {
  Method method;          ///< the contact method
  Integrator integrator;  ///< a concrete integrator (never kAuto)
  /// `auto` resolves to this row's integrator for rtol up to this value
  /// (the method's first such row in the table for the rotor); 0: never.
  std::array<double, kAllRotorKinds.size()> auto_up_to_rtol;
  /// Builds the method for a validated scene with this kind of rotor.
  std::array<ContactMethodFactory, kAllRotorKinds.size()> make;
  /// When to use it, one line (--list-solvers, docs/numerics.md).
  const char* note;
};

/// Every offered pair, methods in paper order, the auto choices first per method.
const std::vector<SolverEntry>& solver_registry();

/// The row of a method on a concrete integrator; nullptr when not offered.
const SolverEntry* find_solver(Method method, Integrator integrator);

/// The integrator `auto` stands for with this method at this rtol on this
/// kind of rotor.
Integrator auto_integrator(Method method, double rtol, RotorKind rotor = RotorKind::kJeffcott);

/// The integrator a run of these settings uses on this kind of rotor (`auto` resolved).
Integrator effective_integrator(const SolverSettings& solver, RotorKind rotor = RotorKind::kJeffcott);
/// The same for a scene (its rotor_kind).
Integrator effective_integrator(const Scene& scene);

/// "dop853, dopri5, rkf78": the integrators offered with a method, in the registry's order.
std::string integrators_of(Method method);

/// What `auto` picks, per method (and where a flexible rotor's pick differs,
/// that too), in one line (the integrator key's
/// description: --help, --list-keys, the template, docs/node.md).
std::string auto_integrator_text();

/// A table for --list-solvers: method, integrator, where auto picks it, note.
std::string solver_table_text();

}  // namespace rotor_rub::core
