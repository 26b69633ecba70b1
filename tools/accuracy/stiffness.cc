#include "tools/accuracy/stiffness.h"

#include <cmath>
#include <string>

#include "core/integrate/integrators.h"
#include "core/integrate/passive_joint_dynamics.h"
#include "core/model/robot_description.h"
#include "core/model_io/urdf_loader.h"

namespace igms::accuracy {

namespace {
// The order of StiffnessResult's columns.
constexpr IntegratorKind kSchemes[] = {IntegratorKind::SemiImplicitEuler, IntegratorKind::Rk4,
                                       IntegratorKind::LinearlyImplicit};
}  // namespace

std::vector<StiffnessResult> stiffnessSweep(double mass, double h, const std::vector<double>& ks, double seconds) {
  const std::string urdf =
      "<robot name=\"slider\"><link name=\"base\"/><link name=\"body\"><inertial><mass value=\"" +
      std::to_string(mass) +
      "\"/><inertia ixx=\"1e-5\" ixy=\"0\" ixz=\"0\" iyy=\"1e-5\" iyz=\"0\" izz=\"1e-5\"/></inertial></link>"
      "<joint name=\"slide\" type=\"prismatic\"><parent link=\"base\"/><child link=\"body\"/><axis xyz=\"1 0 0\"/>"
      "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>";
  BuildOptions o;
  o.gravity = Vector3::Zero();
  const Model m = buildModel(parseUrdfDescription(urdf), o);
  std::vector<StiffnessResult> out;
  for (double k : ks) {
    StiffnessResult r{k, k * h * h / mass, {false, false, false}, {0, 0, 0}};
    for (int method = 0; method < 3; ++method) {
      PassiveJointDynamics f(m, /*joint_damping=*/false, k);
      IntegratorScratch<PassiveJointDynamics::Evaluation> s(m, f);
      VectorX q = VectorX::Constant(1, 0.001), v = VectorX::Zero(1);
      const double E0 = 0.5 * k * q[0] * q[0];
      double worst = 1.0;
      const int n = static_cast<int>(seconds / h);
      for (int i = 0; i < n; ++i) {
        integrateStep(kSchemes[method], m, f, q, v, h, s);
        const double E = 0.5 * k * q[0] * q[0] + 0.5 * mass * v[0] * v[0];
        if (!std::isfinite(E) || E > 1e12 * E0) {
          worst = INFINITY;
          break;
        }
        worst = std::max(worst, E / E0);
      }
      r.energy_ratio[method] = worst;
      // Semi-implicit Euler's energy oscillates by O(k h^2 / m) even when stable;
      // its bound is boundedness. RK4 and the implicit scheme must be passive.
      r.stable[method] = method == 0 ? std::isfinite(worst) && worst < 100.0 : worst <= 1.01;
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace igms::accuracy

namespace igms::accuracy {

double stabilityLimit(int method, double mass, double h, double seconds) {
  double lo = 0.1, hi = 100.0;  // in k h^2 / m
  for (int it = 0; it < 40; ++it) {
    const double mid = std::sqrt(lo * hi);
    const auto r = stiffnessSweep(mass, h, {mid * mass / (h * h)}, seconds);
    if (std::isfinite(r[0].energy_ratio[method])) lo = mid;
    else hi = mid;
  }
  return lo;
}

}  // namespace igms::accuracy
