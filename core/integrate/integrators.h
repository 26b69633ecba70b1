// One step of (q, v) under qdd = f(q, v), for three schemes, and the one
// dispatch every caller uses (integrateStep). q moves on the configuration
// group (integrateConfiguration), so a floating base stays on SO(3) with a
// unit quaternion.
//
// The evaluator f is a value with no hidden inputs: whatever it needs (the
// controller torque, the user's coupling) was bound into it before the step.
// Its contract:
//   using Evaluation = ...;                 // what one evaluation returns, with a VectorX qdd
//   Evaluation makeEvaluation() const;      // sized once (allocates)
//   void evaluate(const VectorX& q, const VectorX& v, Evaluation& out);
// and, for the linearly-implicit scheme, right after evaluate(q, v, at):
//   void linearSystem(const Evaluation& at, const VectorX& v, double h, TreeMatrix& A, VectorX& rhs,
//                     std::vector<char>& factored);
//       A = H + h D + h^2 K, rhs = h (F - h K v), where F = H qdd and
//       K = -dF/dq, D = -dF/dv of the stiff terms (couplings, joint damping),
//       symmetric, within H's sparsity; only the upper triangle is read (the
//       factorisation's), so an evaluator may leave the lower one stale. It may
//       write a block of A as its factors already (ltdl.h: a free body's block,
//       the same every step) and set its entry of `factored` (zero on entry).
// Every scheme leaves the evaluation at the step's start state in
// scratch.start: that is what a step reports (acceleration, force), never
// whatever a later stage left behind.
//
// An evaluator with contact (an environment) also has
//   bool hasContacts() const;
//   void constrain(const VectorX& v0, double h, const TreeMatrix* factored, VectorX& v, VectorX& v_position);
// which the two Euler schemes call after their unconstrained velocity update: v0 the start velocity,
// v in v_free and out v+, factored the step's matrix (the linearly-implicit A, factored; null: H's),
// and the positions then move with v_position (integrateContactStep: floating joints on R^3 x SO(3)).
// RK4 has no contact step (a scene with contact refuses it).
//
// An evaluator whose model has free bodies may also have
//   FreeBodyMotion* freeBodies();   // null: none
// (free_body_motion.h): the two Euler schemes then take a free body's rotation implicitly before the
// contact solve, and move a free body the solve left alone by its exact, conservative step.
#pragma once

#include <algorithm>
#include <type_traits>
#include <vector>

#include "core/dynamics/ltdl.h"
#include "core/integrate/free_body_motion.h"
#include "core/integrate/integrator_kind.h"
#include "core/model/configuration.h"

