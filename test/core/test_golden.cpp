// Whole runs against their figures from a trusted build
// (test/data/golden_runs.txt): six scenes (the paper's run-up; a rigid
// stator with restitution 0.5 and f 0.3; gravity; f 0.8 far above the
// critical speed; a dry-whirl run-down; a flexible rotor's seal rub) on
// every method and integrator of the registry (rk4 is test_fixed_step's and
// test_flexible_rk4's), a test case each (Runs/GoldenRun.*). A regression test fails when the
// physics or the numerics move, not when a libm does: positions and event
// times are held to tolerances, counts exactly. Bitwise equality is a promise within one build
// only (output-rate independence, determinism, lockstep: their own tests).
//
// ROTOR_RUB_WRITE_GOLDEN=1 test_core --gtest_filter='*Golden*' rewrites the
// file from this build; the commit that does it says why and by how much
// the figures moved.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/scene_keys.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// The runs are held at tight tolerances, so that a step-size decision that a
// last bit flips moves the figures by far less than the checks' bounds,
// while a change of the physics moves them by far more (at rtol 1e-6 /
// atol 1e-9 a libm's sin/cos pair flipped step decisions: positions moved by
// up to 6.5e-9 m, a gravity run's event sequence changed). Each method as
// tight as it runs well: switching at rtol 1e-12, the iteration and penalty
// methods at 1e-11 (the iteration method has stalled at 1e-12: numerics.md);
// atol 1e-3 m of rtol, as the orbits are millimetres.
//
// The Jeffcott scenes' bounds, 3.3x to 5.6x what eight libms with other last bits moved
// (test/core/other_libm.cpp, seeds 1 to 8, every case; docs/testing.md,
// "Golden runs"). An event at closing speed v is held to event_s plus
// gap_m / v, the time a gap gap_m off takes to close at that speed (a
// touchdown after a graze comes back nearly tangentially); a lift-off, where
// a force crosses zero, to event_s. Switching locates its events as roots of
// smooth functions of its dense output: positions moved by at most
// 2.8e-13 m, lift-offs by 1.3e-12 s, a gap's crossing by 5.4e-15 m over its
// closing speed. The iteration method's events are where an iterated force
// or a bisected gap crosses zero: lift-offs, where the pressing falls
// through zero slowly, moved by 5.4e-10 s, gaps by 2.0e-14 m, positions by
// 1.2e-13 m (its engaged step redone to end on a lift-off: before that,
// interpolated across the kink there, 1.0e-11 m). The penalty method's
// spring lets go as the penetration returns to zero, slowly: lift-offs moved
// by 2.1e-9 s, gaps by 7.1e-13 m, positions by 1.5e-11 m.
constexpr double kLoosestEvent_s = 1e-6;
struct Tolerances {
  double rtol;
  double position_m;
  double event_s;
  double gap_m;
  double atol_m() const { return 1e-3 * rtol; }
  // No event looser than kLoosestEvent_s, however slowly it closes.
  double event_time_s(double closing_m_per_s) const {
    return std::min(event_s + (closing_m_per_s > 0.0 ? gap_m / closing_m_per_s : kLoosestEvent_s), kLoosestEvent_s);
  }
};
// The Jeffcott's scenes.
Tolerances jeffcott_tolerances(core::Method m) {
  switch (m) {
    case core::Method::kSwitching:
      return {1e-12, 1e-12, 5e-12, 2e-14};
    case core::Method::kIteration:
      return {1e-11, 5e-13, 3e-9, 1e-13};
    case core::Method::kPenalty:
      return {1e-11, 5e-11, 1e-8, 3e-12};
  }
  throw std::logic_error("jeffcott_tolerances: not a Method");
}
// The flexible rotor's seal rub, at the same rtol: its orbit is 20 um, not
// millimetres, and its figures moved far less under the eight libms, so its
// bounds are its own, 4.3x to 7.7x what they moved (positions, lift-offs,
// gaps): switching 1.6e-16 m, 2.3e-13 s, 2.6e-16 m; iteration 3.7e-15 m,
// 1.0e-11 s, 2.3e-14 m; penalty 1.3e-15 m, 3.6e-10 s, 3.2e-15 m. A friction
// coefficient 1e-7 off (0.2 -> 0.20000002) fails every case.
Tolerances flexible_tolerances(core::Method m) {
  switch (m) {
    case core::Method::kSwitching:
      return {1e-12, 1e-15, 1e-12, 1.5e-15};
    case core::Method::kIteration:
      return {1e-11, 2e-14, 5e-11, 1e-13};
    case core::Method::kPenalty:
      return {1e-11, 7e-15, 2e-9, 2e-14};
  }
  throw std::logic_error("flexible_tolerances: not a Method");
}
// A rebound cascade (restitution > 0) closes ever slower until a rebound
// settles (contact_law.hpp), and which graze is the last one before the
// settling touchdown is decided by the settle threshold and the last bits:
// at rtol 1e-10 the rigid scene's cascade on iteration / dop853 had one
// graze more under one libm (closing at 2.06e-6 m/s) than under another. So
// the grazes closing slower than kSlowGraze_m_per_s are counted apart and
// their count held to within kSlowGrazeSlack (at the tolerances above the
// eight libms agreed on every count); the event that ends such a tail is
// always kept and held to kCascadeEnd_s (5.6x the 1.8e-8 s they moved it)
// where the file marks it too. A settle threshold 4x off drops two of those
// grazes (switching on dop853) and moves the touchdown by 1.9e-6 s.
constexpr double kSlowGraze_m_per_s = 1e-5;
constexpr long kSlowGrazeSlack = 1;
constexpr double kCascadeEnd_s = 1e-7;
// Every event counts: among the events, or among the slow grazes. (A gap
// crossing right after a lift-off where the rotor neither closes nor is
// pressed, the gap's rounding, is no event in any method: under other last
// bits the switching method reported such grazes 4e-16 to 1.2e-10 s after
// their lift-offs until it stopped, and the counts would catch one.)
constexpr double kCheckpointEvery_s = 0.25;
constexpr std::size_t kEventsKept = 12;  // the first ones, and the last

