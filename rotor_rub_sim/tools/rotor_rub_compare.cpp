// rotor_rub_compare: compares recorded runs offline. Reads the node's bags
// (every rotor_rub_msgs/RotorState topic <ns>/state is one run, with its
// <ns>/contact_events and <ns>/solver_stats) and the headless runner's output
// (--runner PREFIX reads PREFIX.csv and PREFIX.json), prints a table and
// writes a CSV: touchdown and lift-off times, max and RMS differences of the
// rotor and stator positions against a reference run, contact force figures,
// lost messages, solver cost, and the live changes and faults applied
// (<ns>/parameter_change_feedback).
//
// Exit status: 0 ok; 2 bad input (usage, a missing, truncated or foreign bag).
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cli_options.hpp"
#include "rotor_rub_msgs/ContactEvent.h"
#include "rotor_rub_msgs/ParameterChangeFeedback.h"
#include "rotor_rub_msgs/RotorState.h"
#include "rotor_rub_msgs/SolverStats.h"
#include "rotor_rub_sim/ros/conversions.hpp"
#include "run_comparison.hpp"

namespace {

using rotor_rub::tools::RecordedRun;

[[noreturn]] void bad_input(const std::string& msg) {
  std::cerr << "rotor_rub_compare: " << msg << "\n";
  std::exit(2);
}

std::string run_key(const std::string& topic, const std::string& suffix) {
  return topic.size() > suffix.size() && topic.compare(topic.size() - suffix.size(), suffix.size(), suffix) == 0
             ? topic.substr(0, topic.size() - suffix.size())
             : std::string();
}

std::vector<RecordedRun> read_bag(const std::string& path) {
  // Say what is wrong before rosbag does: a missing file, a file that is
  // not a bag, and an unclosed bag (the only case `rosbag reindex` mends).
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) bad_input("cannot open '" + path + "': no such file, or not readable");
    char magic[13] = {};
    probe.read(magic, 12);
    if (std::string(magic, static_cast<std::size_t>(probe.gcount())) != "#ROSBAG V2.0") {
      bad_input("'" + path + "' is not a rosbag 2.0 file (it does not start with #ROSBAG V2.0)");
    }
  }
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    bad_input("cannot read bag '" + path + "': " + e.what() + " (an unclosed bag needs `rosbag reindex` first)");
  }
  std::map<std::string, RecordedRun> runs;
  std::map<std::string, std::set<uint64_t>> seqs;
  try {
    rosbag::View view(bag);
    for (const rosbag::MessageInstance& m : view) {
      const std::string& topic = m.getTopic();
      if (auto s = m.instantiate<rotor_rub_msgs::RotorState>()) {
        const std::string key = run_key(topic, "/state").empty() ? topic : run_key(topic, "/state");
        runs[key].samples.push_back(rotor_rub::ros_node::from_msg(*s));
        seqs[key].insert(s->sample_index);
      } else if (auto e = m.instantiate<rotor_rub_msgs::ContactEvent>()) {
        runs[run_key(topic, "/contact_events")].events.push_back(rotor_rub::ros_node::from_msg(*e));
      } else if (auto c = m.instantiate<rotor_rub_msgs::ParameterChangeFeedback>()) {
        if (!c->accepted) continue;  // a refused change changed nothing
        auto listed = [&c](const std::vector<double>& vs) {
          std::string out;
          for (std::size_t i = 0; i < c->keys.size() && i < vs.size(); ++i) {
            char v[32];
            std::snprintf(v, sizeof v, "%.9g", vs[i]);
            out += (out.empty() ? "" : " ") + c->keys[i] + "=" + v;
          }
          return out;
        };
        const std::string values = listed(c->values);
        const std::string what = c->source.rfind("fault:", 0) == 0 ? c->source.substr(6) : values;
        runs[run_key(topic, "/parameter_change_feedback")].changes.push_back(
            {c->effective_time, c->end_time, what, c->change_id, listed(c->from_values), values, c->steps});
      } else if (auto st = m.instantiate<rotor_rub_msgs::SolverStats>()) {
        RecordedRun& r = runs[run_key(topic, "/solver_stats")];
        r.method = st->method;
        r.integrator = st->integrator;
        r.steps = st->steps;
        r.rhs_evals = st->rhs_evaluations;
        r.integration_wall_s = st->integration_wall_time;
        r.real_time_factor = st->real_time_factor;
      }
    }
  } catch (const rosbag::BagException& e) {
    bad_input("bag '" + path + "' is damaged: " + e.what());
  }
  std::vector<RecordedRun> out;
  for (auto& [key, run] : runs) {
    if (run.samples.empty()) continue;  // events or stats without states
    run.name = path.substr(path.find_last_of('/') + 1) + ":" + key;
    run.has_events = true;
    std::stable_sort(run.samples.begin(), run.samples.end(),
                     [](const auto& a, const auto& b) { return a.t_s < b.t_s; });
    // Sample indices missing below the largest one received are lost
    // messages (a bag with a reset in it holds each index more than once).
    const auto& s = seqs[key];
    run.lost_samples = static_cast<long>(*s.rbegin()) + 1 - static_cast<long>(s.size());
    out.push_back(std::move(run));
  }
  if (out.empty()) bad_input("bag '" + path + "' holds no rotor_rub_msgs/RotorState topic");
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = rotor_rub::cli;
  std::vector<std::string> bags, runner_prefixes;
  std::string reference, csv_path;
  bool quiet = false;
  CLI::App app(
      "Compares recorded runs offline: the node's bags and the headless runner's output. Prints a table and writes "
      "a CSV: touchdown and lift-off times, max and RMS differences of the rotor and stator positions against a "
      "reference run, contact force figures, lost messages and solver cost.",
      "rotor_rub_compare");
  app.add_option("BAG", bags, "a bag recorded from rotor_rub_sim_node (one run per <ns>/state topic)")
      ->type_name("BAG");
  app.add_option("--runner", runner_prefixes,
                 "the headless runner's PREFIX.csv (and PREFIX.json for its events); repeatable")
      ->type_name("PREFIX")
      ->allow_extra_args(false);
  app.add_option("--reference", reference,
                 "the run the others are compared with, by name or part of it (default: the first --runner, "
                 "else the first run)")
      ->type_name("NAME");
  app.add_option("--csv", csv_path, "write one row per run to this CSV file")->type_name("FILE");
  app.add_flag("--quiet", quiet, "no table on stdout");
  app.footer("Exit status: 0 ok; 2 bad input (usage, a missing, truncated or foreign bag).");
  cli::parse_or_exit(app, argc, argv);
  // The runner's runs first (in their order), then the bags'.
  std::vector<RecordedRun> runs;
  for (const auto& prefix : runner_prefixes) {
    try {
      runs.push_back(rotor_rub::tools::read_runner_csv(prefix + ".csv", prefix + ".json"));
    } catch (const std::exception& e) {
      bad_input(e.what());
    }
  }
  for (const auto& bag : bags) {
    for (auto& r : read_bag(bag)) runs.push_back(std::move(r));
  }
  if (runs.empty()) cli::usage_error(app, "no runs given: name a BAG or --runner PREFIX");
  std::size_t ref = 0;
  if (!reference.empty()) {
    auto it = std::find_if(runs.begin(), runs.end(), [&](const RecordedRun& r) {
      return r.name == reference || r.name.find(reference) != std::string::npos;
    });
    if (it == runs.end()) bad_input("no run named '" + reference + "'");
    ref = static_cast<std::size_t>(it - runs.begin());
  }
  std::vector<rotor_rub::tools::RunFigures> rows;
  for (const auto& r : runs) rows.push_back(rotor_rub::tools::compare_run(r, runs[ref]));
  if (!quiet) rotor_rub::tools::print_table(std::cout, rows, runs[ref].name);
  if (!csv_path.empty()) {
    std::ofstream os(csv_path);
    rotor_rub::tools::write_figures_csv(os, rows);
    if (!os) bad_input("cannot write '" + csv_path + "'");
  }
  return 0;
}
