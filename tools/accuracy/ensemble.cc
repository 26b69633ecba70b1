#include "tools/accuracy/ensemble.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace igms::accuracy {
namespace {

Spread summarise(std::vector<double> x) {
  if (x.empty()) return {NAN, NAN, NAN};
  std::sort(x.begin(), x.end());
  const size_t n = x.size();
  const double median = n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
  return {median, x.front(), x.back()};
}

}  // namespace

std::vector<EnsembleRow> ensemble(const Case& nominal, int starts, double spread, double h, unsigned seed) {
  const Model& m = *nominal.model;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::vector<Method> methods = allMethods();
  std::vector<std::vector<Errors>> errors(methods.size());
  std::vector<int> diverged(methods.size(), 0);
  for (int s = 0; s < starts; ++s) {
    Case c = nominal;
    for (int i = 0; i < m.nb; ++i)
      if (m.joint_type[static_cast<size_t>(i)] != JointType::Floating) c.q0[m.q_index[static_cast<size_t>(i)]] += spread * unit(rng);
    const Run truth = simulate(c, Method::Rk4, 1.0 / 64 * 1e-3);
    for (size_t k = 0; k < methods.size(); ++k) {
      const Run r = simulate(c, methods[k], h);
      if (r.diverged) ++diverged[k];
      else errors[k].push_back(compare(c, r, truth));
    }
  }
  std::vector<EnsembleRow> rows;
  for (size_t k = 0; k < methods.size(); ++k) {
    auto field = [&](double Errors::*f) {
      std::vector<double> x;
      for (const Errors& e : errors[k])
        if (!std::isnan(e.*f)) x.push_back(e.*f);
      return summarise(x);
    };
    rows.push_back({nominal.name, methodName(methods[k]), starts, diverged[k], field(&Errors::q_max),
                    field(&Errors::q_rms), field(&Errors::ee_max), field(&Errors::energy_drift),
                    field(&Errors::energy_rate)});
  }
  return rows;
}

}  // namespace igms::accuracy
