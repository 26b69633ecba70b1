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

#include "server/dynamics/ltdl.h"
#include "server/model/configuration.h"

namespace igms {

struct IntegratorScratch {
  explicit IntegratorScratch(const Model& m)
      : qdd(m.nv), k1(m.nv), k2(m.nv), k3(m.nv), k4(m.nv), v2(m.nv), v3(m.nv), v4(m.nv), vmid(m.nv), qt(m.nq),
        A(m.nv, m.nv), rhs(m.nv), diag(m.nv) {}
  VectorX qdd, k1, k2, k3, k4, v2, v3, v4, vmid, qt;
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

// Classic RK4 on (q, v), stages on the group; q advanced by the weighted mean velocity.
template <typename Eval>
void stepRk4(const Model& m, Eval& f, VectorX& q, VectorX& v, double h, IntegratorScratch& s) {
  // Stage i: q_i = q (+) c_i h v_{i-1}, v_i = v + c_i h k_{i-1}.
  f.accel(q, v, s.k1);
  s.v2 = v + 0.5 * h * s.k1;
  integrateConfiguration(m, q, v, 0.5 * h, s.qt);
  f.accel(s.qt, s.v2, s.k2);
  s.v3 = v + 0.5 * h * s.k2;
  integrateConfiguration(m, q, s.v2, 0.5 * h, s.qt);
  f.accel(s.qt, s.v3, s.k3);
  s.v4 = v + h * s.k3;
  integrateConfiguration(m, q, s.v3, h, s.qt);
  f.accel(s.qt, s.v4, s.k4);
  s.vmid = (v + 2.0 * s.v2 + 2.0 * s.v3 + s.v4) / 6.0;
  integrateConfiguration(m, q, s.vmid, h, q);
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
