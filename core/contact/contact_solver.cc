#include "core/contact/contact_solver.h"

#include <algorithm>
#include <cmath>

#include "core/model/ancestor_runs.h"

namespace igms {

namespace {

constexpr int kCouplingsPerGroup = 12;    // pool: W blocks per pair on average
constexpr double kWarmStartReach = 0.02;  // m: a last step's point this near, of the same pair, starts it
constexpr double kSlop = 1e-6;            // m: overlap the positions leave alone
constexpr double kPatchDepth = 1e-4;      // m: a patch's points this near the deepest carry its friction

// Two unit tangents completing n, a function of n alone.
void tangents(const Vector3& n, Vector3& t1, Vector3& t2) {
  int k = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(n[a]) < std::abs(n[k])) k = a;
  t1 = n.cross(Vector3::Unit(k)).normalized();
  t2 = n.cross(t1);
}

template <typename M>
M regularisedInverse(const M& W) {
  const double eps = 1e-10 * W.diagonal().maxCoeff() + 1e-300;
  return (W + eps * M::Identity()).inverse();
}

}  // namespace

ContactSolver::ContactSolver(const Model& model, const ContactModel& contacts) : model_(model), cm_(contacts) {
  body_chain_.resize(static_cast<size_t>(model.nb));
  part_of_body_.resize(static_cast<size_t>(model.nb));
  int deepest = 0;
  for (int b = 0; b < model.nb; ++b) {
    std::vector<int>& chain = body_chain_[static_cast<size_t>(b)];
    for (int j = b; j >= 0; j = model.parent[j])
      for (int k = model.joint_nv[j] - 1; k >= 0; --k) chain.push_back(model.v_index[j] + k);
    std::reverse(chain.begin(), chain.end());
    deepest = std::max(deepest, static_cast<int>(chain.size()));
    part_of_body_[static_cast<size_t>(b)] = model.partOfBody(b);
  }
  const int capacity = contacts.capacity();
  max_entries_ = 2 * deepest;
  groups_.resize(static_cast<size_t>(capacity));
  dof_.resize(static_cast<size_t>(capacity * max_entries_));
  invD_.resize(dof_.size());
  J_.resize(static_cast<size_t>(capacity * max_entries_ * kMaxRows));
  X_.resize(J_.size());
  nbr_.resize(static_cast<size_t>(capacity * kCouplingsPerGroup));
  block_.resize(nbr_.size());
  stamp_.assign(static_cast<size_t>(capacity), -1);
  tree_groups_.assign(model.parts.size(), std::vector<int>(static_cast<size_t>(capacity)));
  tree_count_.assign(model.parts.size(), 0);
  tree_touched_.assign(model.parts.size(), 0);
  scratch_ = VectorX::Zero(model.nv);
  previous_.resize(static_cast<size_t>(capacity));
  island_.resize(static_cast<size_t>(capacity));
  queue_.resize(static_cast<size_t>(capacity));
  members_.resize(static_cast<size_t>(capacity));
  M_.resize(static_cast<size_t>(kPolishRows * kPolishRows));
  rhs_.resize(kPolishRows);
  pivot_.resize(kPolishRows);
}

