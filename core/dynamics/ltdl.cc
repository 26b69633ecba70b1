#include "core/dynamics/ltdl.h"

#include <cmath>

namespace igms {

int ltdlFactor(const std::vector<int>& lambda, const std::vector<int>& run_start, MatrixX& H, VectorX& diag) {
  const int n = static_cast<int>(H.rows());
  diag = H.diagonal();
  for (int k = n - 1; k >= 0; --k) {
    const double d = H(k, k);
    // A pivot that cancels to round-off of its own diagonal entry is zero.
    if (!std::isfinite(d) || !(d > kSingularPivot * diag[k])) return k;
    // Upper triangle (H(i, k), i an ancestor of k): ancestors walk up a column.
    for (int i = lambda[k]; i >= 0; i = lambda[i]) {
      const double a = H(i, k) / d;
      // Ancestors of i come in runs of consecutive dofs (a chain segment):
      // update each run as one vector operation.
      for (int j = i; j >= 0;) {
        const int r = run_start[j];
        H.col(i).segment(r, j - r + 1) -= a * H.col(k).segment(r, j - r + 1);
        j = lambda[r];
      }
      H(i, k) = a;
    }
  }
  return -1;
}

void ltdlSolve(const std::vector<int>& lambda, const MatrixX& LD, VectorX& b) {
  const int n = static_cast<int>(b.size());
  for (int k = n - 1; k >= 0; --k)  // L^T z = b
    for (int i = lambda[k]; i >= 0; i = lambda[i]) b[i] -= LD(i, k) * b[k];
  for (int k = 0; k < n; ++k) b[k] /= LD(k, k);  // D y = z
  for (int k = 0; k < n; ++k)                    // L x = y
    for (int i = lambda[k]; i >= 0; i = lambda[i]) b[k] -= LD(i, k) * b[i];
}

}  // namespace igms
