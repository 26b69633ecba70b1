#include "core/contact/contact_rows.h"

#include <algorithm>
#include <cmath>

#include "core/contact/patch_radius.h"
#include "core/model/ancestor_runs.h"

namespace igms {

namespace {

constexpr double kPatchCosine = 0.9396926207859084;  // cos 20 deg: a pair's normals this near are one patch's
constexpr double kPatchDepth = 1e-4;  // m: a patch's points this near the deepest carry its friction
constexpr int kListRows = 3;          // complete(): above this many rows, each chain is listed once

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

// z[dof[e]] += invD[e] X_k[e] d_k for N rows at once: each accumulator read and written once, the
// rows' terms added in row order (as a row-by-row pass would: the same sums).
template <int N>
void addRows(const int* dof, const double* invD, const double* const* X, const double* d, int E, double* z) {
  for (int e = 0; e < E; ++e) {
    double t = z[dof[e]];
    for (int k = 0; k < N; ++k) t += invD[e] * X[k][e] * d[k];
    z[dof[e]] = t;
  }
}

// u_r = sum_e X_r[e] z[dof[e]] for N rows at once, each sum in the dofs' order.
template <int N>
void rowVelocities(const int* dof, const double* X, const double* z, int E, double* u) {
  double s[N] = {};
  for (int e = 0; e < E; ++e) {
    const double ze = z[dof[e]];
    for (int k = 0; k < N; ++k) s[k] += X[k * E + e] * ze;
  }
  for (int k = 0; k < N; ++k) u[k] = s[k];
}

// x[a] -= l[a] xk and y[a] -= l[a] yk over a chain's few entries [s, e): scalar (vectorised, the
// checks for overlap and the remainder cost more than the handful of products).
__attribute__((optimize("no-tree-vectorize"))) void chainUpdate2(const double* l, double xk, double yk, int s, int e,
                                                                 double* x, double* y) {
  for (int a = s; a < e; ++a) {
    x[a] -= l[a] * xk;
    y[a] -= l[a] * yk;
  }
}

// u = M y over the entries, M rows x E row-major, up to three rows a pass (rowVelocities).
void rowsTimes(const double* M, const int* dof, const double* y, int rows, int E, double* u) {
  int r = 0;
  for (; r + 3 <= rows; r += 3) rowVelocities<3>(dof, M + r * E, y, E, u + r);
  if (rows - r == 2) rowVelocities<2>(dof, M + r * E, y, E, u + r);
  if (rows - r == 1) rowVelocities<1>(dof, M + r * E, y, E, u + r);
}

}  // namespace

ContactRows::ContactRows(const Model& model, const ContactModel& contacts) : model_(model), cm_(contacts) {
  body_chain_.resize(static_cast<size_t>(model.nb));
  twist_.resize(static_cast<size_t>(model.nb));
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
  sign_.resize(static_cast<size_t>(max_entries_));
  up_.resize(static_cast<size_t>(max_entries_));
  link_.resize(static_cast<size_t>(max_entries_));
  chain_from_.resize(static_cast<size_t>(max_entries_));
  link_value_.resize(static_cast<size_t>(max_entries_));
  pairs_.resize(static_cast<size_t>(capacity));
  groups_.resize(static_cast<size_t>(capacity));
  dof_.resize(static_cast<size_t>(capacity * max_entries_));
  invD_.resize(dof_.size());
  sign_of_.resize(dof_.size());
  J_.resize(static_cast<size_t>(capacity * max_entries_ * kMaxContactRows));
  X_.resize(J_.size());
  part_head_.assign(model.parts.size(), -1);
  part_tail_.assign(model.parts.size(), -1);
  part_next_.assign(static_cast<size_t>(2 * capacity), -1);
  tree_touched_.assign(model.parts.size(), 0);
}

// Each pair: its points' patch, normal and tangents; and its rows now (normals: J, velocities,
// targets) unless every point is apart and not closing, when they wait until a solve needs them.
int ContactRows::build(const Data& data, const TreeMatrix& LD, const ContactSet& contacts, double h, const VectorX& v0,
                       const VectorX& v) {
  data_ = &data;
  contacts_ = &contacts;
  v0_ = &v0;
  h_ = h;
  entry_ = value_ = 0;
  slots_ = 0;
  const int nc = contacts.n;
  std::fill(part_head_.begin(), part_head_.end(), -1);
  int ng = 0;
  twists(v, twist_);  // for the pairs that may wait: their speeds without their rows
  for (int i = 0; i < nc;) {
    // A group: the pair's next points whose normals agree with its first (one flat patch). Points of
    // one pair facing other ways (a peg between a slot's two walls: normals that cancel when averaged)
    // are groups of their own, each with its own friction.
    int end = i + 1;
    while (end < nc && contacts[end].geom_a == contacts[i].geom_a && contacts[end].geom_b == contacts[i].geom_b &&
           contacts[end].normal.dot(contacts[i].normal) > kPatchCosine)
      ++end;
    ContactPair& pair = pairs_[static_cast<size_t>(ng)];
    const Contact& c0 = contacts[i];
    pair.first = i;
    pair.points = end - i;
    pair.tree_a = c0.body_a >= 0 ? part_of_body_[static_cast<size_t>(c0.body_a)] : -1;
    pair.tree_b = c0.body_b >= 0 ? part_of_body_[static_cast<size_t>(c0.body_b)] : -1;
    pair.slot = -1;
    pair.in_solve = false;
    bool apart = true;
    for (int k = i; k < end && apart; ++k)
      apart = contacts[k].distance > 0.0 && contacts[k].distance + h * twistSpeed(contacts[k], twist_) > 0.0;
    if (!apart) buildRows(open(ng), LD, v);
    ++ng;
    i = end;
  }
  ngroups_ = ng;
  return ng;
}

ContactGroup& ContactRows::open(int gi) {
  ContactPair& pair = pairs_[static_cast<size_t>(gi)];
  if (pair.slot >= 0) return groups_[static_cast<size_t>(pair.slot)];
  pair.slot = slots_++;
  ContactGroup& g = groups_[static_cast<size_t>(pair.slot)];
  const Contact& c0 = (*contacts_)[pair.first];
  g.first = pair.first;
  g.points = pair.points;
  g.patch = g.points > 1;
  g.resists = !g.patch && (c0.rolling > 0.0 || c0.torsion > 0.0);
  g.spin_mu = g.resists ? c0.torsion : 0.0;
  g.roll_mu = g.resists ? c0.rolling : 0.0;
  g.rows = g.points + (g.patch ? 3 : g.resists ? 5 : 2);
  g.mu = c0.friction;
  g.framed = false;
  g.surface_hint.setZero();
  g.tree_a = pair.tree_a;
  g.tree_b = pair.tree_b;
  g.built = false;
  g.lambda.setZero();
  return g;
}

// The patch's friction sits where it touches: the centroid (and normal, and radius) of its points
// within kPatchDepth of the deepest (a lying cylinder's two rim ends, not a rim point above them that
// the margin let in: friction there would roll it about the wrong line).
void ContactRows::frame(ContactGroup& g) const {
  if (g.framed) return;
  const ContactSet& contacts = *contacts_;
  const int i = g.first, end = g.first + g.points;
  double deepest = contacts[i].distance;
  for (int k = i + 1; k < end; ++k) deepest = std::min(deepest, contacts[k].distance);
  g.centroid.setZero();
  Vector3 normal = Vector3::Zero();
  int touching = 0;
  for (int k = i; k < end; ++k) {
    g.carries[k - i] = contacts[k].distance <= deepest + kPatchDepth;
    if (g.carries[k - i]) {
      g.centroid += contacts[k].point;
      normal += contacts[k].normal;
      ++touching;
    }
  }
  g.centroid /= touching;
  g.n = normal.normalized();
  tangents(g.n, g.t1, g.t2);
  g.radius = 0.0;
  if (g.patch) {  // the torsion radius of the carrying points, in the patch's plane
    double u[kMaxPairPoints], v[kMaxPairPoints];
    int n = 0;
    for (int k = i; k < end; ++k) {
      if (!g.carries[k - i]) continue;
      const Vector3 r = contacts[k].point - g.centroid;
      u[n] = r.dot(g.t1);
      v[n] = r.dot(g.t2);
      ++n;
    }
    // A pair at rest has the same points step after step: the last radius, where they are the same
    // to the bit (the function is pure: the same answer).
    bool same = n == g.radius_points;
    for (int k = 0; same && k < n; ++k) same = u[k] == g.radius_u[k] && v[k] == g.radius_v[k];
    if (!same) {
      g.radius_of = patchTorsionRadius(u, v, n);
      sampleLimitSurface(u, v, n, g.surface);
      g.radius_points = n;
      std::copy(u, u + n, g.radius_u);
      std::copy(v, v + n, g.radius_v);
    }
    g.radius = g.radius_of;
  }
  g.framed = true;
}

// Group g's normal rows: its dofs (both chains), J's normal rows, their velocities under v, approach
// speeds under v0, bounces and targets.
void ContactRows::buildRows(ContactGroup& g, const TreeMatrix& LD, const VectorX& v) {
  const ContactSet& contacts = *contacts_;
  const Data& data = *data_;
  const VectorX& v0 = *v0_;
  const double h = h_;
  const double bounce_velocity = cm_.settings().bounce_velocity;
  const int i = g.first;
  const Contact& c0 = contacts[i];
  frame(g);
  int entry = entry_, value = value_;
  // The dofs: the union of both bodies' chains, ascending; each with its side's sign.
  static const std::vector<int> kNone;
  const std::vector<int>& ca = c0.body_a >= 0 ? body_chain_[static_cast<size_t>(c0.body_a)] : kNone;
  const std::vector<int>& cb = c0.body_b >= 0 ? body_chain_[static_cast<size_t>(c0.body_b)] : kNone;
  g.first_entry = entry;
  g.first_value = value;
  double* const sign = sign_.data();  // per entry (both chains: max_entries_ at most)
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
    } else {
      // A dof moving both sides (a robot touching itself: the floating base, a common hip) moves the
      // two points alike, so J is zero there; but A^-1 J^T is not: the reaction reaches every
      // ancestor, and X = L^-T J^T must run up through it (left out, the robot's momentum changed).
      k = ca[ia++];
      ++ib;
      s = 0.0;
    }
    dof_[static_cast<size_t>(entry + count)] = k;
    invD_[static_cast<size_t>(entry + count)] = 1.0 / LD.diagonal(k);
    sign[count] = s;
    ++count;
  }
  g.entries = count;
  // J: a row per normal, then the friction rows (at the point, or the patch's centroid).
  // Each row as a spatial vector [d; p x d] (the velocity of point p along d is its dot with the
  // dof's world twist [v; w]); a torsion row [0; n].
  const int P = g.points;
  Vector6 row[kMaxPairPoints];
  for (int k = 0; k < P; ++k) row[k] << contacts[i + k].normal, contacts[i + k].point.cross(contacts[i + k].normal);
  // The normal rows now (whether the pair is in the solve at all), the friction rows in complete().
  for (int e = 0; e < count; ++e) {
    const Eigen::Map<const Vector6> S(data.S_world.col(dof_[static_cast<size_t>(entry + e)]).data());
    double* const J = J_.data() + value;
    for (int r = 0; r < P; ++r) J[r * count + e] = sign[e] * row[r].dot(S);
    sign_of_[static_cast<size_t>(entry + e)] = sign[e];
  }
  // Velocities and targets.
  g.impact.setZero();
  std::fill(g.bounce, g.bounce + kMaxPairPoints, false);
  g.b.setZero();
  g.target.setZero();
  g.sigma.setZero();
  for (int r = 0; r < P; ++r) {
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
    g.bounce[k] = bouncesAt(c, g.approach[k], g.b[k], h, bounce_velocity);
    g.bounce_target[k] = c.restitution * g.approach[k];
    g.target[k] = g.bounce[k] ? g.bounce_target[k] : -std::max(c.distance, 0.0) / h;
  }
  entry += count;
  value += g.rows * count;
  entry_ = entry;
  value_ = value;
  g.built = true;
}

