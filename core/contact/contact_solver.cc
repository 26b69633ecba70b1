#include "core/contact/contact_solver.h"

#include <algorithm>
#include <cmath>

#include "core/contact/contact_impacts.h"
#include "core/contact/contact_sweep.h"

namespace igms {

namespace {

constexpr double kWarmStartReach = 0.02;  // m: a last step's point this near, of the same pair, starts it
constexpr double kSlop = 1e-6;            // m: overlap the positions leave alone
constexpr int kSweepsPerPolish = 10;      // sweeps between the active set's solves

// The largest position target of g's points (0 where none overlaps; a bounce's is its own).
double deepestTarget(const ContactGroup& g) {
  double t = 0.0;
  for (int k = 0; k < g.points; ++k)
    if (!g.bounce[k]) t = std::max(t, g.target[k]);
  return t;
}

// Facings of the same two bodies whose normals oppose (a peg pressed into a slot, both walls one body
// or both the world) cannot all close their overlaps: no motion separates both sides. Asked to, the
// position correction's pseudo-impulses grew every sweep until its limit, and their imbalance turned
// the peg (it rattled, 17 mm into the channel, 5.8 m/s). Each side instead closes half its excess
// over the deepest opposite side's overlap: the peg is centred, and the overlap both share stays
// (also what turning a peg that is turned in its slot would close). share: one entry per group, scratch.
void shareOpposedOverlaps(ContactRows& rows, const ContactSet& contacts, std::vector<double>& share) {
  constexpr double kOpposed = -0.9;  // cos of the angle between two normals beyond which they oppose
  const int ng = rows.size();
  for (int gi = 0; gi < ng; ++gi) {
    share[static_cast<size_t>(gi)] = 0.0;
    if (!rows.inSolve(gi)) continue;
    const ContactGroup& g = rows.group(gi);
    const double deepest = deepestTarget(g);
    if (deepest <= 0.0) continue;
    const Contact& a = contacts[g.first];
    const int tree = g.tree_b >= 0 ? g.tree_b : g.tree_a;
    if (tree < 0) continue;  // two shapes of the world (never a pair today)
    for (const int hi : rows.groupsOn(tree)) {
      const ContactGroup& h = rows.group(hi);
      // The same two parts first: a crowded scene's other pairs are passed without reading their contacts.
      const bool same_parts =
          (h.tree_a == g.tree_a && h.tree_b == g.tree_b) || (h.tree_a == g.tree_b && h.tree_b == g.tree_a);
      if (!same_parts || &h == &g) continue;
      const Contact& b = contacts[h.first];
      double order = 0.0;  // +1: the same two bodies in the same order, -1: swapped
      if (a.body_a == b.body_a && a.body_b == b.body_b) order = 1.0;
      else if (a.body_a == b.body_b && a.body_b == b.body_a) order = -1.0;
      if (order == 0.0 || order * g.n.dot(h.n) > kOpposed) continue;
      const double opposite = deepestTarget(h);
      double& s = share[static_cast<size_t>(gi)];
      if (opposite > 0.0) s = std::max(s, 0.5 * (deepest + opposite));
    }
  }
  for (int gi = 0; gi < ng; ++gi) {
    const double s = share[static_cast<size_t>(gi)];
    if (s == 0.0) continue;
    ContactGroup& g = rows.group(gi);
    for (int k = 0; k < g.points; ++k)
      if (!g.bounce[k]) g.target[k] -= s;
  }
}

}  // namespace

ContactSolver::ContactSolver(const Model& model, const ContactModel& contacts)
    : rows_(model, contacts),
      active_(model, contacts.capacity()),
      z_(VectorX::Zero(model.nv)),
      zs_(VectorX::Zero(model.nv)),
      v_free_(VectorX::Zero(model.nv)),
      twist_(static_cast<size_t>(model.nb)),
      share_(static_cast<size_t>(contacts.capacity())),
      kept_lambda_(static_cast<size_t>(contacts.capacity())),
      previous_(static_cast<size_t>(contacts.capacity())),
      settings_(contacts.settings()) {}

void ContactSolver::warmStart(const ContactSet& contacts) {
  const int ng = rows_.size();
  int p = 0;
  for (int gi = 0; gi < ng; ++gi) {
    const ContactPair& pair = rows_.pair(gi);
    const Contact& c0 = contacts[pair.first];
    while (p < previous_n_ && std::make_pair(previous_[static_cast<size_t>(p)].a, previous_[static_cast<size_t>(p)].b) <
                                  std::make_pair(c0.geom_a, c0.geom_b))
      ++p;
    if (p >= previous_n_ || previous_[static_cast<size_t>(p)].a != c0.geom_a ||
        previous_[static_cast<size_t>(p)].b != c0.geom_b)
      continue;  // no impulse to start from: a pair that waited and waits still has no group
    // Each point's normal impulse: the nearest last point's within reach (a pair in the last solve).
    ContactGroup& g = rows_.open(gi);
    for (int k = 0; k < g.points; ++k) {
      double best = kWarmStartReach * kWarmStartReach;
      for (int q = p; q < previous_n_ && previous_[static_cast<size_t>(q)].a == c0.geom_a &&
                      previous_[static_cast<size_t>(q)].b == c0.geom_b;
           ++q) {
        const Previous& prev = previous_[static_cast<size_t>(q)];
        const double d = (prev.point - contacts[g.first + k].point).squaredNorm();
        if (d < best) {
          best = d;
          g.lambda[k] = prev.normal;
        }
      }
    }
    const Previous& prev = previous_[static_cast<size_t>(p)];
    if (prev.friction.isZero(0.0) && prev.torsion == 0.0) continue;  // none to carry over (a pair that waited)
    rows_.frame(g);
    const int P = g.points;
    double N = 0.0;
    for (int k = 0; k < P; ++k) N += g.lambda[k];
    Vector3 f(prev.friction.dot(g.t1), prev.friction.dot(g.t2), g.patch ? prev.torsion : 0.0);
    // Inside the cone (or the patch's limit surface, or its ellipsoid) of today's load.
    const double rad = g.patch && g.radius > 0.0 ? g.radius : 1.0;
    const double cap = g.mu * N;
    if (shaped(g)) {
      const Vector3 scaled(f.x(), f.y(), f.z() / rad);
      if (!limitInside(g.surface, scaled, cap, &g.surface_hint)) f *= cap / limitSize(g.surface, scaled, &g.surface_hint);
    } else {
      const double size = std::sqrt(f.x() * f.x() + f.y() * f.y() + (f.z() / rad) * (f.z() / rad));
      if (size > cap) f *= cap / size;
    }
    g.lambda.segment<2>(P) = f.head<2>();
    if (g.patch) g.lambda[P + 2] = f.z();
  }
}

// Each point's impulse (its normal, and its share of the pair's friction by its normal load), and
// what the next step starts from.
void ContactSolver::report(ContactSet& contacts) {
  const int ng = rows_.size();
  previous_n_ = 0;  // the points of the pairs in the solve, in the contacts' order (by pair)
  for (int gi = 0; gi < ng; ++gi) {
    if (!rows_.inSolve(gi)) {  // waited outside the solve, no impulse: none to report, none to start from
      const ContactPair& pair = rows_.pair(gi);
      for (int k = 0; k < pair.points; ++k) {
        contacts[pair.first + k].impulse.setZero();
        contacts[pair.first + k].moment.setZero();
      }
      continue;
    }
    const ContactGroup& g = rows_.group(gi);
    const int P = g.points;
    // What the bodies took: the solve's impulses and any impacts passed along before it.
    const ContactRowVector taken = g.impact.isZero(0.0) ? g.lambda : ContactRowVector(g.lambda + g.impact);
    const Vector3 friction = taken[P] * g.t1 + taken[P + 1] * g.t2;
    const double torsion = g.patch ? taken[P + 2] : 0.0;
    // Each point's impulse: its normal one, and its part of the pair's friction, which acts at the
    // centroid of the points that carry it (rows at the centroid): the force split evenly among them
    // (no moment about the centroid: they surround it) and the torsion as tangential forces about it,
    // tau (n x r_k) / sum |r_j|^2. So the points' impulses add up to the wrench the bodies took.
    int carrying = 0;
    double spread = 0.0;  // sum |r_j|^2 over the carrying points, r_j in the tangent plane
    for (int k = 0; k < P; ++k) {
      if (!g.carries[k]) continue;
      ++carrying;
      const Vector3 r = contacts[g.first + k].point - g.centroid;
      spread += (r - r.dot(g.n) * g.n).squaredNorm();
    }
    const Vector3 moment = g.resists ? Vector3(taken[3] * g.n + taken[4] * g.t1 + taken[5] * g.t2) : Vector3::Zero();
    for (int k = 0; k < P; ++k) {
      Contact& c = contacts[g.first + k];
      c.impulse = taken[k] * c.normal;
      c.moment = moment;
      if (g.carries[k] && carrying > 0) {
        c.impulse += friction / carrying;
        if (torsion != 0.0 && spread > 0.0) {
          const Vector3 r = c.point - g.centroid;
          c.impulse += (torsion / spread) * g.n.cross(r - r.dot(g.n) * g.n);
        }
      }
      previous_[static_cast<size_t>(previous_n_++)] = Previous{c.geom_a, c.geom_b, c.point, g.lambda[k], friction, torsion};
    }
  }
}

bool ContactSolver::anySliding() const {
  for (int gi = 0; gi < rows_.size(); ++gi) {
    if (!rows_.inSolve(gi)) continue;  // no impulse
    const ContactGroup& g = rows_.group(gi);
    const int P = g.points;
    double N = 0.0;
    for (int k = 0; k < P; ++k) N += std::max(g.lambda[k], 0.0);
    const double cap = g.mu * N;
    const double rad = g.patch && g.radius > 0.0 ? g.radius : 1.0;
    if (!(cap > 0.0)) continue;
    if (shaped(g)) {
      if (!limitInside(g.surface, Vector3(g.lambda[P], g.lambda[P + 1], g.lambda[P + 2] / rad), (1.0 - 1e-9) * cap,
                       &g.surface_hint))
        return true;
      continue;
    }
    const double size = std::sqrt(g.lambda[P] * g.lambda[P] + g.lambda[P + 1] * g.lambda[P + 1] +
                                  (g.patch ? (g.lambda[P + 2] / rad) * (g.lambda[P + 2] / rad) : 0.0));
    if (size >= (1.0 - 1e-9) * cap) return true;
  }
  return false;
}

// Sweeps, and where they have not converged after a few, the exact solve of the active set they
// found; if that does not hold, more sweeps, another solve, up to the sweep limit. When the first
// sweep from the last step's impulses changes almost nothing and nothing slips (a resting stack:
// its warm start is all but exact, and sweeps would creep towards the tolerance), the active set it
// shows is solved at once. (A slipping friction keeps the direction its guess had: one sweep's is
// not yet right.) \return converged.
bool ContactSolver::solveImpulses() {
  constexpr double kNearlyThere = 1e-6;  // m/s: a first sweep's residual that trusts its active set
  const int limit = settings_.iterations;
  const int start = stats_.iterations;
  bool converged = false;
  while (!converged && stats_.iterations < limit) {
    const bool first = stats_.iterations == start;
    const SweepResult r = sweepImpulses(rows_, z_, std::min(first ? 1 : kSweepsPerPolish, limit - stats_.iterations),
                                        settings_.tolerance);
    stats_.iterations += r.sweeps;
    stats_.residual = r.residual;
    converged = r.converged;
    if (first && !converged && (r.residual > kNearlyThere || anySliding())) continue;  // sweep on first
    if (!converged) {
      // Two polishes failed (21 sweeps), or the sweeps are spent: an island the active set cannot settle
      // is answered on the linearised cone. (Asked only once the sweeps were spent, each such step took
      // 100 sweeps: a step's p99 on puma_table 0.86-0.87 ms, against 0.42-0.44 ms asked after two.)
      const bool linearise = stats_.iterations >= limit || stats_.iterations - start > 2 * kSweepsPerPolish;
      const bool exact = active_.polish(rows_, z_, settings_.tolerance, linearise);
      countPolish();
      stats_.linearised_exact += active_.linearisedExact();
      const int kept = active_.linearised();
      const double kept_angle = active_.linearisedAngle();
      stats_.linearised_failed = active_.linearisedFailed();
      if (exact && kept > 0 && stats_.iterations < limit && refineOnCone(limit)) {
        stats_.linearised_exact += kept;  // settled on the cone from the polytope's answer
        converged = true;
      } else if (exact) {
        converged = true;  // every condition checked, to the tolerance (an island on a polytope: its LCP's)
        stats_.residual = 0.0;
        stats_.linearised += kept;
        stats_.linearised_angle = std::max(stats_.linearised_angle, kept_angle);
      }
    }
  }
  return converged;
}

// The active-set solve's figures of its last call, into the solve's.
void ContactSolver::countPolish() {
  stats_.polish_rounds += active_.rounds();
  stats_.slips_unturned += active_.slipsUnturned();
  stats_.polish_cycles += active_.cycles();
  stats_.large_solves += active_.largeSolves();
  stats_.large_iterations += active_.largeIterations();
  stats_.slip_angle = std::max(stats_.slip_angle, active_.slipAngle());
}

// An island the active set could not settle took a polytope's answer (a slipping friction up to the
// polytope's angle off the one against its slip), and the solve called that settled. With the sweeps
// that are left, the solve goes on from it on the true cone, sweeps and active-set solves as before
// (not on the polytope again): a sweeps' fixed point or an exact active set is the cone's own answer.
// Where neither comes before the sweep limit, the polytope's answer is put back. \return whether the
// cone's answer came.
bool ContactSolver::refineOnCone(int limit) {
  const int ng = rows_.size();
  for (int gi = 0; gi < ng; ++gi)
    if (rows_.inSolve(gi)) kept_lambda_[static_cast<size_t>(gi)] = rows_.group(gi).lambda;
  while (stats_.iterations < limit) {
    const SweepResult r =
        sweepImpulses(rows_, z_, std::min(kSweepsPerPolish, limit - stats_.iterations), settings_.tolerance);
    stats_.iterations += r.sweeps;
    if (r.converged) {
      stats_.residual = r.residual;
      return true;
    }
    const bool exact = active_.polish(rows_, z_, settings_.tolerance, false);
    countPolish();
    if (exact) {
      stats_.residual = 0.0;
      return true;
    }
  }
  for (int gi = 0; gi < ng; ++gi)
    if (rows_.inSolve(gi)) rows_.group(gi).lambda = kept_lambda_[static_cast<size_t>(gi)];
  rows_.accumulate(z_);
  return false;
}

// The impulses' change of kinetic energy (in A's metric): lambda^T J v_free + 1/2 lambda^T W lambda.
double ContactSolver::kineticGain(double* scale) const {
  double gain = 0.0, size = 0.0;
  for (int gi = 0; gi < rows_.size(); ++gi) {
    if (!rows_.inSolve(gi)) continue;
    const ContactGroup& g = rows_.group(gi);
    const ContactRowVector u = rows_.velocity(g, z_, g.rows);
    for (int r = 0; r < g.rows; ++r) {
      gain += g.lambda[r] * (g.b[r] + 0.5 * u[r]);
      size += std::abs(g.lambda[r] * g.b[r]);
    }
  }
  *scale = size;
  return gain;
}

// The warm start against a cold one, as MuJoCo compares them: the solve's cost
// 1/2 lambda^T W lambda + lambda^T (b - u*) (its minimum is the answer where nothing slips) at the
// last step's impulses against its value, zero, at none. Where the warm start costs more (a load
// that has just been lifted, contacts that have turned), it is dropped and the solve starts from
// zero. Counted (warm_dropped).
void ContactSolver::dropWorseWarmStart() {
  double cost = 0.0;
  bool any = false;
  for (int gi = 0; gi < rows_.size(); ++gi) {
    if (!rows_.inSolve(gi)) continue;
    const ContactGroup& g = rows_.group(gi);
    if (g.lambda.isZero(0.0)) continue;
    any = true;
    const ContactRowVector u = rows_.velocity(g, z_, g.rows);
    for (int r = 0; r < g.rows; ++r) cost += g.lambda[r] * (g.b[r] - g.target[r] + 0.5 * u[r]);
  }
  if (!any || cost <= 0.0) return;
  for (int gi = 0; gi < rows_.size(); ++gi) {
    if (!rows_.inSolve(gi)) continue;
    ContactGroup& g = rows_.group(gi);
    rows_.clear(g, z_);
    g.lambda.setZero();
  }
  ++stats_.warm_dropped;
}

// Newton's restitution at several points at once, with friction that sticks or beside a pair that
// separates, can give the bodies more kinetic energy than they brought (a box landing on an edge: 3 %
// more). Where the solve's impulses would, the restitution of every bouncing point is scaled by the
// largest factor in [0, 1] that gives back no more than came in (bisection; the plastic solve, factor
// 0, only takes energy away), and the solve taken again. \return converged.
bool ContactSolver::keepEnergy() {
  constexpr double kRoundOff = 1e-12;
  constexpr int kHalvings = 10;
  double scale = 0.0;
  if (kineticGain(&scale) <= kRoundOff * scale) return true;
  ++stats_.restitution_scaled;
  auto solveWith = [&](double factor) {
    for (int gi = 0; gi < rows_.size(); ++gi) {
      if (!rows_.hasGroup(gi)) continue;
      ContactGroup& g = rows_.group(gi);
      for (int k = 0; g.built && k < g.points; ++k)
        if (g.bounce[k]) g.target[k] = factor * g.bounce_target[k];
    }
    return solveImpulses();
  };
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < kHalvings; ++i) {
    const double mid = 0.5 * (lo + hi);
    solveWith(mid);
    (kineticGain(&scale) <= kRoundOff * scale ? lo : hi) = mid;
  }
  restitution_scale_ = lo;
  return solveWith(lo);
}

