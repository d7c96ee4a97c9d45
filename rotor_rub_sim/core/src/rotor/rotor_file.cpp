#include "rotor_rub_sim/core/rotor_file.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

class Reader {
 public:
  Reader(std::string file, std::string item, const YAML::Node& node, std::vector<std::string> keys)
      : file_(std::move(file)), item_(std::move(item)), node_(node), keys_(std::move(keys)) {
    if (!node_.IsMap()) fail("is not a map of keys (key: value)");
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar()) fail("has a key that is not a name");
      const std::string key = kv.first.as<std::string>();
      if (std::find(keys_.begin(), keys_.end(), key) == keys_.end()) {
        const std::string near = nearest_key(key, keys_);
        fail("has an unknown key '" + key + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?"));
      }
    }
  }
  bool has(const std::string& key) const { return static_cast<bool>(node_[key]); }
  // A number in [lo, hi] (lo excluded when lo_open); def when absent.
  double number(const std::string& key, double lo, bool lo_open, double hi, double def) const {
    if (!has(key)) return def;
    double v = 0.0;
    try {
      v = node_[key].as<double>();
    } catch (const YAML::Exception&) {
      fail("key '" + key + "': value '" + node_[key].as<std::string>("?") + "' is not a number");
    }
    if (!std::isfinite(v) || (lo_open ? !(v > lo) : !(v >= lo)) || v > hi) {
      fail("key '" + key + "': value " + node_[key].as<std::string>("?") + " is out of range; accepted: " +
           (lo_open ? "(" : "[") + shown(lo) + ", " + (std::isinf(hi) ? std::string("inf)") : shown(hi) + "]"));
    }
    return v;
  }
  int node(int last) const {
    const double v = required("node", 0.0, false, last);
    if (v != std::floor(v)) fail("key 'node': value " + shown(v) + " is not a node number");
    return static_cast<int>(v);
  }
  double required(const std::string& key, double lo, bool lo_open, double hi) const {
    if (!has(key)) fail("lacks the key '" + key + "'");
    return number(key, lo, lo_open, hi, 0.0);
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("rotor file '" + file_ + "': " + item_ + " " + what);
  }

 private:
  static std::string shown(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }
  std::string file_, item_;
  YAML::Node node_;
  std::vector<std::string> keys_;
};

ShaftDamping read_damping(const std::string& file, const std::string& item, const YAML::Node& n, ShaftDamping d) {
  const Reader r(file, item, n, {"mass_proportional_per_s", "stiffness_proportional_s"});
  d.mass_proportional_per_s = r.number("mass_proportional_per_s", 0.0, false, kInf, d.mass_proportional_per_s);
  d.stiffness_proportional_s = r.number("stiffness_proportional_s", 0.0, false, kInf, d.stiffness_proportional_s);
  return d;
}

// modal_damping: one of {ratio: z}, {ratios: [z0, z1, ...]} (per natural
// frequency at rest; higher_ratio, or the last, for every higher one) or
// {loss_factor: eta} (FeRotor's modal_damping_ratios and shaft_loss_factor).
void read_modal_damping(const std::string& path, const YAML::Node& n, FeRotor& rotor) {
  const Reader r(path, "modal_damping", n, {"ratio", "ratios", "higher_ratio", "loss_factor"});
  if (r.has("higher_ratio") && !r.has("ratios")) r.fail("gives 'higher_ratio' without 'ratios'; accepted: beside it");
  if (r.has("higher_ratio")) rotor.modal_damping_higher_ratio = r.required("higher_ratio", 0.0, false, 1.0);
  const int given = int{r.has("ratio")} + int{r.has("ratios")} + int{r.has("loss_factor")};
  if (given != 1) r.fail("gives " + std::to_string(given) + " of 'ratio', 'ratios', 'loss_factor'; accepted: one");
  if (r.has("ratio")) rotor.modal_damping_ratios = {r.required("ratio", 0.0, false, 1.0)};
  // A loss factor eta gives a mode that only bends the shaft eta / 2.
  if (r.has("loss_factor")) rotor.shaft_loss_factor = r.required("loss_factor", 0.0, false, 2.0);
  if (!r.has("ratios")) return;
  const YAML::Node list = n["ratios"];
  if (!list.IsSequence() || list.size() == 0) {
    r.fail("key 'ratios' is empty or not a list; accepted: [zeta_0, zeta_1, ...], at least one, each in [0, 1]");
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    double v = -1.0;
    try {
      v = list[i].as<double>();
    } catch (const YAML::Exception&) {
      r.fail("key 'ratios': entry " + std::to_string(i) + " is not a number; accepted: a number in [0, 1]");
    }
    if (!(v >= 0.0 && v <= 1.0)) {
      r.fail("key 'ratios': entry " + std::to_string(i) + " '" + list[i].as<std::string>("?") +
             "' is out of range; accepted: a number in [0, 1]");
    }
    rotor.modal_damping_ratios.push_back(v);
  }
}

