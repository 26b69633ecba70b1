#include "core/contact/contact_active_set.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "core/contact/lu_in_place.h"

namespace igms {

namespace {

constexpr double kInside = 1.0 - 1e-9;  // strictly inside the cone: sticking

// Whether row r (past the normals) is at its limit: the friction's, or a resisting point's spin or
// rolling (rows 3; 4 and 5).
bool slidingRow(const ContactGroup& g, int r) {
  if (g.resists && r >= 3) return r == 3 ? g.spin_sliding : g.roll_sliding;
  return g.sliding;
}

// A group's trial friction s and its slip w (trial_u) in the scaled coordinates.
void scaledFriction(const ContactGroup& g, Vector3& s, Vector3& w) {
  const int P = g.points, F = frictionRows(g);
  const Vector3 scale = scaleOf(g);
  s.setZero();
  w.setZero();
  for (int f = 0; f < F; ++f) {
    s[f] = g.trial[P + f] / scale[f];
    w[f] = g.trial_u[P + f] * scale[f];
  }
}

// The trial's load on a group's touching (unknown) normals.
double tightLoad(const ContactGroup& g) {
  double N = 0.0;
  for (int k = 0; k < g.points; ++k)
    if (g.unknown[k] >= 0) N += g.trial[k];
  return N;
}

}  // namespace

ContactActiveSet::ContactActiveSet(const Model& model, int capacity)
    : island_(static_cast<size_t>(capacity)),
      queue_(static_cast<size_t>(capacity)),
      members_(static_cast<size_t>(capacity)),
      stamp_(static_cast<size_t>(capacity)),
      restuck_(static_cast<size_t>(capacity)),
      M_(kPolishRows, kPolishRows),
      rhs_(kPolishRows),
      x_(kPolishRows),
      pivot_(kPolishRows),
      zt_(VectorX::Zero(model.nv)),
      y_(kPolishRows),
      y_try_(kPolishRows),
      V_(kMaxContactRows, kPolishRows),
      backup_(static_cast<size_t>(capacity)),
      cache_first_(static_cast<size_t>(capacity)),
      cache_count_(static_cast<size_t>(capacity)),
      cache_group_(kCachedCouplings),
      cache_block_(kCachedCouplings),
      block_inverse_(static_cast<size_t>(capacity)),
      cg_rhs_(static_cast<Eigen::Index>(capacity) * kMaxContactRows),
      cg_x_(cg_rhs_.size()),
      cg_r_(cg_rhs_.size()),
      cg_p_(cg_rhs_.size()),
      cg_q_(cg_rhs_.size()),
      cg_s_(cg_rhs_.size()),
      broken_(static_cast<size_t>(capacity) * kMaxContactRows),
      lcp_base_(static_cast<size_t>(capacity)),
      lcp_member_(static_cast<size_t>(capacity)) {}

bool ContactActiveSet::polish(ContactRows& rows, VectorX& z, double tolerance, bool linearise) {
  const int ng = rows.size();
  // Islands: pairs joined through the trees they share (breadth-first over each tree's groups).
  for (int g = 0; g < ng; ++g) {
    island_[static_cast<size_t>(g)] = -1;
    stamp_[static_cast<size_t>(g)] = -1;
  }
  bool all = true;
  rounds_ = 0;
  cycles_ = 0;
  large_solves_ = 0;
  cg_iterations_ = 0;
  slips_unturned_ = 0;
  slip_angle_ = 0.0;
  linearised_exact_ = linearised_ = 0;
  linearised_angle_ = 0.0;
  for (int seed = 0; seed < ng; ++seed) {
    if (island_[static_cast<size_t>(seed)] >= 0 || !rows.inSolve(seed)) continue;
    int head = 0, tail = 0, n = 0;
    queue_[static_cast<size_t>(tail++)] = seed;
    island_[static_cast<size_t>(seed)] = seed;
    while (head < tail) {
      const int g = queue_[static_cast<size_t>(head++)];
      members_[static_cast<size_t>(n++)] = g;
      const ContactGroup& G = rows.group(g);
      for (const int t : {G.tree_a, G.tree_b}) {
        if (t < 0) continue;
        for (const int h : rows.groupsOn(t)) {
          if (island_[static_cast<size_t>(h)] < 0) {
            island_[static_cast<size_t>(h)] = seed;
            queue_[static_cast<size_t>(tail++)] = h;
          }
        }
      }
    }
    std::sort(members_.begin(), members_.begin() + n);  // a fixed order for the unknowns
    bool settled = polishIsland(rows, n, tolerance);
    if (!settled && linearise) {
      // Each polytope in turn (kPolytopes) answers the island, and its answer seeds the active set;
      // the first seed that settles makes the island exact. Where none does, the island keeps the
      // answer of the finest polytope Lemke's method answered (never the sweeps' friction alone where a
      // polytope around the cone answered: that one leaves a friction where the sweeps had it).
      bool answered = false, exact = false;
      int kept_around = -1;
      double kept_angle = 0.0;
      for (const int around : kPolytopes) {
        if (!linearisedIsland(rows, n, tolerance, around)) continue;
        answered = true;
        if (around > kept_around) {
          std::copy(linearised_answer_.begin(), linearised_answer_.begin() + n, kept_answer_.begin());
          kept_around = around;
          kept_angle = island_angle_;
        }
        exact = seededFromLinearised(rows, n, tolerance);
        if (exact) break;
      }
      settled = answered;
      if (exact) {
        ++linearised_exact_;
      } else if (answered) {
        for (int m = 0; m < n; ++m) member(rows, m).lambda = kept_answer_[static_cast<size_t>(m)];
        ++linearised_;
        linearised_angle_ = std::max(linearised_angle_, kept_angle);
      }
    }
    all = settled && all;
  }
  // z for the impulses as they now are (an island that took its solve changed them, whatever the others did).
  rows.accumulate(z);  // z is zero but on the dofs of the groups in the solve
  return all;
}

// LU with partial pivoting of M_'s top-left nx x nx in place, then the two triangular solves, on x_.
bool ContactActiveSet::luSolve(int nx) { return luSolveInPlace(M_.topLeftCorner(nx, nx), x_.head(nx), nx); }

// An active-set method on one island: from the sweeps' guess, solve the tight rows exactly; where the
// answer breaks a condition (a normal pulls, a free point crosses, a sticking friction leaves the cone,
// a slipping one pushes along its slip), change that row's guess and solve again.
// Each other member h coupled to member m (sharing a tree), once: visit(W_mh, h).
template <typename Visit>
void ContactActiveSet::forEachCoupled(ContactRows& rows, int m, Visit&& visit) {
  if (cache_count_[static_cast<size_t>(m)] >= 0) {
    const int first = cache_first_[static_cast<size_t>(m)];
    for (int k = first; k < first + cache_count_[static_cast<size_t>(m)]; ++k)
      visit(cache_block_[static_cast<size_t>(k)], rows.group(cache_group_[static_cast<size_t>(k)]));
    return;
  }
  const ContactGroup& g = rows.group(members_[static_cast<size_t>(m)]);
  const int me = members_[static_cast<size_t>(m)];
  for (const int t : {g.tree_a, g.tree_b}) {
    if (t < 0) continue;
    for (const int h : rows.groupsOn(t)) {
      if (h == me || stamp_[static_cast<size_t>(h)] == me) continue;
      stamp_[static_cast<size_t>(h)] = me;
      rows.coupling(g, rows.group(h), W_);
      visit(W_, rows.group(h));
    }
  }
  for (const int t : {g.tree_a, g.tree_b})  // unstamp for the next pass
    if (t >= 0)
      for (const int h : rows.groupsOn(t)) stamp_[static_cast<size_t>(h)] = -1;
}

// The trial impulses' velocities (trial_u) over the island.
void ContactActiveSet::trialVelocities(ContactRows& rows, int n) {
  for (int m = 0; m < n; ++m) rows.add(member(rows, m), member(rows, m).trial, member(rows, m).rows, zt_);
  for (int m = 0; m < n; ++m) {
    ContactGroup& g = member(rows, m);
    g.trial_u = g.b + rows.velocity(g, zt_, g.rows);
  }
  for (int m = 0; m < n; ++m) rows.clear(member(rows, m), zt_);
}

// The island's guess (which normals touch, which limits slip, along what), hashed (FNV-1a).
uint64_t ContactActiveSet::guessKey(ContactRows& rows, int n) {
  uint64_t key = 1469598103934665603ull;
  auto mix = [&key](const void* data, size_t size) {
    const unsigned char* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) key = (key ^ b[i]) * 1099511628211ull;
  };
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = member(rows, m);
    mix(g.active, sizeof(bool) * static_cast<size_t>(g.points));
    const bool limits[3] = {g.sliding, g.spin_sliding, g.roll_sliding};
    mix(limits, sizeof(limits));
    mix(g.slide, sizeof(double) * static_cast<size_t>(g.rows));
  }
  return key;
}

