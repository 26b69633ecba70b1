// igms-accuracy: error against run time for igms's integrators and ODE.
//   igms-accuracy [--case NAME|all] [--quick] [--duration S] [--csv FILE]
// For each case: the ground truth is igms RK4 at h = 1/64 ms, checked against
// RK4 at 1/128 ms (the step-halving difference is printed); every method then
// runs at h = 1/64 ms ... 32 ms (doubling; --quick: 0.25 ms ... 4 ms) and each
// row gives its errors against the truth and its run time per simulated second.
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "tools/accuracy/accuracy.h"

using namespace igms::accuracy;

int main(int argc, char** argv) {
  std::string which = "all", csv;
  bool quick = false;
  double duration = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--case" && i + 1 < argc) which = argv[++i];
    else if (a == "--quick") quick = true;
    else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
    else if (a == "--duration" && i + 1 < argc) duration = std::atof(argv[++i]);
    else {
      std::fprintf(stderr, "usage: igms-accuracy [--case NAME|all] [--quick] [--duration S] [--csv FILE]\n");
      return 2;
    }
  }
  std::vector<double> steps;
  for (double h = quick ? 0.25e-3 : 1.0 / 64 * 1e-3; h <= (quick ? 4e-3 : 32e-3) * 1.0001; h *= 2) steps.push_back(h);
  std::ofstream out(csv.empty() ? "/dev/null" : csv);
  out << "case,method,h_ms,q_rms,q_max,ee_max,energy_drift,linear_momentum_drift,angular_momentum_drift,"
         "wall_s_per_sim_s,diverged\n";
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
        const double cost = r.wall_seconds / c.duration;
        out << name << "," << methodName(m) << "," << h * 1e3 << "," << e.q_rms << "," << e.q_max << "," << e.ee_max
            << "," << e.energy_drift << "," << e.linear_momentum_drift << "," << e.angular_momentum_drift << ","
            << cost << "," << r.diverged << "\n";
        std::printf("  %-20s h=%8.4f ms  q_max %-10.3g ee_max %-10.3g energy drift %-10.3g %s  %.3g s per s\n",
                    methodName(m), h * 1e3, e.q_max, e.ee_max, e.energy_drift, r.diverged ? "DIVERGED" : "", cost);
      }
    }
  }
  return 0;
}
