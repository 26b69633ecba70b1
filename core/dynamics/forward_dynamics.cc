#include "core/dynamics/forward_dynamics.h"

#include <algorithm>

#include "core/dynamics/crba.h"
#include "core/dynamics/ltdl.h"
#include "core/dynamics/rnea.h"
#include "core/model/ancestor_runs.h"

namespace igms {

// qdd from data.bias, at the placements bias left: H (upper triangle), its factors, the solve.
bool forwardDynamicsAtBias(const Model& model, Data& data, const VectorX& tau, bool world_poses) {
  if (world_poses) crbaUpperAtPoses(model, data);  // H, at the poses bodyKinematics left
  else crbaUpperAtPlacements(model, data);         // H, at the placements bias left
  data.rhs = tau - data.bias;          // U + U_E - C - G
  // The factorisation reads and writes the ancestor entries of the upper triangle only (its
  // fill-in stays there): copy those, run by run; on a humanoid half the triangle is zeros.
  const int n = model.nv;
  for (int c = 0; c < n; ++c) {
    const double* const from = data.H.column(c);
    double* const to = data.Hfact.column(c);
    forEachAncestorRun(model.dof_parent, model.dof_run_start, c,
                       [&](int r, int j) { std::copy(from + r, from + j + 1, to + r); });
  }
  data.singular_dof = ltdlFactor(model.dof_parent, model.dof_run_start, data.Hfact, data.diag);
  if (data.singular_dof >= 0) return false;
  ltdlSolve(model.dof_parent, model.dof_run_start, data.Hfact, data.rhs);
  data.qdd = data.rhs;
  return true;
}

bool forwardDynamics(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX& tau,
                     const std::vector<Force>* fext) {
  bias(model, data, q, v, fext);  // C v + G - U_E
  return forwardDynamicsAtBias(model, data, tau);
}

bool forwardDynamicsAtPoses(const Model& model, Data& data, const VectorX& v, const VectorX& tau,
                            const std::vector<Force>* fext) {
  biasAtPlacements(model, data, v, fext);
  return forwardDynamicsAtBias(model, data, tau, true);
}

std::string dofName(const Model& model, int dof) {
  for (int i = 0; i < model.nb; ++i)
    if (dof >= model.v_index[i] && dof < model.v_index[i] + model.joint_nv[i]) return model.joint_name[i];
  return "?";
}

}  // namespace igms