Material read_material(const std::string& file, const std::string& item, const YAML::Node& n, Material m) {
  const Reader r(file, item, n, {"youngs_modulus_Pa", "shear_modulus_Pa", "density_kg_per_m3"});
  m.youngs_modulus_Pa = r.number("youngs_modulus_Pa", 0.0, true, kInf, m.youngs_modulus_Pa);
  m.shear_modulus_Pa = r.number("shear_modulus_Pa", 0.0, true, kInf, m.shear_modulus_Pa);
  m.density_kg_per_m3 = r.number("density_kg_per_m3", 0.0, false, kInf, m.density_kg_per_m3);
  // Poisson's ratio nu = E / (2 G) - 1 must lie in (-1, 0.5) for a solid.
  const double nu = m.poisson_ratio();
  if (!(nu > -1.0 && nu < 0.5)) {
    r.fail("gives Poisson's ratio E / (2 G) - 1 = " + std::to_string(nu) + "; accepted: (-1, 0.5)");
  }
  return m;
}

YAML::Node sequence(const std::string& file, const YAML::Node& root, const std::string& key) {
  const YAML::Node n = root[key];
  if (n && !n.IsSequence()) {
    throw std::invalid_argument("rotor file '" + file + "': '" + key + "' is not a list (- {...} per item)");
  }
  return n;
}

// A square matrix of `size` rows from its nonzero entries, {size: N,
// nonzeros: [[row, col, value], ...]} (0-based; every other entry 0): an FE
// rotor's matrices are banded, so a 204-DOF rotor's are a few thousand
// entries instead of 41616 each (docs/rotors.md).
Eigen::MatrixXd read_sparse_matrix(const std::string& path, const YAML::Node& n, const std::string& key, int size) {
  const Reader r(path, "matrices key '" + key + "'", n, {"size", "nonzeros"});
  const double given = r.required("size", 1.0, false, 1e6);
  if (static_cast<int>(given) != size || given != std::floor(given)) {
    r.fail("key 'size': value " + n["size"].as<std::string>("?") +
           " is out of range; accepted: " + std::to_string(size) + " (the nodes' DOFs)");
  }
  const YAML::Node entries = n["nonzeros"];
  if (!entries || !entries.IsSequence()) r.fail("lacks the list 'nonzeros' ([row, column, value] per entry)");
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(size, size);
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> given_at = decltype(given_at)::Constant(size, size, false);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const YAML::Node e = entries[k];
    const std::string at = "key 'nonzeros': entry " + std::to_string(k);
    if (!e.IsSequence() || e.size() != 3) r.fail(at + " is not [row, column, value]");
    double v[3];
    for (int c = 0; c < 3; ++c) {
      try {
        v[c] = e[c].as<double>();
      } catch (const YAML::Exception&) {
        r.fail(at + " holds '" + e[c].as<std::string>("?") + "', not a number");
      }
    }
    for (int c = 0; c < 2; ++c) {
      if (!(v[c] >= 0.0 && v[c] < size && v[c] == std::floor(v[c]))) {
        r.fail(at + ": " + (c == 0 ? "row " : "column ") + e[c].as<std::string>("?") +
               " is out of range; accepted: 0 to " + std::to_string(size - 1));
      }
    }
    if (!std::isfinite(v[2])) r.fail(at + ": value " + e[2].as<std::string>("?") + " is not finite");
    const int i = static_cast<int>(v[0]), j = static_cast<int>(v[1]);
    if (given_at(i, j)) r.fail(at + " gives row " + std::to_string(i) + " column " + std::to_string(j) + " again");
    given_at(i, j) = true;
    m(i, j) = v[2];
  }
  return m;
}

