// Joint-space trajectory as piecewise quintic polynomials, C2 where built so.
// Evaluation writes into caller's vectors and never allocates.
#pragma once

#include <vector>

#include "core/model/data.h"

namespace igms {

class PiecewisePolynomial {
 public:
  static constexpr int kOrder = 6;  // coefficients per segment and joint (quintic)

  PiecewisePolynomial() = default;
  // Capacity for `segments` segments of `n` coordinates (allocates once).
  PiecewisePolynomial(int n, int segments);

  // One quintic from (q0, v0, a0) at t0 to (q1, v1, a1) at t0 + T: the resume
  // trajectory. Reuses the storage when it fits (no allocation).
  void setQuintic(double t0, double T, const VectorX& q0, const VectorX& v0, const VectorX& a0, const VectorX& q1,
                  const VectorX& v1, const VectorX& a1);

  // A cubic spline through (times[k], points[k]) with zero velocity at both
  // ends (clamped): C2 everywhere.
  static PiecewisePolynomial clampedCubicSpline(const std::vector<double>& times, const std::vector<VectorX>& points);

  // q, qd, qdd at t (held constant outside [start, end]).
  void evaluate(double t, VectorX& q, VectorX& qd, VectorX& qdd) const;

  double endTime() const { return breaks_.empty() ? 0.0 : breaks_.back(); }
  int segments() const { return segments_; }
  bool empty() const { return segments_ == 0; }
  // Final configuration.
  void finalPoint(VectorX& q) const;
  // Coordinates first .. first + n - 1 alone (one robot's, of an environment's trajectory).
  PiecewisePolynomial slice(int first, int n) const;

 private:
  int n_ = 0, segments_ = 0;
  std::vector<double> breaks_;  // segments_ + 1 times
  MatrixX coeffs_;              // (segments_ * n_) x kOrder, row = segment * n + joint, in (t - break) powers
};

}  // namespace igms
