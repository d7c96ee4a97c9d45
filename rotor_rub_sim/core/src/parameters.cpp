#include "rotor_rub_sim/core/parameters.hpp"

#include <stdexcept>

namespace rotor_rub::core {
namespace {

template <class Table, class Enum>
const char* name_of(const Table& table, Enum v) {
  for (const auto& row : table) {
    if (row.value == v) return row.name;
  }
  return "?";  // unreachable: the tables are exhaustive
}

template <class Table>
auto value_of(const Table& table, const std::string& s, const char* what) {
  for (const auto& row : table) {
    if (s == row.name) return row.value;
  }
  std::string accepted;
  for (const auto& row : table) accepted += std::string(accepted.empty() ? "" : ", ") + row.name;
  throw std::invalid_argument(std::string(what) + " '" + s + "' is not accepted; accepted: " + accepted);
}

}  // namespace

const char* to_string(Method m) { return name_of(kMethodNames, m); }
const char* to_string(Integrator i) { return name_of(kIntegratorNames, i); }
const char* to_string(StatorModel s) { return name_of(kStatorModelNames, s); }
Method method_from_string(const std::string& s) { return value_of(kMethodNames, s, "method"); }
Integrator integrator_from_string(const std::string& s) { return value_of(kIntegratorNames, s, "integrator"); }
StatorModel stator_model_from_string(const std::string& s) { return value_of(kStatorModelNames, s, "stator_model"); }

}  // namespace rotor_rub::core
