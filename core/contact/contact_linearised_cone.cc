// The active set's last resort on an island it could not settle: Coulomb's cone (a patch's limit
// surface) replaced by the polytope of a set of points on its edge (its generators), posed as Stewart
// and Trinkle's LCP and solved by Lemke's method (lemke.h), which ends where principal pivoting need
// not (a sliding system that is not a P-matrix). With the normals lambda_n, per friction its
// generators' weights beta and a slip speed sigma, and u = b + W lambda (lambda = (lambda_n, G beta)):
//   u_n - u*        >= 0  _|_  lambda_n >= 0
//   G^T u_f + sigma >= 0  _|_  beta >= 0        (the friction: the generators most against the slip)
//   mu N - sum beta >= 0  _|_  sigma >= 0       (it slips only on the polytope's edge)
// The polytope has `around` directions in the tangent plane (a patch's torsion: rings of around / 2 at
// +-45 degrees and the pure spins) and the sweeps' friction; with none around, the sweeps' friction
// alone. Its answer seeds the active set once more, in up to three ways (seededFromLinearised()); where
// one settles, the island's answer is exact. Else the next polytope of ContactActiveSet::kPolytopes is
// tried, and after the last the island keeps the finest polytope's answer (counted:
// ContactActiveSet::linearised()). The solver asks for it once two polishes have failed
// (contact_solver.cc): it costs a few dense solves of the island per polytope.
#include <algorithm>
#include <cmath>

#include "core/contact/contact_active_set.h"

namespace igms {

namespace {

// Directions in the friction's scaled coordinates: `around` in the tangent plane; for a patch's
// torsion, rings of around / 2 at +-45 degrees between them and the two pure spins.
int baseDirections(int rows, int around, Vector3* out) {
  int k = 0;
  for (int i = 0; i < around; ++i) {
    const double a = 2.0 * M_PI * i / around;
    out[k++] = Vector3(std::cos(a), std::sin(a), 0.0);
  }
  if (rows == 3) {
    const double c = std::sqrt(0.5);
    for (int i = 0; i < around / 2; ++i) {
      const double a = 2.0 * M_PI * (i + 0.5) / (around / 2);
      out[k++] = Vector3(c * std::cos(a), c * std::sin(a), c);
      out[k++] = Vector3(c * std::cos(a), c * std::sin(a), -c);
    }
    out[k++] = Vector3::UnitZ();
    out[k++] = -Vector3::UnitZ();
  }
  return k;
}

}  // namespace

bool ContactActiveSet::linearisedIsland(ContactRows& rows, int n, double tolerance, int around) {
  auto group = [&](int m) -> ContactGroup& { return member(rows, m); };
  if (n > kLinearisedGroups) return false;
  // The generators (real coordinates, per unit mu N).
  for (int m = 0; m < n; ++m) {
    ContactGroup& g = group(m);
    if (g.resists || cache_count_[static_cast<size_t>(m)] < 0) return false;
    int& count = generator_count_[static_cast<size_t>(m)];
    count = 0;
    if (!(g.mu > 0.0)) continue;
    const int F = frictionRows(g), P = g.points;
    const Vector3 scale = scaleOf(g);
    Vector3 dirs[kMaxGenerators];
    const int nd = baseDirections(F, around, dirs);
    auto& G = generators_[static_cast<size_t>(m)];
    for (int d = 0; d < nd; ++d) G.col(count++) = (dirs[d] / frictionSize(g, dirs[d])).cwiseProduct(scale);
    Vector3 s = Vector3::Zero();  // the sweeps' friction, where it has one
    for (int f = 0; f < F; ++f) s[f] = g.lambda[P + f] / scale[f];
    if (s.norm() > 0.0) G.col(count++) = (s / frictionSize(g, s)).cwiseProduct(scale);
  }
  int size = 0;  // each member's unknowns: its normals, its generators' weights, its slip speed
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = group(m);
    const int gi = rows.slotOf(g);
    lcp_base_[static_cast<size_t>(gi)] = size;
    lcp_member_[static_cast<size_t>(gi)] = m;
    const int d = generator_count_[static_cast<size_t>(m)];
    size += g.points + (d > 0 ? d + 1 : 0);
  }
  if (size > lemke_.capacity()) return false;
  const double big = assembleLinearised(rows, n, size);
  regulariseLinearised(rows, n, kLinearisedRegularisation * big + 1e-300);
  // Where the answer fails its check (Lemke's pivots on near-singular redundant normals lose digits),
  // again with a larger regularisation: over 12 runs of each of solve_ensemble.py's cases, 18 islands
  // failed, 2 of them left unconverged, with 1e-12 alone, none with the retries.
  double added = kLinearisedRegularisation;
  bool solved = lemke_.solve(lcp_M_, lcp_q_, size, lcp_z_);
  for (const double retry : kLinearisedRetries) {
    if (solved) break;
    regulariseLinearised(rows, n, (retry - added) * big);
    added = retry;
    solved = lemke_.solve(lcp_M_, lcp_q_, size, lcp_z_);
  }
  if (!solved) {
    ++linearised_failed_;
    return false;
  }
  // The answer's impulses (kept: linearised_answer_), and the velocities they give.
  for (int m = 0; m < n; ++m) {
    ContactGroup& g = group(m);
    const int gb = lcp_base_[static_cast<size_t>(rows.slotOf(g))];
    const int P = g.points, F = frictionRows(g), d = generator_count_[static_cast<size_t>(m)];
    g.trial.setZero();
    for (int k = 0; k < P; ++k) g.trial[k] = lcp_z_[gb + k];
    for (int j = 0; j < d; ++j)
      for (int f = 0; f < F; ++f) g.trial[P + f] += generators_[static_cast<size_t>(m)](f, j) * lcp_z_[gb + P + j];
    linearised_answer_[static_cast<size_t>(m)] = g.trial;
  }
  trialVelocities(rows, n);
  // The seed: the answer, each slipping friction (sigma > 0, loaded, slipping beyond the tolerance)
  // turned against its slip on the true cone's edge. (Refining the polytope instead, the point against
  // each slip made a generator and the LCP solved again up to three times, settled fewer islands: over
  // 12 runs of puma_table, 365 exact and 255 kept the polytope's answer, against 564 and 213; both
  // measured before Lemke's basis was solved again, lemke.h.)
  island_angle_ = 0.0;
  for (int m = 0; m < n; ++m) {
    ContactGroup& g = group(m);
    g.lambda = g.trial;
    const int gb = lcp_base_[static_cast<size_t>(rows.slotOf(g))];
    const int P = g.points, F = frictionRows(g), d = generator_count_[static_cast<size_t>(m)];
    if (d == 0 || !(lcp_z_[gb + P + d] > 0.0)) continue;
    double N = 0.0;
    for (int k = 0; k < (g.patch ? P : 1); ++k) N += g.trial[k];
    const Vector3 scale = scaleOf(g);
    Vector3 w = Vector3::Zero();
    for (int f = 0; f < F; ++f) w[f] = g.trial_u[P + f] * scale[f];
    if (!(w.norm() > tolerance) || !(N > 0.0)) continue;  // a slip within the tolerance: any direction
    const Vector3 against = -againstSlip(g, w);  // on the edge, per unit mu N
    Vector3 s = Vector3::Zero();  // the polytope's friction
    for (int f = 0; f < F; ++f) s[f] = g.trial[P + f] / scale[f];
    if (s.norm() > 0.0) {
      const double chord = (s.normalized() - against.normalized()).norm();  // 2 sin(angle / 2)
      island_angle_ = std::max(island_angle_, 2.0 * std::asin(std::min(1.0, 0.5 * chord)));
    }
    for (int f = 0; f < F; ++f) g.lambda[P + f] = g.mu * N * scale[f] * against[f];
  }
  return true;
}