// Each pair's rows: their Jacobian on the pair's chains, X = L^-T J^T there, its own W block, its
// velocities and targets.
void ContactSolver::build(const Data& data, const MatrixX& LD, const ContactSet& contacts, double h, const VectorX& v0,
                          const VectorX& v) {
  const int nc = contacts.n;
  const int nv = model_.nv;
  const double* const ld = LD.data();
  const double bounce_velocity = cm_.settings().bounce_velocity;
  std::fill(tree_count_.begin(), tree_count_.end(), 0);
  int ng = 0, entry = 0, value = 0;
  for (int i = 0; i < nc;) {
    int end = i + 1;
    while (end < nc && contacts[end].geom_a == contacts[i].geom_a && contacts[end].geom_b == contacts[i].geom_b) ++end;
    Group& g = groups_[static_cast<size_t>(ng++)];
    const Contact& c0 = contacts[i];
    g.first = i;
    g.points = end - i;
    g.patch = g.points > 1;
    g.rows = g.points + (g.patch ? 3 : 2);
    g.mu = c0.friction;
    // The patch's friction sits where it touches: the centroid (and normal, and radius) of its points
    // within kPatchDepth of the deepest (a lying cylinder's two rim ends, not a rim point above them
    // that the margin let in: friction there would roll it about the wrong line).
    double deepest = contacts[i].distance;
    for (int k = i + 1; k < end; ++k) deepest = std::min(deepest, contacts[k].distance);
    g.centroid.setZero();
    Vector3 normal = Vector3::Zero();
    int touching = 0;
    for (int k = i; k < end; ++k)
      if (contacts[k].distance <= deepest + kPatchDepth) {
        g.centroid += contacts[k].point;
        normal += contacts[k].normal;
        ++touching;
      }
    g.centroid /= touching;
    g.n = normal.normalized();
    tangents(g.n, g.t1, g.t2);
    g.radius = 0.0;
    for (int k = i; k < end; ++k)
      if (contacts[k].distance <= deepest + kPatchDepth) g.radius += (contacts[k].point - g.centroid).norm();
    g.radius /= touching;
    // The dofs: the union of both bodies' chains, ascending; each with its side's sign.
    static const std::vector<int> kNone;
    const std::vector<int>& ca = c0.body_a >= 0 ? body_chain_[static_cast<size_t>(c0.body_a)] : kNone;
    const std::vector<int>& cb = c0.body_b >= 0 ? body_chain_[static_cast<size_t>(c0.body_b)] : kNone;
    g.first_entry = entry;
    g.first_value = value;
    double sign[2 * 64];  // per entry; chains are short (the model's deepest, twice)
    size_t ia = 0, ib = 0;
    int count = 0;
    while (ia < ca.size() || ib < cb.size()) {
      int k;
      double s;
      if (ib >= cb.size() || (ia < ca.size() && ca[ia] < cb[ib])) {
        k = ca[ia++];
        s = -1.0;
      } else if (ia >= ca.size() || cb[ib] < ca[ia]) {
        k = cb[ib++];
        s = 1.0;
      } else {  // a dof moving both sides (a robot touching itself) moves them alike: no relative motion
        ++ia;
        ++ib;
        continue;
      }
      dof_[static_cast<size_t>(entry + count)] = k;
      invD_[static_cast<size_t>(entry + count)] = 1.0 / ld[static_cast<std::ptrdiff_t>(k) * nv + k];
      sign[std::min(count, 127)] = s;
      ++count;
    }
    g.entries = count;
    // J: a row per normal, then the friction rows (at the point, or the patch's centroid).
    // Each row as a spatial vector [d; p x d] (the velocity of point p along d is its dot with the
    // dof's world twist [v; w]); a torsion row [0; n].
    const int P = g.points;
    Vector6 row[kMaxRows];
    for (int k = 0; k < P; ++k) row[k] << contacts[i + k].normal, contacts[i + k].point.cross(contacts[i + k].normal);
    row[P] << g.t1, g.centroid.cross(g.t1);
    row[P + 1] << g.t2, g.centroid.cross(g.t2);
    if (g.patch) row[P + 2] << Vector3::Zero(), g.n;
    for (int e = 0; e < count; ++e) {
      const Eigen::Map<const Vector6> S(data.S_world.col(dof_[static_cast<size_t>(entry + e)]).data());
      double* const J = J_.data() + value;
      for (int r = 0; r < g.rows; ++r) J[r * count + e] = sign[e] * row[r].dot(S);
    }
    // X = L^-T J^T, on the entries alone: each entry's parent dof is an entry too (a chain is closed
    // upward), found below it in the ascending list; from the last entry down, each passes its value
    // up its chain.
    int up[2 * 64];
    for (int e = 0; e < count; ++e) {
      const int parent = model_.dof_parent[dof_[static_cast<size_t>(entry + e)]];
      int a = e - 1;
      while (a >= 0 && dof_[static_cast<size_t>(entry + a)] != parent) --a;
      up[e] = parent < 0 ? -1 : a;
    }
    std::copy(J_.begin() + value, J_.begin() + value + g.rows * count, X_.begin() + value);
    for (int e = count - 1; e >= 0; --e) {
      const double* const lk = ld + static_cast<std::ptrdiff_t>(dof_[static_cast<size_t>(entry + e)]) * nv;
      for (int r = 0; r < g.rows; ++r) {
        double* const X = X_.data() + value + r * count;
        const double xk = X[e];
        if (xk == 0.0) continue;
        for (int a = up[e]; a >= 0; a = up[a]) X[a] -= lk[dof_[static_cast<size_t>(entry + a)]] * xk;
      }
    }
    g.W.setZero();
    for (int r = 0; r < g.rows; ++r)
      for (int s = r; s < g.rows; ++s) {
        const double* const xr = X_.data() + value + r * count;
        const double* const xs = X_.data() + value + s * count;
        double w = 0.0;
        for (int e = 0; e < count; ++e) w += xr[e] * xs[e] * invD_[static_cast<size_t>(entry + e)];
        g.W(r, s) = g.W(s, r) = w;
      }
    if (g.patch) {
      const Eigen::Matrix3d F = g.W.block<3, 3>(P, P);
      g.friction_inverse = regularisedInverse(F);
      const Vector3 scale(1.0, 1.0, g.radius);
      const Eigen::Matrix3d Fs = scale.asDiagonal() * F * scale.asDiagonal();
      g.friction_step = 1.0 / (Fs.cwiseAbs().rowwise().sum().maxCoeff() + 1e-300);
    } else {
      g.friction_inverse = regularisedInverse(Eigen::Matrix3d(g.W.block<3, 3>(0, 0)));
      const double a = g.W(1, 1), b = g.W(1, 2), d = g.W(2, 2);
      g.friction_step = 1.0 / (0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b) + 1e-300);
    }
    // Velocities and targets.
    g.b.setZero();
    g.target.setZero();
    g.sigma.setZero();
    for (int r = 0; r < g.rows; ++r) {
      const double* const J = J_.data() + value + r * count;
      double b = 0.0;
      for (int e = 0; e < count; ++e) b += J[e] * v[dof_[static_cast<size_t>(entry + e)]];
      g.b[r] = b;
    }
    for (int k = 0; k < P; ++k) {
      const Contact& c = contacts[i + k];
      const double* const J = J_.data() + value + k * count;
      double u0 = 0.0;
      for (int e = 0; e < count; ++e) u0 += J[e] * v0[dof_[static_cast<size_t>(entry + e)]];
      g.approach[k] = -u0;
      // An impact that bounces: fast enough, and it reaches the surface within this step.
      g.bounce[k] = c.restitution > 0.0 && g.approach[k] > bounce_velocity && c.distance + h * g.b[k] < 0.0;
      g.target[k] = g.bounce[k] ? c.restitution * g.approach[k] : -std::max(c.distance, 0.0) / h;
    }
    g.tree_a = c0.body_a >= 0 ? part_of_body_[static_cast<size_t>(c0.body_a)] : -1;
    g.tree_b = c0.body_b >= 0 ? part_of_body_[static_cast<size_t>(c0.body_b)] : -1;
    const int me = ng - 1;
    if (g.tree_a >= 0) tree_groups_[static_cast<size_t>(g.tree_a)][static_cast<size_t>(tree_count_[static_cast<size_t>(g.tree_a)]++)] = me;
    if (g.tree_b >= 0 && g.tree_b != g.tree_a)
      tree_groups_[static_cast<size_t>(g.tree_b)][static_cast<size_t>(tree_count_[static_cast<size_t>(g.tree_b)]++)] = me;
    entry += count;
    value += g.rows * count;
    i = end;
  }
}