// The last guard: impulses that would still add kinetic energy (a solve that stopped short of
// converging, its friction not yet at maximal dissipation) are scaled down, all by one factor, to
// the largest that adds none: gain(beta) = beta lambda^T b + beta^2 / 2 lambda^T W lambda. Scaling
// keeps every impulse in its cone and every normal one pushing. Counted.
void ContactSolver::capEnergy() {
  constexpr double kRoundOff = 1e-12;
  double scale = 0.0;
  const double gain = kineticGain(&scale);
  if (gain <= kRoundOff * scale) return;
  double work = 0.0;  // lambda^T b
  for (int gi = 0; gi < rows_.size(); ++gi) {
    if (!rows_.inSolve(gi)) continue;
    const ContactGroup& g = rows_.group(gi);
    work += g.lambda.head(g.rows).dot(g.b.head(g.rows));
  }
  const double quadratic = 2.0 * (gain - work);  // lambda^T W lambda
  const double beta = work < 0.0 && quadratic > 0.0 ? std::min(1.0, -2.0 * work / quadratic) * (1.0 - 1e-12) : 0.0;
  for (int gi = 0; gi < rows_.size(); ++gi)
    if (rows_.inSolve(gi)) rows_.group(gi).lambda *= beta;
  rows_.accumulate(z_);
  ++stats_.energy_capped;
}

