#include "server/loop/command_handler.h"

#include <cmath>
#include <cstdio>

namespace igms {

namespace {

CommandResult rejected(const std::string& why) { return {false, why}; }

// text: the robot's name in the scene ("": the first robot).
int robotNamed(const Simulation& sim, const std::string& name) {
  if (name.empty()) return sim.robots() > 0 ? 0 : -1;
  const auto& robots = sim.resolved().robots;
  for (size_t r = 0; r < robots.size(); ++r)
    if (robots[r].name == name) return static_cast<int>(r);
  return -1;
}

CommandResult setTrajectory(const command_t& c, Simulation& sim) {
  const trajectory_t& tr = c.trajectory;
  if (tr.t.size() != tr.q.size() || tr.t.size() < 2) return rejected("SET_TRAJECTORY: needs two or more points");
  const int robot = robotNamed(sim, c.text);
  if (robot < 0)
    return rejected("SET_TRAJECTORY: no robot " + (c.text.empty() ? std::string("in the scene") : "named '" + c.text + "'"));
  std::vector<double> t(tr.t.begin(), tr.t.end());
  std::vector<VectorX> points;
  for (const auto& row : tr.q) {
    points.push_back(Eigen::Map<const VectorX>(row.data(), static_cast<int>(row.size())));
    if (!points.back().allFinite()) return rejected("SET_TRAJECTORY: a point is not finite");
  }
  try {
    sim.setNominalTrajectory(robot, t, points);
  } catch (const std::exception& e) {
    return rejected(std::string("SET_TRAJECTORY: ") + e.what());
  }
  return {};
}

CommandResult setGains(const command_t& c, Simulation& sim) {
  const size_t n = c.values.size();
  if (c.nvalues != static_cast<int32_t>(n) || (n != 3 && n != 5))
    return rejected("SET_GAINS: needs 3 values (push k_p, pull k, pull b) or 5 (and the 6-D pull's k_rot, b_rot)");
  const double k_p = c.values[0], k = c.values[1], b = c.values[2];
  if (!(std::isfinite(k_p) && std::isfinite(k) && std::isfinite(b) && k_p > 0 && k > 0 && b >= 0))
    return rejected("SET_GAINS: k_p and k must be positive, b non-negative, all finite");
  // The push's virtual coupling stays passive only while its damper holds the stiffer spring: b >= k_p T / 2.
  const Scene& scene = sim.scene();
  if (scene.push.enabled && k_p > 2.0 * scene.push.b * scene.rate_hz) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "SET_GAINS: push k_p %g N/m is over 2 b / T = %g N/m for the coupling's damper b = %g N s/m "
                  "(interaction.coupling.b): it would not be passive",
                  k_p, 2.0 * scene.push.b * scene.rate_hz, scene.push.b);
    return rejected(why);
  }
  if (n == 5 && !(std::isfinite(c.values[3]) && std::isfinite(c.values[4]) && c.values[3] >= 0 && c.values[4] >= 0))
    return rejected("SET_GAINS: k_rot and b_rot must be non-negative and finite");
  sim.setGains(k_p, k, b);
  if (n == 5) sim.setRotationalGains(c.values[3], c.values[4]);
  return {};
}

}  // namespace

CommandResult applyCommand(const command_t& c, Simulation& sim, LoopControl& control) {
  switch (c.kind) {
    case command_t::START: control.paused = false; return {};
    case command_t::PAUSE: control.paused = true; return {};
    case command_t::STEP: ++control.steps_requested; return {};
    case command_t::RESET:
      sim.reset();
      control.new_session = true;
      return {};
    case command_t::LOAD_SCENE:
      if (c.text.empty()) return rejected("LOAD_SCENE: no scene file given");
      control.scene_path = c.text;
      control.reload = true;
      control.running = false;
      return {};
    case command_t::SET_TRAJECTORY: return setTrajectory(c, sim);
    case command_t::SET_GAINS: return setGains(c, sim);
    case command_t::SAVE_TRAJECTORY:
      if (c.text.empty()) return rejected("SAVE_TRAJECTORY: no file given");
      try {
        sim.saveEdited(0, c.text);  // the first robot's
      } catch (const std::exception& e) {
        return rejected(e.what());
      }
      return {};
    case command_t::SHUTDOWN: control.running = false; return {};
    default: return rejected("unknown command kind " + std::to_string(int{c.kind}));
  }
}

}  // namespace igms