void ContactRows::complete(int gi, const TreeMatrix& LD, const VectorX& v_free) {
  if (pairs_[static_cast<size_t>(gi)].in_solve) return;
  ContactGroup& g = open(gi);
  if (!g.built) buildRows(g, LD, v_free);
  const int P = g.points;
  // The friction rows of J (at the point, or the patch's centroid; a torsion row [0; n]) and their
  // velocities under v_free.
  Vector6 row[5];
  row[0] << g.t1, g.centroid.cross(g.t1);
  row[1] << g.t2, g.centroid.cross(g.t2);
  if (g.patch || g.resists) row[2] << Vector3::Zero(), g.n;  // torsion, or spin
  if (g.resists) {  // rolling: the relative angular velocity about the tangents
    row[3] << Vector3::Zero(), g.t1;
    row[4] << Vector3::Zero(), g.t2;
  }
  for (int e = 0; e < g.entries; ++e) {
    const int dof = dof_[static_cast<size_t>(g.first_entry + e)];
    const Eigen::Map<const Vector6> S(data_->S_world.col(dof).data());
    double* const J = J_.data() + g.first_value;
    for (int r = P; r < g.rows; ++r) J[r * g.entries + e] = sign_of_[static_cast<size_t>(g.first_entry + e)] * row[r - P].dot(S);
  }
  // Every row's velocity under v_free (the normals' again: the solve may have moved v_free since
  // build(), passing impacts along; the same sum as build()'s where it has not).
  rowsTimes(J_.data() + g.first_value, dof_.data() + g.first_entry, v_free.data(), g.rows, g.entries, g.b.data());
  // X = L^-T J^T, on the entries alone: each entry's parent dof is an entry too (a chain is closed
  // upward), found below it in the ascending list; from the last entry down, each passes its value up
  // its chain. Where an entry's chain is every entry just below it (a free body's six dofs, a leg on
  // its base: the common case), from[e] is the chain's first entry and the update runs on contiguous
  // values; -1 where it is not (two branches of one tree among the entries). Against the world (a
  // body on the ground), the entries are one body's path from its root: no search.
  int* const up = up_.data();
  int* const from = chain_from_.data();
  if (g.tree_a < 0 || g.tree_b < 0) {
    for (int e = 0; e < g.entries; ++e) {
      up[e] = e - 1;
      from[e] = 0;
    }
  } else {
    for (int e = 0; e < g.entries; ++e) {
      const int parent = model_.dof_parent[dof_[static_cast<size_t>(g.first_entry + e)]];
      int a = e - 1;
      while (a >= 0 && dof_[static_cast<size_t>(g.first_entry + a)] != parent) --a;
      up[e] = parent < 0 ? -1 : a;
      from[e] = up[e] < 0 ? e : (up[e] == e - 1 && from[e - 1] >= 0 ? from[e - 1] : -1);
    }
  }
  std::copy(J_.begin() + g.first_value, J_.begin() + g.first_value + g.rows * g.entries, X_.begin() + g.first_value);
  // From the last entry down, each passes its value up its chain. A patch's many rows read each
  // chain from a list walked once (walked per row, each update waited on the last link's load: Talos
  // and the box stacks 4-5 % slower); a point's three rows walk it each (the list's cost made the
  // piles 3-4 % slower). The same sums in the same order either way.
  double* const X = X_.data() + g.first_value;
  const int* const dof = dof_.data() + g.first_entry;
  const int R = g.rows, E = g.entries;
  // A free body's block of L is the identity when its frame is at its centre of mass on its
  // principal axes (a box, a ball): a chain whose values of L are all 0 moves nothing and is left
  // alone. A robot's chains are not looked at (the look cost Go1 0.4 %).
  const bool free_body = (g.tree_a >= 0 && model_.parts[static_cast<size_t>(g.tree_a)].free_body) ||
                         (g.tree_b >= 0 && model_.parts[static_cast<size_t>(g.tree_b)].free_body);
  for (int e = E - 1; e >= 0; --e) {
    const double* const lk = LD.column(dof[e]);
    if (free_body && from[e] >= 0) {
      bool moves = false;
      for (int a = from[e]; a < e && !moves; ++a) moves = lk[dof[a]] != 0.0;
      if (!moves) continue;
    }
    if (from[e] >= 0 && R == 3 && X[e] != 0.0 && X[E + e] != 0.0 && X[2 * E + e] != 0.0) {
      // its chain is the entries from[e] .. e - 1; a point's three rows at once, L's value read once
      double* const x0 = X;
      double* const x1 = X + E;
      double* const x2 = X + 2 * E;
      const double k0 = x0[e], k1 = x1[e], k2 = x2[e];
      for (int a = from[e]; a < e; ++a) {
        const double l = lk[dof[a]];
        x0[a] -= l * k0;
        x1[a] -= l * k1;
        x2[a] -= l * k2;
      }
    } else if (from[e] >= 0 && R <= kListRows) {  // the same, row by row (a row whose value is 0 left alone)
      for (int r = 0; r < R; ++r) {
        double* const x = X + r * E;
        const double xk = x[e];
        if (xk == 0.0) continue;
        for (int a = from[e]; a < e; ++a) x[a] -= lk[dof[a]] * xk;
      }
    } else if (from[e] >= 0) {  // the same, L's values read once for the rows
      const int s = from[e];
      double* const lval = link_value_.data();
      for (int a = s; a < e; ++a) lval[a] = lk[dof[a]];
      int r = 0;
      for (; r + 1 < R; r += 2) {  // two rows at a time where both move (L's value loaded once)
        double* const x = X + r * E;
        double* const y = x + E;
        const double xk = x[e], yk = y[e];
        if (xk != 0.0 && yk != 0.0) {
          chainUpdate2(lval, xk, yk, s, e, x, y);
        } else if (xk != 0.0) {
          for (int a = s; a < e; ++a) x[a] -= lval[a] * xk;
        } else if (yk != 0.0) {
          for (int a = s; a < e; ++a) y[a] -= lval[a] * yk;
        }
      }
      for (; r < R; ++r) {
        double* const x = X + r * E;
        const double xk = x[e];
        if (xk == 0.0) continue;
        for (int a = s; a < e; ++a) x[a] -= lval[a] * xk;
      }
    } else if (R > kListRows) {
      int* const link = link_.data();
      double* const lval = link_value_.data();
      int n = 0;
      for (int a = up[e]; a >= 0; a = up[a], ++n) {
        link[n] = a;
        lval[n] = lk[dof[a]];
      }
      for (int r = 0; r < R; ++r) {
        double* const x = X + r * E;
        const double xk = x[e];
        if (xk == 0.0) continue;
        for (int j = 0; j < n; ++j) x[link[j]] -= lval[j] * xk;
      }
    } else {
      for (int r = 0; r < R; ++r) {
        double* const x = X + r * E;
        const double xk = x[e];
        if (xk == 0.0) continue;
        for (int a = up[e]; a >= 0; a = up[a]) x[a] -= lk[dof[a]] * xk;
      }
    }
  }
  const double* const invD = invD_.data() + g.first_entry;
  if (R == 3) {  // a point: its six sums in one pass (each the same sum, in the same order)
    double w00 = 0.0, w01 = 0.0, w02 = 0.0, w11 = 0.0, w12 = 0.0, w22 = 0.0;
    const double* const x0 = X;
    const double* const x1 = X + E;
    const double* const x2 = X + 2 * E;
    for (int e = 0; e < E; ++e) {
      w00 += x0[e] * x0[e] * invD[e];
      w01 += x0[e] * x1[e] * invD[e];
      w02 += x0[e] * x2[e] * invD[e];
      w11 += x1[e] * x1[e] * invD[e];
      w12 += x1[e] * x2[e] * invD[e];
      w22 += x2[e] * x2[e] * invD[e];
    }
    g.W(0, 0) = w00;
    g.W(0, 1) = g.W(1, 0) = w01;
    g.W(0, 2) = g.W(2, 0) = w02;
    g.W(1, 1) = w11;
    g.W(1, 2) = g.W(2, 1) = w12;
    g.W(2, 2) = w22;
  }
  // Otherwise rows r and r + 1 against each row s >= r together (each sum as alone); every entry
  // any solve reads (its rows x rows): no zeroing.
  for (int r = 0; r < R && R != 3; r += 2) {
    const double* const xr = X + r * E;
    if (r + 1 == R) {
      double w = 0.0;
      for (int e = 0; e < E; ++e) w += xr[e] * xr[e] * invD[e];
      g.W(r, r) = w;
      break;
    }
    const double* const xq = xr + E;
    double w = 0.0;
    for (int e = 0; e < E; ++e) w += xr[e] * xr[e] * invD[e];
    g.W(r, r) = w;
    for (int s = r + 1; s < R; ++s) {
      const double* const xs = X + s * E;
      double wr = 0.0, wq = 0.0;
      for (int e = 0; e < E; ++e) {
        wr += xr[e] * xs[e] * invD[e];
        wq += xq[e] * xs[e] * invD[e];
      }
      g.W(r, s) = g.W(s, r) = wr;
      g.W(r + 1, s) = g.W(s, r + 1) = wq;
    }
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
    if (g.resists) {
      g.roll_inverse = regularisedInverse(Eigen::Matrix2d(g.W.block<2, 2>(4, 4)));
      const double p = g.W(4, 4), q = g.W(4, 5), r = g.W(5, 5);
      g.roll_step = 1.0 / (0.5 * (p + r) + std::sqrt(0.25 * (p - r) * (p - r) + q * q) + 1e-300);
    }
  }
  auto append = [&](int part, int link) {  // at the end of part's list
    part_next_[static_cast<size_t>(link)] = -1;
    int& head = part_head_[static_cast<size_t>(part)];
    int& tail = part_tail_[static_cast<size_t>(part)];
    if (head < 0) head = link;
    else part_next_[static_cast<size_t>(tail)] = link;
    tail = link;
  };
  if (g.tree_a >= 0) append(g.tree_a, 2 * gi);
  if (g.tree_b >= 0 && g.tree_b != g.tree_a) append(g.tree_b, 2 * gi + 1);
  pairs_[static_cast<size_t>(gi)].in_solve = true;
}

