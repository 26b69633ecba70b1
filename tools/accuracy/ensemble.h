// The chaotic cases as ensembles: one start is one draw from a spread, so the
// report's figures at 1 ms are the median and range over perturbed starts,
// each against its own truth (igms RK4 at 1/64 ms; the nominal start's
// independent truth confirms it, see independent_reference.h).
#pragma once

#include <string>
#include <vector>

#include "tools/accuracy/accuracy.h"

namespace igms::accuracy {

struct Spread {
  double median = 0, min = 0, max = 0;
};

struct EnsembleRow {
  std::string case_name, method;
  int starts = 0, diverged = 0;
  Spread q_max, q_rms, ee_max, energy_drift, energy_rate;
};

// `starts` starts: q0 plus a uniform perturbation in [-spread, spread] rad (or m)
// on every joint coordinate (a floating base's pose is kept), seeded; every
// method at step h. A diverged run is counted, not summarised.
std::vector<EnsembleRow> ensemble(const Case& c, int starts, double spread, double h, unsigned seed = 7);

}  // namespace igms::accuracy