// A square matrix of `size` rows from a list of rows (dofs_per_node: what
// the error says a row holds per node), or from its nonzeros (a map).
Eigen::MatrixXd read_matrix(const Reader& r, const YAML::Node& n, const std::string& key, int size, int dofs_per_node,
                            const std::string& path) {
  const YAML::Node rows = n[key];
  if (rows && rows.IsMap()) return read_sparse_matrix(path, rows, key, size);
  if (!rows || !rows.IsSequence() || static_cast<int>(rows.size()) != size) {
    r.fail("key '" + key +
           "': " + (rows && rows.IsSequence() ? std::to_string(rows.size()) + " rows" : "no list of rows") +
           "; accepted: " + std::to_string(size) + " rows of " + std::to_string(size) + " numbers (" +
           std::to_string(dofs_per_node) + " DOF per node), or {size: " + std::to_string(size) +
           ", nonzeros: [[row, column, value], ...]}");
  }
  Eigen::MatrixXd m(size, size);
  for (int i = 0; i < size; ++i) {
    const YAML::Node row = rows[i];
    if (!row.IsSequence() || static_cast<int>(row.size()) != size) {
      r.fail("key '" + key + "': row " + std::to_string(i) + " has " +
             (row.IsSequence() ? std::to_string(row.size()) : std::string("no list of")) +
             " entries; accepted: " + std::to_string(size));
    }
    for (int j = 0; j < size; ++j) {
      try {
        m(i, j) = row[j].as<double>();
      } catch (const YAML::Exception&) {
        r.fail("key '" + key + "': row " + std::to_string(i) + " entry " + std::to_string(j) + " is not a number");
      }
      if (!std::isfinite(m(i, j))) {
        r.fail("key '" + key + "': row " + std::to_string(i) + " entry " + std::to_string(j) + " is not finite");
      }
    }
  }
  return m;
}

// ROSS's 6 DOF per node, [x, y, z, alpha, beta, theta] (ShaftElement::
// dof_mapping), to the lateral 4, [x, y, alpha, beta]: the axial z and the
// torsional theta are dropped, which is exact when no entry couples them to
// the lateral DOFs (ROSS's linear elements do not); a coupling above 1e-9 of
// the matrix's largest entry is refused, since dropping it would change the
// rotor (test_fe_rotor, RossSixDofMatricesAreTheLateralRotor).
Eigen::MatrixXd lateral_of_six(const Reader& r, const std::string& key, const Eigen::MatrixXd& six, int supports) {
  constexpr int kSixLateral[4] = {0, 1, 3, 4};
  const int nodes = (static_cast<int>(six.rows()) - 3 * supports) / 6;
  std::vector<int> lateral, other;
  for (int node = 0; node < nodes; ++node) {
    for (int d : kSixLateral) lateral.push_back(6 * node + d);
    other.push_back(6 * node + 2);
    other.push_back(6 * node + 5);
  }
  for (int k = 0; k < supports; ++k) {  // a support node's [x, y, z]
    lateral.push_back(6 * nodes + 3 * k);
    lateral.push_back(6 * nodes + 3 * k + 1);
    other.push_back(6 * nodes + 3 * k + 2);
  }
  const double scale = six.cwiseAbs().maxCoeff();
  for (int a : lateral) {
    for (int b : other) {
      if (std::abs(six(a, b)) > 1e-9 * scale || std::abs(six(b, a)) > 1e-9 * scale) {
        std::ostringstream os;
        os << "key '" << key << "': row " << a << " column " << b << " couples a lateral DOF to an axial or torsional"
           << " one (" << six(a, b) << ", " << six(b, a) << " against " << scale
           << "); accepted: none above 1e-9 of the largest entry (6 DOF per node are read as ROSS's [x, y, z, alpha,"
           << " beta, theta], and z and theta dropped)";
        r.fail(os.str());
      }
    }
  }
  Eigen::MatrixXd out(lateral.size(), lateral.size());
  for (std::size_t i = 0; i < lateral.size(); ++i) {
    for (std::size_t j = 0; j < lateral.size(); ++j) out(i, j) = six(lateral[i], lateral[j]);
  }
  return out;
}

