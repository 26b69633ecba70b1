// Data: the preallocated workspace of the algorithms for one Model. Built once
// (allocates); after that no algorithm allocates. One Data per thread.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/model/model.h"
#include "core/model/tree_matrix.h"

namespace igms {

using Matrix6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;

struct Data {
  explicit Data(const Model& model);

  // Kinematics (forwardKinematics / the recursive algorithms).
  std::vector<SE3> liMi;     // body i in its parent body (iR_p, iP_i of the paper, inverted)
  std::vector<SE3> oMi;      // body i in the world
  std::vector<SE3> oMf;      // every frame (URDF link) in the world
  std::vector<Motion> v;     // body spatial velocity, body coordinates
  std::vector<Motion> a;     // body spatial acceleration (gravity folded in for rnea)
  std::vector<Force> f;      // rnea: force transmitted by joint i, body i coordinates
  std::vector<Force> fext;   // external wrench on body i, body coordinates

  // rnea / bias results.
  VectorX tau;               // rnea (and rneaAndBias): generalised force
  VectorX bias;              // b(q, v) = C v + G

  // crba and the factorisation of H (sparse LDL^T along the tree).
  std::vector<SpatialInertia> Ic;  // crba: composite inertia of the subtree, world axes
  Matrix6X S_world;                // crba: motion subspace of every dof, world axes, rows [v; w]
  TreeMatrix H;                    // joint-space inertia: crba fills both triangles, forwardDynamics the upper one
  TreeMatrix Hfact;                // L^T D L factors of H, same sparsity
  VectorX qdd;                     // forward dynamics result
  VectorX rhs;                     // forward dynamics scratch
  VectorX diag;                    // factorisation scratch
  int singular_dof = -1;           // dof whose pivot vanished in the last factorisation

  // Articulated-body algorithm.
  std::vector<Matrix6> IA;
  std::vector<Vector6> pA;
  std::vector<Motion> c;     // velocity-product acceleration v x vJ
  Matrix6X U;                // IA S per dof
  VectorX Dinv, u;

  // Jacobians.
  Matrix6X J;                // 6 x nv frame Jacobian scratch
  std::vector<int> support;  // frameJacobian: the bodies from the frame's up to the root

  // rneaAndBias: the controller's pass beside the bias's (data.a, data.f).
  std::vector<Motion> a_cmd;  // its body accelerations
  std::vector<Force> f_cmd;   // its transmitted forces
};

}  // namespace igms
