// Error against run time: igms's integrators and ODE on the same cases, over
// a sweep of step sizes, against a ground truth (igms RK4 at a tiny step,
// confirmed by step halving).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/integrate/integrator_kind.h"
#include "core/model/data.h"

namespace igms::accuracy {

struct Case {
  std::string name;
  std::shared_ptr<const Model> model;
  VectorX q0, v0;
  double duration = 1.024;       // s, a multiple of the largest step (32 ms)
  bool damping = false;          // the model's joint damping
  std::string ee_frame;
};

// "puma_swing", "puma_swing_damped", "chain30", "tumble" (a floating body in zero g).
Case makeCase(const std::string& name, const std::string& source_dir);
std::vector<std::string> caseNames();

enum class Method { SemiImplicitEuler, Rk4, LinearlyImplicit, Ode, OdeQuick };
const char* methodName(Method m);
// igms's own schemes by their integrator; ODE's are not (isOde).
inline bool isOde(Method m) { return m == Method::Ode || m == Method::OdeQuick; }
inline IntegratorKind integratorOf(Method m) {
  return m == Method::SemiImplicitEuler ? IntegratorKind::SemiImplicitEuler
         : m == Method::Rk4             ? IntegratorKind::Rk4
                                        : IntegratorKind::LinearlyImplicit;
}
std::vector<Method> allMethods();

// A run sampled every 32 ms (the largest step divides it).
struct Run {
  std::vector<VectorX> q;         // at t = 0, 32 ms, 64 ms, ...
  std::vector<Vector3> ee;
  std::vector<double> energy;     // kinetic + potential
  std::vector<Vector6> momentum;  // spatial momentum about the world origin (tumble)
  double wall_seconds = 0.0;      // run time of the simulation itself
  bool diverged = false;
};

Run simulate(const Case& c, Method m, double h);

struct Errors {
  double q_rms = 0, q_max = 0, ee_max = 0, energy_drift = 0;
  double linear_momentum_drift = 0, angular_momentum_drift = 0;  // relative to the initial momenta
  // energy_drift is NaN for a damped case, the momentum drifts for a case
  // under gravity or on a fixed base: they are not conserved there.
};
Errors compare(const Case& c, const Run& run, const Run& truth);

// Kinetic plus potential energy; spatial momentum [linear; angular] about the
// world origin, world axes.
double mechanicalEnergy(const Model& m, Data& d, const VectorX& q, const VectorX& v);
Vector6 spatialMomentum(const Model& m, Data& d, const VectorX& q, const VectorX& v);
// Every coordinate finite and below 1e10: the divergence test of every sweep.
bool finiteAndBounded(const VectorX& q, const VectorX& v);

}  // namespace igms::accuracy