// Every condition on the trial; the one that breaks worst (measured as a velocity: a pull by what its
// impulse would move its point, a crossing by its speed, a friction outside its cone by how far
// outside, one slipping along itself by its slip) in worst_group, worst_row (-1: none breaks).
// \return the touching normals whose impulse pulls.
int ContactActiveSet::brokenConditions(ContactRows& rows, int n, double tolerance, int& worst_group, int& worst_row) {
  double worst = 0.0;
  worst_group = worst_row = -1;
  int pulling = 0;
  broken_n_ = 0;
  auto candidate = [&](double how_bad, int m, int row) {
    if (broken_n_ < static_cast<int>(broken_.size())) broken_[static_cast<size_t>(broken_n_++)] = Broken{how_bad, m, row};
    if (how_bad > worst) {
      worst = how_bad;
      worst_group = m;
      worst_row = row;
    }
  };
  for (int m = 0; m < n; ++m) {
    ContactGroup& g = member(rows, m);
    const int P = g.points;
    double N = 0.0;
    for (int k = 0; k < P; ++k) {
      if (g.active[k] && g.trial[k] < 0.0) {
        candidate(-g.trial[k] * g.W(k, k), m, k);
        ++pulling;
      }
      else if (!g.active[k] && g.trial_u[k] < g.target[k] - tolerance) candidate(g.target[k] - g.trial_u[k], m, k);
      N += std::max(g.trial[k], 0.0);
    }
    Vector3 s, w;
    scaledFriction(g, s, w);
    const double cap = g.mu * (g.patch ? N : std::max(g.trial[0], 0.0));
    if (g.resists) {  // the spin and rolling limits, as the friction's below
      const double load = std::max(g.trial[0], 0.0);
      const double spin = g.trial[3], spin_cap = g.spin_mu * load;
      if (g.spin_mu > 0.0) {
        if (!g.spin_sliding && std::abs(spin) > spin_cap * (1.0 + 1e-9) + 1e-15)
          candidate((std::abs(spin) - spin_cap) * g.W(3, 3) + tolerance, m, 3);
        else if (g.spin_sliding && spin * g.trial_u[3] > tolerance * std::abs(spin))
          candidate(spin * g.trial_u[3] / std::abs(spin), m, 3);
      }
      const Eigen::Vector2d roll = g.trial.segment<2>(4), turn = g.trial_u.segment<2>(4);
      const double roll_cap = g.roll_mu * load;
      if (g.roll_mu > 0.0) {
        if (!g.roll_sliding && roll.norm() > roll_cap * (1.0 + 1e-9) + 1e-15)
          candidate((roll.norm() - roll_cap) / g.roll_step + tolerance, m, 4);
        else if (g.roll_sliding && roll.dot(turn) > tolerance * roll.norm())
          candidate(roll.dot(turn) / roll.norm(), m, 4);
      }
    }
    if (!(g.mu > 0.0)) continue;  // frictionless: its friction is zero, no condition
    // A slipping friction is mu N along its direction: with its load pulling (N < 0) it points along
    // the slip whatever the direction, and the pull is what breaks (a candidate above). Judged as
    // slipping along itself, it was stuck again, then slid again, and the two guesses took turns to
    // the round limit (994 of the 1,223 polishes that failed in puma_table's 8 s cycled in two rounds).
    if (g.sliding && tightLoad(g) < 0.0) continue;
    const double loose = cap * (1.0 + 1e-9) + 1e-15;
    if (!g.sliding && (shaped(g) ? !limitInside(g.surface, s, loose, &g.surface_hint) : s.norm() > loose)) {
      candidate((frictionSize(g, s) - cap) / g.friction_step + tolerance, m, P);
    } else if (g.sliding && s.dot(w) > tolerance * s.norm()) {
      candidate(s.dot(w) / s.norm(), m, P);  // slipping along its friction: it sticks instead
    }
  }
  return pulling;
}

