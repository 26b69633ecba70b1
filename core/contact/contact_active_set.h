// The active-set solve that makes the sweeps' answer exact (contact_sweep.h finds the contact set, this
// solves it): per island of pairs (those coupled through a tree they share), the rows that are tight
// (touching normals, sticking frictions; a slipping friction is mu N along its direction) as one dense
// linear system, kept when it meets every condition; where the answer breaks one, the worst broken
// row's guess changes (or, where that leads back to a guess the island has had, the next worst's) and
// the system is solved again. A stack's load reaches its bottom in one solve
// where the sweeps need hundreds. An island of more than kPolishRows unknowns takes conjugate gradients
// for its system where nothing in it slips, and is left to the sweeps where something does.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/contact/contact_rows.h"
#include "core/contact/lemke.h"

namespace igms {

class ContactActiveSet {
 public:
  static constexpr int kPolishRows = 192;

  ContactActiveSet(const Model& model, int capacity);

  // Every island from the groups' impulses; on success the impulses are the exact solution of the
  // active set and z (the accumulator of the impulses) is rebuilt for them. \return all islands did.
  // linearise: an island the active set cannot settle is answered on the linearised cone
  // (contact_linearised_cone.cc; it costs a few dense solves of the island).
  bool polish(ContactRows& rows, VectorX& z, double tolerance, bool linearise = false);
  // The last polish's rounds (dense solves), over its islands.
  int rounds() const { return rounds_; }
  // Symmetric systems whose Cholesky failed (redundant rows at round-off's mercy) and went to LU, since
  // the start.
  int64_t factorFallbacks() const { return factor_fallbacks_; }
  // The last polish's islands whose slipping frictions it could not turn against their slip (their
  // answer kept as the sweeps' directions gave it), and the largest angle it left between a slipping
  // friction and the reverse of its slip (rad).
  int slipsUnturned() const { return slips_unturned_; }
  // The last polish's islands whose guess came back to the one of two rounds before (a cycle: it would
  // take the same two turns to the round limit but for the rules that break it).
  int cycles() const { return cycles_; }
  double slipAngle() const { return slip_angle_; }
  // The last polish's solves of an island above kPolishRows unknowns (conjugate gradients), and their
  // iterations (each costs about a sweep over the island).
  int largeSolves() const { return large_solves_; }
  int largeIterations() const { return cg_iterations_; }
  // The last polish's islands the active set could not settle that the linearised cone answered
  // (contact_linearised_cone.cc): exactly once seeded by it (linearisedExact), or on the polytope
  // (linearised); and those where Lemke's method found no answer, since the start.
  int linearisedExact() const { return linearised_exact_; }
  int linearised() const { return linearised_; }
  int64_t linearisedFailed() const { return linearised_failed_; }
  // The last polish's largest angle between a slipping friction it kept on a polytope and the friction
  // against its slip on the true cone (rad).
  double linearisedAngle() const { return linearised_angle_; }

