#include "tools/ode_ref/ode_robot.h"

#include <ode/ode.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <mutex>

#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"

namespace igms {
namespace {

std::once_flag g_ode_init;

void toOde(const Matrix3& R, dMatrix3 m) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = R(r, c);
    m[4 * r + 3] = 0.0;
  }
}

Matrix3 fromOde(const dReal* m) {
  Matrix3 R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = m[4 * r + c];
  return R;
}

// A body's mass, inertia about its centre in world axes, centre, and velocities.
struct BodyState {
  double mass;
  Matrix3 I_world;
  Vector3 x, v, w;
};

BodyState bodyState(dBodyID b) {
  dMass m;
  dBodyGetMass(b, &m);
  Matrix3 I;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) I(r, c) = m.I[4 * r + c];
  const Matrix3 R = fromOde(dBodyGetRotation(b));
  const dReal* p = dBodyGetPosition(b);
  const dReal* lv = dBodyGetLinearVel(b);
  const dReal* av = dBodyGetAngularVel(b);
  return {m.mass, R * I * R.transpose(), Vector3(p[0], p[1], p[2]), Vector3(lv[0], lv[1], lv[2]),
          Vector3(av[0], av[1], av[2])};
}

}  // namespace

struct OdeRobot::Impl {
  const Model& model;
  OdeSettings settings;
  dWorldID world = nullptr;
  std::vector<dBodyID> bodies;
  std::vector<dJointID> joints;   // per body; nullptr for a free root
  std::vector<Vector3> com;       // centre of mass in the body frame
  std::vector<double> q0;         // coordinates at build time (ODE measures from there)
  mutable std::vector<double> last_angle, turns;  // unwrapping of hinge angles
  Impl(const Model& m, const OdeSettings& s) : model(m), settings(s) {}
};

