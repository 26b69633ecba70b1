#include "tools/accuracy/step_matrix.h"

#include <cmath>
#include <complex>
#include <limits>
#include <string>

#include "core/integrate/integrators.h"
#include "core/integrate/passive_joint_dynamics.h"
#include "core/model/robot_description.h"
#include "core/model_io/urdf_loader.h"

namespace igms::accuracy {
namespace {

constexpr IntegratorKind kSchemes[] = {IntegratorKind::SemiImplicitEuler, IntegratorKind::Rk4,
                                       IntegratorKind::LinearlyImplicit};

Model slider(double mass, double b) {
  char urdf[1024];
  std::snprintf(urdf, sizeof urdf,
                "<robot name=\"slider\"><link name=\"base\"/><link name=\"body\"><inertial><mass value=\"%.17g\"/>"
                "<inertia ixx=\"1e-5\" ixy=\"0\" ixz=\"0\" iyy=\"1e-5\" iyz=\"0\" izz=\"1e-5\"/></inertial></link>"
                "<joint name=\"slide\" type=\"prismatic\"><parent link=\"base\"/><child link=\"body\"/>"
                "<axis xyz=\"1 0 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>"
                "<dynamics damping=\"%.17g\"/></joint></robot>",
                mass, b);
  BuildOptions o;
  o.gravity = Vector3::Zero();
  return buildModel(parseUrdfDescription(urdf), o);
}

}  // namespace

double stepSpectralRadius(int method, double ratio, double zeta, double mass, double h) {
  const double k = ratio * mass / (h * h), b = 2.0 * zeta * std::sqrt(k * mass);
  const Model m = slider(mass, b);
  PassiveJointDynamics f(m, /*joint_damping=*/b > 0, k);
  IntegratorScratch<PassiveJointDynamics::Evaluation> s(m, f);
  double A[2][2];
  for (int col = 0; col < 2; ++col) {
    VectorX q = VectorX::Constant(1, col == 0 ? 1.0 : 0.0), v = VectorX::Constant(1, col == 1 ? 1.0 : 0.0);
    integrateStep(kSchemes[method], m, f, q, v, h, s);
    A[0][col] = q[0];
    A[1][col] = v[0];
  }
  // Eigenvalues of [[a, b], [c, d]] (the units of x and xdot do not change them).
  const double tr = A[0][0] + A[1][1], det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
  const std::complex<double> root = std::sqrt(std::complex<double>(tr * tr / 4 - det, 0.0));
  return std::max(std::abs(tr / 2 + root), std::abs(tr / 2 - root));
}

double spectralStabilityLimit(int method, double zeta, double mass, double h) {
  double lo = 0.01, hi = 1e4;
  if (stepSpectralRadius(method, hi, zeta, mass, h) <= 1.0 + 1e-12) return std::numeric_limits<double>::infinity();
  for (int it = 0; it < 60; ++it) {
    const double mid = std::sqrt(lo * hi);
    (stepSpectralRadius(method, mid, zeta, mass, h) <= 1.0 + 1e-12 ? lo : hi) = mid;
  }
  return lo;
}

double linearlyImplicitTheory(double ratio) { return 1.0 / std::sqrt(1.0 + ratio); }

}  // namespace igms::accuracy
