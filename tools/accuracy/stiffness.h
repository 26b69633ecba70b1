// Stiff couplings: a light body on a spring of stiffness k (what a pull spring
// or a push contact makes of a light link), integrated at h by each method.
// Stable = bounded and passive (the spring's energy never exceeds its start
// by more than 1 %), as the haptic coupling needs.
#pragma once

#include <vector>

namespace igms::accuracy {

struct StiffnessResult {
  double k;        // N/m
  double k_h2_m;   // the dimensionless stiffness k h^2 / m
  bool stable[3];  // semi-implicit Euler, RK4, linearly implicit
  double energy_ratio[3];  // largest E(t) / E(0)
};

// mass in kg, h in s; ks in N/m.
std::vector<StiffnessResult> stiffnessSweep(double mass, double h, const std::vector<double>& ks, double seconds = 1.0);

// The measured stability limit of k h^2 / m (bisection on blow-up within
// `seconds`) for method 0 (semi-implicit Euler) or 1 (RK4). Theory: 4 and (2 sqrt 2)^2 = 8.
double stabilityLimit(int method, double mass, double h, double seconds = 2.0);

}  // namespace igms::accuracy