OdeRobot::OdeRobot(const Model& model, const VectorX& q0, const VectorX& v0, const OdeSettings& settings)
    : impl_(std::make_unique<Impl>(model, settings)) {
  std::call_once(g_ode_init, [] { dInitODE2(0); });
  Impl& s = *impl_;
  s.world = dWorldCreate();
  dWorldSetGravity(s.world, model.gravity.x(), model.gravity.y(), model.gravity.z());
  dWorldSetERP(s.world, settings.erp);
  dWorldSetCFM(s.world, settings.cfm);
  dWorldSetQuickStepNumIterations(s.world, settings.quickstep_iterations);
  // QuickStep reorders its constraints at random each step: a fixed seed per
  // robot makes its runs repeatable.
  dRandSetSeed(settings.quickstep_seed);
  dWorldSetAutoDisableFlag(s.world, 0);
  dWorldSetMaxAngularSpeed(s.world, dInfinity);
  Data data(model);
  rnea(model, data, q0, v0, VectorX::Zero(model.nv));  // body velocities at (q0, v0)
  bodyKinematics(model, data, q0);
  s.q0.assign(q0.data(), q0.data() + q0.size());
  s.last_angle.assign(static_cast<size_t>(model.nb), 0.0);
  s.turns.assign(static_cast<size_t>(model.nb), 0.0);
  for (int i = 0; i < model.nb; ++i) {
    const SpatialInertia& I = model.inertia[i];
    double mass = I.m;
    Vector3 c = I.com();
    Matrix3 Ic = I.inertiaAboutCom();
    const double smallest = Eigen::SelfAdjointEigenSolver<Matrix3>(Ic).eigenvalues().minCoeff();
    const bool hinged_to_world = model.parent[i] < 0 && model.joint_type[i] == JointType::Revolute;
    if (hinged_to_world && (!(mass > 0.0) || !(smallest > 0.0))) {
      // A body hinged to the world turns about a fixed axis: mass on that axis
      // and inertia about axes across it meet only the hinge's reaction, so
      // 1 kg there and the axial inertia across it leave the motion exactly as
      // it is while giving ODE's solvers a well-conditioned body (1e-6 kg
      // made QuickStep fail on the PUMA's massless link 1).
      const Vector3& a = model.axis[i];
      const double axial = std::max(a.dot(Ic * a), 1e-3);
      if (!(mass > 0.0)) {
        mass = 1.0;
        c = a * a.dot(c);  // the com of nothing: put the added mass on the axis
        regularised_.push_back(model.body_name[i] + " (1 kg on its fixed axis: no effect on the motion)");
      } else {
        regularised_.push_back(model.body_name[i] + " (inertia across its fixed axis: no effect on the motion)");
      }
      Ic += axial * (Matrix3::Identity() - a * a.transpose());
    } else if (!(mass > 0.0) || !(smallest > 0.0)) {
      regularised_.push_back(model.body_name[i] + " (1e-6 kg and 1e-9 kg m^2 added: a small distortion)");
      if (!(mass > 0.0)) mass = 1e-6;
      Ic += 1e-9 * Matrix3::Identity();
    }
    dBodyID b = dBodyCreate(s.world);
    dMass m;
    dMassSetParameters(&m, mass, 0, 0, 0, Ic(0, 0), Ic(1, 1), Ic(2, 2), Ic(0, 1), Ic(0, 2), Ic(1, 2));
    dBodySetMass(b, &m);
    dBodySetGyroscopicMode(b, 1);
    const SE3& X = data.oMi[i];
    const Vector3 p = X.act(c);
    dBodySetPosition(b, p.x(), p.y(), p.z());
    dMatrix3 R;
    toOde(X.R, R);
    dBodySetRotation(b, R);
    // Velocity of the centre of mass and angular velocity, world axes.
    const Motion& v = data.v[i];
    const Vector3 w = X.R * v.w, vc = X.R * (v.v + v.w.cross(c));
    dBodySetLinearVel(b, vc.x(), vc.y(), vc.z());
    dBodySetAngularVel(b, w.x(), w.y(), w.z());
    s.bodies.push_back(b);
    s.com.push_back(c);
    // The joint to the parent body (or to the world), at the same anchor and axis.
    const int p_body = model.parent[i];
    dBodyID parent = p_body >= 0 ? s.bodies[static_cast<size_t>(p_body)] : nullptr;
    dJointID j = nullptr;
    const Vector3 anchor = X.p, axis = X.R * model.axis[i];
    switch (model.joint_type[i]) {
      case JointType::Revolute:
        j = dJointCreateHinge(s.world, nullptr);
        dJointAttach(j, b, parent);
        dJointSetHingeAnchor(j, anchor.x(), anchor.y(), anchor.z());
        dJointSetHingeAxis(j, axis.x(), axis.y(), axis.z());
        break;
      case JointType::Prismatic:
        j = dJointCreateSlider(s.world, nullptr);
        dJointAttach(j, b, parent);
        dJointSetSliderAxis(j, axis.x(), axis.y(), axis.z());
        break;
      case JointType::Floating: break;  // a free body
    }
    s.joints.push_back(j);
  }
}

OdeRobot::~OdeRobot() {
  if (impl_->world) dWorldDestroy(impl_->world);
}

void OdeRobot::step(const VectorX& tau, double h) {
  Impl& s = *impl_;
  const Model& m = s.model;
  VectorX q(m.nq), v(m.nv);
  if (s.settings.joint_damping) state(q, v);
  for (int i = 0; i < m.nb; ++i) {
    const int iv = m.v_index[i];
    double t = tau[iv];
    if (s.settings.joint_damping && m.joint_type[i] != JointType::Floating) t -= m.damping[iv] * v[iv];
    switch (m.joint_type[i]) {
      case JointType::Revolute: dJointAddHingeTorque(s.joints[i], t); break;
      case JointType::Prismatic: dJointAddSliderForce(s.joints[i], t); break;
      case JointType::Floating: {
        // The base wrench [f; n] about the base frame origin, in base axes.
        const SE3 X = bodyPose(i);
        const Vector3 f = X.R * tau.segment<3>(iv), n = X.R * tau.segment<3>(iv + 3);
        dBodyAddForceAtPos(s.bodies[i], f.x(), f.y(), f.z(), X.p.x(), X.p.y(), X.p.z());
        dBodyAddTorque(s.bodies[i], n.x(), n.y(), n.z());
        break;
      }
    }
  }
  if (s.settings.quickstep) dWorldQuickStep(s.world, h);
  else dWorldStep(s.world, h);
}