namespace igms {

template <typename Evaluation>
struct IntegratorScratch {
  template <typename Eval>
  IntegratorScratch(const Model& m, const Eval& f)
      : start(f.makeEvaluation()), stage(f.makeEvaluation()), k2(m.nv), k3(m.nv), v2(m.nv), v3(m.nv),
        v4(m.nv), u(m.nv), r2(m.nv), r3(m.nv), r4(m.nv), qt(m.nq), A(m), rhs(m.nv), diag(m.nv),
        v_free(m.nv), factored(static_cast<size_t>(A.blocks()), 0) {}
  Evaluation start;  // f at the step's start state
  Evaluation stage;  // RK4's later stages
  VectorX k2, k3, v2, v3, v4, u, r2, r3, r4, qt;
  TreeMatrix A;
  VectorX rhs, diag;
  VectorX v_free;  // the contact solve's input
  std::vector<char> factored;  // per block of A: written as its factors by linearSystem
};

// Does the evaluator take a contact step (constrain)?
template <typename T, typename = void>
struct HasContactStep : std::false_type {};
template <typename T>
struct HasContactStep<T, std::void_t<decltype(&T::constrain)>> : std::true_type {};

// Does the evaluator move free bodies by their own step (freeBodies)?
template <typename T, typename = void>
struct HasFreeBodies : std::false_type {};
template <typename T>
struct HasFreeBodies<T, std::void_t<decltype(&T::freeBodies)>> : std::true_type {};

// The Euler schemes' update once v holds the unconstrained v+ (v_start: the step's start velocity):
// with contact, the world-velocity step, the free bodies' implicit rotation, the contact solve on
// `factored` and the contact step's positions; without, q (+) h v. Either way the free bodies the
// solve left alone then take their exact step.
template <typename Eval, typename Scratch>
void finishEulerStep(const Model& m, Eval& f, VectorX& q, VectorX& v, const VectorX& v_start, double h,
                     const TreeMatrix* factored, Scratch& s) {
  FreeBodyMotion* bodies = nullptr;
  if constexpr (HasFreeBodies<Eval>::value) {
    bodies = f.freeBodies();
    if (bodies && bodies->empty()) bodies = nullptr;
    if (bodies) bodies->begin(q, v_start);
  }
  bool contact = false;
  if constexpr (HasContactStep<Eval>::value) {
    if (f.hasContacts()) {
      contact = true;
      worldVelocityStep(m, v_start, h, v);
      if constexpr (HasFreeBodies<Eval>::value) {
        if (bodies) {
          bodies->unconstrained(h, v);
          s.v_free = v;
        }
      }
      f.constrain(v_start, h, factored, v, s.v3);
      if constexpr (HasFreeBodies<Eval>::value) {
        if (bodies) bodies->markUntouched(s.v_free, v, s.v3);
      }
      integrateContactStep(m, q, v, s.v3, h, q);
    }
  }
  if (!contact) integrateConfiguration(m, q, v, h, q);
  if constexpr (HasFreeBodies<Eval>::value) {
    if (bodies) {
      if (!contact) bodies->markAllUntouched();
      bodies->finish(h, q, v);
    }
  }
}

// v+ = v + h f(q, v); q+ = q (+) h v+. Stable for a spring only while k h^2 / m < 4.
template <typename Eval, typename Scratch>
void stepSemiImplicitEuler(const Model& m, Eval& f, VectorX& q, VectorX& v, double h, Scratch& s) {
  f.evaluate(q, v, s.start);
  s.v2 = v;
  v += h * s.start.qdd;
  finishEulerStep(m, f, q, v, s.v2, h, nullptr, s);
}

// Classic RK4 on (q, v), as Runge-Kutta-Munthe-Kaas on the group: stage i
// sits at q (+) u_i, and its configuration rate is v_i carried back to q's
// tangent space through dexp^{-1} (configurationRate). Without that correction
// a floating base would be only second order.
template <typename Eval, typename Scratch>
void stepRk4(const Model& m, Eval& f, VectorX& q, VectorX& v, double h, Scratch& s) {
  f.evaluate(q, v, s.start);                      // stage 1: u = 0, rate v
  const VectorX& k1 = s.start.qdd;
  s.v2 = v + 0.5 * h * k1;
  s.u = 0.5 * h * v;
  integrateConfiguration(m, q, s.u, 1.0, s.qt);
  f.evaluate(s.qt, s.v2, s.stage);
  s.k2 = s.stage.qdd;
  configurationRate(m, s.u, s.v2, s.r2);
  s.v3 = v + 0.5 * h * s.k2;
  s.u = 0.5 * h * s.r2;
  integrateConfiguration(m, q, s.u, 1.0, s.qt);
  f.evaluate(s.qt, s.v3, s.stage);
  s.k3 = s.stage.qdd;
  configurationRate(m, s.u, s.v3, s.r3);
  s.v4 = v + h * s.k3;
  s.u = h * s.r3;
  integrateConfiguration(m, q, s.u, 1.0, s.qt);
  f.evaluate(s.qt, s.v4, s.stage);
  configurationRate(m, s.u, s.v4, s.r4);
  s.u = (h / 6.0) * (v + 2.0 * s.r2 + 2.0 * s.r3 + s.r4);
  integrateConfiguration(m, q, s.u, 1.0, q);
  v += (h / 6.0) * (k1 + 2.0 * s.k2 + 2.0 * s.k3 + s.stage.qdd);
}

// Linearly-implicit Euler: the stiff terms are taken at the end of the step,
//   (H + h D + h^2 K) dv = h (F - h K v),  v+ = v + dv,  q+ = q (+) h v+,
// so springs of any stiffness stay stable (and dissipative) at a fixed h.
// \return false when the system matrix is singular.
template <typename Eval, typename Scratch>
bool stepLinearlyImplicit(const Model& m, Eval& f, VectorX& q, VectorX& v, double h, Scratch& s) {
  f.evaluate(q, v, s.start);
  std::fill(s.factored.begin(), s.factored.end(), 0);
  f.linearSystem(s.start, v, h, s.A, s.rhs, s.factored);
  if (ltdlFactor(m.dof_parent, m.dof_run_start, s.A, s.diag, &s.factored) >= 0) return false;
  ltdlSolve(m.dof_parent, m.dof_run_start, s.A, s.rhs);
  s.v2 = v;
  v += s.rhs;
  finishEulerStep(m, f, q, v, s.v2, h, &s.A, s);
  return true;
}

// One step of the scheme `kind`: the only switch on the scheme in igms.
// \return false when the linearly-implicit system was singular. Either way
// s.start holds f at the start state.
template <typename Eval, typename Scratch>
bool integrateStep(IntegratorKind kind, const Model& m, Eval& f, VectorX& q, VectorX& v, double h, Scratch& s) {
  switch (kind) {
    case IntegratorKind::SemiImplicitEuler: stepSemiImplicitEuler(m, f, q, v, h, s); return true;
    case IntegratorKind::Rk4: stepRk4(m, f, q, v, h, s); return true;
    case IntegratorKind::LinearlyImplicit: return stepLinearlyImplicit(m, f, q, v, h, s);
  }
  return false;
}

}  // namespace igms
