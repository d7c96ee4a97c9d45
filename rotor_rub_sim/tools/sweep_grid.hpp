// A sweep's grid: the runs to make, each a set of scene key overrides.
//
// Grid file: one or more YAML documents (separated by "---"), each a flat
// mapping of scene keys to a value or a list of values, e.g.
//   method: [switching, iteration]
//   rtol: [1.0e-3, 1.0e-6]
//   atol_per_rtol: 1.0e-3        # pseudo-key: atol = rtol * this
//   constant_speed_rad_per_s: 600  # pseudo-key: initial = target speed
// A document contributes the Cartesian product of its lists (the last key
// varies fastest); the grid is the documents' runs in file order. Several
// documents express what one product cannot (rosenbrock4 is for penalty only).
#pragma once

#include <map>
#include <string>
#include <vector>

namespace rotor_rub::tools {

using Values = std::map<std::string, std::string>;

struct GridAxis {
  std::string key;
  std::vector<std::string> values;
};
using GridDocument = std::vector<GridAxis>;

// Throws std::invalid_argument naming the file and line.
std::vector<GridDocument> read_grid_file(const std::string& path);
// "key=v1,v2,v3" from the command line.
GridAxis parse_axis(const std::string& text);

struct SweepRun {
  std::size_t id = 0;  // index in the whole grid (stable across shards)
  Values overrides;    // grid values, pseudo-keys resolved
};

// Expands the documents (command-line axes are added to every document) into
// runs. The pseudo-keys atol_per_rtol and constant_speed_rad_per_s are resolved here.
std::vector<SweepRun> expand_grid(const std::vector<GridDocument>& docs, const std::vector<GridAxis>& extra_axes);

// Shard "i/n" (0 <= i < n): the runs whose id % n == i.
std::vector<SweepRun> select_shard(const std::vector<SweepRun>& runs, std::size_t index, std::size_t count);

}  // namespace rotor_rub::tools