void OdeRobot::addForceAtPoint(int body, const Vector3& point, const Vector3& force) {
  dBodyAddForceAtPos(impl_->bodies[static_cast<size_t>(body)], force.x(), force.y(), force.z(), point.x(), point.y(),
                     point.z());
}

void OdeRobot::addTorque(int body, const Vector3& torque) {
  dBodyAddTorque(impl_->bodies[static_cast<size_t>(body)], torque.x(), torque.y(), torque.z());
}

SE3 OdeRobot::bodyPose(int i) const {
  const Impl& s = *impl_;
  const dReal* p = dBodyGetPosition(s.bodies[i]);
  const Matrix3 R = fromOde(dBodyGetRotation(s.bodies[i]));
  return {R, Vector3(p[0], p[1], p[2]) - R * s.com[i]};
}

void OdeRobot::state(VectorX& q, VectorX& v) const {
  const Impl& s = *impl_;
  const Model& m = s.model;
  q.resize(m.nq);
  v.resize(m.nv);
  for (int i = 0; i < m.nb; ++i) {
    const int iq = m.q_index[i], iv = m.v_index[i];
    switch (m.joint_type[i]) {
      case JointType::Revolute: {
        // ODE's angle is in (-pi, pi] from the build pose: unwrap it.
        const double a = dJointGetHingeAngle(s.joints[i]);
        double d = a - s.last_angle[i];
        if (d > M_PI) s.turns[i] -= 2 * M_PI;
        if (d < -M_PI) s.turns[i] += 2 * M_PI;
        s.last_angle[i] = a;
        q[iq] = s.q0[static_cast<size_t>(iq)] + a + s.turns[i];
        v[iv] = dJointGetHingeAngleRate(s.joints[i]);
        break;
      }
      case JointType::Prismatic:
        q[iq] = s.q0[static_cast<size_t>(iq)] + dJointGetSliderPosition(s.joints[i]);
        v[iv] = dJointGetSliderPositionRate(s.joints[i]);
        break;
      case JointType::Floating: {
        const SE3 X = bodyPose(i);
        const Eigen::Quaterniond quat(X.R);
        q.segment<3>(iq) = X.p;
        q[iq + 3] = quat.w(); q[iq + 4] = quat.x(); q[iq + 5] = quat.y(); q[iq + 6] = quat.z();
        const dReal* lv = dBodyGetLinearVel(s.bodies[i]);
        const dReal* av = dBodyGetAngularVel(s.bodies[i]);
        const Vector3 w(av[0], av[1], av[2]);
        const Vector3 vcom(lv[0], lv[1], lv[2]);
        const Vector3 v_origin = vcom - w.cross(X.R * s.com[i]);  // origin velocity, world
        v.segment<3>(iv) = X.R.transpose() * v_origin;
        v.segment<3>(iv + 3) = X.R.transpose() * w;
        break;
      }
    }
  }
}

double OdeRobot::kineticEnergy() const {
  double T = 0.0;
  for (dBodyID b : impl_->bodies) {
    const BodyState s = bodyState(b);
    T += 0.5 * s.mass * s.v.squaredNorm() + 0.5 * s.w.dot(s.I_world * s.w);
  }
  return T;
}

double OdeRobot::totalEnergy() const {
  double U = 0.0;
  for (dBodyID b : impl_->bodies) {
    const BodyState s = bodyState(b);
    U -= s.mass * impl_->model.gravity.dot(s.x);
  }
  return kineticEnergy() + U;
}

Vector6 OdeRobot::momentum() const {
  Vector3 L = Vector3::Zero(), P = Vector3::Zero();
  for (dBodyID b : impl_->bodies) {
    const BodyState s = bodyState(b);
    P += s.mass * s.v;
    L += s.x.cross(s.mass * s.v) + s.I_world * s.w;
  }
  Vector6 out;
  out << P, L;
  return out;
}

}  // namespace igms
