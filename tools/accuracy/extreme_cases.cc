#include "tools/accuracy/extreme_cases.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/dynamics/crba.h"
#include "core/integrate/integrators.h"
#include "core/integrate/passive_joint_dynamics.h"
#include "core/simulation/simulation.h"
#include "core/model/configuration.h"
#include "core/model_io/model_loader.h"
#include "core/model_io/urdf_loader.h"
#include "tools/accuracy/fd_digits.h"
#include "tools/synthetic/random_urdf.h"
#include "tools/accuracy/accuracy.h"
#include "tools/accuracy/stiffness.h"
#include "tools/ode_ref/ode_robot.h"

namespace igms::accuracy {
namespace {

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

const Method kMethods[] = {Method::SemiImplicitEuler, Method::Rk4, Method::LinearlyImplicit, Method::Ode};

// One run by any method. A divergence (a coordinate non-finite or above 1e10)
// stops it and is reported with its time; the state stays the last good one,
// so nothing downstream ever sees a NaN.
class Integration {
 public:
  Integration(const Model& m, Method method, const VectorX& q0, const VectorX& v0, bool damping = false)
      : m_(m), method_(method), q_(q0), v_(v0), good_q_(q0), good_v_(v0), f_(m, damping), s_(m, f_), d_(m) {
    if (method == Method::Ode || method == Method::OdeQuick) {
      OdeSettings settings;
      settings.quickstep = method == Method::OdeQuick;
      settings.joint_damping = damping;
      ode_ = std::make_unique<OdeRobot>(m, q0, v0, settings);
      tau_ = VectorX::Zero(m.nv);
    }
  }
  bool step(double h) {
    if (diverged_) return false;
    bool ok = true;
    if (isOde(method_)) {
      ode_->step(tau_, h);
      ode_->state(q_, v_);
    } else {
      ok = integrateStep(integratorOf(method_), m_, f_, q_, v_, h, s_);
    }
    t_ += h;
    if (!ok || !finiteAndBounded(q_, v_)) {
      diverged_ = true;
      diverged_at_ = t_;
      q_ = good_q_;
      v_ = good_v_;
      return false;
    }
    normalizeConfiguration(m_, q_);
    good_q_ = q_;
    good_v_ = v_;
    return true;
  }
  // Run for `seconds`; after every `every` steps call sample(*this).
  template <typename F>
  void run(double h, double seconds, int every, F&& sample) {
    const long n = std::lround(seconds / h);
    for (long k = 1; k <= n && step(h); ++k)
      if (k % every == 0) sample(*this);
  }
  double energy() { return ode_ ? ode_->totalEnergy() : mechanicalEnergy(m_, d_, q_, v_); }
  Vector3 angularMomentum() {
    const Vector6 p = ode_ ? ode_->momentum() : spatialMomentum(m_, d_, q_, v_);
    return p.tail<3>();
  }
  double kinetic() { return ode_ ? ode_->kineticEnergy() : 0.5 * v_.dot(crba(m_, d_, q_).symmetricUpperTimes(v_)); }
  const VectorX& q() const { return q_; }
  const VectorX& v() const { return v_; }
  bool diverged() const { return diverged_; }
  double divergedAt() const { return diverged_at_; }