struct GoldenScene {
  const char* name;
  const char* sets;  // scene keys over the base file, "-" for none
  bool with_iteration = true;
  const char* base = "config/paper_runup.yaml";
  Tolerances (*tolerances)(core::Method) = jeffcott_tolerances;
  bool runs(const test::Solver& s) const { return with_iteration || s.method != core::Method::kIteration; }
};
const GoldenScene kScenes[] = {
    {"paper", "-"},
    {"rigid_restitution_high_friction", "stator_model=rigid,restitution=0.5,friction_coefficient=0.3,end_time_s=3"},
    {"gravity", "gravity_m_per_s2=9.81,friction_coefficient=0.2,end_time_s=3"},
    {"above_critical_stick",
     "friction_coefficient=0.8,target_speed_rad_per_s=400,acceleration_rad_per_s2=200,end_time_s=2.5"},
    // config/dry_whirl_rundown.yaml: rolling on a rigid stator that ends at
    // the cone (issue 50), then a slide, a short stick and the lift-off.
    // Without the iteration method: its rolling is projected back onto the
    // bore after every step, and under other libms its positions here moved
    // by up to 1.9e-12 m, 4x its bound (which its other scenes hold 4x
    // inside); test_transitions.cpp holds its rolling to the closed form.
    {"dry_whirl_rundown",
     "stator_model=rigid,rotor_radius_m=0.002,friction_coefficient=0.5,initial_speed_rad_per_s=600,"
     "acceleration_rad_per_s2=500,target_speed_rad_per_s=50,end_time_s=1.2",
     false},
    // config/seal_rub_runup.yaml's flexible rotor at 4 planar modes, from
    // 215 rad/s up towards its first critical speed: a touchdown on the rigid
    // seal at 0.31 s, a lift-off, and the sliding rub from 0.41 s to the end.
    {"seal_rub_flexible", "rotor_planar_modes=4,initial_speed_rad_per_s=215,end_time_s=1", true,
     "config/seal_rub_runup.yaml", flexible_tolerances},
};

struct KeptEvent {
  double t_s = 0.0;
  std::string kind;
  double closing_m_per_s = 0.0;    // the closing speed (touchdown, graze)
  bool ends_slow_cascade = false;  // written as "event T KIND closing V cascade_end"
};
struct Figures {
  long samples = 0, marks = 0, events = 0, slow_grazes = 0;
  std::vector<KeptEvent> kept_events;
  std::vector<std::vector<double>> checkpoints;  // t, x_r, y_r, x_s, y_s
};

struct Recorder : test::Collect {
  long marks = 0;
  bool wants_keyphasor() const override { return true; }
  void on_keyphasor(const core::Sample&) override { ++marks; }
};

