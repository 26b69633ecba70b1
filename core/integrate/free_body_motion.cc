#include "core/integrate/free_body_motion.h"

#include <cmath>

namespace igms {
namespace {

constexpr int kNewtonSteps = 30;

// Newton on r(x) = 0 from x = w, for the two rotation steps; `at` gives r and its Jacobian.
template <typename Residual>
Vector3 newton(const Vector3& w, Residual&& at) {
  Vector3 x = w, r;
  Matrix3 J;
  double last = INFINITY;
  for (int k = 0; k < kNewtonSteps; ++k) {
    at(x, r, J);
    const Vector3 dx = J.partialPivLu().solve(r);
    x -= dx;
    // Quadratic convergence: stop once a step no longer shrinks (round-off reached) or is at it.
    const double size = dx.norm();
    if (size <= 1e-16 * x.norm() || size >= last) break;
    last = size;
  }
  return x;
}

}  // namespace

FreeBodyMotion::FreeBodyMotion(const Model& model) : gravity_(model.gravity) {
  part_index_.assign(model.parts.size(), -1);
  for (size_t p = 0; p < model.parts.size(); ++p) {
    const ModelPart& part = model.parts[p];
    if (!part.free_body || part.body_end - part.body_begin != 1) continue;
    const int b = part.body_begin;
    if (model.joint_type[static_cast<size_t>(b)] != JointType::Floating) continue;
    Body body;
    body.q = model.q_index[static_cast<size_t>(b)];
    body.v = model.v_index[static_cast<size_t>(b)];
    const SpatialInertia& I = model.inertia[static_cast<size_t>(b)];
    body.m = I.m;
    body.c = I.com();
    body.I = I.inertiaAboutCom();
    if (!(body.m > 0.0)) continue;  // massless: nothing to keep
    part_index_[p] = static_cast<int>(bodies_.size());
    bodies_.push_back(body);
  }
}

Vector3 FreeBodyMotion::backwardEuler(const Matrix3& I, const Vector3& w, double h) {
  // A sphere, a spin about a principal axis, or a body all but at rest (h |w| below 1e-12: its
  // gyroscopic change is below the round-off of w itself): w is the answer.
  if (h * w.norm() < 1e-12 || w.cross(I * w).isZero(0.0)) return w;
  return newton(w, [&](const Vector3& x, Vector3& r, Matrix3& J) {
    const Vector3 Ix = I * x;
    r = I * (x - w) + h * x.cross(Ix);
    J = I + h * (skew(x) * I - skew(Ix));
  });
}

Vector3 FreeBodyMotion::midpoint(const Matrix3& I, const Vector3& w, double h, Vector3* wm) {
  if (h * w.norm() < 1e-12 || w.cross(I * w).isZero(0.0)) {  // a steady spin, or at rest: w is the answer
    *wm = w;
    return w;
  }
  const Vector3 wn = newton(w, [&](const Vector3& x, Vector3& r, Matrix3& J) {
    const Vector3 m = 0.5 * (w + x), Im = I * m;
    r = I * (x - w) + h * m.cross(Im);
    J = I + 0.5 * h * (skew(m) * I - skew(Im));
  });
  *wm = 0.5 * (w + wn);
  return wn;
}

void FreeBodyMotion::clearDriven() {
  for (Body& b : bodies_) b.driven = false;
}

void FreeBodyMotion::begin(const VectorX& q, const VectorX& v) {
  for (Body& b : bodies_) {
    b.quat = Eigen::Quaterniond(q[b.q + 3], q[b.q + 4], q[b.q + 5], q[b.q + 6]).normalized();
    const Matrix3 R = b.quat.toRotationMatrix();
    b.w = v.segment<3>(b.v + 3);
    b.x = q.segment<3>(b.q) + R * b.c;
    b.u = R * (v.segment<3>(b.v) + b.w.cross(b.c));
    b.untouched = false;
  }
}

void FreeBodyMotion::unconstrained(double h, VectorX& v) {
  for (const Body& b : bodies_) {
    if (b.driven) continue;
    const Vector3 w = backwardEuler(b.I, b.w, h);
    const Vector3 u = b.u + h * gravity_;
    // The origin's world velocity at the step's end, in the start frame (w turns about itself).
    v.segment<3>(b.v) = b.quat.conjugate() * u - w.cross(b.c);
    v.segment<3>(b.v + 3) = w;
  }
}

void FreeBodyMotion::markUntouched(const VectorX& v_free, const VectorX& v_plus, const VectorX& v_position) {
  for (Body& b : bodies_) {
    b.untouched = !b.driven;
    for (int k = b.v; k < b.v + 6 && b.untouched; ++k)
      b.untouched = v_plus[k] == v_free[k] && v_position[k] == v_plus[k];
  }
}

void FreeBodyMotion::markAllUntouched() {
  for (Body& b : bodies_) b.untouched = !b.driven;
}

void FreeBodyMotion::finish(double h, VectorX& q, VectorX& v) {
  for (const Body& b : bodies_) {
    if (!b.untouched) continue;
    Vector3 wm;
    const Vector3 w = midpoint(b.I, b.w, h, &wm);
    // cay(h wm) as a quaternion: its Gibbs vector is h wm / 2.
    const Vector3 gibbs = 0.5 * h * wm;
    const Eigen::Quaterniond turn = Eigen::Quaterniond(1.0, gibbs.x(), gibbs.y(), gibbs.z()).normalized();
    const Eigen::Quaterniond next = (b.quat * turn).normalized();
    const Vector3 u = b.u + h * gravity_;
    const Vector3 x = b.x + h * u;
    q.segment<3>(b.q) = x - next * b.c;
    q[b.q + 3] = next.w();
    q[b.q + 4] = next.x();
    q[b.q + 5] = next.y();
    q[b.q + 6] = next.z();
    v.segment<3>(b.v) = next.conjugate() * u - w.cross(b.c);
    v.segment<3>(b.v + 3) = w;
  }
}

}  // namespace igms
