// Lemke's complementary pivoting for a linear complementarity problem: find z with
//   w = M z + q >= 0, z >= 0, z^T w = 0.
// Where the problem is copositive-plus and feasible it ends with an answer (Cottle, Pang and Stone,
// "The Linear Complementarity Problem", 4.4); unlike principal pivoting (contact_active_set.h), it does
// not need M to be a P-matrix. The contact solve poses it where its active set has no answer: a
// frictional system with Coulomb's cone replaced by a polygon (Stewart and Trinkle's linearised cone),
// whose LCP Lemke's method solves (contact_linearised_cone.cc). Ties in the ratio test are broken
// lexicographically (no cycling on degenerate problems: a box's four corners on a plane).
// A dense tableau, allocated once for problems of up to `capacity` unknowns: nothing allocates in solve().
#pragma once

#include <vector>

#include "core/model/tree_matrix.h"

namespace igms {

class Lemke {
 public:
  explicit Lemke(int capacity);

  int capacity() const { return capacity_; }
  // M: n x n (the top-left corner of a matrix of at least that size), q: n. z (at least n): the answer.
  // \return whether it ended with one, checked against M and q (false: a ray, the pivot limit, or
  // round-off past repair).
  bool solve(const Eigen::Ref<const MatrixX>& M, const Eigen::Ref<const VectorX>& q, int n, Eigen::Ref<VectorX> z);
  // The last solve's pivots.
  int pivots() const { return pivots_; }

 private:
  void pivot(int n, int row, int column);
  bool finish(const Eigen::Ref<const MatrixX>& M, const Eigen::Ref<const VectorX>& q, int n, Eigen::Ref<VectorX> z);
  int capacity_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> tableau_;  // n x (2n + 1): columns w (0 .. n), z (n .. 2n), the artificial z0 (2n)
  VectorX rhs_;
  std::vector<int> basis_;  // per row: the variable basic in it
  std::vector<int> chosen_;  // finish(): the basic z
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> work_;
  VectorX x_;
  int pivots_ = 0;
};

}  // namespace igms