Figures run_case(const GoldenScene& g, const test::Solver& solver) {
  const Tolerances tol = g.tolerances(solver.method);
  core::Scene scene = test::with_method(core::load_scene(test::source_path(g.base)), solver, tol.rtol, tol.atol_m());
  if (std::string(g.sets) != "-") {
    std::istringstream items(g.sets);
    std::string item;
    while (std::getline(items, item, ',')) {
      const auto eq = item.find('=');
      core::set_scene_value(scene, item.substr(0, eq), item.substr(eq + 1));
    }
  }
  Recorder rec;
  const core::RunResult r = core::run_scene(scene, rec);
  EXPECT_FALSE(r.failure.has_value()) << g.name << " " << solver.name();
  Figures f;
  f.samples = static_cast<long>(rec.samples.size());
  f.marks = rec.marks;
  std::vector<core::ContactEvent> events;
  std::vector<bool> ends_slow_cascade;
  bool after_slow_graze = false;
  for (std::size_t i = 0; i < rec.events.size(); ++i) {
    const core::ContactEvent& e = rec.events[i];
    const bool graze = e.kind == core::EventKind::kGraze;
    if (graze && std::abs(e.normal_velocity_m_per_s) < kSlowGraze_m_per_s) {
      ++f.slow_grazes;
      after_slow_graze = true;
      continue;
    }
    events.push_back(e);
    ends_slow_cascade.push_back(after_slow_graze);
    after_slow_graze = false;
  }
  f.events = static_cast<long>(events.size());
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (i < kEventsKept || i + 1 == events.size() || ends_slow_cascade[i]) {
      f.kept_events.push_back(
          {events[i].t_s, core::to_string(events[i].kind), events[i].normal_velocity_m_per_s, ends_slow_cascade[i]});
    }
  }
  const auto every = static_cast<std::size_t>(std::lround(kCheckpointEvery_s * scene.output_rate_hz));
  for (std::size_t i = every; i < rec.samples.size(); i += every) {
    const core::Sample& s = rec.samples[i];
    f.checkpoints.push_back(
        {s.t_s, s.kin.rotor_pos.x(), s.kin.rotor_pos.y(), s.kin.stator_pos.x(), s.kin.stator_pos.y()});
  }
  return f;
}

std::string key_of(const GoldenScene& g, const test::Solver& s) {
  return std::string(g.name) + " " + core::to_string(s.method) + " " + core::to_string(s.integrator);
}

void write(std::ostream& os, const std::string& key, const Figures& f) {
  char buf[200];
  os << "case " << key << " samples " << f.samples << " marks " << f.marks << " events " << f.events << " slow_grazes "
     << f.slow_grazes << "\n";
  for (const KeptEvent& e : f.kept_events) {
    std::snprintf(buf, sizeof buf, "event %.17g %s closing %.3g%s\n", e.t_s, e.kind.c_str(), e.closing_m_per_s,
                  e.ends_slow_cascade ? " cascade_end" : "");
    os << buf;
  }
  for (const auto& c : f.checkpoints) {
    std::snprintf(buf, sizeof buf, "at %.17g %.17g %.17g %.17g %.17g\n", c[0], c[1], c[2], c[3], c[4]);
    os << buf;
  }
}

std::map<std::string, Figures> read(std::istream& in) {
  std::map<std::string, Figures> out;
  std::string line;
  Figures* cur = nullptr;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "case") {
      std::string name, method, integrator, w;
      Figures f;
      ls >> name >> method >> integrator >> w >> f.samples >> w >> f.marks >> w >> f.events >> w >> f.slow_grazes;
      cur = &(out[name + " " + method + " " + integrator] = f);
    } else if (tag == "event" && cur) {
      double t = 0.0, closing = 0.0;
      std::string kind, w, mark;
      ls >> t >> kind >> w >> closing >> mark;
      cur->kept_events.push_back({t, kind, closing, mark == "cascade_end"});
    } else if (tag == "at" && cur) {
      std::vector<double> c(5);
      for (double& v : c) ls >> v;
      cur->checkpoints.push_back(c);
    }
  }
  return out;
}

const char* kGoldenFile = "test/data/golden_runs.txt";

// Every scene on every solver it runs on: a case each.
struct GoldenCase {
  const GoldenScene* scene;
  test::Solver solver;
  std::string key() const { return key_of(*scene, solver); }
};
// gtest names a failing case by this, not by the parameter's bytes.
void PrintTo(const GoldenCase& c, std::ostream* os) { *os << c.key(); }
std::vector<GoldenCase> golden_cases() {
  std::vector<GoldenCase> out;
  for (const GoldenScene& g : kScenes) {
    for (const test::Solver& s : test::all_solvers())
      if (g.runs(s)) out.push_back({&g, s});
  }
  return out;
}
bool rewriting() { return std::getenv("ROTOR_RUB_WRITE_GOLDEN") != nullptr; }
const std::map<std::string, Figures>& golden_file() {
  static const std::map<std::string, Figures> figures = [] {
    std::ifstream in(test::source_path(kGoldenFile));
    return in.good() ? read(in) : std::map<std::string, Figures>{};
  }();
  return figures;
}

class GoldenRun : public ::testing::TestWithParam<GoldenCase> {};

}  // namespace

