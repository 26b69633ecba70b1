// The contact solve's rows (constraint assembly): per pair of shapes in contact, its rows of J (a
// normal per point, then friction: two tangents, and a torsion for a patch), X = L^-T J^T on the dofs
// that move the pair (A = L^T D L, the step's matrix, factored), its own Delassus block
// W_gg = X_g^T D^-1 X_g, its velocities under v_free and its targets. The solvers (contact_sweep.h,
// contact_active_set.h) never form the blocks between pairs: the impulses' effect lives in an
// accumulator z = D^-1 sum_h X_h lambda_h over the dofs, so a pair's velocity is
// u_g = b_g + X_g^T z, and a change of its impulse updates z on its own dofs. The cost per pair is
// its rows times its dofs, whatever the number of pairs on a tree (a humanoid's many contacts, a
// snake lying on the ground); W_gh is formed only where the active-set solve needs it.
// Allocation-free after construction; the order of every sum is fixed.
#pragma once

#include <vector>

#include "core/contact/contact_model.h"
#include "core/contact/contact_set.h"
#include "core/contact/limit_surface.h"
#include "core/geometry/shape_contact.h"
#include "core/model/data.h"

namespace igms {

constexpr int kMaxContactRows = kMaxPairPoints + 3;  // a patch: its normals, two tangents, a torsion
static_assert(kMaxContactRows >= 6, "a point that resists: n, t1, t2, spin, two rolling rows");
using ContactBlock = Eigen::Matrix<double, kMaxContactRows, kMaxContactRows>;
using ContactRowVector = Eigen::Matrix<double, kMaxContactRows, 1>;

// A pair of shapes in contact, as every pair has it each step: its points in the set, its two parts,
// its group (slot) where it has one, and whether that is in the solve. Compact: a crowded scene's
// many pairs that wait outside the solve (apart and not closing) have only this, and the solve's
// loops over all pairs read an array of these rather than a group each.
struct ContactPair {
  int first = 0, points = 0;     // its contacts in the set
  int tree_a = -1, tree_b = -1;  // the model parts of its two sides (-1: the world)
  int slot = -1;                 // its group in the pool (-1: none, it waits)
  bool in_solve = false;         // its group's X, W and friction block formed (complete())
};

// One pair's contacts: their rows (normals first, then friction) and everything about them.
struct ContactGroup {
  // Its pair's (ContactPair), and its shape.
  int first = 0, points = 0;    // its contacts in the set
  int rows = 0;                 // points + 2 (one point: n, t1, t2; + 3 where it resists) or points + 3
  bool patch = false;           // several points: friction at the centroid (rows: normals, t1, t2, torsion)
  // One point with rolling or torsional resistance (Material): three more rows, its relative angular
  // velocity about n (spin), t1 and t2 (rolling): |tau_spin| <= spin_mu N, |tau_roll| <= roll_mu N.
  bool resists = false;
  bool framed = false;               // centroid, n, t1, t2, radius and carries set (frame())
  bool built = false;                // its normal rows formed (build() did, or complete() will)
  int tree_a = -1, tree_b = -1;      // the model parts of its two sides (-1: the world)
  double mu = 0.0;                   // friction coefficient
  double spin_mu = 0.0, roll_mu = 0.0;  // m
  ContactRowVector lambda;           // impulses
  // Its frame (frame()) and rows (buildRows(), complete()).
  Vector3 centroid = Vector3::Zero(), n = Vector3::UnitZ(), t1 = Vector3::UnitX(), t2 = Vector3::UnitY();
  double radius = 0.0;               // a patch's torsion radius
  // The points it was last computed from (in the patch's plane) and its value: a pair at rest keeps
  // them (a slot holds the same pair while the same pairs have groups; compared each step).
  int radius_points = -1;
  double radius_u[kMaxPairPoints] = {}, radius_v[kMaxPairPoints] = {}, radius_of = 0.0;
  int first_entry = 0, entries = 0;  // the dofs its rows live on (ContactRows::dof, invD)
  int first_value = 0;               // its rows' J and X: rows x entries, row-major
  ContactBlock W;                    // its own Delassus block
  Eigen::Matrix3d friction_inverse;  // of the friction rows' block (stick)
  double friction_step = 0.0;  // 1 / (a bound on the largest eigenvalue of the scaled friction block)
  Eigen::Matrix2d roll_inverse;  // of the rolling rows' block (where it resists)
  double roll_step = 0.0;        // 1 / its largest eigenvalue
  ContactRowVector b, target;          // J v_free; normal rows' u*
  ContactRowVector sigma;              // pseudo-impulses (normal rows)
  ContactRowVector impact;             // impulses of the impacts passed along first (contact_impacts.h)
  bool bounce[kMaxPairPoints] = {};
  bool carries[kMaxPairPoints] = {};  // the points that carry a patch's friction (its centroid's)
  double bounce_target[kMaxPairPoints] = {};  // e times the approach speed (Newton's law), where it bounces
  double approach[kMaxPairPoints] = {};
  // The active-set solve's view (contact_active_set.h): which normals touch, whether the friction
  // sticks or slips (then lambda_row = slide[row] * sum of the normals), each row's unknown (-1: none).
  bool active[kMaxPairPoints] = {};
  bool sliding = false;
  bool spin_sliding = false, roll_sliding = false;  // the resistance's two limits, as `sliding`
  double slide[kMaxContactRows] = {};
  int unknown[kMaxContactRows] = {};
  ContactRowVector trial, trial_u;
  // A patch's limit surface (frame(), with its radius): the friction its sampled grid of points gives.
  LimitSurface surface;
  // The normal its last solve on the surface found in this step (limit_surface.h's hint; zero at
  // each step's start, so a step's answer depends only on the step). Mutable: a start for Newton's
  // method, not the group's state; the answers agree with and without it to round-off.
  mutable Vector3 surface_hint = Vector3::Zero();
};

// A group's friction rows: a patch with a torsion radius has three (two tangents, the torsion).
inline int frictionRows(const ContactGroup& g) { return g.patch && g.radius > 0.0 ? 3 : 2; }
// The friction's scaled coordinates (f_t, tau / r): the patch's ellipsoid is a ball there.
inline Vector3 scaleOf(const ContactGroup& g) { return Vector3(1.0, 1.0, g.radius > 0.0 ? g.radius : 1.0); }

// Whether g's friction is a patch's with a sampled limit surface (else a point's cone, or a patch's
// ellipsoid where its points gave no surface).
inline bool shaped(const ContactGroup& g) { return g.patch && g.radius > 0.0 && g.surface.samples > 0; }
// The size of friction s in the scaled coordinates: mu N on the edge of the cone, the ellipsoid or the
// patch's limit surface.
inline double frictionSize(const ContactGroup& g, const Vector3& s) {
  return shaped(g) ? limitSize(g.surface, s, &g.surface_hint) : s.norm();
}
// The friction per mu N against slip w (w not 0): on the edge, opposite -w in the dissipation's sense.
inline Vector3 againstSlip(const ContactGroup& g, const Vector3& w) {
  return shaped(g) ? limitGradient(g.surface, w) : w / w.norm();
}

// Newton's restitution applies at a point that approaches at `approach` (m/s, from the step's start),
// faster than bounce_velocity, and reaches the surface within the step at normal speed u.
inline bool bouncesAt(const Contact& c, double approach, double u, double h, double bounce_velocity) {
  return c.restitution > 0.0 && approach > bounce_velocity && c.distance + h * u < 0.0;
}

class ContactRows {
 public:
  ContactRows(const Model& model, const ContactModel& contacts);

