#include "haptic_client/servo/state_estimate.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/kinematics/forward_kinematics.h"
#include "core/model/configuration.h"

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
    case FallbackPolicy::Predict: return "predict";
  }
  return "?";
}

bool parseFallback(const std::string& name, FallbackPolicy* out) {
  if (name == "hold") *out = FallbackPolicy::Hold;
  else if (name == "extrapolate") *out = FallbackPolicy::Extrapolate;
  else if (name == "interpolate") *out = FallbackPolicy::Interpolate;
  else if (name == "predict") *out = FallbackPolicy::Predict;
  else return false;
  return true;
}

StateEstimate::StateEstimate(int nlinks, int nq, FallbackPolicy policy) : policy_(policy) {
  if (policy == FallbackPolicy::Predict) throw std::invalid_argument("the predict policy needs the robot's model");
  for (auto& s : s_) {
    s.links.assign(static_cast<size_t>(nlinks), SE3::Identity());
    s.q.assign(static_cast<size_t>(nq), 0.0);
  }
}

StateEstimate::StateEstimate(const Model& model, FallbackPolicy policy, double max_prediction_s)
    : policy_(policy), model_(&model), max_prediction_(max_prediction_s), data_(std::make_unique<Data>(model)),
      q_(VectorX::Zero(model.nq)), v_(VectorX::Zero(model.nv)), q_ahead_(VectorX::Zero(model.nq)),
      v_end_(VectorX::Zero(model.nv)) {
  for (auto& s : s_) {
    s.links.assign(model.frames.size(), SE3::Identity());
    s.q.assign(static_cast<size_t>(model.nq), 0.0);
    s.v.assign(static_cast<size_t>(model.nv), 0.0);
    s.qdd.assign(static_cast<size_t>(model.nv), 0.0);
  }
}

bool StateEstimate::offer(const RobotSample& in, double received) {
  if (count_ > 0 && in.seq <= s_[newest_].seq) return false;  // late or out of order
  const int slot = 1 - newest_;
  RobotSample& s = s_[slot];
  s.seq = in.seq;
  s.input_seq = in.input_seq;
  s.input_client = in.input_client;
  s.mode = in.mode;
  s.own_mode = in.own_mode;
  s.nhands = in.nhands;
  s.nconsumed = in.nconsumed;
  s.own_force = in.own_force;
  s.own_torque = in.own_torque;
  s.sim_time = in.sim_time;
  std::copy(in.links.begin(), in.links.end(), s.links.begin());
  std::copy(in.q.begin(), in.q.end(), s.q.begin());
  // v and qdd only where both sides have them (the prediction's inputs).
  if (in.v.size() == s.v.size()) std::copy(in.v.begin(), in.v.end(), s.v.begin());
  if (in.qdd.size() == s.qdd.size()) std::copy(in.qdd.begin(), in.qdd.end(), s.qdd.begin());
  received_[slot] = received;
  newest_ = slot;
  ++count_;
  return true;
}

bool StateEstimate::estimate(double t, std::vector<SE3>& links, bool* used_fallback,
                             std::vector<Motion>* velocities) {
  if (count_ == 0) return false;
  const RobotSample& b = s_[newest_];
  const RobotSample& a = s_[1 - newest_];
  const bool late = t > b.sim_time + 1e-9;
  if (used_fallback) *used_fallback = late;
  if (!model_) velocities = nullptr;
  if (policy_ == FallbackPolicy::Predict && late) {
    predict(b, std::min(t - b.sim_time, max_prediction_), links, velocities);
    return true;
  }
  if (velocities) velocitiesAt(b, *velocities);
  if (policy_ == FallbackPolicy::Predict) {
    std::copy(b.links.begin(), b.links.end(), links.begin());
    return true;
  }
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

void StateEstimate::predict(const RobotSample& b, double h, std::vector<SE3>& links,
                            std::vector<Motion>* velocities) {
  for (int i = 0; i < model_->nq; ++i) q_[i] = b.q[static_cast<size_t>(i)];
  // The mean velocity over [0, h] under constant acceleration: v + qdd h / 2.
  for (int i = 0; i < model_->nv; ++i)
    v_[i] = b.v[static_cast<size_t>(i)] + 0.5 * h * b.qdd[static_cast<size_t>(i)];
  integrateConfiguration(*model_, q_, v_, h, q_ahead_);
  forwardKinematics(*model_, *data_, q_ahead_);
  for (size_t f = 0; f < links.size(); ++f) links[f] = data_->oMf[f];
  if (!velocities) return;
  for (int i = 0; i < model_->nv; ++i) v_end_[i] = b.v[static_cast<size_t>(i)] + h * b.qdd[static_cast<size_t>(i)];
  frameVelocities(*model_, *data_, v_end_, *velocities);
}

void StateEstimate::velocitiesAt(const RobotSample& b, std::vector<Motion>& velocities) {
  for (int i = 0; i < model_->nq; ++i) q_[i] = b.q[static_cast<size_t>(i)];
  for (int i = 0; i < model_->nv; ++i) v_end_[i] = b.v[static_cast<size_t>(i)];
  bodyKinematics(*model_, *data_, q_);
  frameVelocities(*model_, *data_, v_end_, velocities);
}

}  // namespace igms
