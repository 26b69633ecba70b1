#include "core/contact/lemke.h"

#include <algorithm>
#include <cmath>

#include "core/contact/lu_in_place.h"

namespace igms {

Lemke::Lemke(int capacity)
    : capacity_(capacity),
      tableau_(capacity, 2 * capacity + 1),
      rhs_(capacity),
      basis_(static_cast<size_t>(capacity)),
      chosen_(static_cast<size_t>(capacity)),
      work_(capacity, capacity),
      x_(capacity) {}

// Gauss-Jordan on the tableau: `column`'s variable becomes basic in `row`.
void Lemke::pivot(int n, int row, int column) {
  auto T = tableau_.topLeftCorner(n, 2 * n + 1);
  const double p = T(row, column);
  T.row(row) /= p;
  rhs_[row] /= p;
  for (int i = 0; i < n; ++i) {
    if (i == row) continue;
    const double f = T(i, column);
    if (f == 0.0) continue;
    T.row(i) -= f * T.row(row);
    rhs_[i] -= f * rhs_[row];
  }
  T(row, column) = 1.0;
  basis_[static_cast<size_t>(row)] = column;
  ++pivots_;
}

// The answer of the basis the pivots ended on, solved again from M itself (the tableau's round-off
// grows with the pivots: 5e-2 m/s off in one of puma_table's islands), and checked.
bool Lemke::finish(const Eigen::Ref<const MatrixX>& M, const Eigen::Ref<const VectorX>& q, int n, Eigen::Ref<VectorX> z) {
  // The basic z's rows hold (M z + q)_i = 0 (their w is not basic: 0), the other z are 0.
  int nz = 0;
  for (int i = 0; i < n; ++i) {
    const int b = basis_[static_cast<size_t>(i)];
    if (b >= n && b < 2 * n) chosen_[static_cast<size_t>(nz++)] = b - n;
  }
  std::sort(chosen_.begin(), chosen_.begin() + nz);
  auto A = work_.topLeftCorner(nz, nz);
  for (int r = 0; r < nz; ++r) {
    for (int c = 0; c < nz; ++c) A(r, c) = M(chosen_[static_cast<size_t>(r)], chosen_[static_cast<size_t>(c)]);
    x_[r] = -q[chosen_[static_cast<size_t>(r)]];
  }
  if (!luSolveInPlace(A, x_.head(nz), nz)) return false;
  z.head(n).setZero();
  for (int r = 0; r < nz; ++r) z[chosen_[static_cast<size_t>(r)]] = x_[r];
  // w = M z + q >= 0, z >= 0, and one of them 0 in each row, to round-off of the problem's size.
  double size = 1.0;
  for (int i = 0; i < n; ++i) size = std::max(size, std::abs(q[i]));
  const double eps = 1e-9 * size;
  for (int i = 0; i < n; ++i) {
    const double w = M.row(i).head(n).dot(z.head(n)) + q[i];
    if (!(z[i] >= -eps) || !(w >= -eps) || std::min(z[i], w) > eps) return false;
  }
  for (int i = 0; i < n; ++i) z[i] = std::max(z[i], 0.0);
  return true;
}

bool Lemke::solve(const Eigen::Ref<const MatrixX>& M, const Eigen::Ref<const VectorX>& q, int n, Eigen::Ref<VectorX> z) {
  pivots_ = 0;
  z.head(n).setZero();
  if (n == 0) return true;
  if (n > capacity_) return false;
  int start = 0;
  for (int i = 1; i < n; ++i)
    if (q[i] < q[start]) start = i;
  if (q[start] >= 0.0) return true;  // z = 0
  // w - M z - e z0 = q, w basic.
  auto T = tableau_.topLeftCorner(n, 2 * n + 1);
  T.setZero();
  T.leftCols(n).setIdentity();
  T.middleCols(n, n) = -M.topLeftCorner(n, n);
  T.col(2 * n).setConstant(-1.0);
  rhs_.head(n) = q.head(n);
  for (int i = 0; i < n; ++i) basis_[static_cast<size_t>(i)] = i;
  const int artificial = 2 * n;
  double scale = 0.0;  // for the pivot's threshold
  for (int i = 0; i < n; ++i) scale = std::max(scale, M.row(i).head(n).cwiseAbs().maxCoeff());
  const double tiny = 1e-13 * std::max(scale, 1.0);
  pivot(n, start, artificial);
  int entering = n + start;  // the complement of w_start, which left
  const int limit = 50 * n + 100;
  while (pivots_ < limit) {
    // Ratio test, ties broken lexicographically on the rows of B^-1 (the w columns), the artificial
    // variable leaving first where it ties.
    int leave = -1;
    double best = 0.0;
    for (int i = 0; i < n; ++i) {
      const double a = T(i, entering);
      if (!(a > tiny)) continue;
      const double ratio = rhs_[i] / a;
      if (leave < 0 || ratio < best - 1e-12 * std::max(1.0, std::abs(best))) {
        leave = i;
        best = ratio;
        continue;
      }
      if (ratio > best + 1e-12 * std::max(1.0, std::abs(best))) continue;
      const bool art_i = basis_[static_cast<size_t>(i)] == artificial;
      const bool art_l = basis_[static_cast<size_t>(leave)] == artificial;
      if (art_l) continue;
      if (art_i) {
        leave = i;
        best = ratio;
        continue;
      }
      const double al = T(leave, entering);
      for (int c = 0; c < n; ++c) {
        const double x = T(i, c) / a, y = T(leave, c) / al;
        if (x < y - 1e-15) {
          leave = i;
          best = ratio;
          break;
        }
        if (x > y + 1e-15) break;
      }
    }
    if (leave < 0) return false;  // a ray: no answer this way
    const int left = basis_[static_cast<size_t>(leave)];
    pivot(n, leave, entering);
    if (left == artificial) return finish(M, q, n, z);
    entering = left < n ? left + n : left - n;
  }
  return false;
}

}  // namespace igms
