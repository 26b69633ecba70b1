// The integrators' evaluator (integrators.h) for a robot left to itself:
// forward dynamics with joint torques tau = -d qdot - k q, the model's joint
// damping d (when enabled) and a joint spring of stiffness k towards q = 0.
// Both terms are stiff; the linearly-implicit scheme takes them implicitly.
// Used by the integrator tests and the accuracy and stiffness sweeps.
#pragma once

#include <limits>

#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/joint_damping.h"

namespace igms {

class PassiveJointDynamics {
 public:
  struct Evaluation {
    VectorX qdd;  // NaN when H is singular (the integrators' callers check finiteness)
    VectorX F;    // H qdd
  };

  PassiveJointDynamics(const Model& model, bool joint_damping, double spring_k = 0.0)
      : m_(model), damping_(joint_damping), k_(spring_k), d_(model) {}

  Evaluation makeEvaluation() const { return {VectorX::Zero(m_.nv), VectorX::Zero(m_.nv)}; }

  void evaluate(const VectorX& q, const VectorX& v, Evaluation& out) {
    out.F = -k_ * q.head(m_.nv);
    if (damping_) addJointDamping(m_, v, out.F);
    if (!forwardDynamics(m_, d_, q, v, out.F)) {
      out.qdd.setConstant(std::numeric_limits<double>::quiet_NaN());
      return;
    }
    out.F -= d_.bias;
    out.qdd = d_.qdd;
  }

  void linearSystem(const Evaluation& at, const VectorX& v, double h, TreeMatrix& A, VectorX& rhs,
                    std::vector<char>& /*factored: none here*/) const {
    A.assign(d_.H);  // forwardDynamics leaves H's upper triangle (the lower one is not read)
    rhs = h * at.F;
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
};

}  // namespace igms
