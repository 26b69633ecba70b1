// One step of (q, v) under qdd = f(q, v), for three schemes. q moves on the
// configuration group (integrateConfiguration), so a floating base stays on
// SO(3) with a unit quaternion.
//
// Evaluator interface (one per simulation, preallocated):
//   void accel(const VectorX& q, const VectorX& v, VectorX& qdd);   // forward dynamics
// and, for the linearly-implicit scheme, after accel at (q, v):
//   const MatrixX& H() const;                 // joint-space inertia at q
//   const VectorX& force() const;             // F(q, v) = H qdd
//   void addStiffness(MatrixX& A, VectorX& rhs, const VectorX& v, double h);
//       A += h D + h^2 K, rhs -= h^2 K v, with K = -dF/dq, D = -dF/dv of the
//       stiff terms (couplings, joint damping), symmetric, within H's sparsity.
#pragma once

#include "core/dynamics/ltdl.h"
#include "core/model/configuration.h"

namespace igms {

struct IntegratorScratch {
  explicit IntegratorScratch(const Model& m)
      : qdd(m.nv), k1(m.nv), k2(m.nv), k3(m.nv), k4(m.nv), v2(m.nv), v3(m.nv), v4(m.nv), u(m.nv), r2(m.nv), r3(m.nv), r4(m.nv), qt(m.nq),
        A(m.nv, m.nv), rhs(m.nv), diag(m.nv) {}
  VectorX qdd, k1, k2, k3, k4, v2, v3, v4, u, r2, r3, r4, qt;
  MatrixX A;
  VectorX rhs, diag;
};

// v+ = v + h f(q, v); q+ = q (+) h v+. Stable for a spring only while k h^2 / m < 4.
template <typename Eval>
void stepSemiImplicitEuler(const Model& m, Eval& f, VectorX& q, VectorX& v, double h, IntegratorScratch& s) {
  f.accel(q, v, s.qdd);
  v += h * s.qdd;
  integrateConfiguration(m, q, v, h, q);
}

// Classic RK4 on (q, v), as Runge-Kutta-Munthe-Kaas on the group: stage i
// sits at q (+) u_i, and its configuration rate is v_i carried back to q's
// tangent space through dexp^{-1} (configurationRate). Without that correction
// a floating base would be only second order.
template <typename Eval>
void stepRk4(const Model& m, Eval& f, VectorX& q, VectorX& v, double h, IntegratorScratch& s) {
  f.accel(q, v, s.k1);                            // stage 1: u = 0, rate v
  s.v2 = v + 0.5 * h * s.k1;
  s.u = 0.5 * h * v;
  integrateConfiguration(m, q, s.u, 1.0, s.qt);
  f.accel(s.qt, s.v2, s.k2);
  configurationRate(m, s.u, s.v2, s.r2);
  s.v3 = v + 0.5 * h * s.k2;
  s.u = 0.5 * h * s.r2;
  integrateConfiguration(m, q, s.u, 1.0, s.qt);
  f.accel(s.qt, s.v3, s.k3);
  configurationRate(m, s.u, s.v3, s.r3);
  s.v4 = v + h * s.k3;
  s.u = h * s.r3;
  integrateConfiguration(m, q, s.u, 1.0, s.qt);
  f.accel(s.qt, s.v4, s.k4);
  configurationRate(m, s.u, s.v4, s.r4);
  s.u = (h / 6.0) * (v + 2.0 * s.r2 + 2.0 * s.r3 + s.r4);
  integrateConfiguration(m, q, s.u, 1.0, q);
  v += (h / 6.0) * (s.k1 + 2.0 * s.k2 + 2.0 * s.k3 + s.k4);
}

// Linearly-implicit Euler: the stiff terms are taken at the end of the step,
//   (H + h D + h^2 K) dv = h (F - h K v),  v+ = v + dv,  q+ = q (+) h v+,
// so springs of any stiffness stay stable (and dissipative) at a fixed h.
// \return false when the system matrix is singular.
template <typename Eval>
bool stepLinearlyImplicit(const Model& m, Eval& f, VectorX& q, VectorX& v, double h, IntegratorScratch& s) {
  f.accel(q, v, s.qdd);
  s.A = f.H();
  s.rhs = h * f.force();
  f.addStiffness(s.A, s.rhs, v, h);
  if (ltdlFactor(m.dof_parent, m.dof_run_start, s.A, s.diag) >= 0) return false;
  ltdlSolve(m.dof_parent, s.A, s.rhs);
  v += s.rhs;
  integrateConfiguration(m, q, v, h, q);
  return true;
}

}  // namespace igms