 private:
  bool polishIsland(ContactRows& rows, int n, double tolerance);  // members_[0 .. n): one island
  bool luSolve(int nx);
  bool conjugateGradient(ContactRows& rows, int n, int nx, double tolerance);
  ContactGroup& member(ContactRows& rows, int m) { return rows.group(members_[static_cast<size_t>(m)]); }
  template <typename Visit>
  void forEachCoupled(ContactRows& rows, int m, Visit&& visit);
  void trialVelocities(ContactRows& rows, int n);
  int brokenConditions(ContactRows& rows, int n, double tolerance, int& worst_group, int& worst_row);
  void changeGuess(ContactRows& rows, int m, int row);
  double slipMisalignment(ContactRows& rows, int n, double tolerance);
  bool turnSlips(ContactRows& rows, int n, double tolerance);
  uint64_t guessKey(ContactRows& rows, int n);
  // The island's LCP on the linearised cone, solved: its answer kept, and the impulses seeded from it.
  // \return it had one.
  // around: the polytope's directions around the tangent plane (0: the sweeps' friction alone).
  bool linearisedIsland(ContactRows& rows, int n, double tolerance, int around);
  // The answer's seeds, tried in turn. \return one settled the island (its answer exact).
  bool seededFromLinearised(ContactRows& rows, int n, double tolerance);
  double assembleLinearised(ContactRows& rows, int n, int size);
  void regulariseLinearised(ContactRows& rows, int n, double amount);
  // The polytope's answer as it is (a seed).
  void keepLinearisedAnswer(ContactRows& rows, int n);
  // The polytope's answer with each slipping friction carried out to the cone's edge, in its direction.
  void seedLinearisedOnEdge(ContactRows& rows, int n);
  std::vector<int> island_, queue_, members_, stamp_;
  std::vector<int> restuck_;  // per member: times its friction went back from slipping to sticking in this polish
  // One round's dense system (its top-left nx x nx of kPolishRows square, allocated once), right side
  // and solution.
  MatrixX M_;
  VectorX rhs_, x_;
  std::vector<int> pivot_;
  VectorX zt_;  // the trial impulses' accumulator
  // turnSlips(): its unknowns and a tried step, one member's rows' velocities against every unknown,
  // and the members' trials to go back to.
  VectorX y_, y_try_;
  MatrixX V_;
  std::vector<ContactRowVector> backup_;
  int slips_unturned_ = 0;     // the last polish's islands whose slips could not be turned
  double slip_angle_ = 0.0;    // the last polish's largest angle between a slipping friction and -slip
  ContactBlock W_;
  int rounds_ = 0;
  int cycles_ = 0;
  int64_t factor_fallbacks_ = 0;
  // One island's couplings, formed once per solve: member m's are cache_block_[first .. first + count).
  static constexpr int kCachedCouplings = 2048;
  std::vector<int> cache_first_, cache_count_, cache_group_;
  std::vector<ContactBlock> cache_block_;
  // conjugateGradient(): per member its own block's inverse, and the vectors over the unknowns.
  std::vector<ContactBlock> block_inverse_;
  VectorX cg_rhs_, cg_x_, cg_r_, cg_p_, cg_q_, cg_s_;
  int large_solves_ = 0;
  int cg_iterations_ = 0;
  // A polish's rounds: the guesses it has had (hashed), and the last round's broken conditions (how
  // badly, which member, which row), to change the next worst where the worst's change leads back.
  static constexpr int kRounds = 24;
  std::array<uint64_t, kRounds> seen_{};
  struct Broken {
    double how_bad;
    int group, row;
  };
  std::vector<Broken> broken_;
  // The linearised cone: islands of at most kLinearisedGroups pairs and kLinearisedRows unknowns.
  // The LCP's regularisation, relative to its largest normal diagonal; where Lemke's answer fails its
  // check, again with each larger one in turn (its pivots on near-singular redundant normals lose digits).
  static constexpr double kLinearisedRegularisation = 1e-12;
  static constexpr double kLinearisedRetries[] = {1e-8, 1e-6};
  // The polytopes tried in turn, by their directions around the tangent plane: every 45 degrees; the
  // sweeps' friction alone (a seed unlike the others'); every 22.5 degrees. Over the 48 runs of
  // solve_ensemble.py's three ensembles, the first alone left 131 islands on the polytope, the three 10.
  // A fourth, every 11.25 degrees, left 6 but took 13 ms in an island's step (docs/environment.md,
  // "Seeds and polytopes").
  static constexpr int kPolytopes[] = {8, 0, 16};
  static constexpr int kLinearisedGroups = 32, kLinearisedRows = 384;
  static constexpr int kMaxGenerators = 2 * 16 + 2 + 1;  // the finest patch's (its rings, the spins) and the sweeps' friction
  Lemke lemke_{kLinearisedRows};
  MatrixX lcp_M_ = MatrixX(kLinearisedRows, kLinearisedRows);
  VectorX lcp_q_ = VectorX(kLinearisedRows), lcp_z_ = VectorX(kLinearisedRows);
  std::vector<int> lcp_base_, lcp_member_;  // per group: its first unknown, its member
  std::vector<Eigen::Matrix<double, 3, kMaxGenerators>> generators_ =
      std::vector<Eigen::Matrix<double, 3, kMaxGenerators>>(kLinearisedGroups);
  std::vector<int> generator_count_ = std::vector<int>(kLinearisedGroups);
  std::vector<ContactRowVector> linearised_answer_ = std::vector<ContactRowVector>(kLinearisedGroups);
  std::vector<ContactRowVector> kept_answer_ = std::vector<ContactRowVector>(kLinearisedGroups);  // the finest polytope's
  int linearised_exact_ = 0, linearised_ = 0;
  double island_angle_ = 0.0, linearised_angle_ = 0.0;  // the last linearised island's, the polish's largest kept
  int64_t linearised_failed_ = 0;
  int broken_n_ = 0;
  // One member's guess, to put back a change tried and not taken.
  struct GuessState {
    bool active[kMaxPairPoints];
    bool sliding, spin_sliding, roll_sliding;
    double slide[kMaxContactRows];
    int restuck;
    GuessState(const ContactGroup& g, int restuck_count)
        : sliding(g.sliding), spin_sliding(g.spin_sliding), roll_sliding(g.roll_sliding), restuck(restuck_count) {
      std::copy(g.active, g.active + kMaxPairPoints, active);
      std::copy(g.slide, g.slide + kMaxContactRows, slide);
    }
    void restore(ContactGroup& g, int& restuck_count) const {
      std::copy(active, active + kMaxPairPoints, g.active);
      std::copy(slide, slide + kMaxContactRows, g.slide);
      g.sliding = sliding;
      g.spin_sliding = spin_sliding;
      g.roll_sliding = roll_sliding;
      restuck_count = restuck;
    }
  };
};

}  // namespace igms