void ContactRows::twists(const VectorX& v, std::vector<Motion>& out) const {
  const Matrix6X& S = data_->S_world;
  for (int b = 0; b < model_.nb; ++b) {
    const int p = model_.parent[b];
    Motion t = p < 0 ? Motion::Zero() : out[static_cast<size_t>(p)];
    for (int k = model_.v_index[b]; k < model_.v_index[b] + model_.joint_nv[b]; ++k) {
      t.v += S.col(k).head<3>() * v[k];
      t.w += S.col(k).tail<3>() * v[k];
    }
    out[static_cast<size_t>(b)] = t;
  }
}

double ContactRows::twistSpeed(const Contact& c, const std::vector<Motion>& twist) {
  auto at = [&](int body) {
    if (body < 0) return Vector3(Vector3::Zero());
    const Motion& t = twist[static_cast<size_t>(body)];
    return Vector3(t.v + t.w.cross(c.point));
  };
  return c.normal.dot(at(c.body_b) - at(c.body_a));
}

bool ContactRows::separating(const ContactGroup& g, const ContactSet& contacts, double h) const {
  for (int k = 0; k < g.points; ++k) {
    const double gap = contacts[g.first + k].distance;
    if (!(gap > 0.0) || g.bounce[k] || gap + h * g.b[k] <= 0.0) return false;
  }
  return true;
}