 private:
  const Model& m_;
  Method method_;
  VectorX q_, v_, good_q_, good_v_, tau_;
  PassiveJointDynamics f_;
  IntegratorScratch<PassiveJointDynamics::Evaluation> s_;
  Data d_;
  std::unique_ptr<OdeRobot> ode_;
  bool diverged_ = false;
  double t_ = 0.0, diverged_at_ = 0.0;
};

std::string divergence(const Integration& r) {
  return format("diverged at t = %.3f s: detected and reported, no NaN", r.divergedAt());
}

// --- A physical pendulum released at 2.5 rad: period against the elliptic integral.
void pendulumPeriod(std::vector<ExtremeRow>& rows) {
  const double mass = 1.0, l = 0.5, Ic = 0.01, q0 = 2.5, g = 9.81;
  const std::string urdf =
      "<robot name=\"pendulum\"><link name=\"base\"/><link name=\"bob\"><inertial><origin xyz=\"0 0 -0.5\"/>"
      "<mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>"
      "</link><joint name=\"pivot\" type=\"continuous\"><parent link=\"base\"/><child link=\"bob\"/>"
      "<axis xyz=\"0 1 0\"/></joint></robot>";
  const Model m = buildModel(parseUrdfDescription(urdf), {});
  // T = 4 K(k) sqrt(I_O / (m g l)), k = sin(q0 / 2); K by the arithmetic-geometric mean.
  const double k = std::sin(q0 / 2);
  double a = 1.0, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 30; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  const double exact = 4.0 * (M_PI / (2 * a)) * std::sqrt((Ic + mass * l * l) / (mass * g * l));
  const double h = 1e-3;
  for (Method method : kMethods) {
    Integration r(m, method, VectorX::Constant(1, q0), VectorX::Zero(1));
    // Downward crossings of q = 0 (v < 0), located by cubic Hermite interpolation.
    std::vector<double> crossings;
    double q_prev = q0, v_prev = 0.0, t = 0.0;
    r.run(h, 12.0, 1, [&](Integration& s) {
      const double q1 = s.q()[0], v1 = s.v()[0];
      if (q_prev > 0.0 && q1 <= 0.0) {
        auto p = [&](double x) {
          const double x2 = x * x, x3 = x2 * x;
          return (2 * x3 - 3 * x2 + 1) * q_prev + (x3 - 2 * x2 + x) * h * v_prev + (-2 * x3 + 3 * x2) * q1 +
                 (x3 - x2) * h * v1;
        };
        double lo = 0.0, hi = 1.0;
        for (int i = 0; i < 60; ++i) (p(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
        crossings.push_back(t + 0.5 * (lo + hi) * h);
      }
      q_prev = q1;
      v_prev = v1;
      t += h;
    });
    const double measured =
        crossings.size() >= 2 ? (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1) : 0;
    const double rel = std::abs(measured - exact) / exact;
    const double bound = method == Method::Rk4 ? 1e-8 : 1e-3;
    rows.push_back({"pendulum_period (q0 = 2.5 rad, 1 ms, 12 s)", methodName(method),
                    format("period within %.0e of 4 K(sin(q0/2)) sqrt(I/mgl)", bound),
                    format("T = %.9f s, analytic %.9f s, relative error %.2e", measured, exact, rel),
                    !r.diverged() && rel < bound});
  }
}

// A free rigid body of principal inertias 1, 2, 3 in zero gravity.
Model freeBody() {
  const std::string urdf =
      "<robot name=\"body\"><link name=\"body\"><inertial><mass value=\"1\"/>"
      "<inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"2\" iyz=\"0\" izz=\"3\"/></inertial></link></robot>";
  BuildOptions o;
  o.floating_base = true;
  o.gravity = Vector3::Zero();
  return buildModel(parseUrdfDescription(urdf), o);
}

// Energy and angular momentum, the torque-free body's invariants, over a run.
struct Invariants {
  double energy_max_ratio = 1.0, energy_drift = 0.0, momentum_drift = 0.0;
};

Invariants watchInvariants(Integration& r, double h, double seconds, int every) {
  Invariants out;
  const double E0 = r.energy();
  const Vector3 L0 = r.angularMomentum();
  r.run(h, seconds, every, [&](Integration& s) {
    const double E = s.energy();
    out.energy_max_ratio = std::max(out.energy_max_ratio, E / E0);
    out.energy_drift = std::max(out.energy_drift, std::abs(E - E0) / E0);
    out.momentum_drift = std::max(out.momentum_drift, (s.angularMomentum() - L0).norm() / L0.norm());
  });
  return out;
}

// --- Tumbling about the intermediate axis (unstable: the body flips every few seconds).
void intermediateAxis(std::vector<ExtremeRow>& rows, bool quick) {
  const Model m = freeBody();
  const double seconds = quick ? 20.0 : 100.0, h = 1e-3;
  VectorX q0 = neutralConfiguration(m), v0 = VectorX::Zero(6);
  v0.tail<3>() << 0.01, 5.0, 0.01;
  for (Method method : kMethods) {
    Integration r(m, method, q0, v0);
    const Invariants inv = watchInvariants(r, h, seconds, 10);
    // RK4 conserves both to its truncation error. ODE's implicit gyroscopic
    // term can only lose energy. Semi-implicit Euler (and the linearly-implicit
    // scheme, the same without stiff terms) takes the gyroscopic term
    // explicitly on SO(3): not an energy-conserving method here, so its
    // criterion is boundedness, and its drift is the figure.
    const bool conserving = method == Method::Rk4 || method == Method::Ode;
    const double bound = method == Method::Rk4 ? 1e-6 : 0.2;
    rows.push_back({format("intermediate_axis_tumble (w = 5 rad/s, 1 ms, %.0f s)", seconds), methodName(method),
                    conserving ? format("energy <= 1.01 E0; angular momentum drift < %.0e", bound)
                               : "bounded, no NaN; energy and momentum drift reported",
                    r.diverged() ? divergence(r)
                                 : format("max E/E0 %.6f; |L - L0|/|L0| %.2e", inv.energy_max_ratio, inv.momentum_drift),
                    !r.diverged() && (!conserving || (inv.energy_max_ratio <= 1.01 && inv.momentum_drift < bound))});
  }
}

// --- 500 rad/s about the axis of least inertia, with a small wobble: h w = 0.5 rad per step.
void fastSpin(std::vector<ExtremeRow>& rows) {
  const Model m = freeBody();
  VectorX q0 = neutralConfiguration(m), v0 = VectorX::Zero(6);
  v0.tail<3>() << 500.0, 0.5, 0.5;
  for (Method method : kMethods) {
    Integration r(m, method, q0, v0);
    const Invariants inv = watchInvariants(r, 1e-3, 2.0, 1);
    const bool energy_conserving = method == Method::Rk4 || method == Method::Ode;
    rows.push_back({"fast_spin (500 rad/s single body, 1 ms, 2 s)", methodName(method),
                    energy_conserving ? "no NaN; energy <= 1.01 E0" : "no NaN; bounded, or divergence reported",
                    r.diverged() ? divergence(r)
                                 : format("max E/E0 %.6f; |L - L0|/|L0| %.2e", inv.energy_max_ratio, inv.momentum_drift),
                    energy_conserving ? !r.diverged() && inv.energy_max_ratio <= 1.01 : true});
  }
}

Model puma(const std::string& dir) { return buildModel(loadDescription(dir + "/models/puma560.urdf"), {}); }

VectorX pumaPose() {
  VectorX q(6);
  q << 0.3, 0.2, -0.6, 0.5, 1.0, 0.3;
  return q;
}

// --- The PUMA thrown at 30 rad/s on every joint under gravity.
void fastPuma(std::vector<ExtremeRow>& rows, const std::string& dir) {
  const Model m = puma(dir);
  for (Method method : kMethods) {
    Integration r(m, method, pumaPose(), VectorX::Constant(6, 30.0));
    const Invariants inv = watchInvariants(r, 1e-3, 2.0, 1);
    const bool rk4 = method == Method::Rk4;
    rows.push_back({"fast_puma (30 rad/s on every joint, 1 ms, 2 s)", methodName(method),
                    rk4 ? "no NaN; energy <= 1.01 E0" : "no NaN; bounded, or divergence reported",
                    r.diverged() ? divergence(r)
                                 : format("max E/E0 %.4f; largest |qdot| %.1f rad/s", inv.energy_max_ratio,
                                          r.v().cwiseAbs().maxCoeff()),
                    rk4 ? !r.diverged() && inv.energy_max_ratio <= 1.01 : true});
  }
}

// --- Steps of 10 and 32 ms on the damped PUMA swing, 10 s.
void largeSteps(std::vector<ExtremeRow>& rows, const std::string& dir) {
  Model m = puma(dir);
  m.damping = {0.5, 0.5, 0.5, 0.005, 0.005, 0.002};
  for (double h : {0.010, 0.032}) {
    for (Method method : kMethods) {
      Integration r(m, method, pumaPose(), VectorX::Zero(6), /*damping=*/true);
      const double E0 = r.energy();
      double worst = 1.0;
      r.run(h, 10.0, 1, [&](Integration& s) {
        const double E = s.energy();
        worst = std::max(worst, (E - E0) / std::max(1e-9, std::abs(E0)) + 1.0);
      });
      // Damped: energy may only fall. The linearly-implicit scheme must stay
      // stable; the explicit ones may diverge, as long as it is reported.
      const bool li = method == Method::LinearlyImplicit;
      rows.push_back({format("large_step (damped PUMA, h = %.0f ms, 10 s)", h * 1e3), methodName(method),
                      li ? "stable; energy never above its start (damped)" : "no NaN: bounded, or divergence reported",
                      r.diverged() ? divergence(r)
                                   : format("stable; max (E - E0)/|E0| %.2e; final |qdot| %.2g rad/s", worst - 1.0,
                                            r.v().cwiseAbs().maxCoeff()),
                      li ? !r.diverged() && worst <= 1.0 + 1e-9 : true});
    }
  }
}

// --- 1e6 steps of the free PUMA swing at 1 ms (1000 s): energy drift against the kinetic scale.
// The swing is chaotic, so one start is one draw from a spread: an ensemble of
// starts q0 + j 1e-9 rad on every joint, median and range.
void longRun(std::vector<ExtremeRow>& rows, const std::string& dir, bool quick, int starts) {
  const Model m = puma(dir);
  const double h = 1e-3, seconds = quick ? 100.0 : 1000.0;
  for (Method method : kMethods) {
    std::vector<double> drifts, finals;
    double T_max = 0.0;
    const Integration* failed = nullptr;
    std::vector<std::unique_ptr<Integration>> runs;
    for (int j = 0; j < starts && !failed; ++j) {
      runs.push_back(std::make_unique<Integration>(m, method, pumaPose() + VectorX::Constant(6, j * 1e-9),
                                                   VectorX::Zero(6)));
      Integration& r = *runs.back();
      const double E0 = r.energy();
      double drift = 0.0, final_drift = 0.0, t_max = 0.0;
      r.run(h, seconds, 100, [&](Integration& s) {
        const double E = s.energy();
        t_max = std::max(t_max, s.kinetic());
        drift = std::max(drift, std::abs(E - E0));
        final_drift = E - E0;
      });
      if (r.diverged()) failed = &r;
      drifts.push_back(drift / t_max);
      finals.push_back(std::abs(final_drift) / t_max);
      T_max = std::max(T_max, t_max);
    }
    std::sort(drifts.begin(), drifts.end());
    std::sort(finals.begin(), finals.end());
    const double bound = method == Method::Rk4 ? 1e-3 : 1.0;
    const std::string name =
        "long_run (free PUMA, 1 ms, " + format("%.0e steps, ", seconds / h) + std::to_string(starts) +
        " starts q0 + j 1e-9 rad)";
    rows.push_back({name, methodName(method),
                    format("no NaN, |q|,|v| < 1e10; every start's max |E - E0| / max T < %g", bound),
                    failed ? divergence(*failed)
                           : format("max |E - E0| / max T (each start's own max T): median %.2e [%.2e, %.2e]; ",
                                    drifts[drifts.size() / 2], drifts.front(), drifts.back()) +
                                 format("at the end, median %.2e (max T up to %.3g J)", finals[finals.size() / 2],
                                        T_max),
                    !failed && drifts.back() < bound});
  }
}

// --- Pull at a singular pose: the arm stretched out, the wrist axes aligned,
// the device held still 0.3 m beyond reach. Through the server's own step.
void singularPull(std::vector<ExtremeRow>& rows, const std::string& dir) {
  for (const char* integrator : {"semi_implicit_euler", "rk4", "linearly_implicit"}) {
    const std::string yaml = std::string(R"(name: singular_pull
robot: {model: ../models/puma560.urdf}
initial: {q: [0, 0, -1.5707963, 0, 0, 0]}
trajectory:
  kind: joint_waypoints
  waypoints:
    - {t: 0.0, q: [0, 0, -1.5707963, 0, 0, 0]}
    - {t: 1.0, q: [0, 0, -1.5707963, 0, 0, 0]}
controller: {kp: 400, kd: 40, hold_damping: 2.0}
interaction:
  pull: {k: 800, b: 20, max_force: 60, max_stretch: 0.08, link: ee_link}
simulation: {integrator: )") + integrator + ", dt: 0.001, joint_damping: true}\n";
    Simulation sim(parseScene(yaml, "singular_pull", dir + "/scenes"));
    const int ee = sim.pullFrame();
    const Vector3 x0 = sim.linkPoses()[static_cast<size_t>(ee)].p;
    Vector3 out = x0;
    out.z() = 0.0;
    out = out.norm() > 0 ? out.normalized() : Vector3::UnitX();
    InteractionInput in;
    in.mode = InteractionMode::Pull;
    in.attach_frame = ee;
    in.tip_position = x0 + 0.3 * out;
    double f_max = 0.0, v_max = 0.0, tau_max = 0.0;
    bool ok = true;
    for (int k = 0; k < 3000 && ok; ++k) {
      ok = sim.step(&in);
      f_max = std::max(f_max, sim.outcome().force_on_robot.norm());
      v_max = std::max(v_max, sim.v().cwiseAbs().maxCoeff());
      tau_max = std::max(tau_max, sim.tau().cwiseAbs().maxCoeff());
    }
    const double f_cap = 60.0;
    rows.push_back({"singular_pull (stretched arm, aligned wrist, device 0.3 m beyond reach, 3 s)", integrator,
                    "|F| <= max_force (60 N); |qdot| < 20 rad/s; no divergence",
                    ok ? format("max |F| %.1f N; max |qdot| %.2f rad/s; max |tau| %.1f N m", f_max, v_max, tau_max)
                       : sim.divergenceReport(),
                    ok && f_max <= f_cap + 1e-9 && v_max < 20.0});
  }
}

// --- Stiff couplings (pull spring or push contact on a light link): 0.1 kg at 1 ms.
void stiffCouplings(std::vector<ExtremeRow>& rows) {
  const double mass = 0.1, h = 1e-3;
  const double sie = stabilityLimit(0, mass, h), rk4 = stabilityLimit(1, mass, h);
  rows.push_back({"stiff_coupling (0.1 kg at 1 ms, k swept)", "semi_implicit_euler",
                  "measured limit of k h^2/m within 5 % of theory (4)",
                  format("limit k h^2/m = %.3f: largest stable k %.3g N/m", sie, sie * mass / (h * h)),
                  std::abs(sie - 4.0) < 0.2});
  rows.push_back({"stiff_coupling (0.1 kg at 1 ms, k swept)", "rk4", "measured limit of k h^2/m within 5 % of theory (8)",
                  format("limit k h^2/m = %.3f: largest stable k %.3g N/m", rk4, rk4 * mass / (h * h)),
                  std::abs(rk4 - 8.0) < 0.4});
  std::vector<double> ks;
  for (double k = 1e2; k <= 1e7 * 1.001; k *= std::sqrt(10.0)) ks.push_back(k);
  bool all = true;
  double worst = 0.0;
  for (const auto& r : stiffnessSweep(mass, h, ks)) {
    all = all && r.stable[2];
    worst = std::max(worst, r.energy_ratio[2]);
  }
  rows.push_back({"stiff_coupling (0.1 kg at 1 ms, k swept)", "linearly_implicit",
                  "stable and passive (E <= 1.01 E0) for k = 1e2 .. 1e7 N/m",
                  format("stable at every k up to 1e7 N/m (k h^2/m = 1e2); max E/E0 %.4f", worst), all});
  // Beyond the limit: the explicit blow-up is caught, never printed as NaN.
  const auto beyond = stiffnessSweep(mass, h, {5.0 * mass / (h * h)});
  const bool caught = std::isinf(beyond[0].energy_ratio[0]) && !std::isnan(beyond[0].energy_ratio[0]);
  rows.push_back({"stiff_coupling beyond the limit (k h^2/m = 5)", "semi_implicit_euler",
                  "divergence detected and reported, not NaN", caught ? "blow-up detected" : "not detected", caught});
}

// --- Forward dynamics on ill-conditioned models: digits against cond(H).
void conditioning(std::vector<ExtremeRow>& rows) {
  struct Item {
    const char* name;
    std::string urdf;
    double per_cond, floor;
  };
  const Item items[] = {{"mass_ratio 1e3 (12 links, root to tip)", synthetic::taperedChainUrdf(1.0, 1e3), 1e-13, 1e-12},
                        {"mass_ratio 1e6 (12 links, root to tip)", synthetic::taperedChainUrdf(1.0, 1e6), 1e-13, 1e-12},
                        {"links of 1 g (12 links)", synthetic::taperedChainUrdf(1e-3, 1.0), 1e-13, 1e-12},
                        {"links of 1 t (12 links)", synthetic::taperedChainUrdf(1e3, 1.0), 1e-13, 1e-12},
                        {"long_chain 100 links", synthetic::serialChainUrdf(100), 1e-13, 0.0},
                        {"long_chain 200 links", synthetic::serialChainUrdf(200), 1e-13, 0.0}};
  for (const Item& it : items) {
    const FdDigits r = measureFdDigits(buildModel(parseUrdfDescription(it.urdf), {}), 5, 5, it.per_cond,
                                                   it.floor);
    rows.push_back({it.name, "forward dynamics (LDL^T, ABA)", "FD(ID(a)) and ABA vs LDL^T within cond(H) * 1e-13",
                    format("cond(H) %.2g; FD(ID(a)) error %.2g (%.1f digits); ABA vs LDL^T %.2g", r.worst_cond,
                           r.worst_fd, -std::log10(r.worst_fd), r.worst_aba),
                    r.within_bound});
  }
}

}  // namespace

std::vector<ExtremeRow> extremeCases(const std::string& dir, bool quick, int long_run_starts) {
  std::vector<ExtremeRow> rows;
  pendulumPeriod(rows);
  intermediateAxis(rows, quick);
  fastSpin(rows);
  fastPuma(rows, dir);
  largeSteps(rows, dir);
  longRun(rows, dir, quick, long_run_starts > 0 ? long_run_starts : quick ? 3 : 9);
  singularPull(rows, dir);
  stiffCouplings(rows);
  conditioning(rows);
  return rows;
}

}  // namespace igms::accuracy
