// The contact solve of one step: hard contact with Coulomb friction at the
// velocity level (a complementarity problem per step, as ODE and
// Stewart-Trinkle time stepping pose it), so that what sticks has no slip at
// all (Coulomb's cone itself, not a regularised one), with impacts by Newton's
// restitution and overlap removed at the position level only (split impulses:
// no energy from it).
//
// With the step's unconstrained velocity v_free = v + A^-1 h F (A the matrix
// the step solved with: H, or the linearly-implicit H + h D + h^2 K), the
// impulses lambda give v+ = v_free + A^-1 J^T lambda. The rows of J:
//   each contact point: its normal, lambda_n >= 0, u_n >= u* with one of them tight, where
//     u* = -max(g, 0)/h (do not cross within the step; g the gap at the step's start), or e
//     times the approach speed for an impact that bounces;
//   friction, per pair of shapes: a pair that touches at one point (a sphere, a foot) has two
//     tangents there, |lambda_t| <= mu lambda_n; a pair that touches at several (a box on the
//     floor, a sole) has one friction for the whole patch at the points' centroid, two tangents
//     and a torsion about the normal, inside the patch's limit surface under uniform pressure
//     (limit_surface.h: a sampled grid of Coulomb points, N the patch's normal load, r its mean
//     radius; a patch whose points give no surface keeps Howe and Cutkosky's ellipsoid
//     (|f_t| / mu N)^2 + (tau / mu N r)^2 <= 1). Either way: stick (zero slip) inside, and at the edge the
//     friction opposite the slip (maximal dissipation). One friction per patch has no internal
//     tangential forces between its points (four corners' frictions would fight in their null
//     space and come near the cone), and slides straight whatever the normal loads.
// The parts, each in its own file: the rows (contact_rows.h: J, X = L^-T J^T, each pair's own Delassus
// block, the impulses' accumulator), projected block Gauss-Seidel (contact_sweep.h) warm-started from
// the last step's impulses (matched by pair and nearest point), and the exact solve of the active set
// the sweeps found, island by island (contact_active_set.h). A = L^T D L, W = X^T D^-1 X, and X is
// non-zero only on the dofs that move the pair's bodies, so pairs couple only when they share a tree,
// through an accumulator over the dofs rather than blocks between pairs.
// The positions then move with v+ plus a pseudo-velocity that closes what still overlaps at the
// end of the step (and puts a bounce where it belongs in time).
// Allocation-free after construction; the order of every sum is fixed.
#pragma once

#include <cstdint>
#include <vector>

#include "core/contact/contact_active_set.h"
#include "core/contact/contact_model.h"
#include "core/contact/contact_rows.h"
#include "core/contact/contact_set.h"
#include "core/model/data.h"

