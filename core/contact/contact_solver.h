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
//     and a torsion about the normal, inside the ellipsoid (|f_t| / mu N)^2 + (tau / mu N r)^2
//     <= 1 (N the patch's normal load, r its load-weighted mean radius; the ellipsoidal limit
//     surface of Howe and Cutkosky). Either way: stick (zero slip) inside, and at the edge the
//     friction opposite the slip (maximal dissipation). One friction per patch has no internal
//     tangential forces between its points (four corners' frictions would fight in their null
//     space and come near the cone), and slides straight whatever the normal loads.
// Solved by projected block Gauss-Seidel on the Delassus matrix W = J A^-1 J^T, a block per
// pair, warm-started from the last step's impulses (matched by pair and nearest point). W comes
// from A's sparse factors: A = L^T D L, W = X^T D^-1 X, X = L^-T J^T, and X is non-zero only on
// the dofs that move the pair's bodies, so W couples two pairs only when they share a tree.
// The positions then move with v+ plus a pseudo-velocity that closes what still overlaps at the
// end of the step (and puts a bounce where it belongs in time).
// Allocation-free after construction; the order of every sum is fixed.
#pragma once

#include <cstdint>
#include <vector>

#include "core/contact/contact_model.h"
#include "core/contact/contact_set.h"
#include "core/geometry/shape_contact.h"
#include "core/model/data.h"

namespace igms {

struct ContactSolveStats {
  int iterations = 0;          // sweeps of the last solve
  double residual = 0.0;       // m/s: the largest velocity change of its last sweep
  int64_t unconverged = 0;     // solves that stopped at the sweep limit, since the start
  int64_t blocks_dropped = 0;  // couplings that did not fit (counted, never silent)
};

class ContactSolver {
 public:
  static constexpr int kMaxRows = kMaxPairPoints + 3;  // a patch: its normals, two tangents, a torsion

  ContactSolver(const Model& model, const ContactModel& contacts);

  // v0: the velocity at the step's start; v: in, v_free; out, v+. factored: A's L^T D L factors
  // (ltdl.h), as the step left them. data: the step's start (S_world from the inertia matrix's
  // pass). v_position: out, what the positions move with. Writes each contact's impulse.
  void solve(const Data& data, const MatrixX& factored, double h, const VectorX& v0, ContactSet& contacts, VectorX& v,
             VectorX& v_position);

  const ContactSolveStats& stats() const { return stats_; }
  // Forget the last step's impulses (a re-based state: nothing to start from).
  void resetWarmStart() { previous_n_ = 0; }

 private:
  using Block = Eigen::Matrix<double, kMaxRows, kMaxRows>;
  using Rows = Eigen::Matrix<double, kMaxRows, 1>;
  // One pair's contacts: their rows (normals first, then friction) and everything about them.
  struct Group {
    int first = 0, points = 0;    // its contacts in the set
    bool patch = false;           // several points: friction at the centroid (rows: normals, t1, t2, torsion)
    int rows = 0;                 // points + 2 (one point: n, t1, t2) or points + 3
    Vector3 centroid = Vector3::Zero(), n = Vector3::UnitZ(), t1 = Vector3::UnitX(), t2 = Vector3::UnitY();
    double mu = 0.0, radius = 0.0;  // friction coefficient; a patch's torsion radius
    int first_entry = 0, entries = 0;  // the dofs its rows live on (dof_, invD_)
    int first_value = 0;               // its rows' J_ and X_: rows x entries, row-major
    int tree_a = -1, tree_b = -1;
    Block W;                      // its own block
    Eigen::Matrix3d friction_inverse;  // of the friction rows' block (stick)
    double friction_step = 0.0;   // 1 / (a bound on the largest eigenvalue of the scaled friction block)
    Rows b, target, lambda;       // J v_free; normal rows' u*; impulses
    Rows sigma;                   // pseudo-impulses (normal rows)
    bool bounce[kMaxPairPoints] = {};
    double approach[kMaxPairPoints] = {};
    int nbr_first = 0, nbr_count = 0;
    // The polish's view (polish()): which normals touch, whether the friction sticks or slips (then
    // lambda_row = slide[row] * sum of the normals), each row's unknown (-1: none); its candidate.
    bool active[kMaxPairPoints] = {};
    bool sliding = false;
    double slide[kMaxRows] = {};
    int unknown[kMaxRows] = {};
    Rows trial, trial_u;
  };
  void build(const Data& data, const MatrixX& factored, const ContactSet& contacts, double h, const VectorX& v0,
             const VectorX& v);
  void couple(int ng);
  void warmStart(const ContactSet& contacts, int ng);
  // Sweeps until converged or `sweeps` more; \return converged.
  bool sweep(int ng, int sweeps);
  // The active set the sweeps found, solved exactly: per island of pairs (those coupled through a
  // tree), the rows that are tight (touching normals, sticking frictions; a slipping friction is mu N
  // along its direction) as one linear system, kept when it satisfies every condition. A stack's
  // load reaches its bottom in one solve where the sweeps need hundreds. \return all islands took it.
  bool polish(int ng);
  bool polishIsland(int n);  // members_[0 .. n): one island
  void sweepPseudo(int ng);
  void apply(const MatrixX& factored, int ng, bool pseudo, VectorX& v);
  void report(ContactSet& contacts, int ng);

  const Model& model_;
  const ContactModel& cm_;
  std::vector<std::vector<int>> body_chain_;  // per body: the dofs that move it, ascending
  std::vector<int> part_of_body_;
  int max_entries_ = 0;                       // per group: both chains
  std::vector<Group> groups_;
  std::vector<int> dof_;                      // per group entry: the dof
  std::vector<double> invD_;                  // per group entry: 1 / D of the dof
  std::vector<double> J_, X_;                 // per group: rows x entries, row-major
  std::vector<int> nbr_;                      // couplings: the other group
  std::vector<Block> block_;                  // couplings: W_gh
  std::vector<int> stamp_;
  std::vector<std::vector<int>> tree_groups_;  // per part: its groups (capacity fixed)
  std::vector<int> tree_count_;
  std::vector<char> tree_touched_;
  VectorX scratch_;
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
  // The polish's workspace: islands, and one island's dense system (kPolishRows at most).
  static constexpr int kPolishRows = 192;
  std::vector<int> island_, queue_, members_;
  std::vector<double> M_, rhs_;
  std::vector<int> pivot_;
  ContactSolveStats stats_;
};

}  // namespace igms