// Matrices exported by another FE program (docs/rotors.md): node positions
// and M, K, C, G in 4 DOF per node, or ROSS's 6 (lateral_of_six), checked
// for what the physics demands: M symmetric positive definite (the kinetic
// energy), G skew (gyroscopic forces do no work). K and C may be
// non-symmetric with indefinite symmetric parts: cross-coupled bearings and
// seals are circulatory and can feed a whirl, which is the rotor's physics
// (its modes' growth rates), not a bad file. That each plane stands with the
// station held is the reduction's check (reduce_rotor).
void read_matrices(const std::string& path, const YAML::Node& n, FeRotor& rotor) {
  const Reader r(path, "matrices", n, {"nodes_z_m", "nodes", "support_nodes", "M", "K", "C", "G"});
  if (r.has("nodes_z_m") && r.has("nodes")) r.fail("gives both 'nodes_z_m' and 'nodes'; accepted: one of them");
  const std::string z_key = r.has("nodes") ? "nodes" : "nodes_z_m";  // ROSS's save_mat names it "nodes"
  const YAML::Node z = n[z_key];
  if (!z || !z.IsSequence() || z.size() == 0) {
    r.fail("lacks the list 'nodes_z_m' or 'nodes' (a node's position along the shaft [m] per entry)");
  }
  for (std::size_t i = 0; i < z.size(); ++i) {
    double v = 0.0;
    try {
      v = z[i].as<double>();
    } catch (const YAML::Exception&) {
      r.fail("key '" + z_key + "': entry " + std::to_string(i) + " is not a number");
    }
    if (!std::isfinite(v) || (i > 0 && !(v > rotor.imported_node_z_m.back()))) {
      r.fail("key '" + z_key + "': entry " + std::to_string(i) + " is not finite and above the one before");
    }
    rotor.imported_node_z_m.push_back(v);
  }
  const int nodes = static_cast<int>(z.size());
  // Support nodes (ROSS's point masses past the shaft): their x, y (and z,
  // in ROSS's 6) after the shaft nodes' DOFs.
  const double supports_given = r.number("support_nodes", 0.0, false, 1e5, 0.0);
  if (supports_given != std::floor(supports_given)) {
    r.fail("key 'support_nodes': value " + n["support_nodes"].as<std::string>("?") +
           " is not a whole number; accepted: 0, 1, 2, ...");
  }
  const int supports = static_cast<int>(supports_given);
  // ROSS's 6 DOF per node where M has 6 rows per node (or says so, sparse).
  const YAML::Node m_rows = n["M"];
  const double six_size = 6.0 * nodes + 3.0 * supports;
  const bool six = m_rows && ((m_rows.IsSequence() && static_cast<double>(m_rows.size()) == six_size) ||
                              (m_rows.IsMap() && m_rows["size"] && m_rows["size"].as<double>(0.0) == six_size));
  const int dofs_per_node = six ? 6 : 4;
  const int size = six ? 6 * nodes + 3 * supports : 4 * nodes + 2 * supports;
  auto matrix = [&](const char* key) -> Eigen::MatrixXd {
    const Eigen::MatrixXd read = read_matrix(r, n, key, size, dofs_per_node, path);
    return dofs_per_node == 6 ? lateral_of_six(r, key, read, supports) : read;
  };
  rotor.imported_support_nodes = supports;
  RotorMatrices m;
  m.support_nodes = supports;
  m.M = matrix("M");
  m.K = matrix("K");
  const int lateral = 4 * nodes + 2 * supports;
  m.C = n["C"] ? matrix("C") : Eigen::MatrixXd::Zero(lateral, lateral);  // optional: no damping
  m.G = n["G"] ? matrix("G") : Eigen::MatrixXd::Zero(lateral, lateral);  // optional: no gyroscopics
  const double mass_scale = m.M.cwiseAbs().maxCoeff();
  if ((m.M - m.M.transpose()).cwiseAbs().maxCoeff() > 1e-9 * mass_scale) r.fail("key 'M': not symmetric");
  if (Eigen::LLT<Eigen::MatrixXd>(m.M).info() != Eigen::Success) {
    r.fail("key 'M': not positive definite (a DOF without mass or inertia?)");
  }
  if ((m.G + m.G.transpose()).cwiseAbs().maxCoeff() > 1e-9 * m.G.cwiseAbs().maxCoeff()) {
    r.fail("key 'G': not skew-symmetric (G = -G^T for a gyroscopic matrix)");
  }
  rotor.imported = std::move(m);
}

}  // namespace