namespace igms {

// "The last solve" is the last step's: its figures read 0 after a step without contacts, where no solve ran.
// The counts "since the start" only grow.
struct ContactSolveStats {
  int iterations = 0;          // sweeps of the last solve
  int polish_rounds = 0;       // the active-set solve's dense solves in the last solve
  int deferred = 0;            // pairs apart and not closing the last solve left out (contact_rows.h)
  int64_t let_in = 0;          // pairs left out that the solve's v+ pushed across, let in, since the start
  int64_t restitution_scaled = 0;  // impacts whose restitution was scaled down to add no energy, since the start
  int64_t warm_dropped = 0;        // solves whose warm start cost more than a cold one, so dropped, since the start
  int impact_rounds = 0;           // the last solve's rounds of impacts passed along (contact_impacts.h; 0: none)
  int position_sweeps = 0;         // the position correction's sweeps in the last solve (0: nothing overlapped)
  double position_residual = 0.0;  // m/s: their last sweep's largest change
  int64_t position_unconverged = 0;  // position corrections that stopped at the sweep limit, since the start
  int64_t energy_capped = 0;   // solves whose impulses, still adding energy, were scaled down (capEnergy), since the start
  // Active-set islands it could not settle, answered on the linearised cone (contact_linearised_cone.cc):
  // exactly once seeded by its answer, or with the polytope's answer; and where that found none; since
  // the start.
  int64_t linearised_exact = 0, linearised = 0, linearised_failed = 0;
  double linearised_angle = 0.0;  // rad: the last solve's largest angle between a polytope's slipping friction
                                  // it kept and the one against its slip on the true cone
  int64_t polish_cycles = 0;   // active-set islands whose guess came back to the one two rounds before, since the start
  int64_t large_solves = 0;      // active-set islands above its dense solve's size solved by conjugate gradients,
  int64_t large_iterations = 0;  // and their iterations (each about a sweep's cost), since the start
  int64_t slips_unturned = 0;  // active-set answers whose slipping friction could not be turned against its slip
                               // (kept along the sweeps' direction), since the start (contact_active_set.h)
  double slip_angle = 0.0;     // rad: the last solve's largest angle between a slipping friction the active set
                               // fixed and the reverse of its slip
  double residual = 0.0;       // m/s: the largest velocity change of its last sweep (at least, where pairs were
                               // let in after the sweeps were spent, the fastest of them crossing)
  int64_t unconverged = 0;     // solves that stopped at the sweep limit, since the start
  int64_t solves = 0;          // velocity solves (steps with contacts), since the start
};

class ContactSolver {
 public:
  ContactSolver(const Model& model, const ContactModel& contacts);

  // v0: the velocity at the step's start; v: in, v_free; out, v+. factored: A's L^T D L factors
  // (ltdl.h), as the step left them. data: the step's start (S_world from the inertia matrix's
  // pass). v_position: out, what the positions move with. Writes each contact's impulse.
  void solve(const Data& data, const TreeMatrix& factored, double h, const VectorX& v0, ContactSet& contacts, VectorX& v,
             VectorX& v_position);

  const ContactSolveStats& stats() const { return stats_; }
  // Forget the last step's impulses (a re-based state: nothing to start from).
  void resetWarmStart() { previous_n_ = 0; }

 private:
  void warmStart(const ContactSet& contacts);
  void dropWorseWarmStart();  // the last step's impulses, where they cost more than none
  void report(ContactSet& contacts);
  bool anySliding() const;  // a friction at its cone's edge in the impulses as they stand
  bool solveImpulses();     // sweeps and active-set solves on the pairs in the solve; \return converged
  void countPolish();       // the active-set solve's figures of its last call, into stats_
  bool refineOnCone(int limit);  // the sweeps on from a polytope's answer; \return converged (else it is put back)
  double kineticGain(double* scale) const;  // the impulses' change of kinetic energy (scale: its terms' size)
  bool keepEnergy();        // restitution scaled down where the impulses would add energy
  void capEnergy();         // impulses that still would, scaled down

  ContactRows rows_;
  ContactActiveSet active_;
  VectorX z_, zs_;  // the impulses' and the pseudo-impulses' accumulators (contact_rows.h)
  VectorX v_free_;  // the solve's input, kept to solve again when a pair left out is let in
  std::vector<Motion> twist_;  // the bodies' twists under v+, for the pairs left out without rows
  double restitution_scale_ = 1.0;  // the factor keepEnergy() took, for the bounce's position
  std::vector<double> share_;  // per group: the overlap it shares with opposed facings (scratch)
  std::vector<ContactRowVector> kept_lambda_;  // per group: a polytope's answer, while the sweeps go on from it
  // The last step's contacts, for the warm start: pair, point, normal impulse; and per pair its
  // friction (world force at the centroid, torsion about the normal).
  struct Previous {
    int a, b;
    Vector3 point;
    double normal;
    Vector3 friction;
    double torsion;
  };
  std::vector<Previous> previous_;
  int previous_n_ = 0;
  ContactSettings settings_;
  ContactSolveStats stats_;
};

}  // namespace igms