void ContactSolver::solve(const Data& data, const TreeMatrix& LD, double h, const VectorX& v0, ContactSet& contacts,
                          VectorX& v, VectorX& v_position) {
  // The figures of this step's solve (all 0 on a step without contacts: none ran).
  stats_.iterations = 0;
  stats_.residual = 0.0;
  stats_.polish_rounds = 0;
  stats_.slip_angle = 0.0;
  stats_.linearised_angle = 0.0;
  stats_.deferred = 0;
  stats_.impact_rounds = 0;
  stats_.position_sweeps = 0;
  stats_.position_residual = 0.0;
  if (contacts.n == 0) {
    previous_n_ = 0;
    v_position = v;
    return;
  }
  const int ng = rows_.build(data, LD, contacts, h, v0, v);
  warmStart(contacts);
  // Pairs apart and not closing, with no impulse from the last step, wait outside the solve (a pile's
  // neighbours a millimetre apart inside the margin: most of its pairs); each is checked against the
  // solve's v+ and let in if the others' impulses push it across.
  for (int g = 0; g < ng; ++g) {
    if (!rows_.hasGroup(g)) {  // apart, not closing, no impulse to start from
      ++stats_.deferred;
      continue;
    }
    ContactGroup& G = rows_.group(g);
    if (G.lambda.isZero(0.0) && (!G.built || rows_.separating(G, contacts, h))) {
      ++stats_.deferred;
      continue;
    }
    rows_.complete(g, LD, v);
  }
  v_free_ = v;
  restitution_scale_ = 1.0;
  bool bounces = false;
  for (int g = 0; g < ng && !bounces; ++g)
    for (int k = 0; rows_.hasGroup(g) && rows_.group(g).built && k < rows_.group(g).points; ++k)
      bounces = bounces || rows_.group(g).bounce[k];
  // Impacts that can pass along a chain are passed along first, pair by pair (contact_impacts.h); the
  // solve then starts from the velocity they leave, its contacts plastic.
  if (bounces && impactsCanPass(rows_)) {
    for (int g = 0; g < ng; ++g)  // a pair waiting outside may be struck: all of them in
      if (!rows_.inSolve(g)) rows_.complete(g, LD, v);
    stats_.deferred = 0;
    const ImpactPassing passing =
        passImpacts(rows_, contacts, h, settings_.bounce_velocity, settings_.iterations, settings_.tolerance, z_);
    stats_.impact_rounds = passing.rounds;
    stats_.restitution_scaled += passing.scaled;
    for (int gi = 0; gi < ng; ++gi) {
      ContactGroup& g = rows_.group(gi);
      g.b.head(g.rows) += rows_.velocity(g, z_, g.rows);
      for (int k = 0; k < g.points; ++k) {
        g.bounce[k] = false;
        g.target[k] = -std::max(contacts[g.first + k].distance, 0.0) / h;
      }
    }
    rows_.apply(LD, z_, v);
    v_free_ = v;
    bounces = false;
  }
  bool converged = false;
  constexpr int kLetIn = 4;  // solves with pairs let in before every waiting pair is let in
  double crossing = 0.0;     // m/s: the fastest a pair let in was crossing under the last pass's v+
  for (int pass = 0;; ++pass) {
    for (int g = 0; g < ng; ++g)
      if (rows_.inSolve(g)) rows_.add(rows_.group(g), rows_.group(g).lambda, rows_.group(g).rows, z_);
    if (pass == 0) dropWorseWarmStart();
    const bool spent = stats_.iterations >= settings_.iterations;
    converged = solveImpulses();
    // With the sweeps spent a pass runs none: the pairs let in got no impulse, and its residual is
    // the speed they cross at (it read 0, the unconverged solve looking exact).
    if (spent) stats_.residual = std::max(stats_.residual, crossing);
    if (bounces) converged = keepEnergy() && converged;
    capEnergy();
    rows_.apply(LD, z_, v);
    if (stats_.deferred == 0) break;
    // A waiting pair whose end gap the solve's v+ closes comes in (all of them after kLetIn tries).
    int let_in = 0;
    crossing = 0.0;
    rows_.twists(v, twist_);
    for (int g = 0; g < ng; ++g) {
      if (rows_.inSolve(g)) continue;
      const ContactPair& pair = rows_.pair(g);
      const ContactGroup* const built = rows_.hasGroup(g) && rows_.group(g).built ? &rows_.group(g) : nullptr;
      bool crosses = pass >= kLetIn;
      for (int k = 0; k < pair.points; ++k) {
        const Contact& c = contacts[pair.first + k];
        const double u = built ? rows_.normalSpeed(*built, k, v) : ContactRows::twistSpeed(c, twist_);
        if (c.distance + h * u < -h * settings_.tolerance) {
          crosses = true;
          crossing = std::max(crossing, -(c.distance / h + u));
        }
      }
      if (!crosses) continue;
      rows_.complete(g, LD, v_free_);
      --stats_.deferred;
      ++let_in;
    }
    if (let_in == 0) break;
    stats_.let_in += let_in;
    v = v_free_;
  }
  if (!converged) ++stats_.unconverged;
  ++stats_.solves;
  report(contacts);
  // Positions: what still overlaps at the step's end closes (a bounce ends where it would have,
  // e (approach h - gap) above the surface), by a pseudo-velocity that no velocity keeps.
  bool any = false;
  for (int gi = 0; gi < ng; ++gi) {
    if (!rows_.inSolve(gi)) continue;  // apart at the step's end: nothing to close
    ContactGroup& g = rows_.group(gi);
    for (int k = 0; k < g.points; ++k) {
      const Contact& c = contacts[g.first + k];
      const double end_gap = c.distance + h * rows_.normalSpeed(g, k, v);
      if (g.bounce[k]) {
        g.target[k] = (restitution_scale_ * c.restitution * (g.approach[k] * h - std::max(c.distance, 0.0)) - end_gap) / h;
        any = true;
      } else {
        // Overlaps within the slop stay: correcting round-off's 1e-13 m would tilt a stack's boxes
        // (the pseudo-impulses have no friction to keep them in line).
        g.target[k] = std::max(0.0, -(end_gap + kSlop)) / h;
        any = any || g.target[k] > 0.0;
      }
    }
  }
  v_position = v;
  if (!any) return;
  shareOpposedOverlaps(rows_, contacts, share_);
  const SweepResult pseudo = sweepPseudo(rows_, zs_, settings_.iterations, settings_.tolerance);
  stats_.position_sweeps = pseudo.sweeps;
  stats_.position_residual = pseudo.residual;
  if (!pseudo.converged) ++stats_.position_unconverged;
  rows_.apply(LD, zs_, v_position);
}

}  // namespace igms
