// Error against run time: igms's integrators and ODE on the same cases, over
// a sweep of step sizes, against a ground truth (igms RK4 at a tiny step,
// confirmed by step halving).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/integrate/integrator_kind.h"
#include "core/model/data.h"
#include "core/simulation/coupled_dynamics.h"

namespace igms::accuracy {

// A hand held still on the robot for a whole case, through the server's own
// step (Simulation: eq. 4's pull spring to the device point, or eq. 3's push
// of the device tip into a link), uncapped: the cases haptics lives on.
struct HandCoupling {
  InteractionMode mode = InteractionMode::None;  // None: the robot moves freely
  std::string link;                 // pull: the attachment link; push: the pushed link
  Vector3 point = Vector3::Zero();  // pull: the attachment point in the link frame
  Vector3 tip = Vector3::Zero();    // the device point (pull) or tip centre (push), world
  double k = 0.0, b = 0.0;          // N/m, N s/m (push: k_p, no damping)
  double tip_radius = 0.01;         // m, push
};

struct Case {
  std::string name;
  std::shared_ptr<const Model> model;
  VectorX q0, v0;
  double duration = 1.024;       // s, a multiple of the largest step (32 ms)
  bool damping = false;          // the model's joint damping
  std::string ee_frame;
  std::string urdf;              // the model's URDF text (what an independent engine loads)
  std::string model_path;        // the URDF file (a hand's cases run a scene on it)
  HandCoupling hand;
};

// "puma_swing", "puma_swing_damped", "chain30", "tumble" (a floating body in zero g);
// a hand on the PUMA: "puma_pull_k<K>" (undamped spring, N/m), "puma_pull_k<K>_b<B>",
// "puma_push_k<K>" (penalty contact on link 3).
Case makeCase(const std::string& name, const std::string& source_dir);
std::vector<std::string> caseNames();        // the free cases
std::vector<std::string> hapticCaseNames();  // the hand's cases: k from a PHANToM's 0.4 N/mm to 32 N/mm

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

constexpr double kSamplePeriod = 0.032;  // s: every run is sampled here (the largest step divides it)

// A run sampled every 32 ms.
struct Run {
  std::vector<VectorX> q;         // at t = 0, 32 ms, 64 ms, ...
  std::vector<Vector3> ee;
  std::vector<double> energy;     // kinetic + potential (+ the hand's spring)
  std::vector<Vector6> momentum;  // spatial momentum about the world origin (tumble)
  double wall_seconds = 0.0;      // run time of the simulation itself
  bool diverged = false;
};

Run simulate(const Case& c, Method m, double h);

// The hand's spring energy (1/2 k |stretch|^2 or 1/2 k_p d^2) at the kinematics
// d holds (forwardKinematics at q); 0 for a free case.
double handEnergy(const Case& c, const Data& d);
// k h^2 / m at q0 and 1 ms, m the arm's effective mass at the hand in its
// lightest direction (pull: the spring acts in all three) or along the contact
// normal (push): the stiffest mode the integrator meets.
double handStiffnessRatio(const Case& c, double h = 1e-3);

struct Errors {
  double q_rms = 0, q_max = 0, ee_max = 0, energy_drift = 0;
  double energy_rate = 0;  // W: (E(end) - E(0)) / duration, injected (> 0) or dissipated
  std::vector<double> per_joint;  // max error per body's joint, in body order (a floating base: m, then rad)
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