bool ContactActiveSet::polishIsland(ContactRows& rows, int n, double tolerance) {
  auto group = [&](int m) -> ContactGroup& { return member(rows, m); };
  // The sweeps' guess.
  for (int m = 0; m < n; ++m) {
    ContactGroup& g = group(m);
    const int P = g.points, F = frictionRows(g);
    double N = 0.0;
    for (int k = 0; k < P; ++k) {
      g.active[k] = g.lambda[k] > 0.0;
      N += std::max(g.lambda[k], 0.0);
    }
    const Vector3 scale = scaleOf(g);
    Vector3 s = Vector3::Zero();
    for (int f = 0; f < F; ++f) s[f] = g.lambda[P + f] / scale[f];
    const double cap = g.mu * (g.patch ? N : std::max(g.lambda[0], 0.0));
    g.sliding = cap > 0.0 && (shaped(g) ? !limitInside(g.surface, s, kInside * cap, &g.surface_hint) : s.norm() >= kInside * cap);
    std::fill(g.slide, g.slide + kMaxContactRows, 0.0);
    if (g.sliding) {
      const double size = frictionSize(g, s);
      for (int f = 0; f < F; ++f) g.slide[P + f] = g.mu * scale[f] * s[f] / size;
    }
    g.spin_sliding = g.roll_sliding = false;
    restuck_[static_cast<size_t>(m)] = 0;
    if (g.resists) {
      const double load = std::max(g.lambda[0], 0.0);
      const double spin_cap = g.spin_mu * load, roll_cap = g.roll_mu * load;
      const double roll = std::hypot(g.lambda[4], g.lambda[5]);
      g.spin_sliding = spin_cap > 0.0 && std::abs(g.lambda[3]) >= kInside * spin_cap;
      if (g.spin_sliding) g.slide[3] = g.lambda[3] > 0.0 ? g.spin_mu : -g.spin_mu;
      g.roll_sliding = roll_cap > 0.0 && roll >= kInside * roll_cap;
      if (g.roll_sliding)
        for (int r = 4; r < 6; ++r) g.slide[r] = g.roll_mu * g.lambda[r] / roll;
    }
  }
  int rows_guessed = 0;
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = group(m);
    int active = 0;
    for (int k = 0; k < g.points; ++k) active += g.active[k];
    rows_guessed += active + (active > 0 && !g.sliding && g.mu > 0.0 ? frictionRows(g) : 0);
    if (active > 0 && g.resists)
      rows_guessed += (!g.spin_sliding && g.spin_mu > 0.0) + 2 * (!g.roll_sliding && g.roll_mu > 0.0);
  }
  // The island's couplings W_mh, each member's to each other it shares a tree with, formed once for
  // all the rounds (a member past the cache's room forms its own each time it is needed). An island
  // too large for the dense solve forms none: its conjugate gradients take M's products as the sweeps do.
  const bool dense = rows_guessed <= kPolishRows;
  if (!dense)
    for (int m = 0; m < n; ++m) cache_count_[static_cast<size_t>(m)] = -1;
  int cached = 0;
  for (int m = 0; m < n && dense; ++m) {
    const ContactGroup& g = group(m);
    const int me = members_[static_cast<size_t>(m)];
    cache_first_[static_cast<size_t>(m)] = cached;
    cache_count_[static_cast<size_t>(m)] = -1;  // not cached
    int count = 0;
    bool fits = true;
    for (const int t : {g.tree_a, g.tree_b}) {
      if (t < 0) continue;
      for (const int h : rows.groupsOn(t)) {
        if (!fits) break;
        if (h == me || stamp_[static_cast<size_t>(h)] == me) continue;
        stamp_[static_cast<size_t>(h)] = me;
        if (cached + count >= static_cast<int>(cache_block_.size())) {
          fits = false;
          break;
        }
        cache_group_[static_cast<size_t>(cached + count)] = h;
        rows.coupling(g, rows.group(h), cache_block_[static_cast<size_t>(cached + count)]);
        ++count;
      }
    }
    for (const int t : {g.tree_a, g.tree_b})
      if (t >= 0)
        for (const int h : rows.groupsOn(t)) stamp_[static_cast<size_t>(h)] = -1;
    if (fits) {
      cache_count_[static_cast<size_t>(m)] = count;
      cached += count;
    }
  }
  // Block pivoting on the releases (after Judice and Pires): in an island where nothing slips, while
  // a round leaves fewer touching normals pulling than any round before, every one of them lets go at
  // once (a staggered pyramid's sweeps leave eight to seventeen of its hundred corners pressing where
  // the exact answer lifts them: as many rounds of one change, each a factorisation, became a few);
  // otherwise one change a round, the worst broken condition of any kind, as before. (With slipping
  // friction in the island, releasing together left puma_table 261 unconverged solves in 8 s, not 22.)
  int fewest_pulling = std::numeric_limits<int>::max();
  uint64_t guess[3] = {0, 0, 0};  // the last three rounds' guesses, hashed: a guess two rounds back is a cycle
  bool cycled = false;
  for (int round = 0; round < kRounds; ++round) {
    ++rounds_;
    guess[round % 3] = seen_[static_cast<size_t>(round)] = guessKey(rows, n);
    if (round >= 2 && !cycled && guess[round % 3] == guess[(round + 1) % 3]) {
      cycled = true;
      ++cycles_;
    }
    // Unknowns: touching normals, and a sticking friction's rows where its pair has a load.
    int nx = 0;
    for (int m = 0; m < n; ++m) {
      ContactGroup& g = group(m);
      const int P = g.points, F = frictionRows(g);
      std::fill(g.unknown, g.unknown + kMaxContactRows, -1);
      bool loaded = false;
      for (int k = 0; k < P; ++k)
        if (g.active[k]) {
          g.unknown[k] = nx++;
          loaded = true;
        }
      if (!loaded) g.sliding = g.spin_sliding = g.roll_sliding = false;
      if (loaded && !g.sliding && g.mu > 0.0)  // frictionless: no friction, nothing to solve for
        for (int f = 0; f < F; ++f) g.unknown[P + f] = nx++;
      if (loaded && g.resists) {
        if (!g.spin_sliding && g.spin_mu > 0.0) g.unknown[3] = nx++;
        if (!g.roll_sliding && g.roll_mu > 0.0)
          for (int r = 4; r < 6; ++r) g.unknown[r] = nx++;
      }
    }
    // M x = rhs: each unknown's row u_r = target_r (0 for friction), u = b + sum over the island of W lambda.
    // Above kPolishRows unknowns, by conjugate gradients where nothing slips (else left to the sweeps).
    const bool iterative = nx > kPolishRows;
    if (iterative) {
      for (int m = 0; m < n; ++m)
        if (group(m).sliding || group(m).spin_sliding || group(m).roll_sliding) return false;
      ++large_solves_;
      if (!conjugateGradient(rows, n, nx, tolerance)) return false;
    } else if (nx > 0) {
      auto M = M_.topLeftCorner(nx, nx);
      bool symmetric = true;  // no slipping friction: M is W's rows and columns of the unknowns
      auto assemble = [&] {
        M.setZero();
        for (int m = 0; m < n; ++m) {
          const ContactGroup& g = group(m);
          symmetric = symmetric && !g.sliding && !g.spin_sliding && !g.roll_sliding;
          auto add = [&](const ContactBlock& W, const ContactGroup& h) {
            for (int r = 0; r < g.rows; ++r) {
              const int row = g.unknown[r];
              if (row < 0) continue;
              for (int c = 0; c < h.rows; ++c) {
                if (h.unknown[c] >= 0) {
                  M(row, h.unknown[c]) += W(r, c);
                } else if (c >= h.points && slidingRow(h, c) && h.slide[c] != 0.0) {
                  for (int k = 0; k < h.points; ++k)
                    if (h.unknown[k] >= 0) M(row, h.unknown[k]) += W(r, c) * h.slide[c];
                }
              }
            }
          };
          add(g.W, g);
          forEachCoupled(rows, m, add);
          for (int r = 0; r < g.rows; ++r)
            if (g.unknown[r] >= 0) rhs_[g.unknown[r]] = (r < g.points ? g.target[r] : 0.0) - g.b[r];
        }
        // Redundant normals (four corners carry three degrees of freedom) make M singular: a small
        // regularisation picks the even split among them, sized by the largest diagonal of the
        // contact and friction rows. Not by a resisting point's spin and rolling rows: their 1/I is
        // 10^3 a force's 1/m for a 5 cm ball, and a sticking ball crept at 1e-11 m/s under it.
        double big = 0.0;
        for (int m = 0; m < n; ++m) {
          const ContactGroup& g = group(m);
          for (int r = 0; r < (g.resists ? 3 : g.rows); ++r)
            if (g.unknown[r] >= 0) big = std::max(big, std::abs(M(g.unknown[r], g.unknown[r])));
        }
        M.diagonal().array() += 1e-12 * big + 1e-300;
      };
      assemble();
      x_.head(nx) = rhs_.head(nx);
      bool solved = false;
      if (symmetric) {
        // Symmetric positive definite: Cholesky, in place (Eigen's blocked LLT on a block of M_ and
        // in-place triangular solves: nothing allocated), half an LU's work. Redundant rows can leave
        // a pivot at round-off's mercy: then LU on the matrix again.
        Eigen::LLT<Eigen::Ref<MatrixX>> llt(M);
        if (llt.info() == Eigen::Success) {
          llt.matrixL().solveInPlace(x_.head(nx));
          llt.matrixU().solveInPlace(x_.head(nx));
          solved = true;
        } else {
          ++factor_fallbacks_;
          assemble();  // the factorisation overwrote M
          x_.head(nx) = rhs_.head(nx);
        }
      }
      if (!solved && !luSolve(nx)) return false;
      if (!x_.head(nx).allFinite()) return false;
    }
    // The candidate impulses, then the velocities they give.
    const double* const x = iterative ? cg_x_.data() : x_.data();
    for (int m = 0; m < n; ++m) {
      ContactGroup& g = group(m);
      g.trial.setZero();
      double N = 0.0;
      for (int k = 0; k < g.points; ++k)
        if (g.unknown[k] >= 0) N += g.trial[k] = x[g.unknown[k]];
      for (int r = g.points; r < g.rows; ++r)
        g.trial[r] = g.unknown[r] >= 0 ? x[g.unknown[r]] : (slidingRow(g, r) ? g.slide[r] * N : 0.0);
    }
    trialVelocities(rows, n);
    // Check every condition; change the guess of the one that breaks worst (one change a round:
    // changing every broken one at once can cycle, a pull freed here re-crossing there).
    int worst_group = -1, worst_row = -1;
    const int pulling = brokenConditions(rows, n, tolerance, worst_group, worst_row);
    if (worst_group < 0) {
      // A slipping friction kept along the direction the sweeps guessed: turned against the slip the
      // answer gives, where that holds every condition (else the answer as it is, counted).
      if (!turnSlips(rows, n, tolerance)) ++slips_unturned_;
      slip_angle_ = std::max(slip_angle_, slipMisalignment(rows, n, tolerance));
      for (int m = 0; m < n; ++m) group(m).lambda = group(m).trial;
      return true;
    }
    bool slips = false;
    for (int m = 0; m < n && !slips; ++m) slips = group(m).sliding || group(m).spin_sliding || group(m).roll_sliding;
    if (pulling > 1 && pulling < fewest_pulling && !slips) {
      fewest_pulling = pulling;
      for (int m = 0; m < n; ++m) {
        ContactGroup& h = group(m);
        for (int k = 0; k < h.points; ++k)
          if (h.active[k] && h.trial[k] < 0.0) h.active[k] = false;
      }
      continue;
    }
    fewest_pulling = std::min(fewest_pulling, pulling);
    // The worst broken condition's change, unless it leads back to a guess this polish has had (a
    // cycle of any length: a corner pressed pulls, let go it crosses, and round); then the next worst
    // whose change leads somewhere new; where none does, the worst's.
    auto tryChange = [&](int m, int row) {
      const GuessState before(group(m), restuck_[static_cast<size_t>(m)]);
      changeGuess(rows, m, row);
      const uint64_t key = guessKey(rows, n);
      if (std::find(seen_.begin(), seen_.begin() + round + 1, key) == seen_.begin() + round + 1) return true;
      before.restore(group(m), restuck_[static_cast<size_t>(m)]);
      return false;
    };
    if (tryChange(worst_group, worst_row)) continue;
    std::sort(broken_.begin(), broken_.begin() + broken_n_, [](const Broken& a, const Broken& b) {
      return a.how_bad != b.how_bad ? a.how_bad > b.how_bad : (a.group != b.group ? a.group < b.group : a.row < b.row);
    });
    bool fresh = false;
    for (int c = 0; c < broken_n_ && !fresh; ++c) {
      const Broken& b = broken_[static_cast<size_t>(c)];
      if (b.group != worst_group || b.row != worst_row) fresh = tryChange(b.group, b.row);
    }
    if (!fresh) changeGuess(rows, worst_group, worst_row);
  }
  return false;
}

