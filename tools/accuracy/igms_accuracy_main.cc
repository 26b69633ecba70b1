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
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <algorithm>

#include "tools/accuracy/accuracy.h"
#include "tools/accuracy/extreme_cases.h"
#include "tools/accuracy/stiffness.h"

using namespace igms::accuracy;

int main(int argc, char** argv) {
  std::string which = "all", csv;
  bool quick = false, extreme = false;
  double duration = 0.0;
  int repeats = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--case" && i + 1 < argc) which = argv[++i];
    else if (a == "--quick") quick = true;
    else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
    else if (a == "--duration" && i + 1 < argc) duration = std::atof(argv[++i]);
    else if (a == "--repeats" && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
    else if (a == "--extreme") extreme = true;
    else if (a == "--stiffness") {
      // A 0.1 kg body on springs of 1e2 .. 1e7 N/m at 1 ms.
      std::vector<double> ks;
      for (double k = 100; k <= 1.01e7; k *= std::sqrt(10.0)) ks.push_back(k);
      std::printf("%12s %10s  %-28s %-28s %-28s\n", "k (N/m)", "k h^2/m", "semi-implicit Euler", "RK4",
                  "linearly implicit");
      double largest[3] = {0, 0, 0};
      for (const auto& r : stiffnessSweep(0.1, 1e-3, ks)) {
        std::printf("%12.3g %10.3g", r.k, r.k_h2_m);
        for (int m = 0; m < 3; ++m) {
          std::printf("  %-8s E/E0 max %-12.3g", r.stable[m] ? "stable" : "UNSTABLE", r.energy_ratio[m]);
          if (r.stable[m]) largest[m] = r.k;
        }
        std::printf("\n");
      }
      std::printf("largest stable k at 1 ms on 0.1 kg: semi-implicit Euler %.3g N/m, RK4 %.3g N/m, linearly implicit %.3g N/m\n",
                  largest[0], largest[1], largest[2]);
      std::printf("measured stability limit of k h^2/m: semi-implicit Euler %.3f (theory 4), RK4 %.3f (theory (2 sqrt 2)^2 = 8)\n",
                  stabilityLimit(0, 0.1, 1e-3), stabilityLimit(1, 0.1, 1e-3));
      return 0;
    }
    else {
      std::fprintf(stderr,
                   "usage: igms-accuracy [--case NAME|all] [--quick] [--duration S] [--repeats N] [--csv FILE]\n"
                   "       igms-accuracy --extreme [--quick] [--csv FILE]\n"
                   "       igms-accuracy --stiffness\n");
      return 2;
    }
  }
  if (extreme) {
    const auto rows = extremeCases(IGMS_SOURCE_DIR, quick);
    std::ofstream out(csv.empty() ? "/dev/null" : csv);
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
  std::vector<double> steps;
  for (double h = quick ? 0.25e-3 : 1.0 / 64 * 1e-3; h <= (quick ? 4e-3 : 32e-3) * 1.0001; h *= 2) steps.push_back(h);
  std::ofstream out(csv.empty() ? "/dev/null" : csv);
  out << "case,method,h_ms,q_rms,q_max,ee_max,energy_drift,linear_momentum_drift,angular_momentum_drift,"
         "wall_s_per_sim_s,diverged,timing_runs\n";
  out.precision(10);
  const std::vector<std::string> cases = which == "all" ? caseNames() : std::vector<std::string>{which};
  for (const auto& name : cases) {
    Case c = makeCase(name, IGMS_SOURCE_DIR);
    if (duration > 0) c.duration = duration;
    else if (quick) c.duration = 1.024;
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
        while (r.wall_seconds < 2.0 && static_cast<int>(walls.size()) < repeats)
          walls.push_back(simulate(c, m, h).wall_seconds);
        std::sort(walls.begin(), walls.end());
        const double cost = walls[walls.size() / 2] / c.duration;
        out << name << "," << methodName(m) << "," << h * 1e3 << "," << e.q_rms << "," << e.q_max << "," << e.ee_max
            << "," << e.energy_drift << "," << e.linear_momentum_drift << "," << e.angular_momentum_drift << ","
            << cost << "," << r.diverged << "," << walls.size() << "\n";
        std::printf("  %-20s h=%8.4f ms  q_max %-10.3g ee_max %-10.3g energy drift %-10.3g %s  %.3g s per s\n",
                    methodName(m), h * 1e3, e.q_max, e.ee_max, e.energy_drift, r.diverged ? "DIVERGED" : "", cost);
      }
    }
  }
  return 0;
}
