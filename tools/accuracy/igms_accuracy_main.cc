// igms-accuracy: error against run time for igms's integrators and ODE.
//   igms-accuracy [--case NAME|all] [--quick] [--duration S] [--repeats N] [--csv FILE]
//                 [--reference DIR [--truth-csv FILE]] [--ensemble N --ensemble-csv FILE]
//   igms-accuracy --write-cases DIR [--quick] [--duration S]   the cases for scripts/reports/accuracy_peers.py
//   igms-accuracy --extreme [--quick] [--csv FILE]    the stiff and extreme cases' table
//   igms-accuracy --stiffness [--csv FILE]            the stability table alone (step matrices)
//   igms-accuracy --contact [--quick] [--csv FILE]    contact cases with analytic answers, igms and ODE
//   igms-accuracy --contact --write-cases DIR         those cases' scenes for scripts/bench/contact_peers.py
// For each case: igms's own ground truth is RK4 at h = 1/64 ms, checked against
// RK4 at 1/128 ms (the step-halving difference is printed). With --reference,
// the truth is the independent one in DIR (DOP853 on Pinocchio's ABA, written
// by scripts/reports/accuracy_peers.py) and igms's own is checked against it; every method then
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
#include "core/cli/round_trip.h"
#include "tools/accuracy/accuracy.h"
#include "tools/accuracy/contact_accuracy.h"
#include "tools/accuracy/ensemble.h"
#include "tools/accuracy/extreme_cases.h"
#include "tools/accuracy/independent_reference.h"
#include "tools/accuracy/step_matrix.h"

using namespace igms::accuracy;

