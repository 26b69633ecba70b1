// igms-scenario: a scene and a device script, run in-process (lockstep, no
// network): the outcome as JSON, for designing and checking experiments.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "core/cli/command_line.h"
#include "core/cli/round_trip.h"
#include "tools/scenario/scenario_run.h"

namespace {

nlohmann::json toJson(const igms::ScenarioResult& r) {
  nlohmann::json j = {{"collision_steps_all", r.collision_steps_all},
                      {"min_distance_all", r.min_distance},
                      {"collision_steps", r.collision_steps},
                      {"first_collision", r.first_collision},
                      {"first_collision_what", r.first_collision_what},
                      {"min_distance_excluding_wall", r.min_distance_excluding_goal},
                      {"reached_wall_time", r.reached_wall_time},
                      {"final_ee", {r.final_ee.x(), r.final_ee.y(), r.final_ee.z()}},
                      {"max_user_force", r.max_user_force},
                      {"max_robot_force", r.max_robot_force},
                      {"max_force_step", r.max_force_step},
                      {"max_proxy_penetration", r.max_proxy_penetration},
                      {"max_device_behind_proxy", r.max_device_behind_proxy},
                      {"diverged", r.diverged},
                      {"max_contacts", r.max_contacts},
                      {"max_penetration", r.max_penetration},
                      {"contact_solve",
                       {{"solves", r.solve.solves},
                        {"unconverged", r.solve.unconverged},
                        {"max_sweeps", r.solve.max_sweeps},
                        {"polish_rounds", r.solve.polish_rounds},
                        {"max_residual", r.solve.max_residual},
                        {"warm_dropped", r.solve.warm_dropped},
                        {"restitution_scaled", r.solve.restitution_scaled},
                        {"energy_capped", r.solve.energy_capped},
                        {"position_unconverged", r.solve.position_unconverged},
                        {"near_rebuilds", r.solve.near_rebuilds},
                        {"candidates_dropped", r.solve.candidates_dropped},
                        {"slips_unturned", r.solve.slips_unturned},
                        {"polish_cycles", r.solve.polish_cycles},
                        {"linearised_exact", r.solve.linearised_exact},
                        {"linearised", r.solve.linearised},
                        {"linearised_failed", r.solve.linearised_failed},
                        {"max_linearised_angle", r.solve.max_linearised_angle},
                        {"large_solves", r.solve.large_solves},
                        {"large_iterations", r.solve.large_iterations},
                        {"max_slip_angle", r.solve.max_slip_angle}}},
                      {"bodies", nlohmann::json::object()},
                      {"interactions", nlohmann::json::array()}};
  // Each free body's final pose: [x, y, z, qw, qx, qy, qz].
  for (const std::string& name : r.bodies) {
    nlohmann::json pose = nlohmann::json::array();
    for (size_t c = 0; c < r.q_columns.size() && !r.samples.empty(); ++c)
      if (r.q_columns[c].rfind(name + ".", 0) == 0) pose.push_back(r.samples.back().q[c]);
    j["bodies"][name] = pose;
  }
  for (size_t i = 0; i < r.interactions.size(); ++i)
    j["interactions"].push_back({{"mode", r.interaction_modes[i] == 1 ? "push" : "pull"},
                                 {"start", r.interactions[i].first},
                                 {"end", r.interactions[i].second}});
  return j;
}

void writeCsv(const igms::ScenarioResult& r, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  igms::cli::roundTripDigits(f);
  f << "t,mode,ee_x,ee_y,ee_z,fx,fy,fz,min_distance,in_collision";
  for (const std::string& c : r.q_columns) f << "," << c;
  f << ",contacts,max_penetration,tip_x,tip_y,tip_z,proxy_x,proxy_y,proxy_z,solver_sweeps,solver_residual,"
       "hand_fx,hand_fy,hand_fz\n";
  for (const auto& s : r.samples) {
    f << s.t << "," << s.mode << "," << s.ee.x() << "," << s.ee.y() << "," << s.ee.z() << "," << s.force_on_robot.x()
      << "," << s.force_on_robot.y() << "," << s.force_on_robot.z() << "," << s.min_obstacle_distance << ","
      << s.in_collision;
    for (double q : s.q) f << "," << q;
    f << "," << s.contacts << "," << s.max_penetration;
    for (const igms::Vector3* v : {&s.tip, &s.proxy}) f << "," << v->x() << "," << v->y() << "," << v->z();
    f << "," << s.solver_sweeps << "," << s.solver_residual;
    f << "," << s.rendered.x() << "," << s.rendered.y() << "," << s.rendered.z() << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path, script, save, csv;
  double seconds = 6.0;
  bool device_limits = false;
  CLI::App app{"", "igms-scenario"};
  igms::cli::describe(app, "A scene and a device script run in-process (lockstep, no network); the outcome as JSON.");
  app.add_option("--scene", scene_path, "scene file (YAML)")->required()->check(CLI::ExistingFile);
  app.add_option("--device", script, "scripted:FILE (without one: the nominal run, no haptic input)")
      ->check(CLI::Validator(
          [](std::string& d) { return d.rfind("scripted:", 0) == 0 ? "" : "igms-scenario runs scripted:FILE devices"; },
          "scripted:FILE"));
  app.add_option("--seconds", seconds, "simulated seconds")->check(igms::cli::positive("SECONDS"));
  app.add_option("--save-edited", save, "write the edited trajectory here");
  app.add_option("--csv", csv, "every step as CSV here");
  app.add_flag("--device-limits", device_limits,
               "render within the device's force and per-cycle step, as igms-haptic does (default: unbounded)");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  try {
    for (const std::string& out : {save, csv}) {  // out/x.csv when out/ does not exist yet
      const std::filesystem::path folder = std::filesystem::path(out).parent_path();
      std::error_code ignored;  // an unwritable folder shows as the write's own error
      if (!out.empty() && !folder.empty()) std::filesystem::create_directories(folder, ignored);
    }
    if (!script.empty()) script = script.substr(9);
    const igms::ScenarioResult r = igms::runScenario(igms::loadScene(scene_path), script, seconds, save, 0.01, device_limits);
    std::printf("%s\n", toJson(r).dump().c_str());
    if (!csv.empty()) writeCsv(r, csv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-scenario: %s\n", e.what());
    return 2;
  }
  return 0;
}
