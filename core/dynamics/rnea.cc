// Recursive Newton-Euler, as in Son et al. 2003 (after Craig), in spatial form.
//
// Paper symbol            code (body i coordinates)
//   i omega_i, i v_i      data.v[i]      spatial velocity [v; w]
//   i omegadot_i, i vdot_i data.a[i]     spatial acceleration; gravity enters as
//                                        the base acceleration -g, as in 1Vdot = 1R_0 (vdot_C0 + g)
//   iZ_i thetadot_i       jointMotion(model, i, v)
//   iF_i, iN_i            I_i a_i + v_i x* I_i v_i  (m vdot_Ci and I omegadot + omega x I omega)
//   0f_E, jc_j            fext[i] (external_force.h)
//   if_i, in_i            data.f[i]
//   sum over O_i          children add their force into the parent's (inward iteration)
#include "core/dynamics/rnea.h"

#include "core/model/joint.h"

namespace igms {
namespace {

// q: place each joint at q on the way out; nullptr: data.liMi already holds the placements.
template <bool kHasAcceleration>
void rneaPasses(const Model& model, Data& data, const VectorX* q, const VectorX& v, const VectorX* a,
                const std::vector<Force>* fext, VectorX& tau) {
  const Motion a_world{-model.gravity, Vector3::Zero()};
  // Outward iteration: velocities and accelerations from the base to the leaves.
  for (int i = 0; i < model.nb; ++i) {
    if (q) placeJoint(model, i, *q, data.liMi[i]);
    const SE3& X = data.liMi[i];
    const Motion vJ = jointMotion(model, i, v);
    const int p = model.parent[i];
    Motion& vi = data.v[i];
    Motion& ai = data.a[i];
    if (p < 0) {
      vi = vJ;
      ai = X.actInv(a_world);
    } else {
      vi = X.actInv(data.v[p]) + vJ;
      ai = X.actInv(data.a[p]) + vi.cross(vJ);
    }
    if constexpr (kHasAcceleration) ai += jointMotion(model, i, *a);
    // iF_i and iN_i: the body's rate of change of momentum.
    const SpatialInertia& I = model.inertia[i];
    data.f[i] = I * ai + crossForce(vi, I * vi);
    if (fext) data.f[i] -= (*fext)[i];
  }
  // Inward iteration: forces from the leaves to the base, branches summed.
  for (int i = model.nb - 1; i >= 0; --i) {
    projectOnSubspace(model, i, data.f[i], tau.segment(model.v_index[i], model.joint_nv[i]));
    const int p = model.parent[i];
    if (p >= 0) data.f[p] += data.liMi[i].act(data.f[i]);
  }
}

// rneaPasses twice at one state, sharing what the two have in common (placements, velocities,
// velocity products, v x* I v): the controller's (a_cmd, f_cmd -> tau; `a` null: zero acceleration,
// no fext) and the bias's (a, f -> bias, with fext). Each is computed with the same operations in the
// same order as rneaPasses computes it alone, so both are bit for bit what the two calls give.
void rneaAndBiasPasses(const Model& model, Data& data, const VectorX* q, const VectorX& v, const VectorX* a,
                       const std::vector<Force>* fext) {
  const Motion a_world{-model.gravity, Vector3::Zero()};
  for (int i = 0; i < model.nb; ++i) {
    if (q) placeJoint(model, i, *q, data.liMi[i]);
    const SE3& X = data.liMi[i];
    const Motion vJ = jointMotion(model, i, v);
    const int p = model.parent[i];
    Motion& vi = data.v[i];
    Motion& ai = data.a[i];
    Motion& ci = data.a_cmd[i];
    if (p < 0) {
      vi = vJ;
      ai = X.actInv(a_world);
      ci = ai;
    } else {
      vi = X.actInv(data.v[p]) + vJ;
      const Motion vxvJ = vi.cross(vJ);
      ai = X.actInv(data.a[p]) + vxvJ;
      ci = a ? X.actInv(data.a_cmd[p]) + vxvJ : ai;
    }
    if (a) ci += jointMotion(model, i, *a);
    const SpatialInertia& I = model.inertia[i];
    data.f[i] = I * ai + crossForce(vi, I * vi);
    if (a) data.f_cmd[i] = I * ci + crossForce(vi, I * vi);
    else data.f_cmd[i] = data.f[i];
    if (fext) data.f[i] -= (*fext)[i];
  }
  for (int i = model.nb - 1; i >= 0; --i) {
    projectOnSubspace(model, i, data.f[i], data.bias.segment(model.v_index[i], model.joint_nv[i]));
    projectOnSubspace(model, i, data.f_cmd[i], data.tau.segment(model.v_index[i], model.joint_nv[i]));
    const int p = model.parent[i];
    if (p >= 0) {
      data.f[p] += data.liMi[i].act(data.f[i]);
      data.f_cmd[p] += data.liMi[i].act(data.f_cmd[i]);
    }
  }
}

}  // namespace

void rneaAndBias(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX* a,
                 const std::vector<Force>* fext) {
  rneaAndBiasPasses(model, data, &q, v, a, fext);
}

void rneaAndBiasAtPlacements(const Model& model, Data& data, const VectorX& v, const VectorX* a,
                             const std::vector<Force>* fext) {
  rneaAndBiasPasses(model, data, nullptr, v, a, fext);
}

const VectorX& rnea(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX& a,
                    const std::vector<Force>* fext) {
  rneaPasses<true>(model, data, &q, v, &a, fext, data.tau);
  return data.tau;
}

const VectorX& bias(const Model& model, Data& data, const VectorX& q, const VectorX& v,
                    const std::vector<Force>* fext) {
  rneaPasses<false>(model, data, &q, v, nullptr, fext, data.bias);
  return data.bias;
}

const VectorX& biasAtPlacements(const Model& model, Data& data, const VectorX& v, const std::vector<Force>* fext) {
  rneaPasses<false>(model, data, nullptr, v, nullptr, fext, data.bias);
  return data.bias;
}

}  // namespace igms