namespace {

struct Options {
  std::string which = "all", csv, reference, truth_csv, write_cases, ensemble_csv;
  int ensemble = 0;
  bool quick = false, extreme = false, stiffness = false, contact = false;
  double duration = 0.0;
  int repeats = 3;
};

// A 0.1 kg body on a spring and damper at 1 ms: the amplitude factor per step
// (the step matrix's spectral radius) of each scheme, finely near the limits,
// undamped beside damped; then the limits themselves.
int stiffnessTable(const Options& o) {
  const std::vector<double> ratios = {0.5, 1, 2, 3, 3.5, 3.9, 3.99, 4.01, 4.1, 5, 6, 7, 7.5, 7.9, 7.99, 8.01, 8.1,
                                      10, 30, 100, 1e3, 1e4};
  const std::vector<double> zetas = {0.0, 0.1, 1.0};
  const char* names[3] = {"semi_implicit_euler", "rk4", "linearly_implicit"};
  std::ofstream out(o.csv.empty() ? "/dev/null" : o.csv);
  igms::cli::roundTripDigits(out);
  out << "k_h2_m,zeta,semi_implicit_euler,rk4,linearly_implicit,linearly_implicit_theory\n";
  std::printf("amplitude factor per step (spectral radius of one step; > 1: unstable), 0.1 kg at 1 ms\n");
  std::printf("%9s %9s %5s  %-14s %-14s %-14s %s\n", "k h^2/m", "k (N/m)", "zeta", names[0], names[1], names[2],
              "linearly implicit, theory (zeta 0)");
  for (double ratio : ratios) {
    for (double zeta : zetas) {
      double r[3];
      for (int m = 0; m < 3; ++m) r[m] = stepSpectralRadius(m, ratio, zeta);
      const double theory = zeta == 0 ? linearlyImplicitTheory(ratio) : NAN;
      out << ratio << "," << zeta << "," << r[0] << "," << r[1] << "," << r[2] << "," << theory << "\n";
      std::printf("%9.4g %9.4g %5.1f ", ratio, ratio * 0.1 / 1e-6, zeta);
      for (double x : r) std::printf(" %-8.6f %-5s", x, x > 1.0 + 1e-12 ? "UNST" : "");
      if (zeta == 0) std::printf(" %.6f", theory);
      std::printf("\n");
    }
  }
  for (double zeta : zetas) {
    const double sie = spectralStabilityLimit(0, zeta), rk4 = spectralStabilityLimit(1, zeta),
                 li = spectralStabilityLimit(2, zeta);
    out << "limit," << zeta << "," << sie << "," << rk4 << "," << li << ",\n";
    std::printf("stability limit of k h^2/m at zeta %.1f: semi-implicit Euler %.4f, RK4 %.4f, linearly implicit %s\n",
                zeta, sie, rk4, std::isinf(li) ? "none (stable at every k h^2/m up to 1e4)" : std::to_string(li).c_str());
  }
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

// A case with the run's duration (--duration, or 1.024 s with --quick).
Case caseFor(const std::string& name, const Options& o) {
  Case c = makeCase(name, IGMS_SOURCE_DIR);
  if (o.duration > 0) c.duration = o.duration;
  else if (o.quick) c.duration = 1.024;
  return c;
}

// Every method at every step on one case, against the truth (the independent
// one when --reference has it); one row of the truths' agreement.
void sweepCase(const std::string& name, const Options& o, const std::vector<double>& steps, std::ofstream& out,
               std::ofstream& truths) {
  const Case c = caseFor(name, o);
  const Run own = simulate(c, Method::Rk4, 1.0 / 64 * 1e-3);
  const Run check = simulate(c, Method::Rk4, 1.0 / 128 * 1e-3);
  const Errors halving = compare(c, check, own);
  std::printf("%s (%.2f s): igms's truth RK4 at 1/64 ms; step halving moves q by %.2e (max), so about %.0f digits\n",
              name.c_str(), c.duration, halving.q_max, -std::log10(std::max(halving.q_max, 1e-16)));
  Run truth = own;
  std::string reference = "none";
  double self_check = NAN;
  Errors agree;
  agree.q_max = agree.ee_max = NAN;
  if (!o.reference.empty() && hasReference(c, o.reference)) {
    Reference ref = readReference(c, o.reference);
    agree = compare(c, own, ref.run);
    std::printf("  independent truth: %s (against itself at 10x tighter tolerance: %.2e rad); igms's truth agrees to "
                "%.2e rad (max), %.2e m at the end effector. Errors below are against the independent truth.\n",
                ref.method.c_str(), ref.self_check_q_max, agree.q_max, agree.ee_max);
    reference = ref.method;
    self_check = ref.self_check_q_max;
    truth = std::move(ref.run);
  } else if (!o.reference.empty()) {
    std::printf("  no independent truth for this case in %s: errors below are against igms's truth\n",
                o.reference.c_str());
  }
  const double energy_rate = compare(c, truth, truth).energy_rate;
  truths << name << ",\"" << reference << "\"," << self_check << "," << halving.q_max << "," << agree.q_max << ","
         << agree.ee_max << "," << handStiffnessRatio(c) << "," << energy_rate << "\n";
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
          << "," << r.diverged << "," << walls.size() << "," << walls.front() / c.duration << ","
          << walls.back() / c.duration << "," << e.energy_rate << ",";
      for (size_t j = 0; j < e.per_joint.size(); ++j) out << (j ? ";" : "") << e.per_joint[j];
      out << "\n";
      std::printf("  %-20s h=%8.4f ms  q_max %-10.3g ee_max %-10.3g energy drift %-10.3g (%+.3g W) %s  %.3g s per s\n",
                  methodName(m), h * 1e3, e.q_max, e.ee_max, e.energy_drift, e.energy_rate,
                  r.diverged ? "DIVERGED" : "", cost);
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
  for (const auto& name : hapticCaseNames()) cases.push_back(name);
  cases.push_back("free");
  cases.push_back("haptic");
  cases.push_back("all");
  app.add_option("--case", o.which, "one case, free (the free motions), haptic (a hand on the PUMA) or all")->check(CLI::IsMember(cases));
  app.add_flag("--quick", o.quick, "0.25 .. 4 ms steps over 1.024 s (the extreme table: its short version)");
  app.add_option("--duration", o.duration, "simulated seconds per case (0: the case's own)")->check(igms::cli::Seconds);
  app.add_option("--repeats", o.repeats, "timing runs per row (median), for runs under 2 s")->check(CLI::Range(1, 100));
  app.add_option("--csv", o.csv, "also write the rows here");
  app.add_flag("--extreme", o.extreme, "the stiff and extreme cases' table (exit 1 when a row fails)");
  app.add_flag("--contact", o.contact, "the contact cases (analytic answers; igms and ODE, 0.25 .. 4 ms; exit 1 "
               "when igms misses a goal at 1 ms); with --write-cases, their scenes");
  app.add_flag("--stiffness", o.stiffness, "the stability table alone (each scheme's step matrix on a spring and damper)");
  app.add_option("--reference", o.reference,
                 "measure against the independent truth in DIR (<case>.truth.json, scripts/reports/accuracy_peers.py)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--truth-csv", o.truth_csv, "with --reference: how each truth agrees with the others, as CSV")
      ->needs("--reference");
  app.add_option("--ensemble", o.ensemble, "also N perturbed starts per case at 1 ms (q0 + U(-0.01, 0.01) rad "
                 "per joint): median and range")->check(CLI::Range(1, 1000));
  app.add_option("--ensemble-csv", o.ensemble_csv, "with --ensemble: its rows as CSV")->needs("--ensemble");
  app.add_option("--write-cases", o.write_cases, "write each case (URDF + JSON) into DIR for the independent "
                 "engines, and exit")->check(CLI::ExistingDirectory);
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  if (o.stiffness) return stiffnessTable(o);
  if (o.contact) return contactAccuracy({o.quick, o.repeats, o.csv, o.write_cases, IGMS_SOURCE_DIR});
  if (o.extreme) return extremeTable(o);
  std::vector<std::string> names;
  if (o.which == "free" || o.which == "all") names = caseNames();
  if (o.which == "haptic" || o.which == "all")
    for (const auto& name : hapticCaseNames()) names.push_back(name);
  if (names.empty()) names.push_back(o.which);
  if (!o.write_cases.empty()) {
    for (const auto& name : names) writeCaseFiles(caseFor(name, o), o.write_cases);
    std::printf("wrote %zu cases into %s\n", names.size(), o.write_cases.c_str());
    return 0;
  }
  std::vector<double> steps;
  for (double h = o.quick ? 0.25e-3 : 1.0 / 64 * 1e-3; h <= (o.quick ? 4e-3 : 32e-3) * 1.0001; h *= 2)
    steps.push_back(h);
  std::ofstream out(o.csv.empty() ? "/dev/null" : o.csv);
  out << "case,method,h_ms,q_rms,q_max,ee_max,energy_drift,linear_momentum_drift,angular_momentum_drift,"
         "wall_s_per_sim_s,diverged,timing_runs,wall_s_per_sim_s_min,wall_s_per_sim_s_max,energy_rate_w,"
         "q_max_per_joint\n";
  igms::cli::roundTripDigits(out);
  std::ofstream truths(o.truth_csv.empty() ? "/dev/null" : o.truth_csv);
  truths << "case,reference,reference_self_check_q_max,igms_truth_halving_q_max,igms_truth_vs_reference_q_max,"
            "igms_truth_vs_reference_ee_max,k_h2_over_m_at_1ms,truth_energy_rate_w\n";
  igms::cli::roundTripDigits(truths);
  for (const auto& name : names) sweepCase(name, o, steps, out, truths);
  if (o.ensemble > 0) {
    std::ofstream ens(o.ensemble_csv.empty() ? "/dev/null" : o.ensemble_csv);
    igms::cli::roundTripDigits(ens);
    ens << "case,method,h_ms,starts,diverged";
    for (const char* f : {"q_max", "q_rms", "ee_max", "energy_drift", "energy_rate_w"})
      ens << "," << f << "_median," << f << "_min," << f << "_max";
    ens << "\n";
    std::printf("ensembles at 1 ms: %d starts, q0 + U(-0.01, 0.01) rad per joint, each against its own RK4 truth\n",
                o.ensemble);
    for (const auto& name : names) {
      for (const EnsembleRow& r : ensemble(caseFor(name, o), o.ensemble, 0.01, 1e-3)) {
        ens << r.case_name << "," << r.method << ",1," << r.starts << "," << r.diverged;
        for (const Spread& x : {r.q_max, r.q_rms, r.ee_max, r.energy_drift, r.energy_rate})
          ens << "," << x.median << "," << x.min << "," << x.max;
        ens << "\n";
        std::printf("  %-20s %-20s q_max median %-10.3g [%.3g, %.3g]  energy drift median %-10.3g [%.3g, %.3g]%s\n",
                    r.case_name.c_str(), r.method.c_str(), r.q_max.median, r.q_max.min, r.q_max.max,
                    r.energy_drift.median, r.energy_drift.min, r.energy_drift.max,
                    r.diverged ? (" " + std::to_string(r.diverged) + " diverged").c_str() : "");
      }
    }
  }
  return 0;
}