  // Each pair, and its group with its normal rows of J from the step's start (data: S_world from the
  // inertia matrix's pass; data, contacts and v0 kept until the solve ends), A's diagonal from its
  // factors LD (ltdl.h), their velocities b = J v_free (h, v0: the start velocity), targets and
  // bounces. A pair whose every point is apart and not closing under v_free (its speed from the
  // bodies' twists) gets no group (most of a crowded scene's pairs, which wait outside the solve);
  // open() or complete() makes one. \return the number of pairs. None is in the solve until complete().
  int build(const Data& data, const TreeMatrix& LD, const ContactSet& contacts, double h, const VectorX& v0,
            const VectorX& v_free);
  // Pair g's group (made where it had none, its normal rows formed where they were not) with its
  // friction rows (and their velocities under v_free), X = L^-T J^T, its own block W_gg and its
  // friction block: in the solve from now on.
  void complete(int g, const TreeMatrix& LD, const VectorX& v_free);
  // g's centroid, normal, tangents, torsion radius and carrying points, once a step: a pair that
  // waits outside the solve with no impulse to start from never needs them (build() leaves them).
  void frame(ContactGroup& g) const;
  // Every body's world twist under v (rows [v; w]: a point p moves at v + w x p), into out (nb).
  void twists(const VectorX& v, std::vector<Motion>& out) const;
  // The normal speed of contact c (b's point against a's) from the bodies' twists: J_c v, summed
  // another way (round-off apart).
  static double twistSpeed(const Contact& c, const std::vector<Motion>& twist);
  // Every point of g apart and not closing under v_free within the step (gap + h J v_free > 0), no
  // bounce: a pair the solve may leave out while its impulse is zero (checked after it: a pair that
  // the others' impulses push across is let in, and the solve taken again).
  bool separating(const ContactGroup& g, const ContactSet& contacts, double h) const;