// One broken condition's guess changed: a normal pressed or let go, a spin or rolling limit taken or
// left, a friction slipping (along the trial's friction) or turned against its slip or stuck again.
void ContactActiveSet::changeGuess(ContactRows& rows, int m, int row) {
  ContactGroup& g = member(rows, m);
  if (row < g.points) {
    g.active[row] = !g.active[row];
  } else if (g.resists && row == 3) {  // the spin: to its limit, against its turning, or back
    g.spin_sliding = !g.spin_sliding;
    g.slide[3] = g.spin_sliding ? (g.trial[3] > 0.0 ? g.spin_mu : -g.spin_mu) : 0.0;
  } else if (g.resists && row == 4) {  // the rolling pair, likewise
    g.roll_sliding = !g.roll_sliding;
    const double roll = std::hypot(g.trial[4], g.trial[5]);
    for (int r = 4; r < 6; ++r) g.slide[r] = g.roll_sliding && roll > 0.0 ? g.roll_mu * g.trial[r] / roll : 0.0;
  } else if (!g.sliding) {  // slip, along the friction the trial found
    const int P = g.points, F = frictionRows(g);
    const Vector3 scale = scaleOf(g);
    Vector3 s = Vector3::Zero();
    for (int f = 0; f < F; ++f) s[f] = g.trial[P + f] / scale[f];
    g.sliding = true;
    const double size = frictionSize(g, s);
    for (int f = 0; f < F; ++f) g.slide[P + f] = g.mu * scale[f] * s[f] / size;
  } else if (restuck_[static_cast<size_t>(m)] > 0) {
    // Stuck once already in this polish and slipping along itself again: turned against its slip,
    // not stuck again (stick and slip took turns to the round limit).
    const int P = g.points, F = frictionRows(g);
    const Vector3 scale = scaleOf(g);
    Vector3 s, w;
    scaledFriction(g, s, w);
    if (shaped(g)) {
      const Vector3 against = againstSlip(g, w);
      for (int f = 0; f < F; ++f) g.slide[P + f] = -g.mu * scale[f] * against[f];
    } else {
      for (int f = 0; f < F; ++f) g.slide[P + f] = -g.mu * scale[f] * w[f] / w.norm();
    }
  } else {
    g.sliding = false;
    ++restuck_[static_cast<size_t>(m)];
  }
}

