#include "core/contact/contact_sweep.h"

#include <algorithm>
#include <cmath>

namespace igms {
namespace {

// A point's rolling and torsional resistance, given its angular rows' velocity w (spin, roll t1, roll
// t2) with the normal and friction as they now are: the spin row held inside |tau| <= spin_mu N, then
// the rolling pair inside |tau| <= roll_mu N, each sticking where it can, else at its limit by an
// isotropic step (friction's rule: the limit's torque opposite the turning).
void solveResistance(ContactGroup& g, Vector3 w) {
  const double N = std::max(g.lambda[0], 0.0);
  const double spin = g.lambda[3];
  const double cap_spin = g.spin_mu * N;
  const double ls = std::clamp(spin - w[0] / (g.W(3, 3) + 1e-300), -cap_spin, cap_spin);
  w.tail<2>() += g.W.block<2, 1>(4, 3) * (ls - spin);
  g.lambda[3] = ls;
  const Eigen::Vector2d roll = g.lambda.segment<2>(4);
  Eigen::Vector2d lr = roll - g.roll_inverse * w.tail<2>();
  const double cap = g.roll_mu * N;
  if (lr.norm() > cap) {
    lr = roll - g.roll_step * w.tail<2>();
    const double t = lr.norm();
    if (t > cap) lr *= cap / t;
  }
  g.lambda.segment<2>(4) = lr;
}

// One point: sticking first, the whole block at once, target (u*, 0, 0); where that pulls or leaves
// the cone, the normal row, then the tangential ones against what it changed, onto the cone by an
// isotropic step (a step by W_tt^-1 would settle where W_tt lambda_t opposes the slip instead).
void solvePoint(ContactGroup& g, const ContactRowVector& u) {
  const Vector3 lam = g.lambda.head<3>();
  const Vector3 uu = u.head<3>();
  Vector3 l = lam - g.friction_inverse * (uu - Vector3(g.target[0], 0.0, 0.0));
  if (!(l.x() > 0.0) || l.tail<2>().norm() > g.mu * l.x()) {
    const double ln = std::max(0.0, lam.x() - (uu.x() - g.target[0]) / g.W(0, 0));
    const Eigen::Vector2d ut = uu.tail<2>() + g.W.block<2, 1>(1, 0) * (ln - lam.x());
    Eigen::Vector2d lt = lam.tail<2>() - g.friction_step * ut;
    const double t = lt.norm(), cap = g.mu * ln;
    if (t > cap) lt *= cap / t;
    l = Vector3(ln, lt.x(), lt.y());
  }
  const Vector3 change = l - lam;
  g.lambda.head<3>() = l;
  if (g.resists) solveResistance(g, u.segment<3>(3) + g.W.block<3, 3>(3, 0) * change);
}

// A patch: its normals one by one (u kept current through the group's own block), then its friction
// (two tangents and a torsion) at once, inside its limit surface (limit_surface.h), or where it has
// none the ellipsoid (|f_t| / mu N)^2 + (tau / mu N r)^2 <= 1.
void solvePatch(ContactGroup& g, ContactRowVector u) {
  const int R = g.rows, P = g.points;
  for (int k = 0; k < P; ++k) {
    const double ln = std::max(0.0, g.lambda[k] - (u[k] - g.target[k]) / g.W(k, k));
    const double d = ln - g.lambda[k];
    if (d != 0.0) u.head(R) += g.W.col(k).head(R) * d;
    g.lambda[k] = ln;
  }
  double N = 0.0;
  for (int k = 0; k < P; ++k) N += g.lambda[k];
  const Vector3 lam = g.lambda.segment<3>(P);
  const Vector3 uf = u.segment<3>(P);
  Vector3 l = Vector3::Zero();
  if (N > 0.0 && shaped(g)) {
    // Its sampled limit surface: stick where the friction that stops it is inside, else an isotropic
    // step in the scaled coordinates, then to the nearest point of the surface.
    const double rad = g.radius, cap = g.mu * N;
    const Vector3 scale(1.0, 1.0, rad);
    l = lam - g.friction_inverse * uf;
    if (!limitInside(g.surface, l.cwiseQuotient(scale), cap, &g.surface_hint)) {
      Vector3 s = lam.cwiseQuotient(scale) - g.friction_step * scale.cwiseProduct(uf);
      l = scale.cwiseProduct(limitProject(g.surface, s, cap, &g.surface_hint));
    }
  } else if (N > 0.0) {
    const double rad = g.radius;
    auto size = [&](const Vector3& f) { return rad > 0.0 ? std::sqrt(f.x() * f.x() + f.y() * f.y() + (f.z() / rad) * (f.z() / rad)) : f.head<2>().norm(); };
    l = lam - g.friction_inverse * uf;
    if (rad <= 0.0) l.z() = 0.0;
    if (size(l) > g.mu * N) {
      // Slipping: an isotropic step in the ellipsoid's scaled coordinates (s = (f_t, tau / r), its
      // velocity (u_t, r w)), then onto the ball of radius mu N.
      const Vector3 scale(1.0, 1.0, rad);
      Vector3 s(lam.x(), lam.y(), rad > 0.0 ? lam.z() / rad : 0.0);
      s -= g.friction_step * scale.cwiseProduct(uf);
      if (rad <= 0.0) s.z() = 0.0;
      const double n = s.norm(), cap = g.mu * N;
      if (n > cap) s *= cap / n;
      l = scale.cwiseProduct(s);
    }
  }
  g.lambda.segment<3>(P) = l;
}

// Sweeps over the groups in the solve, `visit(g)` updating one and returning the largest velocity change
// it made, until a sweep changes none by more than the tolerance or `sweeps` are done.
template <typename Visit>
SweepResult sweepGroups(ContactRows& rows, int sweeps, double tolerance, Visit&& visit) {
  SweepResult out;
  for (int pass = 0; pass < sweeps; ++pass) {
    double largest = 0.0;
    for (int gi = 0; gi < rows.size(); ++gi) {
      if (rows.inSolve(gi)) largest = std::max(largest, visit(rows.group(gi)));
    }
    ++out.sweeps;
    out.residual = largest;
    if (largest <= tolerance) {
      out.converged = true;
      break;
    }
  }
  return out;
}

}  // namespace

SweepResult sweepImpulses(ContactRows& rows, VectorX& z, int sweeps, double tolerance) {
  return sweepGroups(rows, sweeps, tolerance, [&](ContactGroup& g) {
    const int R = g.rows;
    const ContactRowVector u = g.b + rows.velocity(g, z, R);
    const ContactRowVector before = g.lambda;
    if (g.patch) solvePatch(g, u);
    else solvePoint(g, u);
    const ContactRowVector delta = g.lambda - before;
    if (delta.head(R).isZero(0.0)) return 0.0;
    rows.add(g, delta, R, z);
    return (g.W.topLeftCorner(R, R) * delta.head(R)).cwiseAbs().maxCoeff();
  });
}

bool solveGroupAlone(ContactGroup& g, const ContactRowVector& u, int sweeps, double tolerance) {
  const int R = g.rows;
  for (int pass = 0; pass < sweeps; ++pass) {
    const ContactRowVector before = g.lambda;
    ContactRowVector now = u;
    now.head(R) += g.W.topLeftCorner(R, R) * g.lambda.head(R);
    if (g.patch) solvePatch(g, now);
    else solvePoint(g, now);
    const ContactRowVector delta = g.lambda - before;
    if ((g.W.topLeftCorner(R, R) * delta.head(R)).cwiseAbs().maxCoeff() <= tolerance) return true;
  }
  return false;
}

SweepResult sweepPseudo(ContactRows& rows, VectorX& zs, int sweeps, double tolerance) {
  return sweepGroups(rows, sweeps, tolerance, [&](ContactGroup& g) {
    const int P = g.points;
    ContactRowVector s = rows.velocity(g, zs, P);
    ContactRowVector delta = ContactRowVector::Zero();
    double largest = 0.0;
    for (int k = 0; k < P; ++k) {
      double sigma = g.sigma[k] - (s[k] - g.target[k]) / (g.W(k, k) + 1e-300);
      if (!g.bounce[k]) sigma = std::max(0.0, sigma);
      const double d = sigma - g.sigma[k];
      if (d == 0.0) continue;
      s.head(P) += g.W.col(k).head(P) * d;
      largest = std::max(largest, std::abs(g.W(k, k) * d));
      g.sigma[k] = sigma;
      delta[k] = d;
    }
    rows.add(g, delta, P, zs);
    return largest;
  });
}

}  // namespace igms
