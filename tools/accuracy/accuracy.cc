#include "tools/accuracy/accuracy.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "core/dynamics/crba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/geometry/deepest_contact.h"
#include "core/integrate/integrators.h"
#include "core/integrate/passive_joint_dynamics.h"
#include "core/interaction/push.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "core/model/robot_description.h"
#include "core/model_io/model_loader.h"
#include "core/model_io/urdf_loader.h"
#include "core/scene/scene.h"
#include "core/simulation/simulation.h"
#include "tools/ode_ref/ode_robot.h"
#include "tools/synthetic/random_urdf.h"

namespace igms::accuracy {

double mechanicalEnergy(const Model& m, Data& d, const VectorX& q, const VectorX& v) {
  // Kinetic from the body velocities, potential -m g . c from the body poses.
  rnea(m, d, q, v, VectorX::Zero(m.nv));
  bodyKinematics(m, d, q);
  double T = 0.0, U = 0.0;
  for (int i = 0; i < m.nb; ++i) {
    T += 0.5 * (m.inertia[i] * d.v[i]).dot(d.v[i]);
    U -= m.inertia[i].m * m.gravity.dot(d.oMi[i].act(m.inertia[i].com()));
  }
  return T + U;
}

Vector6 spatialMomentum(const Model& m, Data& d, const VectorX& q, const VectorX& v) {
  rnea(m, d, q, v, VectorX::Zero(m.nv));
  bodyKinematics(m, d, q);
  Force total;
  for (int i = 0; i < m.nb; ++i) total += d.oMi[i].act(m.inertia[i] * d.v[i]);
  Vector6 out;
  out << total.f, total.n;
  return out;
}

namespace {

void sample(const Case& c, Data& d, const VectorX& q, const VectorX& v, Run& run) {
  const Model& m = *c.model;
  run.q.push_back(q);
  forwardKinematics(m, d, q);
  const int f = m.frameIndex(c.ee_frame);
  run.ee.push_back(d.oMf[static_cast<size_t>(std::max(f, 0))].p);
  const double spring = handEnergy(c, d);  // before mechanicalEnergy moves d on
  run.energy.push_back(mechanicalEnergy(m, d, q, v) + spring);
  run.momentum.push_back(spatialMomentum(m, d, q, v));
}

int frameOf(const Model& m, const std::string& link) {
  const int f = m.frameIndex(link);
  if (f < 0) throw std::runtime_error("no link '" + link + "' in " + m.source);
  return f;
}

LinkContact pushContact(const Case& c, const Data& d) {
  return deepestContact(*c.model, [&](int f) { return d.oMf[static_cast<size_t>(f)]; }, c.hand.tip,
                        c.hand.tip_radius, frameOf(*c.model, c.hand.link));
}

// The hand's force on the robot at (q, v), where it acts: ODE applies it as an
// explicit force each step (ODE has no implicit coupling to a device).
struct HandForce {
  int body = -1;
  Vector3 point = Vector3::Zero(), force = Vector3::Zero();
};

HandForce handForce(const Case& c, Data& d, const VectorX& q, const VectorX& v, Matrix6X& J) {
  const Model& m = *c.model;
  forwardKinematics(m, d, q);
  HandForce out;
  const int f = frameOf(m, c.hand.link);
  if (c.hand.mode == InteractionMode::Pull) {
    out.point = d.oMf[static_cast<size_t>(f)].act(c.hand.point);
    pointJacobian(m, d, f, c.hand.point, J);
    const Vector3 xd = J.topRows<3>() * v;
    out.force = c.hand.k * (c.hand.tip - out.point) - c.hand.b * xd;
    out.body = m.frames[static_cast<size_t>(f)].body;
  } else if (c.hand.mode == InteractionMode::Push) {
    const LinkContact touch = pushContact(c, d);
    if (touch.frame < 0) return out;
    const PushForce p = pushForce(touch.contact, c.hand.k, INFINITY);
    out.point = p.point;
    out.force = p.on_link;
    out.body = m.frames[static_cast<size_t>(touch.frame)].body;
  }
  return out;
}

// The case as a scene for the server's own step: the hand's coupling as the
// scene's push or pull, uncapped; no controller, joint damping or limits.
Scene hapticScene(const Case& c, Method method, double h) {
  auto list = [](const VectorX& x) {
    std::string s = "[";
    char num[32];
    for (int k = 0; k < x.size(); ++k) {
      std::snprintf(num, sizeof num, "%s%.17g", k ? ", " : "", x[k]);
      s += num;
    }
    return s + "]";
  };
  char buf[128];
  std::string hand;
  if (c.hand.mode == InteractionMode::Pull) {
    std::snprintf(buf, sizeof buf, "{k: %.17g, b: %.17g, max_force: 1e12, max_stretch: 1e12, ", c.hand.k, c.hand.b);
    hand = "  pull: " + std::string(buf) + "link: " + c.hand.link + ", point: " + list(c.hand.point) + "}\n";
  } else {
    std::snprintf(buf, sizeof buf, "{k_p: %.17g, max_force: 1e12, tip_radius: %.17g}", c.hand.k, c.hand.tip_radius);
    hand = "  push: " + std::string(buf) + "\n";
  }
  std::snprintf(buf, sizeof buf, "%.17g", h);
  const std::string yaml = "name: " + c.name + "\nrobot: {model: " + c.model_path + "}\ninitial: {q: " + list(c.q0) +
                           ", v: " + list(c.v0) + "}\ninteraction:\n" + hand + "simulation: {integrator: " +
                           methodName(method) + ", dt: " + buf + ", joint_damping: false, joint_limits: false}\n";
  Scene s = parseScene(yaml, c.name + " (igms-accuracy)", ".");
  s.push.b = 0.0;  // eq. (3) alone, as the independent truth writes it: a probe held still, no device to keep passive
  return s;
}

}  // namespace

bool finiteAndBounded(const VectorX& q, const VectorX& v) {
  return q.allFinite() && v.allFinite() && q.cwiseAbs().maxCoeff() < 1e10 && v.cwiseAbs().maxCoeff() < 1e10;
}

std::vector<std::string> caseNames() { return {"puma_swing", "puma_swing_damped", "chain30", "tumble"}; }

std::vector<std::string> hapticCaseNames() {
  // Up to 32 N/mm, four times a stiff device's 8. Beyond that the arm itself has no truth to compare with:
  // at 1e6 N/m the undamped spring spins the light wrist and DOP853 at rtol 1e-12 and 1e-13 disagree by
  // 4e-6 rad, at 1e7 N/m by 300 rad. The stability table (step_matrix.h) covers that range.
  return {"puma_pull_k400",      "puma_pull_k2000", "puma_pull_k8000", "puma_pull_k32000",
          "puma_pull_k8000_b20", "puma_push_k400",  "puma_push_k2000", "puma_push_k8000"};
}

namespace {

// The PUMA released at q0 under gravity with a hand on it: the pull's device
// 5 cm beside the end effector; the push's tip under the forearm (link 3's
// cylinder), 5 mm into it, so the forearm falls onto it.
Case hapticCase(const std::string& name, const std::string& dir) {
  double k = 0, b = 0;
  const bool pull = name.rfind("puma_pull_k", 0) == 0, push = name.rfind("puma_push_k", 0) == 0;
  const std::string rest = name.substr(11);
  const size_t under = rest.find("_b");
  try {
    k = std::stod(rest.substr(0, under));
    if (under != std::string::npos) b = std::stod(rest.substr(under + 2));
  } catch (const std::exception&) {
    throw std::runtime_error("unknown case '" + name + "'");
  }
  if (!(pull || push) || !(k > 0) || (push && b != 0)) throw std::runtime_error("unknown case '" + name + "'");
  Case c = makeCase("puma_swing", dir);
  c.name = name;
  c.duration = 1.024;
  Data d(*c.model);
  forwardKinematics(*c.model, d, c.q0);
  c.hand.k = k;
  c.hand.b = b;
  if (pull) {
    c.hand.mode = InteractionMode::Pull;
    c.hand.link = "ee_link";
    c.hand.tip = d.oMf[static_cast<size_t>(c.model->frameIndex("ee_link"))].p + Vector3(0.05, 0, 0);
  } else {
    c.hand.mode = InteractionMode::Push;
    c.hand.link = "link3";
    const Frame& f = c.model->frames[static_cast<size_t>(c.model->frameIndex("link3"))];
    const SE3 X = d.oMf[static_cast<size_t>(c.model->frameIndex("link3"))] * f.collisions.at(0).placement;
    const Vector3 axis = X.R.col(2);  // the cylinder's
    Vector3 down = -Vector3::UnitZ() + axis * axis.z();
    down.normalize();
    const double radius = f.collisions.at(0).size.x();
    c.hand.tip = X.p + down * (radius + c.hand.tip_radius - 0.005);
  }
  return c;
}

}  // namespace

Case makeCase(const std::string& name, const std::string& dir) {
  if (name.rfind("puma_pull_", 0) == 0 || name.rfind("puma_push_", 0) == 0) return hapticCase(name, dir);
  Case c;
  c.name = name;
  if (name == "puma_swing" || name == "puma_swing_damped") {
    // The PUMA 560 released from a non-trivial pose. The classic data has no
    // joint damping; the damped case gives the arm joints 0.5 N m s/rad and the
    // light wrist joints damping in proportion to their inertia (0.5 on joint 6,
    // whose inertia is 4e-5 kg m^2, would be a time constant of 80 us: stiff).
    // 2.048 s: the free swing is chaotic, and over 10 s halving the ground
    // truth's own step moves it by 0.7 rad, so no accurate reference exists there.
    c.model_path = dir + "/models/puma560.urdf";
    c.urdf = readModelFile(c.model_path);
    auto model = std::make_shared<Model>(loadModel(dir + "/models/puma560.urdf"));
    c.damping = name == "puma_swing_damped";
    if (c.damping) model->damping = {0.5, 0.5, 0.5, 0.005, 0.005, 0.002};
    c.model = model;
    c.q0 = VectorX(6);
    c.q0 << 0.3, 0.2, -0.6, 0.5, 1.0, 0.3;
    c.v0 = VectorX::Zero(6);
    c.duration = 2.048;
    c.ee_frame = "ee_link";
  } else if (name == "chain30") {
    c.urdf = synthetic::serialChainUrdf(30);
    c.model = std::make_shared<Model>(buildModel(parseUrdfDescription(c.urdf), {}));
    c.q0 = VectorX::Constant(30, 0.2);
    c.v0 = VectorX::Zero(30);
    c.ee_frame = "l30";
  } else if (name == "tumble") {
    // A free rigid body (the quadruped's trunk alone would do; the whole robot
    // with its legs held by nothing tumbles and flails): zero gravity.
    BuildOptions o;
    o.floating_base = true;
    o.gravity = Vector3::Zero();
    c.model_path = dir + "/models/quadruped.urdf";
    c.urdf = readModelFile(c.model_path);
    c.model = std::make_shared<Model>(buildModel(loadDescription(dir + "/models/quadruped.urdf"), o));
    c.q0 = neutralConfiguration(*c.model);
    for (int k = 7; k < c.model->nq; ++k) c.q0[k] = k % 3 == 0 ? -1.2 : 0.4;
    c.v0 = VectorX::Zero(c.model->nv);
    c.v0.head<6>() << 0.2, -0.1, 0.05, 1.5, 0.3, -2.0;
    c.ee_frame = "lf_foot";
  } else {
    throw std::runtime_error("unknown case '" + name + "'");
  }
  return c;
}

const char* methodName(Method m) {
  switch (m) {
    case Method::SemiImplicitEuler: return "semi_implicit_euler";
    case Method::Rk4: return "rk4";
    case Method::LinearlyImplicit: return "linearly_implicit";
    case Method::Ode: return "ode_worldstep";
    case Method::OdeQuick: return "ode_quickstep";
  }
  return "?";
}

std::vector<Method> allMethods() {
  return {Method::SemiImplicitEuler, Method::Rk4, Method::LinearlyImplicit, Method::Ode, Method::OdeQuick};
}

Run simulate(const Case& c, Method method, double h) {
  const Model& m = *c.model;
  Run run;
  Data d(m);
  VectorX q = c.q0, v = c.v0;
  const int per_sample = static_cast<int>(std::lround(kSamplePeriod / h));
  const int samples = static_cast<int>(std::lround(c.duration / kSamplePeriod));
  sample(c, d, q, v, run);
  double wall = 0.0;
  if (c.hand.mode != InteractionMode::None && !isOde(method)) {
    // The server's own step: the coupling exactly as a user meets it.
    Simulation sim(hapticScene(c, method, h));
    InteractionInput in;
    in.mode = c.hand.mode;
    in.client = 1;
    in.tip_position = c.hand.tip;
    in.tip_radius = c.hand.tip_radius;
    const int f = sim.model().frameIndex(c.hand.link);
    if (c.hand.mode == InteractionMode::Pull) in.attach_frame = f, in.attach_point = c.hand.point;
    for (int k = 0; k < samples && !run.diverged; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      for (int j = 0; j < per_sample && !run.diverged; ++j) {
        in.seq = static_cast<int64_t>(k) * per_sample + j;
        run.diverged = !sim.step(&in);
      }
      wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      q = sim.q();
      v = sim.v();
      run.diverged = run.diverged || !finiteAndBounded(q, v);
      if (!run.diverged) sample(c, d, q, v, run);
    }
  } else if (method == Method::Ode || method == Method::OdeQuick) {
    OdeSettings s;
    s.quickstep = method == Method::OdeQuick;
    s.joint_damping = c.damping;
    OdeRobot ode(m, q, v, s);
    run.energy.back() = ode.totalEnergy() + handEnergy(c, d);
    run.momentum.back() = ode.momentum();
    const VectorX tau = VectorX::Zero(m.nv);
    Matrix6X J(6, m.nv);
    VectorX qh = q, vh = v;
    for (int k = 0; k < samples && !run.diverged; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      for (int j = 0; j < per_sample; ++j) {
        if (c.hand.mode != InteractionMode::None) {
          ode.state(qh, vh);
          const HandForce u = handForce(c, d, qh, vh, J);
          if (u.body >= 0) ode.addForceAtPoint(u.body, u.point, u.force);
        }
        ode.step(tau, h);
      }
      wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ode.state(q, v);
      run.diverged = !finiteAndBounded(q, v);
      if (run.diverged) break;
      sample(c, d, q, v, run);
      // Energy and momentum of ODE's own bodies, not of the coordinates read back
      // (the hand's spring from the coordinates: sample() left their kinematics in d).
      forwardKinematics(m, d, q);
      run.energy.back() = ode.totalEnergy() + handEnergy(c, d);
      run.momentum.back() = ode.momentum();
    }
  } else {
    PassiveJointDynamics f(m, c.damping);  // free motion: no torques but the joint damping
    IntegratorScratch<PassiveJointDynamics::Evaluation> scratch(m, f);
    const IntegratorKind kind = integratorOf(method);
    for (int k = 0; k < samples && !run.diverged; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      for (int j = 0; j < per_sample && !run.diverged; ++j) {
        run.diverged = !integrateStep(kind, m, f, q, v, h, scratch) || !finiteAndBounded(q, v);
      }
      wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      normalizeConfiguration(m, q);
      if (!run.diverged) sample(c, d, q, v, run);
    }
  }
  run.wall_seconds = wall;
  return run;
}

double handEnergy(const Case& c, const Data& d) {
  if (c.hand.mode == InteractionMode::Pull) {
    const Vector3 x = d.oMf[static_cast<size_t>(frameOf(*c.model, c.hand.link))].act(c.hand.point);
    return 0.5 * c.hand.k * (c.hand.tip - x).squaredNorm();
  }
  if (c.hand.mode == InteractionMode::Push) {
    const LinkContact touch = pushContact(c, d);
    return touch.frame < 0 ? 0.0 : 0.5 * c.hand.k * touch.contact.depth * touch.contact.depth;
  }
  return 0.0;
}

double handStiffnessRatio(const Case& c, double h) {
  if (c.hand.mode == InteractionMode::None) return NAN;
  const Model& m = *c.model;
  Data d(m);
  forwardKinematics(m, d, c.q0);
  const int f = frameOf(m, c.hand.link);
  Vector3 point = c.hand.point, u;
  if (c.hand.mode == InteractionMode::Pull) {
    u = (c.hand.tip - d.oMf[static_cast<size_t>(f)].act(point)).normalized();
  } else {
    const LinkContact touch = pushContact(c, d);
    u = touch.contact.normal;
    point = d.oMf[static_cast<size_t>(f)].inverse().act(touch.contact.point);
  }
  Matrix6X J(6, m.nv);
  pointJacobian(m, d, f, point, J);
  const MatrixX H = crba(m, d, c.q0).dense();
  const Eigen::Matrix<double, 3, Eigen::Dynamic> Jp = J.topRows<3>();
  const Matrix3 inverse_mass = Jp * H.ldlt().solve(Jp.transpose());  // J H^-1 J^T: the hand point's mobility
  // The push's stiffness acts along the normal; the pull's in every direction, so its stiffest mode is
  // along the direction in which the arm is lightest at the hand.
  const double lightest = c.hand.mode == InteractionMode::Push
                              ? u.dot(inverse_mass * u)
                              : Eigen::SelfAdjointEigenSolver<Matrix3>(inverse_mass).eigenvalues().maxCoeff();
  return c.hand.k * h * h * lightest;
}

Errors compare(const Case& c, const Run& run, const Run& truth) {
  Errors e;
  if (run.diverged || run.q.size() != truth.q.size()) {
    e.q_rms = e.q_max = e.ee_max = e.energy_drift = e.linear_momentum_drift = e.angular_momentum_drift = INFINITY;
    e.energy_rate = INFINITY;
    return e;
  }
  const Model& m = *c.model;
  double sum = 0.0;
  int n = 0;
  for (int i = 0; i < m.nb; ++i) e.per_joint.resize(e.per_joint.size() + (m.joint_type[i] == JointType::Floating ? 2 : 1));
  for (size_t k = 0; k < run.q.size(); ++k) {
    size_t slot = 0;
    for (int i = 0; i < m.nb; ++i) {
      const int iq = m.q_index[i];
      if (m.joint_type[i] == JointType::Floating) {
        const double dp = (run.q[k].segment<3>(iq) - truth.q[k].segment<3>(iq)).norm();
        const Eigen::Quaterniond a(run.q[k][iq + 3], run.q[k][iq + 4], run.q[k][iq + 5], run.q[k][iq + 6]),
            b(truth.q[k][iq + 3], truth.q[k][iq + 4], truth.q[k][iq + 5], truth.q[k][iq + 6]);
        const double da = a.angularDistance(b);
        for (double x : {dp, da}) {
          e.q_max = std::max(e.q_max, x);
          e.per_joint[slot] = std::max(e.per_joint[slot], x);
          ++slot;
          sum += x * x;
          ++n;
        }
      } else {
        const double x = std::abs(run.q[k][iq] - truth.q[k][iq]);
        e.q_max = std::max(e.q_max, x);
        e.per_joint[slot] = std::max(e.per_joint[slot], x);
        ++slot;
        sum += x * x;
        ++n;
      }
    }
    e.ee_max = std::max(e.ee_max, (run.ee[k] - truth.ee[k]).norm());
    const double E0 = std::abs(truth.energy[0]) > 1e-9 ? std::abs(truth.energy[0]) : 1.0;
    e.energy_drift = std::max(e.energy_drift, std::abs(run.energy[k] - run.energy[0]) / E0);
    const double P0 = std::max(1e-9, truth.momentum[0].head<3>().norm());
    const double L0 = std::max(1e-9, truth.momentum[0].tail<3>().norm());
    e.linear_momentum_drift =
        std::max(e.linear_momentum_drift, (run.momentum[k] - run.momentum[0]).head<3>().norm() / P0);
    e.angular_momentum_drift =
        std::max(e.angular_momentum_drift, (run.momentum[k] - run.momentum[0]).tail<3>().norm() / L0);
  }
  e.q_rms = std::sqrt(sum / std::max(1, n));
  e.energy_rate = (run.energy.back() - run.energy.front()) / c.duration;
  // Conserved quantities only where they are conserved.
  if (c.damping || c.hand.b > 0) e.energy_drift = NAN;
  if (m.gravity.norm() > 0 || !m.floating_base) e.linear_momentum_drift = e.angular_momentum_drift = NAN;
  return e;
}

}  // namespace igms::accuracy
