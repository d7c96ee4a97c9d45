// Lookups in the enum name tables ({value, name} rows, e.g. kWhirlNames):
// one implementation for every enum of the core and the tools.
#pragma once

#include <string>

namespace rotor_rub::core {

// The row's name for v ("?" if a table is not exhaustive).
template <class Table, class Enum>
const char* name_in_table(const Table& table, Enum v) {
  for (const auto& row : table) {
    if (row.value == v) return row.name;
  }
  return "?";
}

// The value named s; false when no row has that name.
template <class Table, class Enum>
bool value_in_table(const Table& table, const std::string& s, Enum* out) {
  for (const auto& row : table) {
    if (s == row.name) {
      *out = row.value;
      return true;
    }
  }
  return false;
}

}  // namespace rotor_rub::core
