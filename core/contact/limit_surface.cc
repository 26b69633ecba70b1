#include "core/contact/limit_surface.h"

#include <algorithm>
#include <cmath>

#include "core/contact/patch_radius.h"

namespace igms {

namespace {

constexpr int kNewtonSteps = 30;  // each converges in a handful
constexpr int kHalvings = 30;

using SampleArray = Eigen::Array<double, kLimitSamples, 1>;
using SampleMap = Eigen::Map<const SampleArray>;

// Every sample's slip at w, (A, B) = w_t + w_z z x r_k, and its smoothed length Q, over all
// kLimitSamples (the unused ones weigh nothing): fixed-size arrays, so the sums vectorise.
struct SampleSlips {
  SampleArray A, B, Q;
  SampleSlips(const LimitSurface& s, const Vector3& w) {
    const SampleMap x(s.x), y(s.y);
    A = w.x() - w.z() * y;
    B = w.y() + w.z() * x;
    Q = (A.square() + B.square() + kLimitSmoothing * kLimitSmoothing * w.squaredNorm()).sqrt();
  }
};

}  // namespace

void sampleLimitSurface(const double* u, const double* v, int n, LimitSurface& out) {
  out.samples = 0;
  for (int k = 0; k < kLimitSamples; ++k) out.x[k] = out.y[k] = out.weight[k] = 0.0;
  n = std::min(n, 4);
  if (n < 2) return;
  int order[4], a = 0, b = 1;
  patchOrder(u, v, n, order);
  int m = 0;
  if (patchHasArea(u, v, n, order, &a, &b)) {
    // The bilinear map of the corners in turn (a triangle: its last corner twice), each cell's centre
    // weighted by the map's area there.
    const int c0 = order[0], c1 = order[1], c2 = order[2], c3 = order[n == 4 ? 3 : 2];
    for (int i = 0; i < kLimitGrid; ++i) {
      for (int j = 0; j < kLimitGrid; ++j) {
        const double s = (i + 0.5) / kLimitGrid, t = (j + 0.5) / kLimitGrid;
        const double w0 = (1 - s) * (1 - t), w1 = s * (1 - t), w2 = s * t, w3 = (1 - s) * t;
        out.x[m] = w0 * u[c0] + w1 * u[c1] + w2 * u[c2] + w3 * u[c3];
        out.y[m] = w0 * v[c0] + w1 * v[c1] + w2 * v[c2] + w3 * v[c3];
        const double dsx = (1 - t) * (u[c1] - u[c0]) + t * (u[c2] - u[c3]);
        const double dsy = (1 - t) * (v[c1] - v[c0]) + t * (v[c2] - v[c3]);
        const double dtx = (1 - s) * (u[c3] - u[c0]) + s * (u[c2] - u[c1]);
        const double dty = (1 - s) * (v[c3] - v[c0]) + s * (v[c2] - v[c1]);
        out.weight[m] = std::abs(dsx * dty - dsy * dtx);
        ++m;
      }
    }
  } else {  // a line: uniform along its longest chord
    for (int i = 0; i < kLimitGrid; ++i) {
      const double s = (i + 0.5) / kLimitGrid;
      out.x[m] = u[a] + s * (u[b] - u[a]);
      out.y[m] = v[a] + s * (v[b] - v[a]);
      out.weight[m] = 1.0;
      ++m;
    }
  }
  Eigen::Map<SampleArray> x(out.x), y(out.y), weight(out.weight);  // the unused samples are zero
  const double total = weight.sum();
  if (!(total > 0.0)) return;
  weight /= total;
  const SampleArray r2 = x.square() + y.square();
  const double mean = (weight * r2.sqrt()).sum();
  if (!(mean > 0.0)) return;  // all at the centroid: no torsion to shape
  // The positions' scale c with pure spinning's h equal to pure sliding's (both 1 after the
  // normalisation below): sum w sqrt(c^2 r^2 + eps^2) = sqrt(1 + eps^2), by Newton's method from
  // the unsmoothed answer (the left side is convex and rising in c).
  const double e2 = kLimitSmoothing * kLimitSmoothing, target = std::sqrt(1.0 + e2);
  double c = 1.0 / mean;
  for (int it = 0; it < 50; ++it) {
    const SampleArray q = (c * c * r2 + e2).sqrt();
    const double step = ((weight * q).sum() - target) / (c * (weight * r2 / q).sum());
    c -= step;
    if (!(std::abs(step) > 1e-15 * c)) break;
  }
  x *= c;
  y *= c;
  weight /= target;
  // The bounds: h(x) = sum w_k |B_k x| is at most sum w_k ||B_k|| |x| (and below), and at least
  // x^T M x / (max_k ||B_k|| |x|) with M = sum w_k B_k^T B_k (sum w |y| >= sum w |y|^2 / max |y|),
  // ||B_k||^2 = 1 + |r_k|^2 + eps^2 (B_k^T B_k = A_k^T A_k + eps^2 I, A_k A_k^T's eigenvalues 1, 1 + r^2).
  // M = [[A, 0, -Y], [0, A, X], [-Y, X, C]] has the eigenvalue A (along (X, Y, 0)) and the two of
  // [[A, rho], [rho, C]], rho = |(X, Y)|, the least of which is the least of all three.
  const SampleArray scaled2 = c * c * r2, norm = (1.0 + e2 + scaled2).sqrt();
  const double A = weight.sum() * (1.0 + e2), X = (weight * x).sum(), Y = (weight * y).sum();
  const double C = (weight * (scaled2 + e2)).sum();
  out.outer = (weight * norm).sum();
  double largest = 0.0;
  for (int k = 0; k < m; ++k) largest = std::max(largest, norm[k]);
  const double half = 0.5 * (A - C), spread = std::sqrt(half * half + X * X + Y * Y);
  out.inner = (0.5 * (A + C) - spread) / largest;
  // Also h(x)^2 <= sum w * x^T M x (Cauchy-Schwarz), so h(x) <= sqrt(sum w lambda_max(M)) |x|: the
  // tighter of the two (1.05 against 1.43 for a square).
  out.outer = std::min(out.outer, std::sqrt(weight.sum() * (0.5 * (A + C) + spread)));
  out.samples = m;
}

double limitSupport(const LimitSurface& s, const Vector3& w) {
  if (s.samples == 0) return w.norm();
  return (SampleMap(s.weight) * SampleSlips(s, w).Q).sum();
}

// Each sample's length q = |B w|, B^T B = A^T A + eps^2 I (A: w to the sample's slip (a, b)), has the
// gradient G / q, G = B^T B w = (a + eps^2 w_x, b + eps^2 w_y, b x - a y + eps^2 w_z), and the Hessian
// (B^T B - G G^T / q^2) / q. w = 0: no gradient (the smoothed lengths are all zero there).
Vector3 limitGradient(const LimitSurface& s, const Vector3& w) {
  if (s.samples == 0) return w / w.norm();
  if (w.isZero(0.0)) return Vector3::Zero();
  const double e2 = kLimitSmoothing * kLimitSmoothing;
  const SampleSlips p(s, w);
  const SampleArray c = SampleMap(s.weight) / p.Q;
  const double c0 = c.sum();
  return Vector3((c * p.A).sum() + e2 * w.x() * c0, (c * p.B).sum() + e2 * w.y() * c0,
                 (c * (p.B * SampleMap(s.x) - p.A * SampleMap(s.y))).sum() + e2 * w.z() * c0);
}

double limitDerivatives(const LimitSurface& s, const Vector3& w, Vector3& grad, Eigen::Matrix3d& hess) {
  if (s.samples == 0) {
    const double len = w.norm();
    grad = w / len;
    hess = (Eigen::Matrix3d::Identity() - grad * grad.transpose()) / len;
    return len;
  }
  if (w.isZero(0.0)) {
    grad.setZero();
    hess.setZero();
    return 0.0;
  }
  // B^T B is linear in the sample's (x, y, x^2 + y^2), so the sum of c B^T B (c = weight / q) is
  // built from four sums.
  const double e2 = kLimitSmoothing * kLimitSmoothing;
  const SampleMap x(s.x), y(s.y), weight(s.weight);
  const SampleSlips p(s, w);
  const SampleArray c = weight / p.Q, d = c / p.Q.square();
  const SampleArray G0 = p.A + e2 * w.x(), G1 = p.B + e2 * w.y(), G2 = p.B * x - p.A * y + e2 * w.z();
  const double c0 = c.sum(), cx = (c * x).sum(), cy = (c * y).sum(), cr = (c * (x.square() + y.square())).sum();
  grad = Vector3((c * G0).sum(), (c * G1).sum(), (c * G2).sum());
  const SampleArray dG0 = d * G0, dG1 = d * G1;
  const double h00 = (dG0 * G0).sum(), h01 = (dG0 * G1).sum(), h02 = (dG0 * G2).sum();
  const double h11 = (dG1 * G1).sum(), h12 = (dG1 * G2).sum(), h22 = (d * G2.square()).sum();
  const double diag = c0 * (1.0 + e2);
  hess << diag - h00, -h01, -cy - h02,  //
      -h01, diag - h11, cx - h12,         //
      -cy - h02, cx - h12, cr + e2 * c0 - h22;
  return (weight * p.Q).sum();
}

namespace {

// A point of Newton's method below: x, h's derivatives there, and the equation's residual.
struct NewtonPoint {
  Vector3 x, grad, r;
  Eigen::Matrix3d hess;
  double h = 0.0;
};

// Newton's method on an equation in x, residual(p) from h's derivatives at p.x, from p (filled in):
// each step, step(p), halved until it shrinks the residual (the objectives behind both equations
// stop changing at round-off well before the point does), until the residual is below `small`, no
// halving shrinks it, or kNewtonSteps.
template <typename Residual, typename Step>
void newtonSolve(const LimitSurface& s, NewtonPoint& p, double small, Residual residual, Step step) {
  for (int it = 0; it < kNewtonSteps && p.r.norm() > small; ++it) {
    const Vector3 d = step(p);
    bool shrank = false;
    double t = 1.0;
    for (int k = 0; k < kHalvings && !shrank; ++k, t *= 0.5) {
      NewtonPoint y;
      y.x = p.x + t * d;
      y.h = limitDerivatives(s, y.x, y.grad, y.hess);
      y.r = residual(y);
      if (y.r.norm() < p.r.norm()) {
        shrank = true;
        p = y;
      }
    }
    if (!shrank) break;
  }
}

// The dual norm by its smooth form: max over x of f . x - h(x)^2 / 2 is size^2 / 2, at the x where
// f = h grad h, from x = f (the ball's answer); at the answer f's size is h(x). Also gives that x,
// the outward normal of the surface where the ray through f meets it.
double sizeAndNormal(const LimitSurface& s, const Vector3& f, Vector3& normal, const Vector3* hint = nullptr) {
  auto residual = [&](const NewtonPoint& p) -> Vector3 { return f - p.h * p.grad; };
  auto solveFrom = [&](const Vector3& start, NewtonPoint& p) {
    p.x = start;
    p.h = limitDerivatives(s, p.x, p.grad, p.hess);
    p.r = residual(p);
    newtonSolve(s, p, 1e-15 * f.norm(), residual, [](const NewtonPoint& q) -> Vector3 {
      return (q.grad * q.grad.transpose() + q.h * q.hess).ldlt().solve(q.r);
    });
  };
  NewtonPoint p;
  // From the hint (the normal this patch's last solve in the step found, scaled to f), else from f;
  // a hinted solve that does not converge is taken again from f.
  if (hint && !hint->isZero(0.0)) {
    solveFrom(*hint * (f.norm() / hint->norm()), p);
    if (!(p.r.norm() <= 1e-12 * f.norm())) solveFrom(f, p);
  } else {
    solveFrom(f, p);
  }
  normal = p.x;
  return p.h;
}

}  // namespace

double limitSize(const LimitSurface& s, const Vector3& f, Vector3* hint) {
  if (s.samples == 0) return f.norm();
  if (f.isZero(0.0)) return 0.0;
  Vector3 normal;
  const double size = sizeAndNormal(s, f, normal, hint);
  if (hint) *hint = normal;
  return size;
}

bool limitInside(const LimitSurface& s, const Vector3& f, double cap, Vector3* hint) {
  if (s.samples == 0) return !(f.norm() > cap);
  const double len = f.norm();
  if (len <= s.inner * cap) return true;
  if (len > s.outer * cap) return false;
  // f is outside exactly when some normal n has f . n > cap h(n): the hint's often shows it, for h's
  // value alone (a slow slide: each visit's friction just outside, near the last answer's normal).
  if (hint && !hint->isZero(0.0) && f.dot(*hint) > cap * limitSupport(s, *hint)) return false;
  Vector3 normal;
  const double size = sizeAndNormal(s, f, normal, hint);
  if (hint) *hint = normal;
  return !(size > cap);
}

namespace {

// Newton's method on the projection's equation cap grad h(x) + x = f, from p (filled in).
Vector3 projectFrom(const LimitSurface& s, const Vector3& f, double cap, NewtonPoint& p) {
  auto residual = [&](const NewtonPoint& q) -> Vector3 { return cap * q.grad + q.x - f; };
  p.h = limitDerivatives(s, p.x, p.grad, p.hess);
  p.r = residual(p);
  newtonSolve(s, p, 1e-15 * f.norm(), residual, [&](const NewtonPoint& q) -> Vector3 {
    return -(cap * q.hess + Eigen::Matrix3d::Identity()).ldlt().solve(q.r);
  });
  return cap * p.grad;  // f - x, on the surface by construction
}

}  // namespace

// The nearest point of cap C to f is f - x, x the minimiser of cap h(x) + |x - f|^2 / 2 (Moreau):
// cap grad h(x) + x = f. Newton's method on that, each step halved until it shrinks the residual.
Vector3 limitProject(const LimitSurface& s, const Vector3& f, double cap, Vector3* hint) {
  if (s.samples == 0) {
    const double size = f.norm();
    return size > cap ? Vector3(f * (cap / size)) : f;
  }
  // From x = f - cap grad h(n) where f is far outside, n the hint or else f (grad h(x) is nearly
  // grad h(f) then; x at least half f, whatever n); else, where the hint's normal n shows f outside (f . n > cap h(n)), from x along n by
  // that much (the answer itself when n is the answer's normal), taken again as below if it does not
  // converge; else along the surface's normal where the ray through f meets it, as long as f is from
  // there (f near the surface: x small, and its direction is what matters).
  const double len = f.norm();
  NewtonPoint p;
  if (len > 2.0 * s.outer * cap) {
    p.x = f - cap * limitGradient(s, hint && !hint->isZero(0.0) ? *hint : f);
  } else {
    if (len <= s.inner * cap) return f;
    if (hint && !hint->isZero(0.0)) {
      const Vector3 n = hint->normalized();
      const double beyond = f.dot(n) - cap * limitSupport(s, n);
      if (beyond > 0.0) {
        p.x = beyond * n;
        const Vector3 answer = projectFrom(s, f, cap, p);
        if (p.r.norm() <= 1e-12 * len) {
          *hint = p.x;
          return answer;
        }
      }
    }
    Vector3 normal;
    const double size = sizeAndNormal(s, f, normal, hint);
    if (!(size > cap)) return f;
    p.x = normal * (len * (1.0 - cap / size) / normal.norm());
  }
  const Vector3 answer = projectFrom(s, f, cap, p);
  if (hint) *hint = p.x;  // the answer's normal
  return answer;
}

}  // namespace igms
