// For the every-key tests: a value just outside a key's documented accepted
// range ("(0, inf)", "[1e-14, 1]", "integer in [1, 1000]"), or "" when the
// range has no finite bound to step over (a name list, a path, (-inf, inf)).
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace rotor_rub::test {

inline std::string outside_range(const std::string& accepted) {
  const auto open = accepted.find_first_of("([");
  const auto comma = accepted.find(',', open);
  const auto close = accepted.find_first_of(")]", comma);
  if (open == std::string::npos || comma == std::string::npos || close == std::string::npos) return "";
  const std::string lo_text = accepted.substr(open + 1, comma - open - 1);
  const std::string hi_text = accepted.substr(comma + 1, close - comma - 1);
  const double lo = std::strtod(lo_text.c_str(), nullptr), hi = std::strtod(hi_text.c_str(), nullptr);
  char buf[40];
  if (std::isfinite(lo)) {
    // Exclusive: the bound itself; inclusive: a step below it.
    std::snprintf(buf, sizeof buf, "%.17g", accepted[open] == '(' ? lo : lo - std::max(1.0, std::abs(lo)));
    return buf;
  }
  if (std::isfinite(hi)) {
    std::snprintf(buf, sizeof buf, "%.17g", accepted[close] == ')' ? hi : hi + std::max(1.0, std::abs(hi)));
    return buf;
  }
  return "";
}

}  // namespace rotor_rub::test
