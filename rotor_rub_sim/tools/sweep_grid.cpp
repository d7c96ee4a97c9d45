#include "sweep_grid.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "rotor_rub_sim/core/yaml_values.hpp"

namespace rotor_rub::tools {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::string item;
  for (char c : text) {
    if (c == ',') {
      out.push_back(trim(item));
      item.clear();
    } else {
      item += c;
    }
  }
  out.push_back(trim(item));
  for (const auto& v : out) {
    if (v.empty()) throw std::invalid_argument("empty value in list '" + text + "'");
  }
  return out;
}

// A number the grid itself computes with (atol = rtol * atol_per_rtol).
double grid_number(const std::string& key, const std::string& text) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v) || !(v > 0.0)) {
    throw std::invalid_argument(
        "grid key '" + key + "': value '" + text +
        "' is not a positive number, which atol = rtol * atol_per_rtol needs; accepted: a number > 0 "
        "(and rtol within its own range, checked per run)");
  }
  return v;
}

std::string format_double(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

std::vector<GridDocument> read_grid_file(const std::string& path) {
  std::vector<core::YamlDocument> yaml;
  try {
    yaml = core::read_yaml_documents(path);
  } catch (const core::YamlError& e) {
    throw std::invalid_argument(std::string("grid file ") + e.what());
  }
  std::vector<GridDocument> docs;
  for (const auto& y : yaml) {
    if (y.empty()) continue;  // a document of comments only
    GridDocument doc;
    for (const auto& e : y) doc.push_back({e.key, e.values});
    docs.push_back(std::move(doc));
  }
  if (docs.empty()) docs.emplace_back();
  return docs;
}

GridAxis parse_axis(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument("--set expects key=v1[,v2...], got '" + text + "'");
  return {trim(text.substr(0, eq)), split_list(text.substr(eq + 1))};
}

std::vector<SweepRun> expand_grid(const std::vector<GridDocument>& docs, const std::vector<GridAxis>& extra_axes) {
  std::vector<SweepRun> runs;
  std::vector<GridDocument> all = docs.empty() ? std::vector<GridDocument>(1) : docs;
  for (GridDocument doc : all) {
    for (const auto& a : extra_axes) {
      bool replaced = false;
      for (auto& d : doc) {
        if (d.key == a.key) {
          d = a;  // the command line wins over the file
          replaced = true;
        }
      }
      if (!replaced) doc.push_back(a);
    }
    // Odometer over the axes, the last one fastest.
    std::vector<std::size_t> idx(doc.size(), 0);
    for (;;) {
      SweepRun r;
      for (std::size_t i = 0; i < doc.size(); ++i) r.overrides[doc[i].key] = doc[i].values[idx[i]];
      const auto ratio = r.overrides.find("atol_per_rtol");
      if (ratio != r.overrides.end()) {
        const auto rtol = r.overrides.find("rtol");
        if (rtol == r.overrides.end() || r.overrides.count("atol")) {
          throw std::invalid_argument("grid key 'atol_per_rtol' needs 'rtol' and excludes 'atol'");
        }
        r.overrides["atol"] =
            format_double(grid_number("rtol", rtol->second) * grid_number("atol_per_rtol", ratio->second));
        r.overrides.erase(ratio);
      }
      const auto speed = r.overrides.find("constant_speed_rad_per_s");
      if (speed != r.overrides.end()) {
        r.overrides["initial_speed_rad_per_s"] = speed->second;
        r.overrides["target_speed_rad_per_s"] = speed->second;
        r.overrides.erase(speed);
      }
      r.id = runs.size();
      runs.push_back(std::move(r));
      bool done = true;
      for (std::size_t i = doc.size(); i-- > 0;) {
        if (++idx[i] < doc[i].values.size()) {
          done = false;
          break;
        }
        idx[i] = 0;
      }
      if (done) break;
    }
  }
  return runs;
}

std::vector<SweepRun> select_shard(const std::vector<SweepRun>& runs, std::size_t index, std::size_t count) {
  if (count == 0 || index >= count) {
    throw std::invalid_argument("--shard i/n needs 0 <= i < n, got " + std::to_string(index) + "/" +
                                std::to_string(count));
  }
  std::vector<SweepRun> out;
  for (const auto& r : runs) {
    if (r.id % count == index) out.push_back(r);
  }
  return out;
}

}  // namespace rotor_rub::tools
