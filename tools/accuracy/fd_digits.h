// How exactly forward dynamics inverts inverse dynamics on a model, against
// the conditioning of H: the shared measurement of the stress tests.
#pragma once

#include <Eigen/Eigenvalues>
#include <random>

#include "core/dynamics/aba.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/model/configuration.h"

namespace igms::accuracy {

struct FdDigits {
  double worst_cond = 0;   // largest cond(H) over the states
  double worst_fd = 0;     // max |FD(ID(a)) - a| / |a|
  double worst_aba = 0;    // max |ABA - LDL^T| / |LDL^T|
  bool within_bound = true;  // both errors <= max(floor, cond(H) * per_cond) in every state
};

inline FdDigits measureFdDigits(const Model& m, int states, unsigned seed, double per_cond, double floor = 0.0) {
  Data d(m);
  std::mt19937 rng(seed);
  FdDigits out;
  for (int s = 0; s < states; ++s) {
    const VectorX q = randomConfiguration(m, rng), v = randomVector(m.nv, rng), a = randomVector(m.nv, rng);
    const VectorX tau = rnea(m, d, q, v, a);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<MatrixX>(crba(m, d, q).dense()).eigenvalues();
    const double cond = ev.maxCoeff() / ev.minCoeff();
    if (!forwardDynamics(m, d, q, v, tau)) return FdDigits{cond, INFINITY, INFINITY, false};
    const VectorX ldlt = d.qdd;
    if (!aba(m, d, q, v, tau)) return FdDigits{cond, INFINITY, INFINITY, false};
    const double fd = (ldlt - a).norm() / a.norm(), ab = (d.qdd - ldlt).norm() / ldlt.norm();
    const double bound = std::max(floor, cond * per_cond);
    out.within_bound = out.within_bound && fd <= bound && ab <= bound;
    out.worst_fd = std::max(out.worst_fd, fd);
    out.worst_aba = std::max(out.worst_aba, ab);
    out.worst_cond = std::max(out.worst_cond, cond);
  }
  return out;
}

}  // namespace igms::accuracy
