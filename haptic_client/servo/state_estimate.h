// The client's estimate of the robot for the current servo cycle, from the
// server's states. States are judged by age, not by whether they echo this
// cycle's input: the servo loop asks for the robot at a simulated time
// `t` = newest state's time + its age, and the policy says how to get there
// from states that may be old (Son et al. 2003: "uses the results computed at
// a previous time cycle if the remote server does not return the dynamics
// results after a certain preset time"):
//   Predict      the newest state's q, v and qdd carried to t (joint space,
//                q + v h + qdd h^2 / 2, at most max_prediction ahead) and its
//                links by forward kinematics: exact at h = 0, right to second
//                order in h, valid across any delay the bound allows;
//   Hold         the newest state as it is (the paper);
//   Extrapolate  link poses at constant velocity from the last two states;
//   Interpolate  between the last two states, always one period behind
//                (smooth, one period of extra delay even when on time).
// States older than the newest (by seq) are discarded. Allocation-free after
// construction.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/model/data.h"
#include "core/model/spatial.h"

namespace igms {

enum class FallbackPolicy { Hold, Extrapolate, Interpolate, Predict };
const char* fallbackName(FallbackPolicy p);
bool parseFallback(const std::string& name, FallbackPolicy* out);

// What the client needs of a robot_state_t.
struct RobotSample {
  int64_t seq = -1;
  int64_t input_seq = -1;   // this client's input the step consumed (-1: none of ours)
  int32_t input_client = -1;  // this client's id when input_seq is ours, else -1
  int8_t mode = 0;          // the interaction the server applied in this step (any hand's: the robot was held)
  int8_t own_mode = 0;      // this client's hand's
  int nhands = 0;           // hands that acted on the robot in this step (several people at once)
  int nconsumed = 0;        // clients whose input the step consumed (ours among them or not)
  Vector3 own_force = Vector3::Zero();   // this client's force on the robot, world, N (the server's figure)
  Vector3 own_torque = Vector3::Zero();  // N m
  double sim_time = 0.0;
  std::vector<SE3> links;   // world pose of every link
  std::vector<double> q, v, qdd;
};

class StateEstimate {
 public:
  // Hold, Extrapolate, Interpolate: link poses only.
  StateEstimate(int nlinks, int nq, FallbackPolicy policy);
  // Any policy; Predict needs the model (and predicts at most max_prediction_s ahead).
  StateEstimate(const Model& model, FallbackPolicy policy, double max_prediction_s = 0.1);

  // A state arrived at `received` (monotonic s). false: older than or equal to the newest (discarded).
  bool offer(const RobotSample& s, double received = 0.0);
  // The estimate for simulated time t (s), by the policy. Returns false before
  // any state. used_fallback: the newest state was older than t.
  // velocities (with the model only; else left alone): every link's velocity in the estimate, world axes
  // (the predicted state's, or the newest state's for the other policies).
  bool estimate(double t, std::vector<SE3>& links, bool* used_fallback, std::vector<Motion>* velocities = nullptr);
  bool hasModel() const { return model_ != nullptr; }

  bool any() const { return count_ > 0; }
  const RobotSample& newest() const { return s_[newest_]; }
  double newestReceived() const { return received_[newest_]; }
  FallbackPolicy policy() const { return policy_; }

 private:
  void predict(const RobotSample& b, double h, std::vector<SE3>& links, std::vector<Motion>* velocities);
  // The newest state's link velocities (its q placed anew).
  void velocitiesAt(const RobotSample& b, std::vector<Motion>& velocities);

  FallbackPolicy policy_;
  const Model* model_ = nullptr;
  double max_prediction_ = 0.1;
  std::unique_ptr<Data> data_;  // forward kinematics of the prediction
  VectorX q_, v_, q_ahead_, v_end_;
  RobotSample s_[2];
  double received_[2] = {0.0, 0.0};
  int newest_ = 0, count_ = 0;
};

}  // namespace igms
