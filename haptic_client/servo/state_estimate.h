// The client's estimate of the robot for the current servo cycle, from the
// server's states. When the reply for this cycle is late, a fallback keeps the
// rate (Son et al. 2003: "uses the results computed at a previous time cycle
// if the remote server does not return the dynamics results after a certain
// preset time"):
//   Hold         the newest state as it is (the paper);
//   Extrapolate  constant velocity from the last two states;
//   Interpolate  between the last two states, always one period behind
//                (smooth, one period of extra delay even when on time).
// States older than the newest (by seq) are discarded. Allocation-free after
// construction.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/model/spatial.h"

namespace igms {

enum class FallbackPolicy { Hold, Extrapolate, Interpolate };
const char* fallbackName(FallbackPolicy p);
bool parseFallback(const std::string& name, FallbackPolicy* out);

// What the client needs of a robot_state_t.
struct RobotSample {
  int64_t seq = -1;
  int64_t input_seq = -1;
  double sim_time = 0.0;
  std::vector<SE3> links;   // world pose of every link
  std::vector<double> q;
};

class StateEstimate {
 public:
  StateEstimate(int nlinks, int nq, FallbackPolicy policy);

  // A state arrived. false: older than or equal to the newest (discarded).
  bool offer(const RobotSample& s);
  // The estimate for a cycle at simulated time t (s): exact when a state for
  // t has arrived, else by the policy. Returns false before any state.
  // used_fallback tells whether the newest state was older than t.
  bool estimate(double t, std::vector<SE3>& links, bool* used_fallback) const;

  bool any() const { return count_ > 0; }
  const RobotSample& newest() const { return s_[newest_]; }
  FallbackPolicy policy() const { return policy_; }

 private:
  FallbackPolicy policy_;
  RobotSample s_[2];
  int newest_ = 0, count_ = 0;
};

}  // namespace igms
