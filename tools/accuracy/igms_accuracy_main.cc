// igms-accuracy: error against run time for igms's integrators and ODE.
//   igms-accuracy [--case NAME|all] [--quick] [--duration S] [--repeats N] [--csv FILE]
//   igms-accuracy --extreme [--quick] [--csv FILE]    the stiff and extreme cases' table
//   igms-accuracy --stiffness                         the stiffness sweep alone
// For each case: the ground truth is igms RK4 at h = 1/64 ms, checked against
// RK4 at 1/128 ms (the step-halving difference is printed); every method then
// runs at h = 1/64 ms ... 32 ms (doubling; --quick: 0.25 ms ... 4 ms) and each
// row gives its errors against the truth and its run time per simulated second
// (the median of --repeats runs, 3 by default, for every run shorter than 2 s
// of wall time; a longer run is timed once).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "core/cli/command_line.h"
#include "tools/accuracy/accuracy.h"
#include "tools/accuracy/extreme_cases.h"
#include "tools/accuracy/stiffness.h"

using namespace igms::accuracy;

namespace {

struct Options {
  std::string which = "all", csv;
  bool quick = false, extreme = false, stiffness = false;
  double duration = 0.0;
  int repeats = 3;
};

// A 0.1 kg body on springs of 1e2 .. 1e7 N/m at 1 ms.
int stiffnessTable() {
  std::vector<double> ks;
  for (double k = 100; k <= 1.01e7; k *= std::sqrt(10.0)) ks.push_back(k);
  std::printf("%12s %10s  %-28s %-28s %-28s\n", "k (N/m)", "k h^2/m", "semi-implicit Euler", "RK4", "linearly implicit");
  double largest[3] = {0, 0, 0};
  for (const auto& r : stiffnessSweep(0.1, 1e-3, ks)) {
    std::printf("%12.3g %10.3g", r.k, r.k_h2_m);
    for (int m = 0; m < 3; ++m) {
      std::printf("  %-8s E/E0 max %-12.3g", r.stable[m] ? "stable" : "UNSTABLE", r.energy_ratio[m]);
      if (r.stable[m]) largest[m] = r.k;
    }
    std::printf("\n");
  }
  std::printf(
      "largest stable k at 1 ms on 0.1 kg: semi-implicit Euler %.3g N/m, RK4 %.3g N/m, linearly implicit %.3g N/m\n",
      largest[0], largest[1], largest[2]);
  std::printf(
      "measured stability limit of k h^2/m: semi-implicit Euler %.3f (theory 4), RK4 %.3f (theory (2 sqrt 2)^2 = 8)\n",
      stabilityLimit(0, 0.1, 1e-3), stabilityLimit(1, 0.1, 1e-3));
  return 0;
}

int extremeTable(const Options& o) {
  const auto rows = extremeCases(IGMS_SOURCE_DIR, o.quick);
  std::ofstream out(o.csv.empty() ? "/dev/null" : o.csv);
  out << "case,method,criterion,figure,pass\n";
  int failed = 0;
  for (const auto& r : rows) {
    out << '"' << r.name << "\",\"" << r.method << "\",\"" << r.criterion << "\",\"" << r.figure << "\","
        << (r.pass ? "pass" : "FAIL") << "\n";
    std::printf("%-4s  %-62s %-30s %s\n", r.pass ? "pass" : "FAIL", r.name.c_str(), r.method.c_str(), r.figure.c_str());
    failed += !r.pass;
  }
  std::printf("%zu rows, %d failed\n", rows.size(), failed);
  return failed ? 1 : 0;
}

// Every method at every step on one case, against the ground truth.
void sweepCase(const std::string& name, const Options& o, const std::vector<double>& steps, std::ofstream& out) {
  Case c = makeCase(name, IGMS_SOURCE_DIR);
  if (o.duration > 0) c.duration = o.duration;
  else if (o.quick) c.duration = 1.024;
  const Run truth = simulate(c, Method::Rk4, 1.0 / 64 * 1e-3);
  const Run check = simulate(c, Method::Rk4, 1.0 / 128 * 1e-3);
  const Errors halving = compare(c, check, truth);
  std::printf("%s (%.2f s): ground truth RK4 at 1/64 ms; step halving moves q by %.2e (max), so about %.0f digits\n",
              name.c_str(), c.duration, halving.q_max, -std::log10(std::max(halving.q_max, 1e-16)));
  for (Method m : allMethods()) {
    for (double h : steps) {
      const Run r = simulate(c, m, h);
      const Errors e = compare(c, r, truth);
      std::vector<double> walls{r.wall_seconds};
      while (r.wall_seconds < 2.0 && static_cast<int>(walls.size()) < o.repeats)
        walls.push_back(simulate(c, m, h).wall_seconds);
      std::sort(walls.begin(), walls.end());
      const double cost = walls[walls.size() / 2] / c.duration;
      out << name << "," << methodName(m) << "," << h * 1e3 << "," << e.q_rms << "," << e.q_max << "," << e.ee_max
          << "," << e.energy_drift << "," << e.linear_momentum_drift << "," << e.angular_momentum_drift << "," << cost
          << "," << r.diverged << "," << walls.size() << "\n";
      std::printf("  %-20s h=%8.4f ms  q_max %-10.3g ee_max %-10.3g energy drift %-10.3g %s  %.3g s per s\n",
                  methodName(m), h * 1e3, e.q_max, e.ee_max, e.energy_drift, r.diverged ? "DIVERGED" : "", cost);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"", "igms-accuracy"};
  igms::cli::describe(app, "Error against run time for igms's integrators and ODE; the stiffness sweep; the stiff "
                           "and extreme cases' table.");
  std::vector<std::string> cases = caseNames();
  cases.push_back("all");
  app.add_option("--case", o.which, "one case or all")->check(CLI::IsMember(cases));
  app.add_flag("--quick", o.quick, "0.25 .. 4 ms steps over 1.024 s (the extreme table: its short version)");
  app.add_option("--duration", o.duration, "simulated seconds per case (0: the case's own)")->check(igms::cli::Seconds);
  app.add_option("--repeats", o.repeats, "timing runs per row (median), for runs under 2 s")->check(CLI::Range(1, 100));
  app.add_option("--csv", o.csv, "also write the rows here");
  app.add_flag("--extreme", o.extreme, "the stiff and extreme cases' table (exit 1 when a row fails)");
  app.add_flag("--stiffness", o.stiffness, "the stiffness sweep alone");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  if (o.stiffness) return stiffnessTable();
  if (o.extreme) return extremeTable(o);
  std::vector<double> steps;
  for (double h = o.quick ? 0.25e-3 : 1.0 / 64 * 1e-3; h <= (o.quick ? 4e-3 : 32e-3) * 1.0001; h *= 2)
    steps.push_back(h);
  std::ofstream out(o.csv.empty() ? "/dev/null" : o.csv);
  out << "case,method,h_ms,q_rms,q_max,ee_max,energy_drift,linear_momentum_drift,angular_momentum_drift,"
         "wall_s_per_sim_s,diverged,timing_runs\n";
  out.precision(10);
  for (const auto& name : o.which == "all" ? caseNames() : std::vector<std::string>{o.which})
    sweepCase(name, o, steps, out);
  return 0;
}
