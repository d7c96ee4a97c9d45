#include "rotor_rub_sim/core/rotor_file.hpp"

#include <yaml-cpp/yaml.h>

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

}  // namespace

FeRotor load_rotor_file(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument("rotor file '" + path + "': cannot be read: " + e.what());
  }
  const Reader top(path, "(top level)", root, {"material", "shaft", "disks", "bearings"});
  Material material;
  if (top.has("material")) material = read_material(path, "material", root["material"], material);
  FeRotor rotor;
  const YAML::Node shaft = sequence(path, root, "shaft");
  if (!shaft || shaft.size() == 0) top.fail("lacks the list 'shaft' (at least one element)");
  for (std::size_t i = 0; i < shaft.size(); ++i) {
    const std::string item = "shaft entry " + std::to_string(i);
    const Reader r(path, item, shaft[i], {"elements", "length_m", "outer_diameter_m", "inner_diameter_m", "material"});
    ShaftElement e;
    e.length_m = r.required("length_m", 0.0, true, kInf);
    e.outer_diameter_m = r.required("outer_diameter_m", 0.0, true, kInf);
    e.inner_diameter_m = r.number("inner_diameter_m", 0.0, false, kInf, 0.0);
    if (!(e.inner_diameter_m < e.outer_diameter_m)) {
      r.fail("key 'inner_diameter_m': value " + std::to_string(e.inner_diameter_m) +
             " is out of range; accepted: [0, outer_diameter_m)");
    }
    e.material = r.has("material") ? read_material(path, item + " material", shaft[i]["material"], material) : material;
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
      const double id = r.number("inner_diameter_m", 0.0, false, od, 0.0);
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
  return rotor;
}

}  // namespace rotor_rub::core
