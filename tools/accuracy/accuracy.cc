#include "tools/accuracy/accuracy.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/integrate/integrators.h"
#include "core/integrate/passive_joint_dynamics.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/model/configuration.h"
#include "core/model_io/model_loader.h"
#include "core/model_io/urdf_loader.h"
#include "tools/synthetic/random_urdf.h"
#include "tools/ode_ref/ode_robot.h"

namespace igms::accuracy {
namespace {

constexpr double kSample = 0.032;  // s

}  // namespace

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
  run.energy.push_back(mechanicalEnergy(m, d, q, v));
  run.momentum.push_back(spatialMomentum(m, d, q, v));
}

}  // namespace

bool finiteAndBounded(const VectorX& q, const VectorX& v) {
  return q.allFinite() && v.allFinite() && q.cwiseAbs().maxCoeff() < 1e10 && v.cwiseAbs().maxCoeff() < 1e10;
}

std::vector<std::string> caseNames() { return {"puma_swing", "puma_swing_damped", "chain30", "tumble"}; }

Case makeCase(const std::string& name, const std::string& dir) {
  Case c;
  c.name = name;
  if (name == "puma_swing" || name == "puma_swing_damped") {
    // The PUMA 560 released from a non-trivial pose. The classic data has no
    // joint damping; the damped case gives the arm joints 0.5 N m s/rad and the
    // light wrist joints damping in proportion to their inertia (0.5 on joint 6,
    // whose inertia is 4e-5 kg m^2, would be a time constant of 80 us: stiff).
    // 2.048 s: the free swing is chaotic, and over 10 s halving the ground
    // truth's own step moves it by 0.7 rad, so no accurate reference exists there.
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
    c.model = std::make_shared<Model>(buildModel(parseUrdfDescription(synthetic::serialChainUrdf(30)), {}));
    c.q0 = VectorX::Constant(30, 0.2);
    c.v0 = VectorX::Zero(30);
    c.ee_frame = "l30";
  } else if (name == "tumble") {
    // A free rigid body (the quadruped's trunk alone would do; the whole robot
    // with its legs held by nothing tumbles and flails): zero gravity.
    BuildOptions o;
    o.floating_base = true;
    o.gravity = Vector3::Zero();
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
  const int per_sample = static_cast<int>(std::lround(kSample / h));
  const int samples = static_cast<int>(std::lround(c.duration / kSample));
  sample(c, d, q, v, run);
  double wall = 0.0;
  if (method == Method::Ode || method == Method::OdeQuick) {
    OdeSettings s;
    s.quickstep = method == Method::OdeQuick;
    s.joint_damping = c.damping;
    OdeRobot ode(m, q, v, s);
    run.energy.back() = ode.totalEnergy();
    run.momentum.back() = ode.momentum();
    const VectorX tau = VectorX::Zero(m.nv);
    for (int k = 0; k < samples && !run.diverged; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      for (int j = 0; j < per_sample; ++j) ode.step(tau, h);
      wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ode.state(q, v);
      run.diverged = !finiteAndBounded(q, v);
      if (run.diverged) break;
      sample(c, d, q, v, run);
      // Energy and momentum of ODE's own bodies, not of the coordinates read back.
      run.energy.back() = ode.totalEnergy();
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

Errors compare(const Case& c, const Run& run, const Run& truth) {
  Errors e;
  if (run.diverged || run.q.size() != truth.q.size()) {
    e.q_rms = e.q_max = e.ee_max = e.energy_drift = e.linear_momentum_drift = e.angular_momentum_drift = INFINITY;
    return e;
  }
  const Model& m = *c.model;
  double sum = 0.0;
  int n = 0;
  for (size_t k = 0; k < run.q.size(); ++k) {
    for (int i = 0; i < m.nb; ++i) {
      const int iq = m.q_index[i];
      if (m.joint_type[i] == JointType::Floating) {
        const double dp = (run.q[k].segment<3>(iq) - truth.q[k].segment<3>(iq)).norm();
        const Eigen::Quaterniond a(run.q[k][iq + 3], run.q[k][iq + 4], run.q[k][iq + 5], run.q[k][iq + 6]),
            b(truth.q[k][iq + 3], truth.q[k][iq + 4], truth.q[k][iq + 5], truth.q[k][iq + 6]);
        const double da = a.angularDistance(b);
        for (double x : {dp, da}) {
          e.q_max = std::max(e.q_max, x);
          sum += x * x;
          ++n;
        }
      } else {
        const double x = std::abs(run.q[k][iq] - truth.q[k][iq]);
        e.q_max = std::max(e.q_max, x);
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
  // Conserved quantities only where they are conserved.
  if (c.damping) e.energy_drift = NAN;
  if (m.gravity.norm() > 0 || !m.floating_base) e.linear_momentum_drift = e.angular_momentum_drift = NAN;
  return e;
}

}  // namespace igms::accuracy