// The LCP (M: lcp_M_, q: lcp_q_) of the island's generators and places (lcp_base_), `size` unknowns,
// unregularised. \return the largest diagonal of a normal (the scale of regulariseLinearised()).
double ContactActiveSet::assembleLinearised(ContactRows& rows, int n, int size) {
  auto M = lcp_M_.topLeftCorner(size, size);
  M.setZero();
  double big = 0.0;
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = member(rows, m);
    const int gb = lcp_base_[static_cast<size_t>(rows.slotOf(g))];
    const int Pg = g.points, Fg = frictionRows(g), dg = generator_count_[static_cast<size_t>(m)];
    const auto& Gg = generators_[static_cast<size_t>(m)];
    // W_gh's part, in the unknowns: normals as they are, friction rows through the generators.
    auto add = [&](const ContactBlock& W, const ContactGroup& h) {
      const int hi = rows.slotOf(h);
      const int hb = lcp_base_[static_cast<size_t>(hi)], hm = lcp_member_[static_cast<size_t>(hi)];
      const int Ph = h.points, Fh = frictionRows(h), dh = generator_count_[static_cast<size_t>(hm)];
      const auto& Gh = generators_[static_cast<size_t>(hm)];
      for (int k = 0; k < Pg; ++k) {
        for (int l = 0; l < Ph; ++l) M(gb + k, hb + l) += W(k, l);
        for (int j = 0; j < dh; ++j) {
          double v = 0.0;
          for (int f = 0; f < Fh; ++f) v += W(k, Ph + f) * Gh(f, j);
          M(gb + k, hb + Ph + j) += v;
        }
      }
      for (int i = 0; i < dg; ++i) {
        for (int l = 0; l < Ph; ++l) {
          double v = 0.0;
          for (int f = 0; f < Fg; ++f) v += Gg(f, i) * W(Pg + f, l);
          M(gb + Pg + i, hb + l) += v;
        }
        double gw[3] = {0.0, 0.0, 0.0};  // G_g(:, i)^T W_ff
        for (int c = 0; c < Fh; ++c)
          for (int f = 0; f < Fg; ++f) gw[c] += Gg(f, i) * W(Pg + f, Ph + c);
        for (int j = 0; j < dh; ++j) {
          double v = 0.0;
          for (int c = 0; c < Fh; ++c) v += gw[c] * Gh(c, j);
          M(gb + Pg + i, hb + Ph + j) += v;
        }
      }
    };
    add(g.W, g);
    const int first = cache_first_[static_cast<size_t>(m)];  // the couplings the polish cached
    for (int k = first; k < first + cache_count_[static_cast<size_t>(m)]; ++k)
      add(cache_block_[static_cast<size_t>(k)], rows.group(cache_group_[static_cast<size_t>(k)]));
    for (int k = 0; k < Pg; ++k) {
      lcp_q_[gb + k] = g.b[k] - g.target[k];
      big = std::max(big, std::abs(g.W(k, k)));
    }
    if (dg == 0) continue;
    const int sg = gb + Pg + dg;  // the slip speed's row
    for (int i = 0; i < dg; ++i) {
      double v = 0.0;
      for (int f = 0; f < Fg; ++f) v += Gg(f, i) * g.b[Pg + f];
      lcp_q_[gb + Pg + i] = v;
      M(gb + Pg + i, sg) = 1.0;
      M(sg, gb + Pg + i) = -1.0;
    }
    for (int k = 0; k < (g.patch ? Pg : 1); ++k) M(sg, gb + k) = g.mu;
    lcp_q_[sg] = 0.0;
  }
  return big;
}

