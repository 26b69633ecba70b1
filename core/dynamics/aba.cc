// Articulated-body algorithm (Featherstone, RBDA table 7.1), in body coordinates.
//   pass 1 (outward): v_i, c_i = v_i x vJ, IA_i = I_i, pA_i = v_i x* I_i v_i - f_ext,i
//   pass 2 (inward):  U_i = IA_i S_i, D_i = S_i^T U_i, u_i = tau_i - S_i^T pA_i,
//                     the parent takes X^T (IA_i - U D^-1 U^T) X and X^T (pA_i + Ia c_i + U D^-1 u_i)
//   pass 3 (outward): qdd_i = D^-1 (u_i - U_i^T a'), a_i = a' + S_i qdd_i, a' = X a_p + c_i
// A floating root has S = 1 (6 x 6), so its D is IA itself.
#include "core/dynamics/aba.h"

#include <Eigen/Cholesky>
#include <cmath>

#include "core/model/joint.h"

namespace igms {

bool aba(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX& tau,
         const std::vector<Force>* fext) {
  const Motion a_world{-model.gravity, Vector3::Zero()};
  for (int i = 0; i < model.nb; ++i) {
    placeJoint(model, i, q, data.liMi[i]);
    const SE3& X = data.liMi[i];
    const Motion vJ = jointMotion(model, i, v);
    const int p = model.parent[i];
    if (p < 0) {
      data.v[i] = vJ;
      data.c[i] = Motion::Zero();
    } else {
      data.v[i] = X.actInv(data.v[p]) + vJ;
      data.c[i] = data.v[i].cross(vJ);
    }
    const SpatialInertia& I = model.inertia[i];
    data.IA[i] = I.matrix();
    Force pA = crossForce(data.v[i], I * data.v[i]);
    if (fext) pA -= (*fext)[i];
    data.pA[i] = pA.toVector();
  }
  data.singular_dof = -1;
  for (int i = model.nb - 1; i >= 0; --i) {
    const int iv = model.v_index[i];
    const int p = model.parent[i];
    if (model.joint_type[i] == JointType::Floating) {
      // The root: nothing to pass on; factorised in pass 3.
      continue;
    }
    const Vector6 S = subspaceColumn(model, i, 0).toVector();
    // IA S: a revolute joint's S is [0; axis], three columns of IA.
    const Vector6 Ui = model.joint_type[i] == JointType::Revolute ? Vector6(data.IA[i].rightCols<3>() * model.axis[i])
                                                                  : Vector6(data.IA[i] * S);
    const double D = S.dot(Ui);
    if (!(D > 0.0) || !std::isfinite(D)) {
      data.singular_dof = iv;
      return false;
    }
    data.U.col(iv) = Ui;
    data.Dinv[iv] = 1.0 / D;
    data.u[iv] = tau[iv] - S.dot(data.pA[i]);
    if (p < 0) continue;
    // Ia = IA - U D^-1 U^T, in place (IA_i is not needed again for a joint with one dof).
    Matrix6& Ia = data.IA[i];
    Ia.noalias() -= Ui * (Ui.transpose() * data.Dinv[iv]);
    const Vector6 pa = data.pA[i] + Ia * data.c[i].toVector() + Ui * (data.Dinv[iv] * data.u[iv]);
    addInertiaToParent(data.liMi[i], Ia, data.IA[p]);
    const Force pa_parent = data.liMi[i].act(Force{pa.head<3>(), pa.tail<3>()});
    data.pA[p].head<3>() += pa_parent.f;  // no Vector6 round trip: its narrow stores stall the read
    data.pA[p].tail<3>() += pa_parent.n;
  }
  for (int i = 0; i < model.nb; ++i) {
    const int iv = model.v_index[i];
    const int p = model.parent[i];
    const Motion a_parent = p < 0 ? data.liMi[i].actInv(a_world) : data.liMi[i].actInv(data.a[p]);
    const Motion a_sum = a_parent + data.c[i];  // a' = X a_p + c_i
    if (model.joint_type[i] == JointType::Floating) {
      const Vector6 a_prime = a_sum.toVector();
      Eigen::LLT<Matrix6> llt(data.IA[i]);
      if (llt.info() != Eigen::Success) {
        data.singular_dof = iv;
        return false;
      }
      const Vector6 qdd = llt.solve(tau.segment<6>(iv) - data.pA[i]) - a_prime;
      data.qdd.segment<6>(iv) = qdd;
      data.a[i] = Motion::fromVector(a_prime + qdd);
      continue;
    }
    const auto Ui = data.U.col(iv);
    const double qdd = data.Dinv[iv] * (data.u[iv] - Ui.head<3>().dot(a_sum.v) - Ui.tail<3>().dot(a_sum.w));
    data.qdd[iv] = qdd;
    data.a[i] = a_sum + subspaceColumn(model, i, 0) * qdd;
  }
  return true;
}

}  // namespace igms
