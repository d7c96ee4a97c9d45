#include "rotor_rub_sim/core/rotor_file.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Eigenvalues>
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

// A square matrix of `size` rows from a list of rows.
Eigen::MatrixXd read_matrix(const Reader& r, const YAML::Node& n, const std::string& key, int size) {
  const YAML::Node rows = n[key];
  if (!rows || !rows.IsSequence() || static_cast<int>(rows.size()) != size) {
    r.fail("key '" + key +
           "': " + (rows && rows.IsSequence() ? std::to_string(rows.size()) + " rows" : "no list of rows") +
           "; accepted: " + std::to_string(size) + " rows of " + std::to_string(size) + " numbers (4 DOF per node)");
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

// The smallest eigenvalue of a matrix's symmetric part against its largest
// magnitude: >= -1e-9 of it counts as positive semi-definite (roundoff).
void require_semidefinite(const Reader& r, const std::string& key, const Eigen::MatrixXd& m) {
  const Eigen::MatrixXd sym = 0.5 * (m + m.transpose());
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(sym, Eigen::EigenvaluesOnly).eigenvalues();
  const double scale = eig.cwiseAbs().maxCoeff();
  if (eig.minCoeff() < -1e-9 * scale) {
    std::ostringstream os;
    os << "key '" << key << "': not positive semi-definite (its symmetric part has the eigenvalue " << eig.minCoeff()
       << " against " << scale << ")";
    r.fail(os.str());
  }
}

// Matrices exported by another FE program (docs/rotors.md): node positions
// and M, K, C, G in 4 DOF per node, checked for what the physics demands.
void read_matrices(const std::string& path, const YAML::Node& n, FeRotor& rotor) {
  const Reader r(path, "matrices", n, {"nodes_z_m", "M", "K", "C", "G"});
  const YAML::Node z = n["nodes_z_m"];
  if (!z || !z.IsSequence() || z.size() == 0) r.fail("lacks the list 'nodes_z_m' (a node's position per entry)");
  for (std::size_t i = 0; i < z.size(); ++i) {
    double v = 0.0;
    try {
      v = z[i].as<double>();
    } catch (const YAML::Exception&) {
      r.fail("key 'nodes_z_m': entry " + std::to_string(i) + " is not a number");
    }
    if (!std::isfinite(v) || (i > 0 && !(v > rotor.imported_node_z_m.back()))) {
      r.fail("key 'nodes_z_m': entry " + std::to_string(i) + " is not finite and above the one before");
    }
    rotor.imported_node_z_m.push_back(v);
  }
  const int size = 4 * static_cast<int>(z.size());
  RotorMatrices m;
  m.M = read_matrix(r, n, "M", size);
  m.K = read_matrix(r, n, "K", size);
  m.C = n["C"] ? read_matrix(r, n, "C", size) : Eigen::MatrixXd::Zero(size, size);
  m.G = n["G"] ? read_matrix(r, n, "G", size) : Eigen::MatrixXd::Zero(size, size);
  const double mass_scale = m.M.cwiseAbs().maxCoeff();
  if ((m.M - m.M.transpose()).cwiseAbs().maxCoeff() > 1e-9 * mass_scale) r.fail("key 'M': not symmetric");
  if (Eigen::LLT<Eigen::MatrixXd>(m.M).info() != Eigen::Success) {
    r.fail("key 'M': not positive definite (a DOF without mass or inertia?)");
  }
  require_semidefinite(r, "K", m.K);
  require_semidefinite(r, "C", m.C);
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
  const Reader top(
      path, "(top level)", root,
      {"material", "shaft_damping", "shaft", "disks", "bearings", "unbalances", "rub_station", "probes", "matrices"});
  FeRotor rotor;
  if (top.has("matrices")) {
    for (const char* key : {"material", "shaft_damping", "shaft", "disks", "bearings"}) {
      if (top.has(key)) top.fail("gives both 'matrices' and '" + std::string(key) + "'; accepted: one of them");
    }
    read_matrices(path, root["matrices"], rotor);
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
  const YAML::Node bearings = sequence(path, root, "bearings");
  for (std::size_t i = 0; bearings && i < bearings.size(); ++i) {
    const Reader r(path, "bearing " + std::to_string(i), bearings[i],
                   {"node", "kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"});
    BearingElement b;
    b.node = r.node(last_node);
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
