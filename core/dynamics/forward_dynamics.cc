#include "core/dynamics/forward_dynamics.h"

#include "core/dynamics/crba.h"
#include "core/dynamics/ltdl.h"
#include "core/dynamics/rnea.h"

namespace igms {

bool forwardDynamics(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX& tau,
                     const std::vector<Force>* fext) {
  const VectorX& b = bias(model, data, q, v, fext);  // C v + G - U_E
  crbaUpperAtPlacements(model, data);                // H, at the placements bias left
  data.rhs = tau - b;                                // U + U_E - C - G
  // The factorisation reads and writes the upper triangle only: no mirror, no full copy.
  data.Hfact.triangularView<Eigen::Upper>() = data.H;
  data.singular_dof = ltdlFactor(model.dof_parent, model.dof_run_start, data.Hfact, data.diag);
  if (data.singular_dof >= 0) return false;
  ltdlSolve(model.dof_parent, data.Hfact, data.rhs);
  data.qdd = data.rhs;
  return true;
}

std::string dofName(const Model& model, int dof) {
  for (int i = 0; i < model.nb; ++i)
    if (dof >= model.v_index[i] && dof < model.v_index[i] + model.joint_nv[i]) return model.joint_name[i];
  return "?";
}

}  // namespace igms
