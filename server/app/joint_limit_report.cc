#include "server/app/joint_limit_report.h"

#include <algorithm>
#include <cmath>

namespace igms {

JointLimitReport::JointLimitReport(const Model& m) {
  for (int j = 0; j < m.nb; ++j) {
    if (m.joint_nv[static_cast<size_t>(j)] != 1) continue;
    const int v = m.v_index[static_cast<size_t>(j)];
    const double lo = m.lower[static_cast<size_t>(v)], hi = m.upper[static_cast<size_t>(v)];
    if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
    joints_.push_back({m.joint_name[static_cast<size_t>(j)], m.q_index[static_cast<size_t>(j)], lo, hi, 0, 0.0});
  }
}

void JointLimitReport::observe(const std::vector<double>& q) {
  for (Joint& j : joints_) {
    const double x = q[static_cast<size_t>(j.q)];
    const double beyond = std::max(x - j.upper, j.lower - x);
    if (beyond <= 0.0) continue;
    ++j.steps;
    j.excess = std::max(j.excess, beyond);
  }
}

std::vector<JointLimitReport::Entry> JointLimitReport::hits() const {
  std::vector<Entry> out;
  for (const Joint& j : joints_)
    if (j.steps > 0) out.push_back({j.name, j.steps, j.excess});
  return out;
}

}  // namespace igms
