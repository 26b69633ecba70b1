// The same articulated body in ODE 0.16, the independent reference simulator:
// one ODE body per igms body (links merged through fixed joints), placed at
// its centre of mass with the same mass and inertia; hinge and slider joints
// with the same world anchors and axes; the root fixed to the world or free.
// ODE integrates in maximal coordinates with constraint stabilisation, a
// method independent of igms's reduced-coordinate recursions.
//
// Honest settings: CFM 1e-10 (rigid joints; ODE's default 1e-5 is soft), ERP
// 0.2 (ODE's default drift correction), no damping but the joint damping we
// apply ourselves as explicit torques -d qdot, no velocity clamping, no
// auto-disable. ODE needs positive mass and definite inertia. A body hinged to
// the world without them (PUMA link 1 has no mass, only a rotor inertia) gets
// 1 kg on its axis and inertia across it, which leaves the motion unchanged;
// any other gets 1e-6 kg and 1e-9 kg m^2 added. regularised() says which.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/model/data.h"

namespace igms {

struct OdeSettings {
  bool quickstep = false;       // dWorldQuickStep (iterative) instead of dWorldStep (exact LCP)
  int quickstep_iterations = 100;  // ODE's SOR over-relaxation stays at its default, 1.3
  unsigned long quickstep_seed = 1;  // the seed of QuickStep's constraint reordering (dRandSetSeed)
  double erp = 0.2;
  double cfm = 1e-10;
  bool joint_damping = false;   // apply -d qdot from the model's damping
};

class OdeRobot {
 public:
  OdeRobot(const Model& model, const VectorX& q0, const VectorX& v0, const OdeSettings& settings = {});
  ~OdeRobot();
  OdeRobot(const OdeRobot&) = delete;
  OdeRobot& operator=(const OdeRobot&) = delete;

  // One step of h seconds with joint torques tau (size nv; a floating base's
  // first 6 entries, its wrench, are applied to the base body in its frame).
  void step(const VectorX& tau, double h);
  // A force at a world point on body i, world axes, for the next step only
  // (ODE clears accumulated forces after each step).
  void addForceAtPoint(int body, const Vector3& point, const Vector3& force);
  // A moment on body i, world axes, N m, for the next step only.
  void addTorque(int body, const Vector3& torque);
  // Reduced coordinates read back from ODE (joint angles unwrapped).
  void state(VectorX& q, VectorX& v) const;
  // World pose of body i's frame (not its centre of mass).
  SE3 bodyPose(int i) const;
  // From ODE's own bodies (maximal coordinates): kinetic energy, kinetic plus
  // potential energy, and spatial momentum about the world origin [linear; angular].
  double kineticEnergy() const;
  double totalEnergy() const;
  Vector6 momentum() const;
  const std::vector<std::string>& regularised() const { return regularised_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::string> regularised_;
};

}  // namespace igms