FeRotor load_rotor_file(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument("rotor file '" + path + "': cannot be read: " + e.what());
  }
  const Reader top(path, "(top level)", root,
                   {"material", "shaft_damping", "modal_damping", "shaft", "disks", "bearings", "point_masses",
                    "unbalances", "rub_station", "probes", "matrices"});
  FeRotor rotor;
  if (top.has("modal_damping")) {
    if (top.has("shaft_damping")) top.fail("gives both 'shaft_damping' and 'modal_damping'; accepted: one of them");
    read_modal_damping(path, root["modal_damping"], rotor);
  }
  if (top.has("matrices")) {
    for (const char* key : {"material", "shaft_damping", "shaft", "disks", "bearings", "point_masses"}) {
      if (top.has(key)) top.fail("gives both 'matrices' and '" + std::string(key) + "'; accepted: one of them");
    }
    read_matrices(path, root["matrices"], rotor);
    if (rotor.shaft_loss_factor != 0.0) {
      top.fail(
          "gives 'matrices' and modal_damping's 'loss_factor', which needs the shaft's elements; accepted: "
          "modal_damping's 'ratio' or 'ratios'");
    }
  }
  Material material;
  if (top.has("material")) material = read_material(path, "material", root["material"], material);
  ShaftDamping damping;
  if (top.has("shaft_damping")) damping = read_damping(path, "shaft_damping", root["shaft_damping"], damping);
  const YAML::Node shaft = sequence(path, root, "shaft");
  if (!rotor.imported && (!shaft || shaft.size() == 0)) {
    top.fail("lacks the list 'shaft' (at least one element) or the map 'matrices'");
  }
  for (std::size_t i = 0; shaft && i < shaft.size(); ++i) {
    const std::string item = "shaft entry " + std::to_string(i);
    const Reader r(path, item, shaft[i],
                   {"elements", "length_m", "outer_diameter_m", "inner_diameter_m", "material", "damping"});
    ShaftElement e;
    e.length_m = r.required("length_m", 0.0, true, kInf);
    e.outer_diameter_m = r.required("outer_diameter_m", 0.0, true, kInf);
    e.inner_diameter_m = r.number("inner_diameter_m", 0.0, false, kInf, 0.0);
    if (!(e.inner_diameter_m < e.outer_diameter_m)) {
      r.fail("key 'inner_diameter_m': value " + std::to_string(e.inner_diameter_m) +
             " is out of range; accepted: [0, outer_diameter_m)");
    }
    e.material = r.has("material") ? read_material(path, item + " material", shaft[i]["material"], material) : material;
    if (r.has("damping") && top.has("modal_damping")) {
      r.fail("gives 'damping' beside the file's 'modal_damping'; accepted: one of them");
    }
    e.damping = r.has("damping") ? read_damping(path, item + " damping", shaft[i]["damping"], damping) : damping;
    const double repeat = r.number("elements", 1.0, false, 10000.0, 1.0);
    if (repeat != std::floor(repeat))
      r.fail("key 'elements': value " + std::to_string(repeat) + " is not a whole number");
    for (int k = 0; k < static_cast<int>(repeat); ++k) rotor.shaft.push_back(e);
  }
  const int last_node = rotor.nodes() - 1;
  const YAML::Node disks = sequence(path, root, "disks");
  for (std::size_t i = 0; disks && i < disks.size(); ++i) {
    const Reader r(path, "disk " + std::to_string(i), disks[i],
                   {"node", "width_m", "inner_diameter_m", "outer_diameter_m", "mass_kg", "polar_inertia_kg_m2",
                    "diametral_inertia_kg_m2"});
    const int node = r.node(last_node);
    if (r.has("mass_kg")) {
      if (r.has("width_m") || r.has("outer_diameter_m") || r.has("inner_diameter_m")) {
        r.fail("gives both a mass and a geometry; accepted: one of them");
      }
      DiskElement d;
      d.node = node;
      d.mass_kg = r.required("mass_kg", 0.0, false, kInf);
      d.polar_inertia_kg_m2 = r.number("polar_inertia_kg_m2", 0.0, false, kInf, 0.0);
      d.diametral_inertia_kg_m2 = r.number("diametral_inertia_kg_m2", 0.0, false, kInf, 0.0);
      rotor.disks.push_back(d);
    } else {
      const double od = r.required("outer_diameter_m", 0.0, true, kInf);
      const double id = r.number("inner_diameter_m", 0.0, false, kInf, 0.0);
      if (!(id < od)) {
        r.fail("key 'inner_diameter_m': value " + std::to_string(id) +
               " is out of range; accepted: [0, outer_diameter_m)");
      }
      rotor.disks.push_back(DiskElement::from_geometry(node, material, r.required("width_m", 0.0, true, kInf), id, od));
    }
  }
  // Point masses first: those past the shaft's last node make the support
  // nodes, which bearings may join (fe_rotor.hpp's PointMass).
  const YAML::Node point_masses = sequence(path, root, "point_masses");
  const int most_nodes = last_node + 1 + static_cast<int>(point_masses ? point_masses.size() : 0);
  for (std::size_t i = 0; point_masses && i < point_masses.size(); ++i) {
    const Reader r(path, "point mass " + std::to_string(i), point_masses[i], {"node", "mass_kg", "mx_kg", "my_kg"});
    PointMass p;
    p.node = r.node(most_nodes - 1);
    if (r.has("mass_kg") == (r.has("mx_kg") || r.has("my_kg"))) {
      r.fail("gives " + std::string(r.has("mass_kg") ? "both 'mass_kg' and 'mx_kg'/'my_kg'" : "no mass") +
             "; accepted: mass_kg, or mx_kg and my_kg");
    }
    p.mx_kg = r.has("mass_kg") ? r.required("mass_kg", 0.0, false, kInf) : r.required("mx_kg", 0.0, false, kInf);
    p.my_kg = r.has("mass_kg") ? p.mx_kg : r.required("my_kg", 0.0, false, kInf);
    for (const PointMass& q : rotor.point_masses) {
      if (p.node > last_node && q.node == p.node) {
        r.fail("key 'node': value " + std::to_string(p.node) +
               " is a support node that has a point mass already; accepted: one point mass per support node");
      }
    }
    rotor.point_masses.push_back(p);
  }
  // Support nodes in turn, from the shaft's last node on (no gap).
  for (std::size_t i = 0; point_masses && i < rotor.point_masses.size(); ++i) {
    const int node = rotor.point_masses[i].node;
    if (node > last_node + rotor.support_nodes()) {
      throw std::invalid_argument("rotor file '" + path + "': point mass " + std::to_string(i) + " key 'node': value " +
                                  std::to_string(node) + " leaves a gap; accepted: support nodes numbered in turn, " +
                                  std::to_string(last_node + 1) + " to " +
                                  std::to_string(last_node + rotor.support_nodes()));
    }
  }
  const int all_nodes = rotor.nodes() + rotor.support_nodes();
  const YAML::Node bearings = sequence(path, root, "bearings");
  for (std::size_t i = 0; bearings && i < bearings.size(); ++i) {
    const Reader r(
        path, "bearing " + std::to_string(i), bearings[i],
        {"node", "link_node", "kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy", "mxx", "mxy", "myx", "myy"});
    BearingElement b;
    b.node = r.node(all_nodes - 1);
    const double link = r.number("link_node", -1.0, false, all_nodes - 1, -1.0);
    b.link_node = static_cast<int>(link);
    if (link != std::floor(link) || b.link_node == b.node) {
      r.fail("key 'link_node': value " + bearings[i]["link_node"].as<std::string>("?") +
             " is not another node; accepted: a node number other than 'node', or -1 (the ground)");
    }
    // Direct terms are non-negative; cross-coupled ones (a seal's, an oil
    // film's) take either sign.
    b.kxx = r.number("kxx", 0.0, false, kInf, 0.0);
    b.kyy = r.number("kyy", 0.0, false, kInf, 0.0);
    b.cxx = r.number("cxx", 0.0, false, kInf, 0.0);
    b.cyy = r.number("cyy", 0.0, false, kInf, 0.0);
    b.kxy = r.number("kxy", -kInf, false, kInf, 0.0);
    b.kyx = r.number("kyx", -kInf, false, kInf, 0.0);
    b.cxy = r.number("cxy", -kInf, false, kInf, 0.0);
    b.cyx = r.number("cyx", -kInf, false, kInf, 0.0);
    // The added mass is a kinetic energy's: symmetric, positive semi-definite.
    b.mxx = r.number("mxx", 0.0, false, kInf, 0.0);
    b.myy = r.number("myy", 0.0, false, kInf, 0.0);
    b.mxy = r.number("mxy", -kInf, false, kInf, 0.0);
    b.myx = r.number("myx", -kInf, false, kInf, 0.0);
    if (b.mxy != b.myx || b.mxy * b.mxy > b.mxx * b.myy) {
      r.fail("gives mxx " + std::to_string(b.mxx) + ", mxy " + std::to_string(b.mxy) + ", myx " +
             std::to_string(b.myx) + ", myy " + std::to_string(b.myy) +
             "; accepted: mxy == myx and mxy^2 <= mxx myy (an added mass is symmetric and positive semi-definite)");
    }
    rotor.bearings.push_back(b);
  }
  const YAML::Node unbalances = sequence(path, root, "unbalances");
  for (std::size_t i = 0; unbalances && i < unbalances.size(); ++i) {
    const Reader r(path, "unbalance " + std::to_string(i), unbalances[i], {"node", "me_kg_m", "phase_rad"});
    RotorUnbalance u;
    u.node = r.node(last_node);
    u.me_kg_m = r.required("me_kg_m", 0.0, false, kInf);
    u.phase_rad = r.number("phase_rad", -kInf, false, kInf, 0.0);
    rotor.unbalances.push_back(u);
  }
  if (top.has("rub_station")) {
    const Reader r(path, "rub_station", root["rub_station"], {"node", "contact_radius_m"});
    rotor.rub_station_node = r.node(last_node);
    rotor.rub_contact_radius_m = r.required("contact_radius_m", 0.0, true, kInf);
  }
  const YAML::Node probes = sequence(path, root, "probes");
  for (std::size_t i = 0; probes && i < probes.size(); ++i) {
    const Reader r(path, "probe " + std::to_string(i), probes[i], {"node"});
    rotor.probe_nodes.push_back(r.node(last_node));
  }
  return rotor;
}

}  // namespace rotor_rub::core
