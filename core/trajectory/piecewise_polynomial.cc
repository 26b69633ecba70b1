#include "core/trajectory/piecewise_polynomial.h"

#include <algorithm>
#include <stdexcept>

namespace igms {

PiecewisePolynomial::PiecewisePolynomial(int n, int segments)
    : n_(n), segments_(0), breaks_(), coeffs_(MatrixX::Zero(n * segments, kOrder)) {
  breaks_.reserve(static_cast<size_t>(segments + 1));
}

void PiecewisePolynomial::setQuintic(double t0, double T, const VectorX& q0, const VectorX& v0, const VectorX& a0,
                                     const VectorX& q1, const VectorX& v1, const VectorX& a1) {
  const int n = static_cast<int>(q0.size());
  if (coeffs_.rows() < n) coeffs_.resize(n, kOrder);  // allocates only when too small
  n_ = n;
  segments_ = 1;
  breaks_.resize(2);  // within reserved capacity after the first call
  breaks_[0] = t0;
  breaks_[1] = t0 + T;
  const double T2 = T * T, T3 = T2 * T, T4 = T3 * T, T5 = T4 * T;
  for (int j = 0; j < n; ++j) {
    const double h = q1[j] - q0[j];
    auto c = coeffs_.row(j);
    c[0] = q0[j];
    c[1] = v0[j];
    c[2] = 0.5 * a0[j];
    c[3] = (20 * h - (8 * v1[j] + 12 * v0[j]) * T - (3 * a0[j] - a1[j]) * T2) / (2 * T3);
    c[4] = (-30 * h + (14 * v1[j] + 16 * v0[j]) * T + (3 * a0[j] - 2 * a1[j]) * T2) / (2 * T4);
    c[5] = (12 * h - 6 * (v1[j] + v0[j]) * T - (a0[j] - a1[j]) * T2) / (2 * T5);
  }
}

PiecewisePolynomial PiecewisePolynomial::clampedCubicSpline(const std::vector<double>& t,
                                                            const std::vector<VectorX>& p) {
  const int m = static_cast<int>(t.size());
  if (m < 2 || p.size() != t.size()) throw std::invalid_argument("a spline needs two or more points");
  for (int k = 1; k < m; ++k)
    if (!(t[k] > t[k - 1])) throw std::invalid_argument("spline times must increase");
  const int n = static_cast<int>(p[0].size());
  PiecewisePolynomial out(n, m - 1);
  out.segments_ = m - 1;
  out.breaks_ = t;
  // Second derivatives M_k from the clamped-spline tridiagonal system, per joint.
  std::vector<double> h(static_cast<size_t>(m - 1)), a(m), b(m), c(m), r(m), M(m);
  for (int k = 0; k + 1 < m; ++k) h[k] = t[k + 1] - t[k];
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < m; ++k) {
      const double dl = k > 0 ? (p[k][j] - p[k - 1][j]) / h[k - 1] : 0.0;
      const double dr = k + 1 < m ? (p[k + 1][j] - p[k][j]) / h[k] : 0.0;
      a[k] = k > 0 ? h[k - 1] : 0.0;
      c[k] = k + 1 < m ? h[k] : 0.0;
      b[k] = 2.0 * ((k > 0 ? h[k - 1] : 0.0) + (k + 1 < m ? h[k] : 0.0));
      r[k] = 6.0 * (dr - dl);  // zero end slopes: dl = 0 at the start, dr = 0 at the end
    }
    // Thomas algorithm.
    for (int k = 1; k < m; ++k) {
      const double w = a[k] / b[k - 1];
      b[k] -= w * c[k - 1];
      r[k] -= w * r[k - 1];
    }
    M[m - 1] = r[m - 1] / b[m - 1];
    for (int k = m - 2; k >= 0; --k) M[k] = (r[k] - c[k] * M[k + 1]) / b[k];
    for (int k = 0; k + 1 < m; ++k) {
      auto co = out.coeffs_.row(k * n + j);
      co.setZero();
      co[0] = p[k][j];
      co[1] = (p[k + 1][j] - p[k][j]) / h[k] - h[k] * (2 * M[k] + M[k + 1]) / 6.0;
      co[2] = M[k] / 2.0;
      co[3] = (M[k + 1] - M[k]) / (6.0 * h[k]);
    }
  }
  return out;
}

void PiecewisePolynomial::evaluate(double t, VectorX& q, VectorX& qd, VectorX& qdd) const {
  if (segments_ == 0) return;
  int s = 0;
  bool hold = false;
  if (t <= breaks_.front()) {
    t = breaks_.front();
    hold = true;
  } else if (t >= breaks_.back()) {
    t = breaks_.back();
    s = segments_ - 1;
    hold = true;
  } else {
    s = static_cast<int>(std::upper_bound(breaks_.begin(), breaks_.end(), t) - breaks_.begin()) - 1;
    s = std::clamp(s, 0, segments_ - 1);
  }
  const double x = t - breaks_[static_cast<size_t>(s)];
  for (int j = 0; j < n_; ++j) {
    const auto c = coeffs_.row(s * n_ + j);
    q[j] = c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * c[5]))));
    qd[j] = c[1] + x * (2 * c[2] + x * (3 * c[3] + x * (4 * c[4] + x * 5 * c[5])));
    qdd[j] = 2 * c[2] + x * (6 * c[3] + x * (12 * c[4] + x * 20 * c[5]));
  }
  if (hold) {  // before the start and after the end the trajectory rests
    qd.head(n_).setZero();
    qdd.head(n_).setZero();
  }
}

void PiecewisePolynomial::finalPoint(VectorX& q) const {
  VectorX qd(n_), qdd(n_);
  q.resize(n_);
  evaluate(endTime(), q, qd, qdd);
}

PiecewisePolynomial PiecewisePolynomial::slice(int first, int n) const {
  PiecewisePolynomial out(n, segments_);
  out.segments_ = segments_;
  out.breaks_ = breaks_;
  for (int s = 0; s < segments_; ++s)
    for (int j = 0; j < n; ++j) out.coeffs_.row(s * n + j) = coeffs_.row(s * n_ + first + j);
  return out;
}

}  // namespace igms
