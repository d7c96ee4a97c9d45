#include "sweep_grid.hpp"

#include <cstdio>
#include <fstream>
#include <stdexcept>

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

std::string format_double(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

std::vector<GridDocument> read_grid_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("grid file '" + path + "' cannot be read");
  std::vector<GridDocument> docs(1);
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    if (line == "---") {
      if (!docs.back().empty()) docs.emplace_back();
      continue;
    }
    const auto colon = line.find(':');
    const auto where = "grid file '" + path + "' line " + std::to_string(line_no);
    if (colon == std::string::npos || colon == 0) throw std::invalid_argument(where + ": expected 'key: value'");
    GridAxis axis{trim(line.substr(0, colon)), {}};
    std::string value = trim(line.substr(colon + 1));
    try {
      if (!value.empty() && value.front() == '[') {
        if (value.back() != ']') throw std::invalid_argument("unclosed list");
        axis.values = split_list(value.substr(1, value.size() - 2));
      } else {
        if (value.empty()) throw std::invalid_argument("no value");
        axis.values = {value};
      }
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(where + ": " + e.what());
    }
    for (const auto& a : docs.back()) {
      if (a.key == axis.key) throw std::invalid_argument(where + ": key '" + axis.key + "' given twice");
    }
    docs.back().push_back(axis);
  }
  if (docs.back().empty() && docs.size() > 1) docs.pop_back();
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
        r.overrides["atol"] = format_double(std::stod(rtol->second) * std::stod(ratio->second));
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
