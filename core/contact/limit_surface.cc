#include "core/contact/limit_surface.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "core/contact/patch_radius.h"

namespace igms {

namespace {

constexpr int kNewtonSteps = 30;  // each converges in a handful
constexpr int kHalvings = 30;

// Sample k's slip at w, w_t + w_z z x r_k, and its smoothed length sqrt(|slip|^2 + eps^2 |w|^2).
inline double sampleLength(const LimitSurface& s, int k, const Vector3& w, double& a, double& b) {
  a = w.x() - w.z() * s.y[k];
  b = w.y() + w.z() * s.x[k];
  return std::sqrt(a * a + b * b + kLimitSmoothing * kLimitSmoothing * w.squaredNorm());
}

}  // namespace

void sampleLimitSurface(const double* u, const double* v, int n, LimitSurface& out) {
  out.samples = 0;
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
  double total = 0.0, mean = 0.0;
  for (int k = 0; k < m; ++k) total += out.weight[k];
  if (!(total > 0.0)) return;
  for (int k = 0; k < m; ++k) {
    out.weight[k] /= total;
    mean += out.weight[k] * std::sqrt(out.x[k] * out.x[k] + out.y[k] * out.y[k]);
  }
  if (!(mean > 0.0)) return;  // all at the centroid: no torsion to shape
  // The positions' scale c with pure spinning's h equal to pure sliding's (both 1 after the
  // normalisation below): sum w sqrt(c^2 r^2 + eps^2) = sqrt(1 + eps^2), by Newton's method from
  // the unsmoothed answer (the left side is convex and rising in c).
  const double e2 = kLimitSmoothing * kLimitSmoothing, target = std::sqrt(1.0 + e2);
  double c = 1.0 / mean;
  for (int it = 0; it < 50; ++it) {
    double f = -target, df = 0.0;
    for (int k = 0; k < m; ++k) {
      const double r2 = out.x[k] * out.x[k] + out.y[k] * out.y[k], q = std::sqrt(c * c * r2 + e2);
      f += out.weight[k] * q;
      df += out.weight[k] * c * r2 / q;
    }
    const double step = f / df;
    c -= step;
    if (!(std::abs(step) > 1e-15 * c)) break;
  }
  // The bounds: h(x) = sum w_k |B_k x| is at most sum w_k ||B_k|| |x|, and at least
  // x^T M x / (max_k ||B_k|| |x|) with M = sum w_k B_k^T B_k (sum w |y| >= sum w |y|^2 / max |y|),
  // ||B_k||^2 = 1 + |r_k|^2 + eps^2 (B_k^T B_k = A_k^T A_k + eps^2 I, A_k A_k^T's eigenvalues 1, 1 + r^2).
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  double largest = 0.0;
  out.outer = 0.0;
  for (int k = 0; k < m; ++k) {
    out.x[k] *= c;
    out.y[k] *= c;
    out.weight[k] /= target;
    const double x = out.x[k], y = out.y[k], norm = std::sqrt(1.0 + x * x + y * y + e2);
    Eigen::Matrix3d BB;
    BB << 1.0 + e2, 0.0, -y, 0.0, 1.0 + e2, x, -y, x, x * x + y * y + e2;
    M += out.weight[k] * BB;
    largest = std::max(largest, norm);
    out.outer += out.weight[k] * norm;
  }
  out.inner = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(M, Eigen::EigenvaluesOnly).eigenvalues()[0] / largest;
  out.samples = m;
}

double limitSupport(const LimitSurface& s, const Vector3& w) {
  if (s.samples == 0) return w.norm();
  double h = 0.0, a, b;
  for (int k = 0; k < s.samples; ++k) h += s.weight[k] * sampleLength(s, k, w, a, b);
  return h;
}

Vector3 limitGradient(const LimitSurface& s, const Vector3& w) {
  if (s.samples == 0) return w / w.norm();
  const double e2 = kLimitSmoothing * kLimitSmoothing;
  Vector3 g = Vector3::Zero();
  for (int k = 0; k < s.samples; ++k) {
    double a, b;
    const double q = sampleLength(s, k, w, a, b);
    if (!(q > 0.0)) continue;
    g += (s.weight[k] / q) * Vector3(a + e2 * w.x(), b + e2 * w.y(), b * s.x[k] - a * s.y[k] + e2 * w.z());
  }
  return g;
}

double limitDerivatives(const LimitSurface& s, const Vector3& w, Vector3& grad, Eigen::Matrix3d& hess) {
  if (s.samples == 0) {
    const double len = w.norm();
    grad = w / len;
    hess = (Eigen::Matrix3d::Identity() - grad * grad.transpose()) / len;
    return len;
  }
  const double e2 = kLimitSmoothing * kLimitSmoothing;
  double h = 0.0;
  grad.setZero();
  hess.setZero();
  for (int k = 0; k < s.samples; ++k) {
    double a, b;
    const double q = sampleLength(s, k, w, a, b);
    h += s.weight[k] * q;
    if (!(q > 0.0)) continue;
    // q = |B w| with B^T B = A^T A + eps^2 I (A: w to the sample's slip): its gradient B^T B w / q,
    // its Hessian (B^T B - G G^T / q^2) / q.
    const double x = s.x[k], y = s.y[k];
    Eigen::Matrix3d BB;
    BB << 1.0 + e2, 0.0, -y, 0.0, 1.0 + e2, x, -y, x, x * x + y * y + e2;
    const Vector3 G(a + e2 * w.x(), b + e2 * w.y(), b * x - a * y + e2 * w.z());
    grad += (s.weight[k] / q) * G;
    hess.noalias() += (s.weight[k] / q) * (BB - G * G.transpose() / (q * q));
  }
  return h;
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
double sizeAndNormal(const LimitSurface& s, const Vector3& f, Vector3& normal) {
  auto residual = [&](const NewtonPoint& p) -> Vector3 { return f - p.h * p.grad; };
  NewtonPoint p;
  p.x = f;
  p.h = limitDerivatives(s, p.x, p.grad, p.hess);
  p.r = residual(p);
  newtonSolve(s, p, 1e-15 * f.norm(), residual, [](const NewtonPoint& q) -> Vector3 {
    return (q.grad * q.grad.transpose() + q.h * q.hess).ldlt().solve(q.r);
  });
  normal = p.x;
  return p.h;
}

}  // namespace

double limitSize(const LimitSurface& s, const Vector3& f) {
  if (s.samples == 0) return f.norm();
  if (f.isZero(0.0)) return 0.0;
  Vector3 normal;
  return sizeAndNormal(s, f, normal);
}

bool limitInside(const LimitSurface& s, const Vector3& f, double cap) {
  if (s.samples == 0) return !(f.norm() > cap);
  const double len = f.norm();
  if (len <= s.inner * cap) return true;
  if (len > s.outer * cap) return false;
  return !(limitSize(s, f) > cap);
}

// The nearest point of cap C to f is f - x, x the minimiser of cap h(x) + |x - f|^2 / 2 (Moreau):
// cap grad h(x) + x = f. Newton's method on that, each step halved until it shrinks the residual.
Vector3 limitProject(const LimitSurface& s, const Vector3& f, double cap) {
  if (s.samples == 0) {
    const double size = f.norm();
    return size > cap ? Vector3(f * (cap / size)) : f;
  }
  // From x = f - cap grad h(f) where f is far outside (grad h(x) is nearly grad h(f) then; x at least
  // half f), else along the surface's normal where the ray through f meets it, as long as f is from
  // there (f near the surface: x small, and its direction is what matters).
  const double len = f.norm();
  Vector3 x;
  if (len > 2.0 * s.outer * cap) {
    x = f - cap * limitGradient(s, f);
  } else {
    if (len <= s.inner * cap) return f;
    Vector3 normal;
    const double size = sizeAndNormal(s, f, normal);
    if (!(size > cap)) return f;
    x = normal * (len * (1.0 - cap / size) / normal.norm());
  }
  auto residual = [&](const NewtonPoint& p) -> Vector3 { return cap * p.grad + p.x - f; };
  NewtonPoint p;
  p.x = x;
  p.h = limitDerivatives(s, p.x, p.grad, p.hess);
  p.r = residual(p);
  newtonSolve(s, p, 1e-15 * f.norm(), residual, [&](const NewtonPoint& q) -> Vector3 {
    return -(cap * q.hess + Eigen::Matrix3d::Identity()).ldlt().solve(q.r);
  });
  return cap * p.grad;  // f - x, on the surface by construction
}

}  // namespace igms
