// The free bodies' own step: a free body (a one-body tree on a floating joint) moves under gravity
// and contact alone, and its rotation about its centre of mass obeys Euler's equations,
//   I w' + w x I w = 0,
// whose w x I w the integrators' linear step takes explicitly. Taken so at 1 ms, a top spinning at
// 50 rad/s gains energy a thousandfold in 10 s (the explicit term pumps its wobble). Here it is
// taken two ways, each chosen for what the contact solve needs:
//   - before the contact solve, backward Euler, I (w+ - w) = -h w+ x I w+ (Newton on three
//     unknowns): w+ . I w+ = w+ . I w <= |w+|_I |w|_I, so the rotation never gains energy and the
//     contact solve (which dissipates) starts from a velocity that turns about itself, as the
//     contact step moves it;
//   - a free body the contact solve left alone (no impulse on it: nothing touches it, no hand
//     holds it) then moves exactly by the implicit midpoint of Euler's equations with a Cayley
//     turn, I (w+ - w) = -h wm x I wm with wm = (w + w+)/2, R+ = R cay(h wm): a Lie-Poisson
//     scheme (Moser-Veselov family) that keeps the energy w . I w and the world angular momentum
//     R I w exactly (to the Newton solve's round-off), and the centre of mass moves by symplectic
//     Euler under gravity.
// The contact step's convention for floating joints (configuration.h: integrateContactStep) is kept:
// before the solve a free body's linear velocity holds its origin's world velocity at the step's
// end in the start frame. Allocation-free after construction.
#pragma once

#include <vector>

#include "core/model/data.h"

namespace igms {

class FreeBodyMotion {
 public:
  explicit FreeBodyMotion(const Model& model);
  bool empty() const { return bodies_.empty(); }
  int size() const { return static_cast<int>(bodies_.size()); }

  // A hand acts on free body k (its index among the model's free bodies) this step: it takes the
  // integrators' own step, its coupling taken implicitly there. clearDriven() forgets them all.
  void setDriven(int k) { bodies_[static_cast<size_t>(k)].driven = true; }
  void clearDriven();
  // The free body index of model part `part`, -1 when it is not a free body.
  int ofPart(int part) const { return part_index_[static_cast<size_t>(part)]; }

  // The step's start state (q, v).
  void begin(const VectorX& q, const VectorX& v);
  // The free bodies' velocities before the contact solve (the contact step's convention), written
  // into v over what the linear step left there.
  void unconstrained(double h, VectorX& v);
  // After the contact solve: marks the bodies it left alone (v+ = v_free and no position correction).
  void markUntouched(const VectorX& v_free, const VectorX& v_plus, const VectorX& v_position);
  // Every body not driven is untouched (a step without a contact solve).
  void markAllUntouched();
  // The untouched bodies' exact step from the start state: written into q and v over the scheme's.
  void finish(double h, VectorX& q, VectorX& v);

  // The rotation's two steps, exposed for tests: body angular velocity w, inertia I about the
  // centre of mass (body axes), step h; each returns the new body angular velocity.
  static Vector3 backwardEuler(const Matrix3& I, const Vector3& w, double h);
  // The midpoint step's new w (in the turned frame) and wm, the turn being cay(h wm).
  static Vector3 midpoint(const Matrix3& I, const Vector3& w, double h, Vector3* wm);

 private:
  struct Body {
    int q = 0, v = 0;  // its coordinates
    double m = 0.0;
    Vector3 c = Vector3::Zero();  // centre of mass, body frame
    Matrix3 I = Matrix3::Zero();  // about the centre of mass, body axes
    bool driven = false, untouched = false;
    // The start state: orientation, centre-of-mass position and world velocity, body angular velocity.
    Eigen::Quaterniond quat = Eigen::Quaterniond::Identity();
    Vector3 x = Vector3::Zero(), u = Vector3::Zero(), w = Vector3::Zero();
  };
  std::vector<Body> bodies_;
  std::vector<int> part_index_;
  Vector3 gravity_;
};

}  // namespace igms
