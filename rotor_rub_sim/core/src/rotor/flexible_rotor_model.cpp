#include "rotor_rub_sim/core/flexible_rotor_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::core {

FlexibleRotorModel::FlexibleRotorModel(const ReducedRotor& rotor, const std::vector<RotorUnbalance>& unbalances,
                                       double contact_radius_m, int probe_node, double gravity_m_per_s2)
    : rotor_(rotor),
      station_mass_kg_(rotor.station_mass_kg),
      contact_radius_m_(contact_radius_m),
      probe_node_(probe_node < 0 ? rotor.station_node : probe_node),
      gravity_m_per_s2_(gravity_m_per_s2),
      k_(rotor.matrices.K),
      c_(rotor.matrices.C),
      g_(rotor.matrices.G) {
  if (rotor.planar_modes > kMaxPlanarModes) {
    throw std::invalid_argument("flexible rotor: " + std::to_string(rotor.planar_modes) +
                                " planar modes; accepted: 1 to " + std::to_string(kMaxPlanarModes));
  }
  a_ = Eigen::VectorXd::Zero(rotor.size());
  b_ = Eigen::VectorXd::Zero(rotor.size());
  for (const RotorUnbalance& u : unbalances) add_unbalance(u);
  if (gravity_m_per_s2 != 0.0 && rotor.unit_weight_kg.size() != rotor.size()) {
    throw std::logic_error("flexible rotor: gravity without the reduced rotor's unit weight (reduce_rotor sets it)");
  }
  weight_ = gravity_m_per_s2 != 0.0 ? Eigen::VectorXd(-gravity_m_per_s2 * rotor.unit_weight_kg)
                                    : Eigen::VectorXd::Zero(rotor.size());
  if (probe_node_ >= nodes()) {
    throw std::invalid_argument("probe node " + std::to_string(probe_node_) + " is out of range; accepted: 0 to " +
                                std::to_string(nodes() - 1));
  }
  probe_rows_.resize(2, rotor.size());
  probe_rows_.row(0) = rotor.expansion.row(dof_index(probe_node_, kDofX));
  probe_rows_.row(1) = rotor.expansion.row(dof_index(probe_node_, kDofY));
  node_rows_.resize(2 * nodes(), rotor.size());
  for (int node = 0; node < nodes(); ++node) {
    node_rows_.row(2 * node) = rotor.expansion.row(dof_index(node, kDofX));
    node_rows_.row(2 * node + 1) = rotor.expansion.row(dof_index(node, kDofY));
  }
}

void FlexibleRotorModel::add_unbalance(const RotorUnbalance& u) {
  if (u.node < 0 || u.node >= nodes()) {
    throw std::invalid_argument("unbalance: node " + std::to_string(u.node) + " is out of range; accepted: 0 to " +
                                std::to_string(nodes() - 1));
  }
  // At spin angle 0 the force points along beta; a quarter turn on, along beta + pi/2.
  const auto x = rotor_.expansion.row(dof_index(u.node, kDofX));
  const auto y = rotor_.expansion.row(dof_index(u.node, kDofY));
  const double c = u.me_kg_m * std::cos(u.phase_rad), s = u.me_kg_m * std::sin(u.phase_rad);
  a_ += (c * x + s * y).transpose();
  b_ += (-s * x + c * y).transpose();
  pendulum_N_m_ += gravity_m_per_s2_ * Vec2(c, s);
}

FlexibleRotorModel FlexibleRotorModel::with_unbalances(const std::vector<RotorUnbalance>& added) const {
  FlexibleRotorModel out = *this;
  for (const RotorUnbalance& u : added) out.add_unbalance(u);
  return out;
}