// Adds `amount` to the diagonal of the normals and the generators, as the active set regularises:
// redundant normals pick the even split, and generators that give the same friction share it.
void ContactActiveSet::regulariseLinearised(ContactRows& rows, int n, double amount) {
  for (int m = 0; m < n; ++m) {
    const ContactGroup& g = member(rows, m);
    const int gb = lcp_base_[static_cast<size_t>(rows.slotOf(g))];
    for (int r = 0; r < g.points + generator_count_[static_cast<size_t>(m)]; ++r) lcp_M_(gb + r, gb + r) += amount;
  }
}

void ContactActiveSet::seedLinearisedOnEdge(ContactRows& rows, int n) {
  for (int m = 0; m < n; ++m) {
    ContactGroup& g = member(rows, m);
    g.lambda = linearised_answer_[static_cast<size_t>(m)];
    const int gb = lcp_base_[static_cast<size_t>(rows.slotOf(g))];
    const int P = g.points, F = frictionRows(g), d = generator_count_[static_cast<size_t>(m)];
    if (d == 0 || !(lcp_z_[gb + P + d] > 0.0)) continue;  // not slipping (sigma = 0)
    double N = 0.0;
    for (int k = 0; k < (g.patch ? P : 1); ++k) N += g.lambda[k];
    const Vector3 scale = scaleOf(g);
    Vector3 s = Vector3::Zero();
    for (int f = 0; f < F; ++f) s[f] = g.lambda[P + f] / scale[f];
    if (!(s.norm() > 0.0) || !(N > 0.0)) continue;
    const double size = frictionSize(g, s);
    for (int f = 0; f < F; ++f) g.lambda[P + f] = g.mu * N * scale[f] * s[f] / size;
  }
}

// Three seeds from the answer, each tried where the one before did not settle: each slipping friction
// turned against its slip on the cone's edge (as linearisedIsland() left it); the polytope's answer as
// it is (a friction inside the cone there is a guess of sticking); each slipping friction carried out
// to the cone's edge in its own direction. Over 12 runs of each of solve_ensemble.py's cases, with the
// first polytope alone, puma_table's islands left on it were 253 with the first seed, 98 with two, 50
// with three (docs/environment.md, "Seeds and polytopes").
bool ContactActiveSet::seededFromLinearised(ContactRows& rows, int n, double tolerance) {
  if (polishIsland(rows, n, tolerance)) return true;
  keepLinearisedAnswer(rows, n);
  if (polishIsland(rows, n, tolerance)) return true;
  seedLinearisedOnEdge(rows, n);
  return polishIsland(rows, n, tolerance);
}

void ContactActiveSet::keepLinearisedAnswer(ContactRows& rows, int n) {
  for (int m = 0; m < n; ++m) member(rows, m).lambda = linearised_answer_[static_cast<size_t>(m)];
}

}  // namespace igms
