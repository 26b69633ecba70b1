#include "core/dynamics/ltdl.h"

#include <cmath>
#include <cstddef>

#include "core/model/ancestor_runs.h"

namespace igms {

// Raw columns throughout: the updates are a few entries long, too short for a
// vector expression's set-up; each run of ancestors is a plain loop.

int ltdlFactorBlock(const std::vector<int>& lambda, const std::vector<int>& run_start, TreeMatrix& H, VectorX& diag,
                    int b) {
  const int begin = H.blockBegin(b), end = H.blockEnd(b);
  for (int k = begin; k < end; ++k) diag[k] = H.diagonal(k);
  for (int k = end - 1; k >= begin; --k) {
    double* const hk = H.column(k);
    const double d = hk[k];
    // A pivot that cancels to round-off of its own diagonal entry is zero.
    if (!std::isfinite(d) || !(d > kSingularPivot * diag[k])) return k;
    // Upper triangle (H(i, k), i an ancestor of k): ancestors walk up a column.
    for (int i = lambda[k]; i >= 0; i = lambda[i]) {
      double* const hi = H.column(i);
      const double a = hk[i] / d;
      forEachAncestorRun(lambda, run_start, i, [&](int r, int j) {
        for (int t = r; t <= j; ++t) hi[t] -= a * hk[t];
      });
      hk[i] = a;
    }
  }
  return -1;
}

// Block by block from the last dof down (no dof's ancestors leave its block): the order of every
// update is that of one pass over all dofs.
int ltdlFactor(const std::vector<int>& lambda, const std::vector<int>& run_start, TreeMatrix& H, VectorX& diag,
               const std::vector<char>* factored) {
  for (int b = H.blocks() - 1; b >= 0; --b) {
    if (factored && (*factored)[static_cast<size_t>(b)]) continue;
    const int k = ltdlFactorBlock(lambda, run_start, H, diag, b);
    if (k >= 0) return k;
  }
  return -1;
}

void ltdlSolve(const std::vector<int>& lambda, const std::vector<int>& run_start, const TreeMatrix& LD, VectorX& b) {
  const int n = static_cast<int>(b.size());
  double* const x = b.data();
  for (int k = n - 1; k >= 0; --k) {  // L^T z = b
    const double* const lk = LD.column(k);
    const double xk = x[k];
    forEachAncestorRun(lambda, run_start, lambda[k], [&](int r, int j) {
      for (int t = r; t <= j; ++t) x[t] -= lk[t] * xk;
    });
  }
  for (int k = 0; k < n; ++k) x[k] /= LD.diagonal(k);  // D y = z
  for (int k = 0; k < n; ++k) {                                                    // L x = y
    // Two partial sums: one chain of dependent subtractions per dof was the solve's critical path.
    const double* const lk = LD.column(k);
    double even = 0.0, odd = 0.0;
    forEachAncestorRun(lambda, run_start, lambda[k], [&](int r, int j) {
      int t = r;
      for (; t + 1 <= j; t += 2) {
        even += lk[t] * x[t];
        odd += lk[t + 1] * x[t + 1];
      }
      if (t == j) even += lk[t] * x[t];
    });
    x[k] -= even + odd;
  }
}

}  // namespace igms
