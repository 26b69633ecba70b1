#include "core/contact/contact_impacts.h"

#include <algorithm>
#include <cmath>

#include "core/contact/contact_sweep.h"

namespace igms {
namespace {

constexpr int kGroupSweeps = 200;  // one pair's block solves at most
constexpr int kHalvings = 20;      // of the restitution factor, where a pair's impact would add energy

}  // namespace

bool impactsCanPass(const ContactRows& rows) {
  // Over every group, in the solve or not (the trees' lists hold only those in the solve): bouncing
  // groups are few, so a scan of the others for each is cheap.
  for (int gi = 0; gi < rows.size(); ++gi) {
    if (!rows.inSolve(gi)) continue;
    const ContactGroup& g = rows.group(gi);
    bool bounces = false;
    for (int k = 0; k < g.points; ++k) bounces = bounces || g.bounce[k];
    if (!bounces) continue;
    for (int gj = 0; gj < rows.size(); ++gj) {
      if (gj == gi) continue;
      const ContactPair& o = rows.pair(gj);
      for (const int t : {g.tree_a, g.tree_b})
        if (t >= 0 && (o.tree_a == t || o.tree_b == t)) return true;
    }
  }
  return false;
}

namespace {

// The change of kinetic energy the impulse lambda makes at velocity u (A's metric).
double gainOf(const ContactGroup& g, const ContactRowVector& u, double* scale) {
  const int R = g.rows;
  const double work = g.lambda.head(R).dot(u.head(R));
  *scale = std::abs(work);
  return work + 0.5 * g.lambda.head(R).dot(g.W.topLeftCorner(R, R) * g.lambda.head(R));
}

}  // namespace

ImpactPassing passImpacts(ContactRows& rows, const ContactSet& contacts, double h, double bounce_velocity,
                          int max_rounds, double tolerance, VectorX& z) {
  ImpactPassing out;
  for (; out.rounds < max_rounds; ++out.rounds) {
    bool any = false;
    for (int gi = 0; gi < rows.size(); ++gi) {
      if (!rows.inSolve(gi)) continue;
      ContactGroup& g = rows.group(gi);
      const int R = g.rows, P = g.points;
      const ContactRowVector u = g.b + rows.velocity(g, z, R);  // its velocity now, its own impacts included
      const ContactRowVector moved = rows.velocity(g, z, P);    // what the impacts so far changed
      // Its points' approach now (from the step's start, as the solve's bounces), and which bounce.
      double approach[kMaxPairPoints];
      bool bounce[kMaxPairPoints];
      bool impacts = false;
      for (int k = 0; k < P; ++k) {
        const Contact& c = contacts[g.first + k];
        approach[k] = g.approach[k] - moved[k];
        bounce[k] = bouncesAt(c, approach[k], u[k], h, bounce_velocity);
        impacts = impacts || bounce[k];
      }
      if (!impacts) continue;
      any = true;
      const ContactRowVector kept_lambda = g.lambda, kept_target = g.target;
      auto solveWith = [&](double factor) {
        g.lambda.setZero();
        for (int k = 0; k < P; ++k)
          g.target[k] = bounce[k] ? factor * contacts[g.first + k].restitution * approach[k]
                                  : -std::max(contacts[g.first + k].distance, 0.0) / h;
        solveGroupAlone(g, u, kGroupSweeps, tolerance);
      };
      solveWith(1.0);
      double scale = 0.0;
      if (gainOf(g, u, &scale) > 1e-12 * scale) {
        ++out.scaled;
        double lo = 0.0, hi = 1.0;
        for (int i = 0; i < kHalvings; ++i) {
          const double mid = 0.5 * (lo + hi);
          solveWith(mid);
          (gainOf(g, u, &scale) <= 1e-12 * scale ? lo : hi) = mid;
        }
        solveWith(lo);
      }
      g.impact += g.lambda;
      rows.add(g, g.lambda, R, z);
      g.lambda = kept_lambda;
      g.target = kept_target;
    }
    if (!any) {
      out.settled = true;
      break;
    }
  }
  return out;
}

}  // namespace igms
