// igms-scenario: a scene and a device script, run in-process (lockstep, no
// network): the outcome as JSON, for designing and checking experiments.
//   igms-scenario --scene S --device scripted:FILE [--seconds T] [--save-edited FILE] [--csv FILE]
#include <cstdio>
#include <fstream>
#include <string>

#include "tools/scenario/scenario_run.h"

int main(int argc, char** argv) {
  std::string scene_path, device, save, csv;
  double seconds = 6.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--scene") scene_path = argv[i + 1];
    else if (a == "--device") device = argv[i + 1];
    else if (a == "--seconds") seconds = std::atof(argv[i + 1]);
    else if (a == "--save-edited") save = argv[i + 1];
    else if (a == "--csv") csv = argv[i + 1];
  }
  if (scene_path.empty()) {
    std::fprintf(stderr, "usage: igms-scenario --scene S [--device scripted:FILE] [--seconds T] [--save-edited F] [--csv F]\n");
    return 2;
  }
  try {
    const igms::Scene scene = igms::loadScene(scene_path);
    const std::string script = device.rfind("scripted:", 0) == 0 ? device.substr(9) : "";
    const igms::ScenarioResult r = igms::runScenario(scene, script, seconds, save);
    std::printf("{\"collision_steps_all\": %lld, \"min_distance_all\": %.4f, \"collision_steps\": %lld, \"first_collision\": %.3f, \"first_collision_what\": \"%s\", "
                "\"min_distance_excluding_wall\": %.4f, \"reached_wall_time\": %.3f, "
                "\"final_ee\": [%.4f, %.4f, %.4f], \"max_user_force\": %.3f, \"max_robot_force\": %.3f, "
                "\"diverged\": %s, \"interactions\": [",
                static_cast<long long>(r.collision_steps_all), r.min_distance, static_cast<long long>(r.collision_steps), r.first_collision, r.first_collision_what.c_str(),
                r.min_distance_excluding_goal, r.reached_wall_time, r.final_ee.x(), r.final_ee.y(), r.final_ee.z(),
                r.max_user_force, r.max_robot_force, r.diverged ? "true" : "false");
    for (size_t i = 0; i < r.interactions.size(); ++i)
      std::printf("%s{\"mode\": \"%s\", \"start\": %.3f, \"end\": %.3f}", i ? ", " : "",
                  r.interaction_modes[i] == 1 ? "push" : "pull", r.interactions[i].first, r.interactions[i].second);
    std::printf("]}\n");
    if (!csv.empty()) {
      std::ofstream f(csv);
      f << "t,mode,ee_x,ee_y,ee_z,fx,fy,fz,min_distance,in_collision";
      for (size_t j = 0; j < r.samples.front().q.size(); ++j) f << ",q" << j;
      f << "\n";
      for (const auto& s : r.samples) {
        f << s.t << "," << s.mode << "," << s.ee.x() << "," << s.ee.y() << "," << s.ee.z() << ","
          << s.force_on_robot.x() << "," << s.force_on_robot.y() << "," << s.force_on_robot.z() << ","
          << s.min_obstacle_distance << "," << s.in_collision;
        for (double q : s.q) f << "," << q;
        f << "\n";
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-scenario: %s\n", e.what());
    return 2;
  }
  return 0;
}