std::string to_string(long planar_modes, const TruncationReport& t) {
  std::ostringstream os;
  os.precision(3);
  os << planar_modes << " planar modes";
  if (t.chosen) os << " (auto, rotor_truncation_tolerance " << t.tolerance << ")";
  if (std::isnan(t.response_error)) {
    os << ": truncation not judged (no unbalance in the rotor file, or no speed above 0)";
  } else {
    os << ": unbalance response within " << std::scientific << t.response_error << std::defaultfloat
       << " of the full model's largest displacement at " << t.min_speed_rad_per_s << " .. " << t.max_speed_rad_per_s
       << " rad/s";
    if (!t.critical_speeds_rad_per_s.empty()) {
      os << " and the flanks of its " << t.critical_speeds_rad_per_s.size() << " critical speed"
         << (t.critical_speeds_rad_per_s.size() == 1 ? "" : "s") << " there";
    }
    os << " (rub station and probe nodes)";
  }
  return os.str();
}

double FlexibleRotorModel::max_spin_lever_kg_m2() const {
  // h = a sin phi - b cos phi: h^T M^-1 h is the quadratic form of
  // [[A, -X], [-X, B]] in (sin, cos), A = a^T M^-1 a, B = b^T M^-1 b,
  // X = a^T M^-1 b; its maximum on the unit circle the larger eigenvalue.
  const auto inner = [this](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
    const Eigen::Index n = x.size() - 2;
    return x.head<2>().dot(y.head<2>()) / station_mass_kg_ + x.tail(n).dot(y.tail(n));
  };
  const double a = inner(a_, a_), b = inner(b_, b_), x = inner(a_, b_);
  return 0.5 * (a + b) + std::sqrt(0.25 * (a - b) * (a - b) + x * x);
}