// W_gh = sum over the dofs both pairs' chains share of X_g X_h^T / D, for pairs on a common tree.
void ContactSolver::couple(int ng) {
  int pool = 0;
  for (int g = 0; g < ng; ++g) stamp_[static_cast<size_t>(g)] = -1;
  for (int gi = 0; gi < ng; ++gi) {
    Group& g = groups_[static_cast<size_t>(gi)];
    g.nbr_first = pool;
    g.nbr_count = 0;
    for (int t : {g.tree_a, g.tree_b}) {
      if (t < 0) continue;
      const std::vector<int>& list = tree_groups_[static_cast<size_t>(t)];
      for (int m = 0; m < tree_count_[static_cast<size_t>(t)]; ++m) {
        const int hi = list[static_cast<size_t>(m)];
        if (hi == gi || stamp_[static_cast<size_t>(hi)] == gi) continue;
        stamp_[static_cast<size_t>(hi)] = gi;
        if (pool >= static_cast<int>(nbr_.size())) {
          ++stats_.blocks_dropped;
          continue;
        }
        const Group& h = groups_[static_cast<size_t>(hi)];
        Block& W = block_[static_cast<size_t>(pool)];
        nbr_[static_cast<size_t>(pool)] = hi;
        ++pool;
        ++g.nbr_count;
        // W_gh = W_hg^T: an earlier pair has it already.
        if (hi < gi) {
          int m2 = 0;
          while (m2 < h.nbr_count && nbr_[static_cast<size_t>(h.nbr_first + m2)] != gi) ++m2;
          if (m2 < h.nbr_count) {
            W = block_[static_cast<size_t>(h.nbr_first + m2)].transpose();
            continue;
          }
        }
        W.setZero();
        int p = 0, q = 0;
        while (p < g.entries && q < h.entries) {
          const int dp = dof_[static_cast<size_t>(g.first_entry + p)], dq = dof_[static_cast<size_t>(h.first_entry + q)];
          if (dp < dq) {
            ++p;
          } else if (dq < dp) {
            ++q;
          } else {
            const double inv = invD_[static_cast<size_t>(g.first_entry + p)];
            for (int r = 0; r < g.rows; ++r) {
              const double xr = inv * X_[static_cast<size_t>(g.first_value + r * g.entries + p)];
              for (int s = 0; s < h.rows; ++s) W(r, s) += xr * X_[static_cast<size_t>(h.first_value + s * h.entries + q)];
            }
            ++p;
            ++q;
          }
        }
      }
    }
  }
}

