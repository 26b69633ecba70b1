#include "core/dynamics/ltdl.h"

#include <cmath>
#include <cstddef>

namespace igms {

// Raw columns throughout: the updates are a few entries long, too short for a
// vector expression's set-up, and a run of consecutive dofs is a plain loop the
// compiler vectorises (walking dof_parent one entry at a time is a chain of
// dependent loads).

int ltdlFactor(const std::vector<int>& lambda, const std::vector<int>& run_start, MatrixX& H, VectorX& diag) {
  const int n = static_cast<int>(H.rows());
  diag = H.diagonal();
  double* const data = H.data();
  for (int k = n - 1; k >= 0; --k) {
    double* const hk = data + static_cast<std::ptrdiff_t>(k) * n;
    const double d = hk[k];
    // A pivot that cancels to round-off of its own diagonal entry is zero.
    if (!std::isfinite(d) || !(d > kSingularPivot * diag[k])) return k;
    // Upper triangle (H(i, k), i an ancestor of k): ancestors walk up a column.
    for (int i = lambda[k]; i >= 0; i = lambda[i]) {
      double* const hi = data + static_cast<std::ptrdiff_t>(i) * n;
      const double a = hk[i] / d;
      // Ancestors of i come in runs of consecutive dofs (a chain segment).
      for (int j = i; j >= 0;) {
        const int r = run_start[j];
        for (int t = r; t <= j; ++t) hi[t] -= a * hk[t];
        j = lambda[r];
      }
      hk[i] = a;
    }
  }
  return -1;
}

void ltdlSolve(const std::vector<int>& lambda, const std::vector<int>& run_start, const MatrixX& LD, VectorX& b) {
  const int n = static_cast<int>(b.size());
  const double* const data = LD.data();
  double* const x = b.data();
  for (int k = n - 1; k >= 0; --k) {  // L^T z = b
    const double* const lk = data + static_cast<std::ptrdiff_t>(k) * n;
    const double xk = x[k];
    for (int j = lambda[k]; j >= 0;) {
      const int r = run_start[j];
      for (int t = r; t <= j; ++t) x[t] -= lk[t] * xk;
      j = lambda[r];
    }
  }
  for (int k = 0; k < n; ++k) x[k] /= data[static_cast<std::ptrdiff_t>(k) * n + k];  // D y = z
  for (int k = 0; k < n; ++k) {                                                    // L x = y
    // Two partial sums: one chain of dependent subtractions per dof was the solve's critical path.
    const double* const lk = data + static_cast<std::ptrdiff_t>(k) * n;
    double even = 0.0, odd = 0.0;
    for (int j = lambda[k]; j >= 0;) {
      const int r = run_start[j];
      int t = r;
      for (; t + 1 <= j; t += 2) {
        even += lk[t] * x[t];
        odd += lk[t + 1] * x[t + 1];
      }
      if (t == j) even += lk[t] * x[t];
      j = lambda[r];
    }
    x[k] -= even + odd;
  }
}

}  // namespace igms
