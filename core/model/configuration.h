// Operations on configurations q (nq) and velocities v (nv): the floating
// base's q holds a unit quaternion [w x y z], so q is not a vector space.
#pragma once

#include <random>
#include <vector>

#include "core/model/data.h"

namespace igms {

// Zero joint angles, base at the origin with identity orientation.
VectorX neutralConfiguration(const Model& model);

// Joints uniform within their limits (or [-pi, pi] where unlimited; prismatic
// without limits in [-0.5, 0.5] m); base position in [-1, 1]^3, a uniform random orientation.
VectorX randomConfiguration(const Model& model, std::mt19937& rng);

// Uniform in [-scale, scale]^nv.
VectorX randomVector(int n, std::mt19937& rng, double scale = 1.0);

// q_out = q (+) v dt: joints q + v dt; the floating base moves along the
// constant body twist v for dt (exact SE(3) exponential). q_out may alias q.
void integrateConfiguration(const Model& model, const VectorX& q, const VectorX& v, double dt, VectorX& q_out);

// The two Euler schemes with contact (an environment) move floating joints on R^3 x SO(3), as MuJoCo
// moves a free joint: a body's world velocity is what the contact solve sees and what moves it.
// Their body-frame linear velocity v turns with the body; the dynamics' -w x v (that turning, taken
// explicitly) would add (w h)^2 / 2 of a spinning body's speed a step (a rolling ball: w h = 0.04),
// so before the contact solve worldVelocityStep adds h w0 x v0 back (v then holds the step's world
// velocity change in the start frame), and integrateContactStep moves the origin by h R v and turns
// by exp(h w), and carries v into the turned frame. Joints: q + h v.
// v0: the step's start velocity; v: in and out; v_position: what the positions move with (v+ and
// the contact's pseudo-velocity). q_out may alias q.
void worldVelocityStep(const Model& model, const VectorX& v0, double h, VectorX& v);
void integrateContactStep(const Model& model, const VectorX& q, VectorX& v, const VectorX& v_position, double h,
                          VectorX& q_out);
// The rate of u in q = q0 (+) u when the velocity is v: v itself for the
// joints; for a floating base dexp^{-1}_{-u}(v) = v + [u, v]/2 + [u, [u, v]]/12
// (se(3) brackets), truncated where a 4th-order Runge-Kutta-Munthe-Kaas step
// needs it. out must not alias u or v.
void configurationRate(const Model& model, const VectorX& u, const VectorX& v, VectorX& out);

// A batch of random states (q, v, a, tau) for benchmarks and tests.
struct RandomStates {
  std::vector<VectorX> q, v, a, tau;
};
RandomStates randomStates(const Model& model, int count, std::mt19937& rng, double tau_scale = 10.0);

// Renormalises the floating base's quaternion (drift from integration).
void normalizeConfiguration(const Model& model, VectorX& q);

}  // namespace igms
