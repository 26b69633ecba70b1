// A scene of free bodies in ODE 0.16, the independent reference for contact:
// the scene's free bodies (box, sphere, cylinder, capsule as ODE's own; a mesh,
// or any kind ODE lacks, as a trimesh of its surface) as ODE bodies at
// their centres of mass with the same mass and inertia, its ground plane and
// solid obstacles as static geoms, ODE's own collision (dCollide) and its hard
// contact (an LCP per step with dWorldStep, Dantzig's method; or QuickStep's
// iterations). ODE's traps, set as its documentation asks (ENVIRONMENT_NOTES):
// dContactApprox1, so that mu is a coefficient and not a force; fdir1 along each
// contact's slip, so that its two-direction pyramid is not anisotropic; ERP
// and CFM set explicitly (0.2 and 1e-10 by default: rigid); restitution by
// dContactBounce above the scene's bounce_velocity. Robots are not included:
// OdeRobot (ode_robot.h) is the articulated reference.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/scene/resolved_scene.h"

namespace igms {

struct OdeContactSettings {
  bool quickstep = false;
  int quickstep_iterations = 100;
  double erp = 0.2;
  double cfm = 1e-10;
  int max_points = 8;  // per pair, what dCollide may return
};

class OdeContactScene {
 public:
  // Throws std::invalid_argument for a scene ODE cannot take here (robots, a mesh read without its
  // triangles, a body whose centre of mass is off its shape's origin).
  explicit OdeContactScene(const ResolvedScene& scene, const OdeContactSettings& settings = {});
  ~OdeContactScene();
  OdeContactScene(const OdeContactScene&) = delete;
  OdeContactScene& operator=(const OdeContactScene&) = delete;

  void step(double h);
  int bodies() const;
  const std::string& name(int body) const;
  // Body k's frame (its centre of mass: the shapes' centres) in the world, and its velocities, world.
  SE3 pose(int body) const;
  Vector3 velocity(int body) const;
  Vector3 angularVelocity(int body) const;
  int contactsLastStep() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace igms
