// Forward dynamics, eq. (2) of Son et al. 2003:
//   qdd = H^-1 (U + U_E - C - G)
// with H from crba, C v + G - U_E from rnea at zero acceleration (U_E = J^T f_E
// from the external forces), and H factorised by the sparse L^T D L of ltdl.h.
#pragma once

#include <vector>

#include "core/model/data.h"

namespace igms {

// \return true and data.qdd; false when H is singular at q (a joint moves no
// mass), with data.singular_dof naming the dof. data.H keeps H's upper triangle
// (the lower part is stale: use H.selfadjointView<Eigen::Upper>()), data.Hfact
// its factors, data.bias holds C v + G - U_E.
bool forwardDynamics(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX& tau,
                     const std::vector<Force>* fext = nullptr);

// The same with data.liMi and data.oMi already at q (bodyKinematics placed them).
bool forwardDynamicsAtPoses(const Model& model, Data& data, const VectorX& v, const VectorX& tau,
                            const std::vector<Force>* fext = nullptr);

// The same with data.liMi at q and data.bias = b(q, v) - J^T f_E already computed there
// (rneaAndBias, beside a controller's inverse dynamics); world_poses: data.oMi is at q too.
bool forwardDynamicsAtBias(const Model& model, Data& data, const VectorX& tau, bool world_poses = false);

// The dof's joint name, for messages about data.singular_dof.
std::string dofName(const Model& model, int dof);

}  // namespace igms
