// igms-contact-bench: igms's step against MuJoCo's mj_step on the same
// environment scenes (contact included), interleaved in one process: per
// scene, both are warmed up, then rounds alternate a batch of igms steps and a
// batch of mj_step calls (the same number, 1 ms each), and each engine's median
// batch gives its microseconds per step; the ratio igms / MuJoCo is printed.
// MuJoCo reads the MJCF that scripts/bench/contact_peers.py writes from the same scene
// (the same URDF, shapes, masses, poses, PD gains; its own soft contact and
// Newton solver with their defaults). Built with IGMS_PEER_BENCH (MuJoCo's C
// library from its PyPI wheel); scripts/bench/bench.sh --contact does all of it.
//   igms-contact-bench --mjcf-dir DIR --scene scenes/go1_stand.yaml [--scene ...] [--rounds 9] [--steps 1000]
//                      [--warm 2000] [--json FILE]
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/cli/command_line.h"
#include "core/simulation/simulation.h"

namespace {

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

template <typename F>
double batchMicroseconds(int steps, F&& step) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) step();
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / steps;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes;
  std::string mjcf_dir, json_path;
  int rounds = 9, steps = 1000, warm = 2000;
  CLI::App app{"", "igms-contact-bench"};
  igms::cli::describe(app, "igms's step against MuJoCo's mj_step on the same contact scenes, interleaved.");
  app.add_option("--scene", scenes, "scene file (YAML); repeat for several")->required()->check(CLI::ExistingFile);
  app.add_option("--mjcf-dir", mjcf_dir, "the MJCF that scripts/bench/contact_peers.py wrote")->required();
  app.add_option("--rounds", rounds, "rounds (each a batch per engine)")->check(CLI::PositiveNumber);
  app.add_option("--steps", steps, "steps per batch")->check(CLI::PositiveNumber);
  app.add_option("--warm", warm, "steps before timing (settling)")->check(CLI::NonNegativeNumber);
  app.add_option("--json", json_path, "the rows as JSON here");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  nlohmann::json rows = nlohmann::json::array();
  std::printf("%-14s %6s %9s %6s %12s %12s %8s\n", "scene", "nv", "contacts", "apart", "igms us", "MuJoCo us", "ratio");
  for (const std::string& path : scenes) {
    std::unique_ptr<igms::Simulation> sim;
    try {
      sim = std::make_unique<igms::Simulation>(igms::loadScene(path));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "igms-contact-bench: %s\n", e.what());
      return 2;
    }
    const std::string xml = mjcf_dir + "/" + sim->scene().name + ".xml";
    char error[1000] = "";
    mjModel* m = mj_loadXML(xml.c_str(), nullptr, error, sizeof error);
    if (!m) {
      std::fprintf(stderr, "igms-contact-bench: %s: %s\n", xml.c_str(), error);
      return 2;
    }
    mjData* d = mj_makeData(m);
    mj_resetDataKeyframe(m, d, 0);
    for (int k = 0; k < warm; ++k) {
      sim->step(nullptr);
      mj_step(m, d);
    }
    std::vector<double> ours, theirs;
    for (int r = 0; r < rounds; ++r) {
      ours.push_back(batchMicroseconds(steps, [&] { sim->step(nullptr); }));
      theirs.push_back(batchMicroseconds(steps, [&] { mj_step(m, d); }));
    }
    const double a = median(ours), b = median(theirs);
    // apart: igms's pairs of shapes within the margin but apart and not closing, left out of the solve.
    const int apart = sim->contactStats().deferred;
    std::printf("%-14s %6d %4d/%-4d %6d %12.2f %12.2f %8.2f\n", sim->scene().name.c_str(), sim->model().nv,
                sim->contacts().n, d->ncon, apart, a, b, a / b);
    rows.push_back({{"scene", sim->scene().name}, {"nv", sim->model().nv}, {"contacts_igms", sim->contacts().n},
                    {"contacts_mujoco", d->ncon}, {"igms_pairs_apart", apart}, {"igms_us", a}, {"mujoco_us", b}, {"ratio", a / b},
                    {"igms_rounds_us", ours}, {"mujoco_rounds_us", theirs}});
    mj_deleteData(d);
    mj_deleteModel(m);
  }
  if (!json_path.empty()) std::ofstream(json_path) << rows.dump(1) << "\n";
  return 0;
}
