#include "haptic_client/servo/state_estimate.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <string>

namespace igms {
namespace {

// Pose between a (at 0) and b (at 1), for any u (u > 1 extrapolates).
SE3 blend(const SE3& a, const SE3& b, double u) {
  const Eigen::AngleAxisd d(b.R * a.R.transpose());
  return {Eigen::AngleAxisd(d.angle() * u, d.axis()).toRotationMatrix() * a.R, a.p + u * (b.p - a.p)};
}

}  // namespace

const char* fallbackName(FallbackPolicy p) {
  switch (p) {
    case FallbackPolicy::Hold: return "hold";
    case FallbackPolicy::Extrapolate: return "extrapolate";
    case FallbackPolicy::Interpolate: return "interpolate";
  }
  return "?";
}

bool parseFallback(const std::string& name, FallbackPolicy* out) {
  if (name == "hold") *out = FallbackPolicy::Hold;
  else if (name == "extrapolate") *out = FallbackPolicy::Extrapolate;
  else if (name == "interpolate") *out = FallbackPolicy::Interpolate;
  else return false;
  return true;
}

StateEstimate::StateEstimate(int nlinks, int nq, FallbackPolicy policy) : policy_(policy) {
  for (auto& s : s_) {
    s.links.assign(static_cast<size_t>(nlinks), SE3::Identity());
    s.q.assign(static_cast<size_t>(nq), 0.0);
  }
}

bool StateEstimate::offer(const RobotSample& in) {
  if (count_ > 0 && in.seq <= s_[newest_].seq) return false;  // late or out of order
  const int slot = 1 - newest_;
  RobotSample& s = s_[slot];
  s.seq = in.seq;
  s.input_seq = in.input_seq;
  s.sim_time = in.sim_time;
  std::copy(in.links.begin(), in.links.end(), s.links.begin());
  std::copy(in.q.begin(), in.q.end(), s.q.begin());
  newest_ = slot;
  ++count_;
  return true;
}

bool StateEstimate::estimate(double t, std::vector<SE3>& links, bool* used_fallback) const {
  if (count_ == 0) return false;
  const RobotSample& b = s_[newest_];
  const RobotSample& a = s_[1 - newest_];
  const bool late = t > b.sim_time + 1e-9;
  if (used_fallback) *used_fallback = late;
  const bool two = count_ >= 2 && b.sim_time > a.sim_time;
  // Interpolate always runs one period behind, late or not: smooth but delayed.
  const bool blend_now = two && (policy_ == FallbackPolicy::Interpolate || (late && policy_ == FallbackPolicy::Extrapolate));
  if (!blend_now) {
    std::copy(b.links.begin(), b.links.end(), links.begin());
    return true;
  }
  const double span = b.sim_time - a.sim_time;
  // Extrapolate: ahead of b at constant velocity (at most 10 periods, so a
  // long outage does not fling the estimate away). Interpolate: one period
  // behind t, between a and b (clamped to b).
  double u;
  if (policy_ == FallbackPolicy::Extrapolate) {
    u = 1.0 + std::min(t - b.sim_time, 10.0 * span) / span;
  } else {
    u = std::clamp((t - span - a.sim_time) / span, 0.0, 1.0);
  }
  for (size_t k = 0; k < links.size(); ++k) links[k] = blend(a.links[k], b.links[k], u);
  return true;
}

}  // namespace igms
