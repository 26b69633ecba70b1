#include "server/dynamics/ltdl.h"

#include <cmath>

namespace igms {

int ltdlFactor(const std::vector<int>& lambda, MatrixX& H, VectorX& diag) {
  const int n = static_cast<int>(H.rows());
  diag = H.diagonal();
  for (int k = n - 1; k >= 0; --k) {
    const double d = H(k, k);
    // A pivot that cancels to round-off of its own diagonal entry is zero.
    if (!std::isfinite(d) || !(d > kSingularPivot * diag[k])) return k;
    for (int i = lambda[k]; i >= 0; i = lambda[i]) {
      const double a = H(k, i) / d;
      for (int j = i; j >= 0; j = lambda[j]) H(i, j) -= a * H(k, j);
      H(k, i) = a;
    }
  }
  return -1;
}

void ltdlSolve(const std::vector<int>& lambda, const MatrixX& LD, VectorX& b) {
  const int n = static_cast<int>(b.size());
  for (int k = n - 1; k >= 0; --k)  // L^T z = b
    for (int i = lambda[k]; i >= 0; i = lambda[i]) b[i] -= LD(k, i) * b[k];
  for (int k = 0; k < n; ++k) b[k] /= LD(k, k);  // D y = z
  for (int k = 0; k < n; ++k)                    // L x = y
    for (int i = lambda[k]; i >= 0; i = lambda[i]) b[k] -= LD(k, i) * b[i];
}

}  // namespace igms