// The sweeps' most frequent calls: the rows that change, up to three at once (a point's, a patch's
// friction), in one pass over the dofs.
void ContactRows::add(const ContactGroup& g, const ContactRowVector& delta, int rows, VectorX& z) const {
  const int* const dof = dof_.data() + g.first_entry;
  const double* const invD = invD_.data() + g.first_entry;
  const int E = g.entries;
  const double* X[3];
  double d[3];
  if (rows == 3 && delta[0] != 0.0 && delta[1] != 0.0 && delta[2] != 0.0) {  // a point's three
    const double* const X0 = X_.data() + g.first_value;
    X[0] = X0;
    X[1] = X0 + E;
    X[2] = X0 + 2 * E;
    d[0] = delta[0];
    d[1] = delta[1];
    d[2] = delta[2];
    addRows<3>(dof, invD, X, d, E, z.data());
    return;
  }
  int n = 0;
  for (int r = 0; r < rows; ++r) {
    if (delta[r] == 0.0) continue;
    if (n == 3) {  // more than three change: row by row from here
      addRows<3>(dof, invD, X, d, E, z.data());
      n = 0;
    }
    X[n] = X_.data() + g.first_value + r * E;
    d[n++] = delta[r];
  }
  if (n == 3) addRows<3>(dof, invD, X, d, E, z.data());
  if (n == 2) addRows<2>(dof, invD, X, d, E, z.data());
  if (n == 1) addRows<1>(dof, invD, X, d, E, z.data());
}