namespace {

// The speeds a reduction is judged on: kJudgedSpeeds evenly from lo to hi,
// those above 0 (one where lo == hi: a constant speed), and on a run-up
// the flanks of the full model's resonances between them, which a lightly
// damped mode's can hide between the grid's speeds (the anisotropic rig's at
// 160.63 rad/s, damping ratio 4e-6: FlexibleRotorRuns.AutoModesAreTheFewestWithinTheTolerance).
// A run-up at alpha passes a critical speed w_c too fast to build its steady
// peak: it reaches about that of a damping ratio sqrt(2 alpha / pi) / (2 w_c)
// (Lewis's passage through resonance), so each critical speed is judged at
// w_c (1 -+ delta), delta the larger of that and the mode's own ratio (an
// undamped rotor's response at w_c itself is singular). Where the search for
// critical speeds fails, the grid alone (the report lists none).
constexpr int kJudgedSpeeds = 24;
std::vector<double> judged_speeds(const RotorMatrices& full, double lo, double hi, double acceleration_rad_per_s2,
                                  bool with_critical, std::vector<double>& critical_rad_per_s) {
  std::vector<double> out;
  const int n = hi > lo ? kJudgedSpeeds : 1;
  for (int k = 0; k < n; ++k) {
    const double w = n == 1 ? hi : lo + (hi - lo) * k / (n - 1);
    if (w > 0.0) out.push_back(w);
  }
  if (!with_critical || n == 1 || !(hi > 0.0)) return out;
  std::vector<CriticalSpeed> found;
  try {
    found = critical_speeds(full, std::numeric_limits<int>::max(), hi, kJudgedSpeeds,
                            std::max(1u, std::thread::hardware_concurrency()));
  } catch (const std::runtime_error&) {
    return out;  // an eigensolve that did not converge: the grid alone
  }
  for (const CriticalSpeed& c : found) {
    const double w = c.speed_rad_per_s;
    if (!(w >= lo && w > 0.0)) continue;
    if (!critical_rad_per_s.empty() && w == critical_rad_per_s.back()) continue;  // one crossing found twice
    critical_rad_per_s.push_back(w);
    const double passage = std::sqrt(2.0 * acceleration_rad_per_s2 / M_PI) / (2.0 * w);
    const double delta = std::max(c.damping_ratio, passage);
    for (const double side : {-1.0, 1.0}) {
      const double judged = w * (1.0 + side * delta);
      if (judged > 0.0) out.push_back(judged);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

namespace {

// A scene key's value the rotor file cannot take: "KEY: value ...", typed
// with its key (validate_scene names it so).
[[noreturn]] void refuse_key(const std::string& key, const std::string& what) {
  throw SceneError(key + ": " + what, key);
}

}  // namespace

FlexibleRotorModel load_flexible_rotor(const RotorSettings& settings, double gravity_m_per_s2,
                                       double min_speed_rad_per_s, double max_speed_rad_per_s,
                                       double acceleration_rad_per_s2) {
  const FeRotor rotor = load_rotor_file(settings.file);
  if (rotor.rub_station_node < 0) {
    throw std::invalid_argument("rotor file '" + settings.file +
                                "': no rub_station; a run needs one ({node: N, contact_radius_m: R})");
  }
  // The reduction's twin planes need one mass in x and y (the contact's
  // station mass is one number); the reduction refuses it too, less plainly
  // (test_rotor_supports, BadSupportsNameTheItemTheKeyAndTheRange).
  for (std::size_t i = 0; i < rotor.point_masses.size(); ++i) {
    const PointMass& p = rotor.point_masses[i];
    if (p.mx_kg != p.my_kg) {
      throw std::invalid_argument("rotor file '" + settings.file + "': point mass " + std::to_string(i) + " (node " +
                                  std::to_string(p.node) + ") has mx_kg " + std::to_string(p.mx_kg) + ", my_kg " +
                                  std::to_string(p.my_kg) +
                                  "; a run needs them equal (its modal analysis takes any); accepted: mass_kg");
    }
  }
  for (std::size_t i = 0; i < rotor.bearings.size(); ++i) {
    const BearingElement& b = rotor.bearings[i];
    if (b.mxx != b.myy || b.mxy != 0.0) {
      throw std::invalid_argument("rotor file '" + settings.file + "': bearing " + std::to_string(i) +
                                  " has an added mass mxx " + std::to_string(b.mxx) + ", mxy " + std::to_string(b.mxy) +
                                  ", myy " + std::to_string(b.myy) +
                                  "; a run needs mxx == myy and mxy == 0 (its modal analysis takes any)");
    }
  }
  const long most = std::min<long>(kMaxPlanarModes, max_planar_modes(rotor));
  const bool automatic = settings.planar_modes == 0;
  if (!automatic && (settings.planar_modes < 1 || settings.planar_modes > most)) {
    refuse_key("rotor_planar_modes", "value " + std::to_string(settings.planar_modes) +
                                         " is out of range; accepted for '" + settings.file + "': auto or 1 to " +
                                         std::to_string(most));
  }
  if (settings.probe_node >= rotor.nodes()) {
    refuse_key("rotor_probe_node", "value " + std::to_string(settings.probe_node) + " is out of range; accepted for '" +
                                       settings.file + "': -1 to " + std::to_string(rotor.nodes() - 1));
  }
  const RotorMatrices full = assemble(rotor);
  std::vector<int> watched{rotor.rub_station_node};
  watched.insert(watched.end(), rotor.probe_nodes.begin(), rotor.probe_nodes.end());
  TruncationReport report;
  const std::vector<double> speeds =
      judged_speeds(full, min_speed_rad_per_s, max_speed_rad_per_s, acceleration_rad_per_s2, !rotor.unbalances.empty(),
                    report.critical_speeds_rad_per_s);
  const ResponseReference reference(rotor, full, rotor.unbalances, speeds, watched);
  report.min_speed_rad_per_s = speeds.empty() ? 0.0 : speeds.front();
  report.max_speed_rad_per_s = speeds.empty() ? 0.0 : speeds.back();
  const bool judged = !speeds.empty() && !rotor.unbalances.empty();
  long count = settings.planar_modes;
  if (automatic) {
    if (!judged) {
      refuse_key("rotor_planar_modes",
                 "value auto needs the rotor file's unbalances and a speed above 0 to judge the unbalance response "
                 "by; accepted for '" +
                     settings.file + "': 1 to " + std::to_string(most));
    }
    report.chosen = true;
    report.tolerance = settings.truncation_tolerance;
  }
  // One basis for every count tried: the search pays its eigensolves once.
  const RotorReduction reduction(rotor, full, rotor.rub_station_node, static_cast<int>(automatic ? most : count));
  if (automatic) {
    double best = std::numeric_limits<double>::infinity();
    for (count = 1; count <= most; ++count) {
      const double error = reference.error(reduction.reduce(static_cast<int>(count)));
      best = std::min(best, error);
      if (error <= settings.truncation_tolerance) break;
    }
    if (count > most) {
      std::ostringstream os;
      os << "value auto finds no model of 1 to " << most
         << " planar modes within rotor_truncation_tolerance = " << settings.truncation_tolerance
         << " (the best: " << best << "); accepted for '" << settings.file << "': 1 to " << most;
      refuse_key("rotor_planar_modes", os.str());
    }
  }
  const ReducedRotor reduced = reduction.reduce(static_cast<int>(count));
  if (judged) report.response_error = reference.error(reduced);
  const int probe_node = settings.probe_node >= 0     ? static_cast<int>(settings.probe_node)
                         : !rotor.probe_nodes.empty() ? rotor.probe_nodes.front()
                                                      : rotor.rub_station_node;
  FlexibleRotorModel model(reduced, rotor.unbalances, rotor.rub_contact_radius_m, probe_node, gravity_m_per_s2);
  model.set_truncation(report);
  std::vector<int> disks;
  for (const DiskElement& d : rotor.disks) disks.push_back(d.node);
  std::sort(disks.begin(), disks.end());
  disks.erase(std::unique(disks.begin(), disks.end()), disks.end());
  model.set_disk_nodes(std::move(disks));
  return model;
}

ModelParameters station_parameters(const ModelParameters& scene, const FlexibleRotorModel& rotor) {
  ModelParameters p = scene;
  p.rotor_mass_kg = rotor.station_mass_kg();
  if (rotor.contact_radius_m() > 0.0) p.rotor_radius_m = rotor.contact_radius_m();
  return p;
}

double contact_radius_of(const Scene& scene) {
  if (rotor_kind(scene) == RotorKind::kJeffcott) return scene.model.rotor_radius_m;
  const double r = flexible_rotor_of(scene)->contact_radius_m();
  return r > 0.0 ? r : scene.model.rotor_radius_m;
}

namespace {

// The speeds a scene runs at without a command: its run-up's or run-down's.
std::pair<double, double> scene_speeds(const Scene& scene) {
  return std::minmax(scene.speed.initial_speed_rad_per_s, scene.speed.target_speed_rad_per_s);
}

}  // namespace

std::shared_ptr<const FlexibleRotorModel> flexible_rotor_of(const Scene& scene) {
  const RotorSettings& r = scene.rotor;
  const double g = scene.model.gravity_m_per_s2;
  const auto [lo, hi] = scene_speeds(scene);
  if (r.loaded && r.loaded->file == r.file && r.loaded->planar_modes == r.planar_modes &&
      r.loaded->probe_node == r.probe_node && r.loaded->gravity_m_per_s2 == g &&
      r.loaded->truncation_tolerance == r.truncation_tolerance && r.loaded->min_speed_rad_per_s == lo &&
      r.loaded->max_speed_rad_per_s == hi && r.loaded->acceleration_rad_per_s2 == scene.speed.acceleration_rad_per_s2) {
    return r.loaded->model;
  }
  return std::make_shared<const FlexibleRotorModel>(
      load_flexible_rotor(r, g, lo, hi, scene.speed.acceleration_rad_per_s2));
}

void load_rotor(Scene& scene) {
  if (rotor_kind(scene) == RotorKind::kJeffcott) return;
  auto model = flexible_rotor_of(scene);
  if (scene.rotor.loaded && scene.rotor.loaded->model == model) return;
  const auto [lo, hi] = scene_speeds(scene);
  scene.rotor.loaded = std::make_shared<const LoadedFlexibleRotor>(LoadedFlexibleRotor{
      scene.rotor.file, scene.rotor.planar_modes, scene.rotor.truncation_tolerance, lo, hi,
      scene.speed.acceleration_rad_per_s2, scene.rotor.probe_node, scene.model.gravity_m_per_s2, model});
}

}  // namespace rotor_rub::core
