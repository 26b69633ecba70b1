// A simulation's state as the client receives it (RobotSample), and how far
// apart two sets of link poses are: for the tests of the client's estimate.
#pragma once

#include <algorithm>
#include <vector>

#include "core/simulation/simulation.h"
#include "haptic_client/servo/state_estimate.h"

namespace igms::test {

// What a robot_state_t of this simulation would carry; the echoed input is client 1's input_seq.
inline RobotSample sampleOf(Simulation& sim, int64_t input_seq) {
  RobotSample s;
  s.seq = sim.steps();
  s.input_seq = input_seq;
  s.input_client = 1;
  s.mode = static_cast<int8_t>(sim.outcome().mode);
  s.sim_time = sim.time();
  s.links = sim.linkPoses();
  s.q.assign(sim.q().data(), sim.q().data() + sim.q().size());
  s.v.assign(sim.v().data(), sim.v().data() + sim.v().size());
  s.qdd.assign(sim.qdd().data(), sim.qdd().data() + sim.qdd().size());
  return s;
}

// The largest distance between corresponding link origins, m.
inline double worstLinkError(const std::vector<SE3>& a, const std::vector<SE3>& b) {
  double e = 0.0;
  for (size_t k = 0; k < a.size(); ++k) e = std::max(e, (a[k].p - b[k].p).norm());
  return e;
}

}  // namespace igms::test