// The tight rows' system M x = rhs of an island too large for the dense solve (a lattice of balls
// touching on every side: 576 pairs, 1,728 unknowns), where nothing slips: M is symmetric, positive
// definite with the dense solve's regularisation. Conjugate gradients, M's products formed through the
// accumulator as the sweeps form velocities (no block of M is formed: a product costs what a sweep
// does), preconditioned by each member's own block, from the sweeps' impulses; until the residual is
// a hundredth of the tolerance, checked on M x formed afresh. The answer in cg_x_. \return converged.
bool ContactActiveSet::conjugateGradient(ContactRows& rows, int n, int nx, double tolerance) {
  constexpr int kIterations = 1000;
  auto group = [&](int m) -> ContactGroup& { return member(rows, m); };
  const double small = 0.01 * tolerance;
  // The regularisation the dense solve adds (sized by the contact and friction rows' diagonal).
  double big = 0.0;
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = group(m);
    for (int r = 0; r < (g.resists ? 3 : g.rows); ++r)
      if (g.unknown[r] >= 0) big = std::max(big, std::abs(g.W(r, r)));
  }
  const double reg = 1e-12 * big + 1e-300;
  // A member's rows of a vector over the unknowns (0 on its other rows), and back.
  auto gather = [](const ContactGroup& g, const VectorX& x) {
    ContactRowVector l = ContactRowVector::Zero();
    for (int r = 0; r < g.rows; ++r)
      if (g.unknown[r] >= 0) l[r] = x[g.unknown[r]];
    return l;
  };
  auto scatter = [](const ContactGroup& g, const ContactRowVector& l, VectorX& x) {
    for (int r = 0; r < g.rows; ++r)
      if (g.unknown[r] >= 0) x[g.unknown[r]] = l[r];
  };
  // q = M p over the island: p's impulses into the accumulator, each unknown row's velocity out.
  auto product = [&](const VectorX& p, VectorX& q) {
    for (int m = 0; m < n; ++m) rows.add(group(m), gather(group(m), p), group(m).rows, zt_);
    for (int m = 0; m < n; ++m) {
      const ContactGroup& g = group(m);
      scatter(g, rows.velocity(g, zt_, g.rows) + reg * gather(g, p), q);
    }
    for (int m = 0; m < n; ++m) rows.clear(group(m), zt_);
  };
  // Each member's own block over its unknowns, inverted (the identity on its other rows), and the start.
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = group(m);
    ContactBlock B = ContactBlock::Identity();
    for (int r = 0; r < g.rows; ++r)
      for (int c = 0; c < g.rows; ++c)
        if (g.unknown[r] >= 0 && g.unknown[c] >= 0) B(r, c) = g.W(r, c) + (r == c ? reg : 0.0);
    block_inverse_[static_cast<size_t>(m)] = B.llt().solve(ContactBlock::Identity());
    for (int r = 0; r < g.rows; ++r)
      if (g.unknown[r] >= 0) {
        cg_rhs_[g.unknown[r]] = (r < g.points ? g.target[r] : 0.0) - g.b[r];
        cg_x_[g.unknown[r]] = g.lambda[r];
      }
  }
  auto precondition = [&](const VectorX& r, VectorX& z) {
    for (int m = 0; m < n; ++m)
      scatter(group(m), block_inverse_[static_cast<size_t>(m)] * gather(group(m), r), z);
  };
  auto worst = [&](const VectorX& r) { return r.head(nx).cwiseAbs().maxCoeff(); };
  // The residual formed afresh (the recurrence's drifts from it), p restarted along it; whether it is
  // small.
  double rs = 0.0;
  auto restart = [&] {
    product(cg_x_, cg_q_);
    cg_r_.head(nx) = cg_rhs_.head(nx) - cg_q_.head(nx);
    if (worst(cg_r_) <= small) return true;
    precondition(cg_r_, cg_s_);
    cg_p_.head(nx) = cg_s_.head(nx);
    rs = cg_r_.head(nx).dot(cg_s_.head(nx));
    return false;
  };
  if (restart()) return cg_x_.head(nx).allFinite();
  for (int it = 0; it < kIterations; ++it) {
    product(cg_p_, cg_q_);
    const double pq = cg_p_.head(nx).dot(cg_q_.head(nx));
    if (!(pq > 0.0)) return false;
    const double alpha = rs / pq;
    cg_x_.head(nx) += alpha * cg_p_.head(nx);
    cg_r_.head(nx) -= alpha * cg_q_.head(nx);
    ++cg_iterations_;
    if (worst(cg_r_) <= small) {
      if (restart()) return cg_x_.head(nx).allFinite();
      continue;
    }
    precondition(cg_r_, cg_s_);
    const double rs_next = cg_r_.head(nx).dot(cg_s_.head(nx));
    cg_p_.head(nx) = cg_s_.head(nx) + (rs_next / rs) * cg_p_.head(nx);
    rs = rs_next;
  }
  return false;
}