void ContactSolver::warmStart(const ContactSet& contacts, int ng) {
  int p = 0;
  for (int gi = 0; gi < ng; ++gi) {
    Group& g = groups_[static_cast<size_t>(gi)];
    g.lambda.setZero();
    const Contact& c0 = contacts[g.first];
    while (p < previous_n_ && std::make_pair(previous_[static_cast<size_t>(p)].a, previous_[static_cast<size_t>(p)].b) <
                                  std::make_pair(c0.geom_a, c0.geom_b))
      ++p;
    bool found = false;
    for (int k = 0; k < g.points; ++k) {
      double best = kWarmStartReach * kWarmStartReach;
      for (int q = p; q < previous_n_ && previous_[static_cast<size_t>(q)].a == c0.geom_a &&
                      previous_[static_cast<size_t>(q)].b == c0.geom_b;
           ++q) {
        const Previous& prev = previous_[static_cast<size_t>(q)];
        found = true;
        const double d = (prev.point - contacts[g.first + k].point).squaredNorm();
        if (d < best) {
          best = d;
          g.lambda[k] = prev.normal;
        }
      }
    }
    if (!found) continue;
    const Previous& prev = previous_[static_cast<size_t>(p)];
    const int P = g.points;
    double N = 0.0;
    for (int k = 0; k < P; ++k) N += g.lambda[k];
    Vector3 f(prev.friction.dot(g.t1), prev.friction.dot(g.t2), g.patch ? prev.torsion : 0.0);
    // Inside the cone (or the patch's ellipsoid) of today's load.
    const double rad = g.patch && g.radius > 0.0 ? g.radius : 1.0;
    const double size = std::hypot(std::hypot(f.x(), f.y()), f.z() / rad), cap = g.mu * N;
    if (size > cap) f *= cap / size;
    g.lambda.segment<2>(P) = f.head<2>();
    if (g.patch) g.lambda[P + 2] = f.z();
  }
}

