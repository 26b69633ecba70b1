// The integrators' evaluator (integrators.h) for a robot left to itself:
// forward dynamics with joint torques tau = -d qdot - k q, the model's joint
// damping d (when enabled) and a joint spring of stiffness k towards q = 0.
// Both terms are stiff; the linearly-implicit scheme takes them implicitly.
// Used by the integrator tests and the accuracy and stiffness sweeps.
#pragma once

#include <limits>

#include "core/dynamics/forward_dynamics.h"

namespace igms {

class PassiveJointDynamics {
 public:
  PassiveJointDynamics(const Model& model, bool joint_damping, double spring_k = 0.0)
      : m_(model), damping_(joint_damping), k_(spring_k), d_(model), tau_(model.nv), F_(model.nv) {}

  // qdd is NaN when H is singular (the integrators' callers check finiteness).
  void accel(const VectorX& q, const VectorX& v, VectorX& qdd) {
    for (int i = 0; i < m_.nv; ++i) tau_[i] = -(damping_ ? m_.damping[i] * v[i] : 0.0) - k_ * q[i];
    if (!forwardDynamics(m_, d_, q, v, tau_)) {
      qdd.setConstant(std::numeric_limits<double>::quiet_NaN());
      return;
    }
    F_ = tau_ - d_.bias;
    qdd = d_.qdd;
  }
  const MatrixX& H() const { return d_.H; }
  const VectorX& force() const { return F_; }
  void addStiffness(MatrixX& A, VectorX& rhs, const VectorX& v, double h) {
    for (int i = 0; i < m_.nv; ++i) {
      A(i, i) += h * (damping_ ? m_.damping[i] : 0.0) + h * h * k_;
      rhs[i] -= h * h * k_ * v[i];
    }
  }

 private:
  const Model& m_;
  bool damping_;
  double k_;
  Data d_;
  VectorX tau_, F_;
};

}  // namespace igms
