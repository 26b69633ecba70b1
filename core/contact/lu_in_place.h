// Gaussian elimination with partial pivoting of a square block in place, and the two triangular
// solves: the active set's unsymmetric systems (a slipping friction's rows) and the basis Lemke's
// method ends on. Allocation-free, the order of every operation fixed.
#pragma once

#include <cmath>
#include <utility>

namespace igms {

// M: an n x n block (a view; overwritten by its factors), x: a view of n, in the right side, out the
// answer. \return no pivot was 0.
template <typename Block, typename Vector>
bool luSolveInPlace(Block M, Vector x, int n) {
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (std::abs(M(i, k)) > std::abs(M(p, k))) p = i;
    if (!(std::abs(M(p, k)) > 0.0)) return false;
    if (p != k) {
      M.row(k).swap(M.row(p));
      std::swap(x[k], x[p]);
    }
    const double d = M(k, k);
    for (int i = k + 1; i < n; ++i) {
      const double f = M(i, k) / d;
      if (f == 0.0) continue;
      M.row(i).tail(n - k - 1) -= f * M.row(k).tail(n - k - 1);
      x[i] -= f * x[k];
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    double v = x[k];
    for (int j = k + 1; j < n; ++j) v -= M(k, j) * x[j];
    x[k] = v / M(k, k);
  }
  return true;
}

}  // namespace igms
