#include "rotor_rub_sim/core/parameters.hpp"

#include <stdexcept>

#include "rotor_rub_sim/core/name_table.hpp"

namespace rotor_rub::core {
namespace {

template <class Table>
auto value_of(const Table& table, const std::string& s, const char* what) {
  auto v = table[0].value;
  if (value_in_table(table, s, &v)) return v;
  std::string accepted;
  for (const auto& row : table) accepted += std::string(accepted.empty() ? "" : ", ") + row.name;
  throw std::invalid_argument(std::string(what) + " '" + s + "' is not accepted; accepted: " + accepted);
}

}  // namespace

const char* to_string(Method m) { return name_in_table(kMethodNames, m); }
const char* to_string(Integrator i) { return name_in_table(kIntegratorNames, i); }
const char* to_string(StatorModel s) { return name_in_table(kStatorModelNames, s); }
const char* to_string(DriveModel d) { return name_in_table(kDriveModelNames, d); }
Method method_from_string(const std::string& s) { return value_of(kMethodNames, s, "method"); }
Integrator integrator_from_string(const std::string& s) { return value_of(kIntegratorNames, s, "integrator"); }
StatorModel stator_model_from_string(const std::string& s) { return value_of(kStatorModelNames, s, "stator_model"); }
DriveModel drive_model_from_string(const std::string& s) { return value_of(kDriveModelNames, s, "drive_model"); }

}  // namespace rotor_rub::core