// The largest angle between a slipping friction of the trial and the reverse of its slip (a slip
// within the tolerance is none: the friction may point anywhere on the cone's edge).
double ContactActiveSet::slipMisalignment(ContactRows& rows, int n, double tolerance) {
  double worst = 0.0;
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = member(rows, m);
    if (!g.sliding) continue;
    Vector3 s, w;
    scaledFriction(g, s, w);
    if (!(s.norm() > 0.0) || !(w.norm() > tolerance)) continue;
    const Vector3 against = shaped(g) ? againstSlip(g, w).normalized() : w.normalized();
    const double chord = (s.normalized() + against).norm();  // 2 sin(angle / 2)
    worst = std::max(worst, 2.0 * std::asin(std::min(1.0, 0.5 * chord)));
  }
  return worst;
}

// Newton's method on the island's tight rows with each slipping friction's rows as unknowns too. The
// round's answer keeps a slipping friction along the direction the sweeps guessed, which need not be
// against the slip that answer gives (up to 90 degrees off). With s the friction and w its slip in
// the scaled coordinates (where a patch's ellipsoid is a ball), s |w| + mu N w = 0 puts it against
// the slip on the cone's edge; on a patch's limit surface, s h(w) + mu N h(w) grad h(w) = 0. From the round's answer, at most kSteps steps, each halved while it
// does not lower the residual. \return the friction was already against its slip, or the turned
// answer meets every condition (it is then the trial); else the trial is left as it was.
bool ContactActiveSet::turnSlips(ContactRows& rows, int n, double tolerance) {
  constexpr int kSteps = 20, kHalvings = 12;
  constexpr double kAgainst = 1e-9;  // rad: against the slip
  auto group = [&](int m) -> ContactGroup& { return member(rows, m); };
  if (slipMisalignment(rows, n, tolerance) <= kAgainst) return true;
  // Unknowns: the round's tight rows (their indices kept), then each slipping friction's rows.
  int tight = 0;
  for (int m = 0; m < n; ++m)
    for (int r = 0; r < group(m).rows; ++r) tight = std::max(tight, group(m).unknown[r] + 1);
  int nx = tight;
  for (int m = 0; m < n; ++m) {
    ContactGroup& g = group(m);
    if (g.sliding)
      for (int f = 0; f < frictionRows(g); ++f) g.unknown[g.points + f] = nx++;
  }
  auto isSlipRow = [&](const ContactGroup& g, int r) { return g.sliding && r >= g.points && r < g.points + frictionRows(g); };
  auto restore = [&](bool keep_trial) {
    for (int m = 0; m < n; ++m) {
      ContactGroup& g = group(m);
      for (int r = g.points; r < g.rows; ++r)
        if (isSlipRow(g, r)) g.unknown[r] = -1;
      if (!keep_trial) g.trial = backup_[static_cast<size_t>(m)];
    }
    if (!keep_trial) trialVelocities(rows, n);
  };
  for (int m = 0; m < n; ++m) backup_[static_cast<size_t>(m)] = group(m).trial;
  if (nx > kPolishRows) {
    restore(false);
    return false;
  }
  // y: the unknowns (a slipping friction's in scaled coordinates); the trial from it.
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = group(m);
    const Vector3 scale = scaleOf(g);
    for (int r = 0; r < g.rows; ++r)
      if (g.unknown[r] >= 0) y_[g.unknown[r]] = isSlipRow(g, r) ? g.trial[r] / scale[r - g.points] : g.trial[r];
  }
  auto setTrial = [&](const VectorX& y) {
    for (int m = 0; m < n; ++m) {
      ContactGroup& g = group(m);
      const Vector3 scale = scaleOf(g);
      g.trial.setZero();
      double N = 0.0;
      for (int k = 0; k < g.points; ++k)
        if (g.unknown[k] >= 0) N += g.trial[k] = y[g.unknown[k]];
      for (int r = g.points; r < g.rows; ++r) {
        if (g.unknown[r] >= 0) g.trial[r] = isSlipRow(g, r) ? y[g.unknown[r]] * scale[r - g.points] : y[g.unknown[r]];
        else if (slidingRow(g, r)) g.trial[r] = g.slide[r] * N;  // a resisting point's spin or rolling
      }
    }
    trialVelocities(rows, n);
  };
  // The residual: the tight rows' velocities less their targets; a slipping friction's
  // s |w| + mu N w, over mu N (a velocity, as theirs). \return its squared norm; largest tight one in *tight_residual.
  auto residual = [&](VectorX& G, double* tight_residual) {
    double sum = 0.0, largest = 0.0;
    for (int m = 0; m < n; ++m) {
      const ContactGroup& g = group(m);
      const int P = g.points, F = frictionRows(g);
      for (int r = 0; r < g.rows; ++r) {
        const int i = g.unknown[r];
        if (i < 0 || isSlipRow(g, r)) continue;
        G[i] = g.trial_u[r] - (r < P ? g.target[r] : 0.0);
        largest = std::max(largest, std::abs(G[i]));
        sum += G[i] * G[i];
      }
      if (!g.sliding) continue;
      Vector3 s, w;
      scaledFriction(g, s, w);
      const double muN = g.mu * tightLoad(g);
      // h grad h(w): w itself for the cone and the ellipsoid.
      const double h = shaped(g) ? limitSupport(g.surface, w) : w.norm();
      const Vector3 along = shaped(g) ? Vector3(h * limitGradient(g.surface, w)) : w;
      for (int f = 0; f < F; ++f) {
        const int i = g.unknown[P + f];
        G[i] = s[f] * h + muN * along[f];
        const double e = muN > 0.0 ? G[i] / muN : G[i];
        sum += e * e;
      }
    }
    *tight_residual = largest;
    return sum;
  };
  double tight_residual = 0.0;
  setTrial(y_);
  double merit = residual(rhs_, &tight_residual);
  bool converged = false;
  for (int step = 0;; ++step) {
    if (tight_residual <= tolerance && slipMisalignment(rows, n, tolerance) <= kAgainst) {
      converged = true;
      break;
    }
    if (step == kSteps) break;
    // The Jacobian, member by member: each unknown row's velocity against every unknown (V), then
    // the rows' own equations from it.
    auto J = M_.topLeftCorner(nx, nx);
    J.setZero();
    double big = 0.0;
    for (int m = 0; m < n; ++m) {
      ContactGroup& g = group(m);
      const int P = g.points, F = frictionRows(g);
      auto V = V_.topLeftCorner(g.rows, nx);
      V.setZero();
      auto add = [&](const ContactBlock& W, const ContactGroup& h) {
        const Vector3 hs = scaleOf(h);
        for (int r = 0; r < g.rows; ++r) {
          if (g.unknown[r] < 0) continue;
          for (int c = 0; c < h.rows; ++c) {
            if (h.unknown[c] >= 0) {
              V(r, h.unknown[c]) += W(r, c) * (isSlipRow(h, c) ? hs[c - h.points] : 1.0);
            } else if (c >= h.points && slidingRow(h, c) && h.slide[c] != 0.0) {
              for (int k = 0; k < h.points; ++k)
                if (h.unknown[k] >= 0) V(r, h.unknown[k]) += W(r, c) * h.slide[c];
            }
          }
        }
      };
      add(g.W, g);
      forEachCoupled(rows, m, add);
      for (int r = 0; r < g.rows; ++r) {
        const int i = g.unknown[r];
        if (i < 0 || isSlipRow(g, r)) continue;
        J.row(i) = V.row(r);
        if (r < (g.resists ? 3 : g.rows)) big = std::max(big, std::abs(V(r, i)));
      }
      if (!g.sliding) continue;
      const Vector3 scale = scaleOf(g);
      const double N = tightLoad(g);
      Vector3 s, w;
      scaledFriction(g, s, w);
      const double speed = w.norm();
      if (!(speed > tolerance)) {  // its slip has gone: it sticks, not for this solve
        restore(false);
        return false;
      }
      if (shaped(g)) {  // G = s h + mu N h grad h, with h grad h's Jacobian grad h grad h^T + h Hess h
        Vector3 grad;
        Eigen::Matrix3d hess;
        const double h = limitDerivatives(g.surface, w, grad, hess);
        const Eigen::Matrix3d along = grad * grad.transpose() + h * hess;
        for (int f = 0; f < F; ++f) {
          const int i = g.unknown[P + f];
          for (int j = 0; j < F; ++j)
            J.row(i) += ((s[f] * grad[j] + g.mu * N * along(f, j)) * scale[j]) * V.row(P + j);
          J(i, i) += h;
          for (int k = 0; k < P; ++k)
            if (g.unknown[k] >= 0) J(i, g.unknown[k]) += g.mu * h * grad[f];
        }
        continue;
      }
      for (int f = 0; f < F; ++f) {
        const int i = g.unknown[P + f];
        for (int j = 0; j < F; ++j) J.row(i) += (s[f] * w[j] / speed * scale[j]) * V.row(P + j);
        J.row(i) += (g.mu * N * scale[f]) * V.row(P + f);
        J(i, i) += speed;
        for (int k = 0; k < P; ++k)
          if (g.unknown[k] >= 0) J(i, g.unknown[k]) += g.mu * w[f];
      }
    }
    for (int m = 0; m < n; ++m)  // the round's regularisation of the tight rows (redundant normals)
      for (int r = 0; r < group(m).rows; ++r)
        if (group(m).unknown[r] >= 0 && !isSlipRow(group(m), r))
          J(group(m).unknown[r], group(m).unknown[r]) += 1e-12 * big + 1e-300;
    x_.head(nx) = -rhs_.head(nx);
    if (!luSolve(nx) || !x_.head(nx).allFinite()) {
      restore(false);
      return false;
    }
    // The step, halved until it lowers the residual.
    bool lowered = false;
    double t = 1.0;
    for (int h = 0; h < kHalvings && !lowered; ++h, t *= 0.5) {
      y_try_.head(nx) = y_.head(nx) + t * x_.head(nx);
      setTrial(y_try_);
      double tried_tight = 0.0;
      const double tried = residual(rhs_, &tried_tight);
      if (tried < merit) {
        lowered = true;
        merit = tried;
        tight_residual = tried_tight;
        y_.head(nx) = y_try_.head(nx);
      }
    }
    if (!lowered) break;
  }
  if (converged) {
    int worst_group = -1, worst_row = -1;
    brokenConditions(rows, n, tolerance, worst_group, worst_row);
    converged = worst_group < 0;
  }
  restore(converged);
  return converged;
}

}  // namespace igms
