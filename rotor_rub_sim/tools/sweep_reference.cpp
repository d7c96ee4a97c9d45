#include "sweep_reference.hpp"

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>

#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::tools {
namespace {

// Keys that choose how a run is computed, not what it models: the reference
// sets its own (the budgets at their defaults: a run's small wall budget or
// iteration limit must not fail its reference). contact_stiffness_N_per_m is
// the penalty method's numerical parameter: the reference is the rigid limit
// it should converge to.
const char* const kMethodOnlyKeys[] = {"method",
                                       "integrator",
                                       "rtol",
                                       "atol",
                                       "initial_step_s",
                                       "min_step_s",
                                       "max_steps",
                                       "max_wall_time_s",
                                       "fixed_step_s",
                                       "iteration_force_rtol",
                                       "iteration_max_iterations",
                                       "max_events_per_ms",
                                       "output_rate_hz",
                                       "contact_stiffness_N_per_m"};

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// The build of the core that computes references: part of the cache key, so
// a rebuilt core never reads references its predecessor computed.
std::string core_build_stamp() {
  Dl_info info;
  struct stat st;
  if (dladdr(reinterpret_cast<void*>(&core::record_reference), &info) != 0 && info.dli_fname != nullptr &&
      ::stat(info.dli_fname, &st) == 0) {
    return std::string(info.dli_fname) + "@" + std::to_string(st.st_mtime) + "+" + std::to_string(st.st_size);
  }
  return "";  // unknown: caching off (see compute)
}

// ---- the on-disk cache: a binary file per reference, its key inside ----
constexpr uint32_t kCacheMagic = 0x52524632;  // "RRF2"

template <class T>
void put(std::ostream& os, const T& v) {
  os.write(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
bool get(std::istream& is, T& v) {
  return static_cast<bool>(is.read(reinterpret_cast<char*>(&v), sizeof v));
}

void save(const std::string& path, const std::string& key, const core::ReferenceTrace& t) {
  // A temporary file of this process's own: shards on several hosts may
  // write the same reference at once into a shared cache.
  char host[256] = "host";
  gethostname(host, sizeof host - 1);
  const std::string tmp = path + ".tmp." + host + "." + std::to_string(getpid());
  std::ofstream os(tmp, std::ios::binary);
  put(os, kCacheMagic);
  put<uint64_t>(os, key.size());
  os.write(key.data(), static_cast<std::streamsize>(key.size()));
  put<uint64_t>(os, t.t_s.size());
  for (std::size_t i = 0; i < t.t_s.size(); ++i) {
    put(os, t.t_s[i]);
    put(os, t.rotor_pos_m[i].x());
    put(os, t.rotor_pos_m[i].y());
    put(os, t.stator_pos_m[i].x());
    put(os, t.stator_pos_m[i].y());
  }
  put<uint64_t>(os, t.events.size());
  for (const auto& e : t.events) {
    put(os, e.t_s);
    put<int32_t>(os, static_cast<int32_t>(e.kind));
    put(os, e.normal_velocity_m_per_s);
    put(os, e.impulse_N_s);
  }
  const auto& wi = t.windows.impulse_N_s();
  const auto& wc = t.windows.in_contact();
  put<uint64_t>(os, wi.size());
  for (std::size_t k = 0; k < wi.size(); ++k) {
    put(os, wi[k]);
    put<uint8_t>(os, wc[k] ? 1 : 0);
  }
  put<uint8_t>(os, t.failed ? 1 : 0);
  put<uint64_t>(os, t.failure_message.size());
  os.write(t.failure_message.data(), static_cast<std::streamsize>(t.failure_message.size()));
  os.close();
  if (os) {
    std::rename(tmp.c_str(), path.c_str());  // atomic: a reader sees the old file or the whole new one
  } else {
    std::remove(tmp.c_str());
  }
}

// Loads the trace if the file holds this key; rebuilds the windows from it.
bool load(const std::string& path, const std::string& key, double window_s, core::ReferenceTrace& t) {
  std::ifstream is(path, std::ios::binary);
  uint32_t magic = 0;
  uint64_t n = 0;
  if (!is || !get(is, magic) || magic != kCacheMagic || !get(is, n) || n > (1u << 20)) return false;
  std::string stored(n, '\0');
  if (!is.read(stored.data(), static_cast<std::streamsize>(n)) || stored != key) return false;
  t = core::ReferenceTrace{};
  t.windows = core::ImpulseWindows(window_s);
  if (!get(is, n)) return false;
  for (uint64_t i = 0; i < n; ++i) {
    double ts, rx, ry, sx, sy;
    if (!get(is, ts) || !get(is, rx) || !get(is, ry) || !get(is, sx) || !get(is, sy)) return false;
    t.t_s.push_back(ts);
    t.rotor_pos_m.emplace_back(rx, ry);
    t.stator_pos_m.emplace_back(sx, sy);
  }
  if (!get(is, n)) return false;
  for (uint64_t i = 0; i < n; ++i) {
    core::ContactEvent e;
    int32_t kind;
    if (!get(is, e.t_s) || !get(is, kind) || !get(is, e.normal_velocity_m_per_s) || !get(is, e.impulse_N_s)) {
      return false;
    }
    e.kind = static_cast<core::EventKind>(kind);
    t.events.push_back(e);
  }
  if (!get(is, n)) return false;
  std::vector<double> impulse(n);
  std::vector<bool> contact(n);
  for (uint64_t k = 0; k < n; ++k) {
    uint8_t c = 0;
    if (!get(is, impulse[k]) || !get(is, c)) return false;
    contact[k] = c != 0;
  }
  t.windows = core::ImpulseWindows(window_s, std::move(impulse), std::move(contact));
  uint8_t failed = 0;
  if (!get(is, failed)) return false;
  t.failed = failed != 0;
  if (!get(is, n) || n > (1u << 20)) return false;
  t.failure_message.assign(n, '\0');
  return static_cast<bool>(is.read(t.failure_message.data(), static_cast<std::streamsize>(n)));
}

}  // namespace

Values ReferenceStore::reference_values(const Values& run_values) const {
  Values v = run_values;
  for (const char* k : kMethodOnlyKeys) v.erase(k);
  v["method"] = "switching";
  v["integrator"] = "dopri5";
  v["rtol"] = num(settings_.rtol);
  v["atol"] = num(settings_.atol);
  v["output_rate_hz"] = num(settings_.sample_rate_hz);
  return v;
}

Judged ReferenceStore::judge(const Values& run_values, double run_atol_m) {
  Judged out;
  const Values ref_values = reference_values(run_values);
  out.reference = trace_of(ref_values);
  if (!settings_.witness) return out;
  // What the run's precision cannot tell apart: the bore moved by its atol.
  Values moved = run_values;
  const auto offset = run_values.find("stator_offset_x_m");
  moved["stator_offset_x_m"] = num((offset == run_values.end() ? 0.0 : std::stod(offset->second)) + run_atol_m);
  std::vector<std::pair<std::string, Values>> witnesses{{"the bore moved by the run's atol", reference_values(moved)}};
  for (const char* method : {"switching", "iteration"}) {
    Values v = ref_values;
    v["method"] = method;
    v["integrator"] = "dop853";
    witnesses.emplace_back(std::string(method) + " on dop853", v);
  }
  // A witness that fails (or whose scene is refused: the moved bore beyond
  // the clearance) says nothing about sensitivity: it is left out of the
  // horizon and named in the row's message.
  auto failed = [&out](const std::string& name, const std::string& why) {
    out.witness_failures += (out.witness_failures.empty() ? "" : "; ") + name + ": " + why;
  };
  for (const auto& [name, values] : witnesses) {
    std::shared_ptr<const core::ReferenceTrace> w;
    try {
      w = trace_of(values);
    } catch (const core::SceneError& e) {
      failed(name, e.what());
      continue;
    }
    if (w->failed) {
      failed(name, w->failure_message);
      continue;
    }
    out.horizon_s = std::min(out.horizon_s, core::sensitivity_horizon_s(*out.reference, *w, settings_.horizon_apart_m));
  }
  return out;
}

std::shared_ptr<const core::ReferenceTrace> ReferenceStore::trace_of(const Values& ref_values) {
  std::string key;
  for (const auto& [k, v] : ref_values) key += k + "=" + v + "\n";
  key += "window_s=" + num(settings_.window_s) + "\n";
  key += "core_build=" + core_build_stamp() + "\n";
  std::shared_future<std::shared_ptr<const core::ReferenceTrace>> future;
  std::promise<std::shared_ptr<const core::ReferenceTrace>> promise;
  bool mine = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = traces_.find(key);
    if (it == traces_.end()) {
      future = promise.get_future().share();
      traces_.emplace(key, future);
      mine = true;
    } else {
      future = it->second;
    }
  }
  if (mine) {
    try {
      promise.set_value(compute(ref_values, key));
    } catch (...) {
      promise.set_exception(std::current_exception());
    }
  }
  return future.get();
}

std::shared_ptr<const core::ReferenceTrace> ReferenceStore::compute(const Values& ref_values, const std::string& key) {
  auto trace = std::make_shared<core::ReferenceTrace>();
  std::string path;  // the file holds its key: a hash collision is a cache miss
  if (!cache_dir_.empty() && !core_build_stamp().empty()) {
    std::ostringstream name;
    name << cache_dir_ << "/reference_" << std::hex << std::hash<std::string>{}(key) << ".bin";
    path = name.str();
    if (load(path, key, settings_.window_s, *trace)) return trace;
  }
  const core::Scene scene = core::scene_from_values(ref_values);
  *trace = core::record_reference(scene, settings_.window_s);
  if (!path.empty()) save(path, key, *trace);
  return trace;
}

}  // namespace rotor_rub::tools
