// igms-step-bench: time of one full server step (trajectory point, computed
// torque, forward dynamics, integration; or the coupling), median and p99 over
// 20000 steps, per scene and interaction; and the FCL collision check that
// runs beside the step on the publishing thread.
//   igms-step-bench [--quick]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "core/cli/command_line.h"
#include "server/collision/collision_world.h"
#include "core/geometry/deepest_contact.h"
#include "core/simulation/simulation.h"

namespace {

using namespace igms;
using Clock = std::chrono::steady_clock;

struct Stats {
  double median, p99;
};

Stats stats(std::vector<double>& us) {
  std::sort(us.begin(), us.end());
  return {us[us.size() / 2], us[static_cast<size_t>(0.99 * static_cast<double>(us.size()))]};
}

void report(const char* what, std::vector<double>& us) {
  const Stats s = stats(us);
  std::printf("  %-52s median %7.2f us   p99 %7.2f us\n", what, s.median, s.p99);
}

std::vector<double> timeSteps(Simulation& sim, const InteractionInput* in, int n) {
  std::vector<double> us;
  us.reserve(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const auto t0 = Clock::now();
    sim.step(in);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    if (sim.diverged()) break;
  }
  return us;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  CLI::App app{"", "igms-step-bench"};
  igms::cli::describe(app, "One server step (the paper's loop) on the committed scenes: median and p99.");
  app.add_flag("--quick", quick, "3000 steps per row instead of 20000");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  const int n = quick ? 3000 : 20000;
  const std::string dir = std::string(IGMS_SOURCE_DIR) + "/scenes/";
  std::printf("igms-step-bench: one simulation step, %d steps each (1 kHz scenes)\n", n);
  for (const char* integrator : {"linearly_implicit", "semi_implicit_euler", "rk4"}) {
    Scene scene = loadScene(dir + "puma_wall.yaml");
    parseIntegrator(integrator, &scene.integrator);
    Simulation sim(scene);
    auto us = timeSteps(sim, nullptr, n);
    report(("PUMA, trajectory + computed torque + FD, " + std::string(integrator)).c_str(), us);
  }
  {
    Simulation sim(loadScene(dir + "puma_wall.yaml"));
    sim.step(nullptr);
    const auto& poses = sim.linkPoses();
    InteractionInput push;
    push.mode = InteractionMode::Push;
    push.contact_frame = sim.model().frameIndex("link3");
    push.tip_position = poses[static_cast<size_t>(push.contact_frame)].p + Vector3(0, 0, 0.055);
    auto us = timeSteps(sim, &push, n);
    report("PUMA, push coupling (hold + contact), linearly_implicit", us);
  }
  {
    Simulation sim(loadScene(dir + "puma_wall.yaml"));
    InteractionInput pull;
    pull.mode = InteractionMode::Pull;
    pull.tip_position = sim.linkPoses()[static_cast<size_t>(sim.pullFrame())].p + Vector3(0.02, 0, 0);
    auto us = timeSteps(sim, &pull, n);
    report("PUMA, pull coupling (hold + spring-damper), linearly_implicit", us);
  }
  {
    Simulation sim(loadScene(dir + "puma_obstacle.yaml"));
    CollisionWorld world(sim.model(), sim.scene().obstacles);
    std::vector<double> step_us, check_us;
    for (int k = 0; k < n; ++k) {
      auto t0 = Clock::now();
      sim.step(nullptr);
      step_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
      t0 = Clock::now();
      const auto& poses = sim.linkPoses();
      world.check(poses);
      check_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    }
    std::vector<double> total(step_us.size());
    for (size_t k = 0; k < total.size(); ++k) total[k] = step_us[k] + check_us[k];
    report("PUMA + FCL obstacles: FK + collision check (publisher)", check_us);
    report("PUMA + FCL obstacles: step + check", total);
  }
  {
    Simulation sim(loadScene(dir + "quadruped_float.yaml"));
    auto us = timeSteps(sim, nullptr, n);
    report("quadruped, floating base (18 dof), linearly_implicit", us);
  }
  // Robots from example-robot-data (scripts/fetch_robots.sh), pushed on a collision mesh and pulled.
  struct RealRobot {
    const char* scene;
    const char* label;
    const char* pushed;
  };
  for (const RealRobot& r : {RealRobot{"panda_obstacle.yaml", "Panda (9 dof, meshes)", "panda_link4"},
                             RealRobot{"ur5_line.yaml", "UR5 (6 dof, meshes)", "forearm_link"},
                             RealRobot{"talos_float.yaml", "Talos (44 dof + floating base, meshes)", "torso_2_link"}}) {
    Scene scene;
    try {
      scene = loadScene(dir + r.scene);
      Simulation probe(scene);
    } catch (const std::exception& e) {
      std::printf("%-62s skipped: %s\n", r.label, e.what());
      continue;
    }
    {
      Simulation sim(scene);
      sim.step(nullptr);
      // A tip just touching the link's mesh: marched in from 30 cm above its origin.
      const int f = sim.model().frameIndex(r.pushed);
      InteractionInput push;
      push.mode = InteractionMode::Push;
      push.contact_frame = f;
      const auto& poses = sim.linkPoses();
      Vector3 tip = poses[static_cast<size_t>(f)].p + Vector3(0, 0, 0.3);
      for (int k = 0; k < 3000; ++k, tip.z() -= 1e-4) {
        const LinkContact c = deepestContact(sim.model(), [&](int g) { return poses[static_cast<size_t>(g)]; }, tip,
                                             sim.scene().push.tip_radius, f);
        if (c.contact.touching && c.contact.depth > 0.005) break;
      }
      push.tip_position = tip;
      auto us = timeSteps(sim, &push, n);
      report((std::string(r.label) + ", push on a mesh link").c_str(), us);
    }
    {
      Simulation sim(scene);
      InteractionInput pull;
      pull.mode = InteractionMode::Pull;
      pull.tip_position = sim.linkPoses()[static_cast<size_t>(std::max(0, sim.pullFrame()))].p + Vector3(0.02, 0, 0);
      auto us = timeSteps(sim, &pull, n);
      report((std::string(r.label) + ", pull").c_str(), us);
    }
  }
  return 0;
}