  // The step's pairs, in the contacts' order; g below is a pair's index.
  int size() const { return ngroups_; }
  const ContactPair& pair(int g) const { return pairs_[static_cast<size_t>(g)]; }
  bool hasGroup(int g) const { return pairs_[static_cast<size_t>(g)].slot >= 0; }
  bool inSolve(int g) const { return pairs_[static_cast<size_t>(g)].in_solve; }
  // Pair g's group (hasGroup(g)).
  ContactGroup& group(int g) { return groups_[static_cast<size_t>(pairs_[static_cast<size_t>(g)].slot)]; }
  const ContactGroup& group(int g) const { return groups_[static_cast<size_t>(pairs_[static_cast<size_t>(g)].slot)]; }
  // Pair g's group, made from its points (no rows yet, built false) where it had none.
  ContactGroup& open(int g);
  // A group's place in the pool (a dense index over the groups that exist this step).
  int slotOf(const ContactGroup& g) const { return static_cast<int>(&g - groups_.data()); }
  // The groups in the solve that touch model part t (their sides), in the order complete() took
  // them: for (int h : rows.groupsOn(t)).
  class PartGroups;
  PartGroups groupsOn(int t) const;

  // An accumulator z (nv, zero where nothing was added): z += D^-1 X_g^T delta (the first `rows` of delta).
  void add(const ContactGroup& g, const ContactRowVector& delta, int rows, VectorX& z) const;
  // X_g^T z on its first `rows` rows (J_g A^-1 J^T lambda for the impulses z holds; the rest zero).
  ContactRowVector velocity(const ContactGroup& g, const VectorX& z, int rows) const;
  // Zeroes z on g's dofs (where add() wrote).
  void clear(const ContactGroup& g, VectorX& z) const;
  // z for the impulses as they stand: zeroed on the dofs of the groups in the solve, then each one's
  // lambda added, in order.
  void accumulate(VectorX& z) const;
  // W_gh = X_g^T D^-1 X_h over the dofs both share (zero when they share no tree).
  void coupling(const ContactGroup& g, const ContactGroup& h, ContactBlock& W) const;
  // v += L^-1 z on every tree a group touches (z = D^-1 sum X lambda: v += A^-1 J^T lambda); z is
  // left zero.
  void apply(const TreeMatrix& LD, VectorX& z, VectorX& v);
  // The normal speed of point k of g under v (J_k v).
  double normalSpeed(const ContactGroup& g, int k, const VectorX& v) const;

 private:
  const Model& model_;
  const ContactModel& cm_;
  std::vector<std::vector<int>> body_chain_;  // per body: the dofs that move it, ascending
  std::vector<int> part_of_body_;
  int max_entries_ = 0;                       // per group: both chains
  std::vector<ContactPair> pairs_;
  int ngroups_ = 0;                            // pairs
  std::vector<ContactGroup> groups_;           // the pool: the step's groups in the order they were made
  int slots_ = 0;
  std::vector<int> dof_;                      // per group entry: the dof
  std::vector<double> invD_;                  // per group entry: 1 / D of the dof
  std::vector<double> J_, X_;                 // per group: rows x entries, row-major
  std::vector<double> sign_;                  // build(): per entry of one group, its side (-1 a, +1 b, 0 both)
  std::vector<double> sign_of_;               // per group entry: that side, kept for complete()
  void buildRows(ContactGroup& g, const TreeMatrix& LD, const VectorX& v);
  const Data* data_ = nullptr;                // the step's start, from build()
  const ContactSet* contacts_ = nullptr;      // the step's contacts, from build()
  const VectorX* v0_ = nullptr;               // the step's start velocity, from build()
  double h_ = 0.0;
  int entry_ = 0, value_ = 0;                 // the next group's first entry and value
  std::vector<Motion> twist_;                 // build(): per body, under v_free
  std::vector<int> up_;                       // build(): per entry, its parent dof's entry (-1: none)
  std::vector<int> link_;                     // complete(): one entry's chain upward (entries)
  std::vector<int> chain_from_;               // complete(): where an entry's chain is contiguous, its first entry
  std::vector<double> link_value_;            // complete(): L's values along it
  // Per part, its groups as a list (head, tail; each group's link per side, 2 g + side, to the next):
  // a crowded scene's thousand parts each with its own array of the capacity cost complete() a cache
  // miss per store (its 11 MB touched at random).
  std::vector<int> part_head_, part_tail_, part_next_;
  std::vector<char> tree_touched_;
};

class ContactRows::PartGroups {
 public:
  class Iterator {
   public:
    Iterator(const int* next, int link) : next_(next), link_(link) {}
    int operator*() const { return link_ >> 1; }
    Iterator& operator++() {
      link_ = next_[link_];
      return *this;
    }
    bool operator!=(const Iterator& o) const { return link_ != o.link_; }

   private:
    const int* next_;
    int link_;
  };
  PartGroups(const int* next, int head) : next_(next), head_(head) {}
  Iterator begin() const { return Iterator(next_, head_); }
  Iterator end() const { return Iterator(next_, -1); }

 private:
  const int* next_;
  int head_;
};

inline ContactRows::PartGroups ContactRows::groupsOn(int t) const {
  return PartGroups(part_next_.data(), part_head_[static_cast<size_t>(t)]);
}

}  // namespace igms