ContactRowVector ContactRows::velocity(const ContactGroup& g, const VectorX& z, int rows) const {
  ContactRowVector u = ContactRowVector::Zero();
  rowsTimes(X_.data() + g.first_value, dof_.data() + g.first_entry, z.data(), rows, g.entries, u.data());
  return u;
}

void ContactRows::clear(const ContactGroup& g, VectorX& z) const {
  for (int e = 0; e < g.entries; ++e) z[dof_[static_cast<size_t>(g.first_entry + e)]] = 0.0;
}

void ContactRows::accumulate(VectorX& z) const {
  for (int gi = 0; gi < ngroups_; ++gi)
    if (inSolve(gi)) clear(group(gi), z);
  for (int gi = 0; gi < ngroups_; ++gi)
    if (inSolve(gi)) add(group(gi), group(gi).lambda, group(gi).rows, z);
}

void ContactRows::coupling(const ContactGroup& g, const ContactGroup& h, ContactBlock& W) const {
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

void ContactRows::apply(const TreeMatrix& LD, VectorX& z, VectorX& v) {
  std::fill(tree_touched_.begin(), tree_touched_.end(), 0);
  for (int gi = 0; gi < ngroups_; ++gi) {
    const ContactPair& p = pairs_[static_cast<size_t>(gi)];
    if (!p.in_solve) continue;
    if (p.tree_a >= 0) tree_touched_[static_cast<size_t>(p.tree_a)] = 1;
    if (p.tree_b >= 0) tree_touched_[static_cast<size_t>(p.tree_b)] = 1;
  }
  // L x = z, tree by tree, from the root down (each dof's L row reaches its ancestors).
  for (size_t t = 0; t < model_.parts.size(); ++t) {
    if (!tree_touched_[t]) continue;
    const ModelPart& part = model_.parts[t];
    for (int k = part.dof_begin; k < part.dof_end; ++k) {
      const double* const lk = LD.column(k);
      double sum = 0.0;
      forEachAncestorRun(model_.dof_parent, model_.dof_run_start, model_.dof_parent[k], [&](int s, int j) {
        for (int t2 = s; t2 <= j; ++t2) sum += lk[t2] * z[t2];
      });
      z[k] -= sum;
    }
    for (int k = part.dof_begin; k < part.dof_end; ++k) {
      v[k] += z[k];
      z[k] = 0.0;
    }
  }
}

double ContactRows::normalSpeed(const ContactGroup& g, int k, const VectorX& v) const {
  const double* const J = J_.data() + g.first_value + k * g.entries;
  double u = 0.0;
  for (int e = 0; e < g.entries; ++e) u += J[e] * v[dof_[static_cast<size_t>(g.first_entry + e)]];
  return u;
}

}  // namespace igms