bool ContactSolver::sweep(int ng, int sweeps) {
  const double tolerance = cm_.settings().tolerance;
  for (int pass = 0; pass < sweeps; ++pass) {
    double largest = 0.0;
    for (int gi = 0; gi < ng; ++gi) {
      Group& g = groups_[static_cast<size_t>(gi)];
      const int R = g.rows, P = g.points;
      Rows u = g.b + g.W * g.lambda;
      for (int m = 0; m < g.nbr_count; ++m) {
        const int q = g.nbr_first + m;
        u.head(R).noalias() += block_[static_cast<size_t>(q)].topLeftCorner(R, kMaxRows) *
                               groups_[static_cast<size_t>(nbr_[static_cast<size_t>(q)])].lambda;
      }
      const Rows before = g.lambda;
      if (!g.patch) {
        // One point: sticking first, the whole block at once, target (u*, 0, 0).
        const Vector3 lam = g.lambda.head<3>();
        const Vector3 uu = u.head<3>();
        Vector3 l = lam - g.friction_inverse * (uu - Vector3(g.target[0], 0.0, 0.0));
        if (!(l.x() > 0.0) || l.tail<2>().norm() > g.mu * l.x()) {
          // Slipping: the normal row, then the tangential ones against what it changed, onto the cone,
          // by an isotropic step (1 / the largest eigenvalue of W_tt): its fixed point has the friction
          // opposite the slip (maximal dissipation); a step by W_tt^-1 would settle where W_tt lambda_t
          // opposes it instead.
          const double ln = std::max(0.0, lam.x() - (uu.x() - g.target[0]) / g.W(0, 0));
          const Eigen::Vector2d ut = uu.tail<2>() + g.W.block<2, 1>(1, 0) * (ln - lam.x());
          Eigen::Vector2d lt = lam.tail<2>() - g.friction_step * ut;
          const double t = lt.norm(), cap = g.mu * ln;
          if (t > cap) lt *= cap / t;
          l = Vector3(ln, lt.x(), lt.y());
        }
        g.lambda.head<3>() = l;
      } else {
        // A patch: its normals one by one, then its friction (two tangents and a torsion) at once.
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
        if (N > 0.0) {
          const double rad = g.radius;
          auto size = [&](const Vector3& f) { return rad > 0.0 ? std::hypot(std::hypot(f.x(), f.y()), f.z() / rad) : f.head<2>().norm(); };
          l = lam - g.friction_inverse * uf;
          if (rad <= 0.0) l.z() = 0.0;
          if (size(l) > g.mu * N) {
            // Slipping: an isotropic step in the ellipsoid's scaled coordinates (s = (f_t, tau / r),
            // its velocity (u_t, r w)), then onto the ball of radius mu N.
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
      const double change = (g.W.topLeftCorner(R, R) * (g.lambda - before).head(R)).cwiseAbs().maxCoeff();
      largest = std::max(largest, change);
    }
    ++stats_.iterations;
    stats_.residual = largest;
    if (largest <= tolerance) return true;
  }
  return false;
}

bool ContactSolver::polish(int ng) {
  // Islands: pairs joined through shared trees (breadth-first over the couplings).
  for (int g = 0; g < ng; ++g) island_[static_cast<size_t>(g)] = -1;
  bool all = true;
  for (int seed = 0; seed < ng; ++seed) {
    if (island_[static_cast<size_t>(seed)] >= 0) continue;
    int head = 0, tail = 0, n = 0;
    queue_[static_cast<size_t>(tail++)] = seed;
    island_[static_cast<size_t>(seed)] = seed;
    while (head < tail) {
      const int g = queue_[static_cast<size_t>(head++)];
      members_[static_cast<size_t>(n++)] = g;
      const Group& G = groups_[static_cast<size_t>(g)];
      for (int m = 0; m < G.nbr_count; ++m) {
        const int h = nbr_[static_cast<size_t>(G.nbr_first + m)];
        if (island_[static_cast<size_t>(h)] < 0) {
          island_[static_cast<size_t>(h)] = seed;
          queue_[static_cast<size_t>(tail++)] = h;
        }
      }
    }
    std::sort(members_.begin(), members_.begin() + n);  // a fixed order for the unknowns
    all = polishIsland(n) && all;
  }
  return all;
}

// An active-set method on one island: from the sweeps' guess, solve the tight rows exactly; where the
// answer breaks a condition (a normal pulls, a free point crosses, a sticking friction leaves the cone,
// a slipping one pushes along its slip), change that row's guess and solve again.
bool ContactSolver::polishIsland(int n) {
  constexpr int kRounds = 24;
  constexpr double kInside = 1.0 - 1e-9;  // strictly inside the cone: sticking
  const double tolerance = cm_.settings().tolerance;
  auto group = [&](int m) -> Group& { return groups_[static_cast<size_t>(members_[static_cast<size_t>(m)])]; };
  auto frictionRows = [](const Group& g) { return g.patch && g.radius > 0.0 ? 3 : 2; };
  auto scaleOf = [](const Group& g) { return Vector3(1.0, 1.0, g.radius > 0.0 ? g.radius : 1.0); };
  // The sweeps' guess.
  for (int m = 0; m < n; ++m) {
    Group& g = group(m);
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
    g.sliding = cap > 0.0 && s.norm() >= kInside * cap;
    std::fill(g.slide, g.slide + kMaxRows, 0.0);
    if (g.sliding)
      for (int f = 0; f < F; ++f) g.slide[P + f] = g.mu * scale[f] * s[f] / s.norm();
  }
  for (int round = 0; round < kRounds; ++round) {
    // Unknowns: touching normals, and a sticking friction's rows where its pair has a load.
    int nx = 0;
    for (int m = 0; m < n; ++m) {
      Group& g = group(m);
      const int P = g.points, F = frictionRows(g);
      std::fill(g.unknown, g.unknown + kMaxRows, -1);
      bool loaded = false;
      for (int k = 0; k < P; ++k)
        if (g.active[k]) {
          g.unknown[k] = nx++;
          loaded = true;
        }
      if (!loaded) g.sliding = false;
      if (loaded && !g.sliding)
        for (int f = 0; f < F; ++f) g.unknown[P + f] = nx++;
    }
    if (nx > kPolishRows) return false;
    // M x = rhs: each unknown's row u_r = target_r (0 for friction), u = b + sum over the island of W lambda.
    if (nx > 0) {
      std::fill(M_.begin(), M_.begin() + nx * nx, 0.0);
      for (int m = 0; m < n; ++m) {
        const Group& g = group(m);
        auto add = [&](const Block& W, const Group& h) {
          for (int r = 0; r < g.rows; ++r) {
            const int row = g.unknown[r];
            if (row < 0) continue;
            for (int c = 0; c < h.rows; ++c) {
              if (h.unknown[c] >= 0) {
                M_[static_cast<size_t>(row * nx + h.unknown[c])] += W(r, c);
              } else if (h.sliding && h.slide[c] != 0.0) {
                for (int k = 0; k < h.points; ++k)
                  if (h.unknown[k] >= 0) M_[static_cast<size_t>(row * nx + h.unknown[k])] += W(r, c) * h.slide[c];
              }
            }
          }
        };
        add(g.W, g);
        for (int q = 0; q < g.nbr_count; ++q)
          add(block_[static_cast<size_t>(g.nbr_first + q)],
              groups_[static_cast<size_t>(nbr_[static_cast<size_t>(g.nbr_first + q)])]);
        for (int r = 0; r < g.rows; ++r)
          if (g.unknown[r] >= 0) rhs_[static_cast<size_t>(g.unknown[r])] = (r < g.points ? g.target[r] : 0.0) - g.b[r];
      }
      // Redundant normals (four corners carry three degrees of freedom) make M singular: a small
      // regularisation picks the even split among them.
      double big = 0.0;
      for (int k = 0; k < nx; ++k) big = std::max(big, std::abs(M_[static_cast<size_t>(k * nx + k)]));
      for (int k = 0; k < nx; ++k) M_[static_cast<size_t>(k * nx + k)] += 1e-12 * big + 1e-300;
      // LU with partial pivoting, in place, then the two triangular solves.
      for (int k = 0; k < nx; ++k) {
        int p = k;
        for (int i = k + 1; i < nx; ++i)
          if (std::abs(M_[static_cast<size_t>(i * nx + k)]) > std::abs(M_[static_cast<size_t>(p * nx + k)])) p = i;
        if (!(std::abs(M_[static_cast<size_t>(p * nx + k)]) > 0.0)) return false;
        if (p != k) {
          for (int j = 0; j < nx; ++j) std::swap(M_[static_cast<size_t>(k * nx + j)], M_[static_cast<size_t>(p * nx + j)]);
          std::swap(rhs_[static_cast<size_t>(k)], rhs_[static_cast<size_t>(p)]);
        }
        const double d = M_[static_cast<size_t>(k * nx + k)];
        for (int i = k + 1; i < nx; ++i) {
          const double f = M_[static_cast<size_t>(i * nx + k)] / d;
          if (f == 0.0) continue;
          for (int j = k + 1; j < nx; ++j) M_[static_cast<size_t>(i * nx + j)] -= f * M_[static_cast<size_t>(k * nx + j)];
          rhs_[static_cast<size_t>(i)] -= f * rhs_[static_cast<size_t>(k)];
        }
      }
      for (int k = nx - 1; k >= 0; --k) {
        double x = rhs_[static_cast<size_t>(k)];
        for (int j = k + 1; j < nx; ++j) x -= M_[static_cast<size_t>(k * nx + j)] * rhs_[static_cast<size_t>(j)];
        rhs_[static_cast<size_t>(k)] = x / M_[static_cast<size_t>(k * nx + k)];
      }
    }
    // The candidate impulses, then the velocities they give.
    for (int m = 0; m < n; ++m) {
      Group& g = group(m);
      g.trial.setZero();
      double N = 0.0;
      for (int k = 0; k < g.points; ++k)
        if (g.unknown[k] >= 0) N += g.trial[k] = rhs_[static_cast<size_t>(g.unknown[k])];
      for (int r = g.points; r < g.rows; ++r)
        g.trial[r] = g.unknown[r] >= 0 ? rhs_[static_cast<size_t>(g.unknown[r])] : (g.sliding ? g.slide[r] * N : 0.0);
    }
    for (int m = 0; m < n; ++m) {
      Group& g = group(m);
      g.trial_u = g.b + g.W * g.trial;
      for (int q = 0; q < g.nbr_count; ++q)
        g.trial_u.noalias() += block_[static_cast<size_t>(g.nbr_first + q)] *
                               groups_[static_cast<size_t>(nbr_[static_cast<size_t>(g.nbr_first + q)])].trial;
    }
    // Check every condition; change the guess of the one that breaks worst (one change a round:
    // changing every broken one at once can cycle, a pull freed here re-crossing there), measured as
    // a velocity: a pull by what its impulse would move its point, a crossing by its speed, a friction
    // outside its cone by how far outside, one slipping along itself by its slip.
    double worst = 0.0;
    int worst_group = -1, worst_row = -1;
    auto candidate = [&](double how_bad, int m, int row) {
      if (how_bad > worst) {
        worst = how_bad;
        worst_group = m;
        worst_row = row;
      }
    };
    for (int m = 0; m < n; ++m) {
      Group& g = group(m);
      const int P = g.points, F = frictionRows(g);
      double N = 0.0;
      for (int k = 0; k < P; ++k) {
        if (g.active[k] && g.trial[k] < 0.0) candidate(-g.trial[k] * g.W(k, k), m, k);
        else if (!g.active[k] && g.trial_u[k] < g.target[k] - tolerance) candidate(g.target[k] - g.trial_u[k], m, k);
        N += std::max(g.trial[k], 0.0);
      }
      const Vector3 scale = scaleOf(g);
      Vector3 s = Vector3::Zero(), w = Vector3::Zero();
      for (int f = 0; f < F; ++f) {
        s[f] = g.trial[P + f] / scale[f];
        w[f] = g.trial_u[P + f] * scale[f];
      }
      const double cap = g.mu * (g.patch ? N : std::max(g.trial[0], 0.0));
      if (!g.sliding && s.norm() > cap * (1.0 + 1e-9) + 1e-15)
        candidate((s.norm() - cap) / g.friction_step + tolerance, m, P);
      else if (g.sliding && s.dot(w) > tolerance * s.norm())
        candidate(s.dot(w) / s.norm(), m, P);
    }
    if (worst_group < 0) {
      for (int m = 0; m < n; ++m) group(m).lambda = group(m).trial;
      return true;
    }
    Group& g = group(worst_group);
    if (worst_row < g.points) {
      g.active[worst_row] = !g.active[worst_row];
    } else if (!g.sliding) {  // slip, along the friction the trial found
      const int P = g.points, F = frictionRows(g);
      const Vector3 scale = scaleOf(g);
      Vector3 s = Vector3::Zero();
      for (int f = 0; f < F; ++f) s[f] = g.trial[P + f] / scale[f];
      g.sliding = true;
      for (int f = 0; f < F; ++f) g.slide[P + f] = g.mu * scale[f] * s[f] / s.norm();
    } else {
      g.sliding = false;
    }
  }
  return false;
}

// The pseudo-impulses: normal rows only, each >= 0 but where a bounce sets the end gap (free sign).
void ContactSolver::sweepPseudo(int ng) {
  const int max_sweeps = cm_.settings().iterations;
  const double tolerance = cm_.settings().tolerance;
  for (int pass = 0; pass < max_sweeps; ++pass) {
    double largest = 0.0;
    for (int gi = 0; gi < ng; ++gi) {
      Group& g = groups_[static_cast<size_t>(gi)];
      for (int k = 0; k < g.points; ++k) {
        double s = 0.0;
        for (int j = 0; j < g.points; ++j) s += g.W(k, j) * g.sigma[j];
        for (int m = 0; m < g.nbr_count; ++m) {
          const int q = g.nbr_first + m;
          const Group& h = groups_[static_cast<size_t>(nbr_[static_cast<size_t>(q)])];
          for (int j = 0; j < h.points; ++j) s += block_[static_cast<size_t>(q)](k, j) * h.sigma[j];
        }
        double sigma = g.sigma[k] - (s - g.target[k]) / (g.W(k, k) + 1e-300);
        if (!g.bounce[k]) sigma = std::max(0.0, sigma);
        largest = std::max(largest, std::abs(g.W(k, k) * (sigma - g.sigma[k])));
        g.sigma[k] = sigma;
      }
    }
    if (largest <= tolerance) return;
  }
}

// v += A^-1 J^T lambda (pseudo: the normal rows' sigma instead), on the trees the pairs touch:
// z = D^-1 sum X lambda, then L x = z.
void ContactSolver::apply(const MatrixX& LD, int ng, bool pseudo, VectorX& v) {
  const int nv = model_.nv;
  const double* const ld = LD.data();
  std::fill(tree_touched_.begin(), tree_touched_.end(), 0);
  for (int gi = 0; gi < ng; ++gi) {
    const Group& g = groups_[static_cast<size_t>(gi)];
    const int R = pseudo ? g.points : g.rows;
    const Rows& l = pseudo ? g.sigma : g.lambda;
    bool any = false;
    for (int r = 0; r < R; ++r) {
      if (l[r] == 0.0) continue;
      any = true;
      const double* const X = X_.data() + g.first_value + r * g.entries;
      for (int e = 0; e < g.entries; ++e) scratch_[dof_[static_cast<size_t>(g.first_entry + e)]] += X[e] * l[r];
    }
    if (!any) continue;
    if (g.tree_a >= 0) tree_touched_[static_cast<size_t>(g.tree_a)] = 1;
    if (g.tree_b >= 0) tree_touched_[static_cast<size_t>(g.tree_b)] = 1;
  }
  for (size_t t = 0; t < model_.parts.size(); ++t) {
    if (!tree_touched_[t]) continue;
    const ModelPart& part = model_.parts[t];
    for (int k = part.dof_begin; k < part.dof_end; ++k) scratch_[k] /= ld[static_cast<std::ptrdiff_t>(k) * nv + k];
    for (int k = part.dof_begin; k < part.dof_end; ++k) {
      const double* const lk = ld + static_cast<std::ptrdiff_t>(k) * nv;
      double sum = 0.0;
      forEachAncestorRun(model_.dof_parent, model_.dof_run_start, model_.dof_parent[k], [&](int s, int j) {
        for (int t2 = s; t2 <= j; ++t2) sum += lk[t2] * scratch_[t2];
      });
      scratch_[k] -= sum;
    }
    for (int k = part.dof_begin; k < part.dof_end; ++k) {
      v[k] += scratch_[k];
      scratch_[k] = 0.0;
    }
  }
}

// Each point's impulse (its normal, and its share of the pair's friction by its normal load), and
// what the next step starts from.
void ContactSolver::report(ContactSet& contacts, int ng) {
  previous_n_ = contacts.n;
  for (int gi = 0; gi < ng; ++gi) {
    const Group& g = groups_[static_cast<size_t>(gi)];
    const int P = g.points;
    double N = 0.0;
    for (int k = 0; k < P; ++k) N += g.lambda[k];
    const Vector3 friction = g.lambda[P] * g.t1 + g.lambda[P + 1] * g.t2;
    const double torsion = g.patch ? g.lambda[P + 2] : 0.0;
    for (int k = 0; k < P; ++k) {
      Contact& c = contacts[g.first + k];
      const double share = P == 1 ? 1.0 : (N > 0.0 ? g.lambda[k] / N : 0.0);
      c.impulse = g.lambda[k] * c.normal + share * friction;
      previous_[static_cast<size_t>(g.first + k)] = Previous{c.geom_a, c.geom_b, c.point, g.lambda[k], friction, torsion};
    }
  }
}

void ContactSolver::solve(const Data& data, const MatrixX& LD, double h, const VectorX& v0, ContactSet& contacts,
                          VectorX& v, VectorX& v_position) {
  if (contacts.n == 0) {
    previous_n_ = 0;
    v_position = v;
    return;
  }
  build(data, LD, contacts, h, v0, v);
  int ng = 0;
  for (int i = 0; i < contacts.n; ++ng) {
    i += groups_[static_cast<size_t>(ng)].points;
  }
  couple(ng);
  warmStart(contacts, ng);
  // Sweeps, and where they have not converged after a few, the exact solve of the active set they
  // found; if that does not hold, more sweeps, another solve, up to the sweep limit.
  constexpr int kSweepsPerPolish = 10;
  const int limit = cm_.settings().iterations;
  stats_.iterations = 0;
  stats_.residual = 0.0;
  bool converged = false;
  while (!converged && stats_.iterations < limit) {
    converged = sweep(ng, std::min(kSweepsPerPolish, limit - stats_.iterations));
    if (!converged && polish(ng)) {
      converged = true;  // every condition checked, to the tolerance
      stats_.residual = 0.0;
    }
  }
  if (!converged) ++stats_.unconverged;
  apply(LD, ng, false, v);
  report(contacts, ng);
  // Positions: what still overlaps at the step's end closes (a bounce ends where it would have,
  // e (approach h - gap) above the surface), by a pseudo-velocity that no velocity keeps.
  bool any = false;
  for (int gi = 0; gi < ng; ++gi) {
    Group& g = groups_[static_cast<size_t>(gi)];
    for (int k = 0; k < g.points; ++k) {
      const double* const J = J_.data() + g.first_value + k * g.entries;
      double un = 0.0;
      for (int e = 0; e < g.entries; ++e) un += J[e] * v[dof_[static_cast<size_t>(g.first_entry + e)]];
      const Contact& c = contacts[g.first + k];
      const double end_gap = c.distance + h * un;
      if (g.bounce[k]) {
        g.target[k] = (c.restitution * (g.approach[k] * h - std::max(c.distance, 0.0)) - end_gap) / h;
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
  sweepPseudo(ng);
  apply(LD, ng, true, v_position);
}

}  // namespace igms
