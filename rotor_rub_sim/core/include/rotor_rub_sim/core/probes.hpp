// The proximity probes' signals (ProbeParameters in parameters.hpp says what
// they measure and how they are mounted). The simulation samples the state
// for them at the probes' own rate from the dense output
// (SimulationObserver::on_probe_sample), so the rate never changes the
// solution; ProbePair turns each such sample into the two signals.
#pragma once

#include <random>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

struct ProbeReading {
  double t_s = 0.0;
  double x_V = 0.0, y_V = 0.0;  // the signals, noise included
  double x_m = 0.0, y_m = 0.0;  // what they measure: displacement plus runout along each axis, no noise
};

class ProbePair {
 public:
  explicit ProbePair(const ProbeParameters& p);
  // Call in time order: the noise is one seeded sequence, two draws per sample.
  ProbeReading read(const Sample& s);

 private:
  ProbeParameters p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> noise_{0.0, 1.0};
};

}  // namespace rotor_rub::core