TEST_P(GoldenRun, MatchesItsFiguresWithinTolerances) {
  if (rewriting()) GTEST_SKIP() << "rewriting " << kGoldenFile;
  const GoldenCase& c = GetParam();
  const std::string key = c.key();
  const auto it = golden_file().find(key);
  ASSERT_NE(it, golden_file().end()) << "no golden figures for " << key << " in " << kGoldenFile
                                     << " (a new solver or scene? rewrite the file, see above)";
  const Figures& want = it->second;
  const Figures got = run_case(*c.scene, c.solver);
  EXPECT_EQ(got.samples, want.samples);
  EXPECT_EQ(got.marks, want.marks);
  EXPECT_EQ(got.events, want.events);
  EXPECT_LE(std::abs(got.slow_grazes - want.slow_grazes), kSlowGrazeSlack)
      << "the grazes closing slower than kSlowGraze_m_per_s";
  ASSERT_EQ(got.kept_events.size(), want.kept_events.size()) << "events kept";
  const Tolerances bounds = c.scene->tolerances(c.solver.method);
  for (std::size_t i = 0; i < want.kept_events.size(); ++i) {
    const KeptEvent& e = got.kept_events[i];
    const KeptEvent& w = want.kept_events[i];
    EXPECT_EQ(e.kind, w.kind) << "event " << i;
    EXPECT_EQ(e.ends_slow_cascade, w.ends_slow_cascade) << "event " << i << " ends a slow cascade";
    // The loose bound only where both the run and the file say the event ends a cascade.
    const bool cascade_end = e.ends_slow_cascade && w.ends_slow_cascade;
    EXPECT_NEAR(e.t_s, w.t_s, cascade_end ? kCascadeEnd_s : bounds.event_time_s(w.closing_m_per_s))
        << "event " << i << " closing at " << w.closing_m_per_s << " m/s";
  }
  ASSERT_EQ(got.checkpoints.size(), want.checkpoints.size()) << "checkpoints";
  for (std::size_t i = 0; i < want.checkpoints.size(); ++i) {
    EXPECT_EQ(got.checkpoints[i][0], want.checkpoints[i][0]);  // k / rate: exact
    for (int col = 1; col < 5; ++col) {
      EXPECT_NEAR(got.checkpoints[i][col], want.checkpoints[i][col], bounds.position_m)
          << "t " << want.checkpoints[i][0] << " column " << col;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Runs, GoldenRun, ::testing::ValuesIn(golden_cases()),
                         [](const ::testing::TestParamInfo<GoldenCase>& info) {
                           return std::string(info.param.scene->name) + "_" + info.param.solver.name();
                         });

// The file holds a case for every run and no case that is no longer run.
TEST(Golden, FileHoldsExactlyTheRunCases) {
  if (rewriting()) GTEST_SKIP() << "rewriting " << kGoldenFile;
  std::map<std::string, Figures> left = golden_file();
  ASSERT_FALSE(left.empty()) << kGoldenFile << " missing or empty";
  for (const GoldenCase& c : golden_cases()) EXPECT_EQ(left.erase(c.key()), 1u) << "no figures for " << c.key();
  for (const auto& [key, figures] : left) ADD_FAILURE() << kGoldenFile << " holds " << key << ", which no case runs";
}

// ROTOR_RUB_WRITE_GOLDEN=1: writes the file from this build (the cases skip).
TEST(Golden, RewritesTheFileWhenAsked) {
  if (!rewriting()) GTEST_SKIP() << "ROTOR_RUB_WRITE_GOLDEN not set";
  std::ofstream os(test::source_path(kGoldenFile));
  os << "# Written by test_golden.cpp (ROTOR_RUB_WRITE_GOLDEN=1): per scene, method and integrator at the\n"
        "# method's tolerances: the counts of samples, keyphasor marks, events and, apart, of grazes closing\n"
        "# slower than 1e-5 m/s; the first events, the last, and any that ends a cascade of those, with their\n"
        "# closing speeds; the rotor's and stator's positions every 0.25 s. Held to bounds per\n"
        "# method (test_golden.cpp says which and why).\n";
  for (const GoldenCase& c : golden_cases()) write(os, c.key(), run_case(*c.scene, c.solver));
  ASSERT_TRUE(os.good());
}

// Under test/core/other_libm.cpp, preloaded with ROTOR_RUB_LIBM_SEED set
// (CMakeLists.txt: golden_other_libm_N): it is in effect, so the runs above
// met other last bits. sin through the libm symbol the core calls too,
// against sinl rounded to double (the same double for every argument here
// without it).
TEST(Golden, OtherLibmIsInEffectWhenPreloaded) {
  if (std::getenv("ROTOR_RUB_LIBM_SEED") == nullptr) GTEST_SKIP() << "not under other_libm";
  int moved = 0;
  for (int i = 0; i < 1000; ++i) {
    volatile double x = 0.3 + 1e-3 * i;
    if (std::sin(x) != static_cast<double>(sinl(x))) ++moved;
  }
  EXPECT_GT(moved, 300) << "other_libm moves two results in three by one ulp";
}
