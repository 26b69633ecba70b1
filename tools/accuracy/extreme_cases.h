// Stiff and extreme cases: each states its pass criterion, runs on each
// integrator (and on ODE where it applies), and yields a row of the report's
// table. The stress test asserts that every row passes; igms-accuracy
// --extreme prints and writes them.
#pragma once

#include <string>
#include <vector>

namespace igms::accuracy {

struct ExtremeRow {
  std::string name;       // the case
  std::string method;     // semi_implicit_euler, rk4, linearly_implicit, ode_worldstep, or "-"
  std::string criterion;  // what passing means
  std::string figure;     // what was measured
  bool pass = false;
};

// quick: shorter runs (1e5 instead of 1e6 steps, 20 s instead of 100 s of
// tumbling, 3 starts of the long run instead of 9) for a first look; the
// report runs in full. long_run_starts > 0 sets the long run's ensemble size
// (the stress test: the full runs, 3 starts, to stay within its time).
std::vector<ExtremeRow> extremeCases(const std::string& source_dir, bool quick = false, int long_run_starts = 0);

}  // namespace igms::accuracy
