// igms-contact-bench: igms's step against MuJoCo's mj_step on the same
// environment scenes (contact included), interleaved in one process: per
// scene, both are warmed up, then rounds alternate a batch of igms steps and a
// batch of mj_step calls (the same number, 1 ms each), and each engine's median
// batch gives its microseconds per step; the ratio igms / MuJoCo is printed.
// MuJoCo reads the MJCF that scripts/bench/contact_peers.py writes from the same scene
// (the same URDF, shapes, masses, poses, PD gains; its own soft contact and
// Newton solver with their defaults). Each row also gives how far each engine's
// free bodies went from where they started (the largest, at the end): a scene
// that comes apart in one engine and stands in the other is not the same work.
// Built with IGMS_PEER_BENCH (MuJoCo's C
// library from its PyPI wheel); scripts/bench/bench.sh --contact does all of it.
//   igms-contact-bench --mjcf-dir DIR --scene scenes/go1_stand.yaml [--scene ...] [--rounds 9] [--steps 1000]
//                      [--warm 2000] [--json FILE]
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/cli/command_line.h"
#include "core/model/environment_model.h"
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

// The free bodies' positions (not a robot's base), world (x, y, z each), in each engine's body order.
std::vector<double> freeBodyPositions(const igms::Simulation& sim) {
  std::vector<double> out;
  for (const igms::ModelPart& part : sim.model().parts) {
    if (!part.free_body) continue;
    const igms::Vector3 p = igms::freeBodyState(part, sim.q(), sim.v()).p;
    out.insert(out.end(), {p.x(), p.y(), p.z()});
  }
  return out;
}
std::vector<double> freeBodyPositions(const mjModel* m, const mjData* d) {
  std::vector<double> out;
  for (int j = 0; j < m->njnt; ++j) {
    // a free body's, not a robot's floating base (a body with children), as igms's parts count them
    bool parent = false;
    for (int b = 1; b < m->nbody && !parent; ++b) parent = m->body_parentid[b] == m->jnt_bodyid[j];
    if (m->jnt_type[j] == mjJNT_FREE && !parent) out.insert(out.end(), d->qpos + m->jnt_qposadr[j], d->qpos + m->jnt_qposadr[j] + 3);
  }
  return out;
}
// The largest distance a body went from its start, m.
double farthest(const std::vector<double>& start, const std::vector<double>& now) {
  double most = 0.0;
  for (size_t i = 0; i + 2 < start.size() && i + 2 < now.size(); i += 3)
    most = std::max(most, std::hypot(now[i] - start[i], now[i + 1] - start[i + 1], now[i + 2] - start[i + 2]));
  return most;
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
  std::printf("%-14s %6s %9s %6s %12s %12s %8s %17s\n", "scene", "nv", "contacts", "apart", "igms us", "MuJoCo us", "ratio",
              "went mm igms/MJ");
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
    const std::vector<double> ours_from = freeBodyPositions(*sim), theirs_from = freeBodyPositions(m, d);
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
    const double ours_went = farthest(ours_from, freeBodyPositions(*sim));
    const double theirs_went = farthest(theirs_from, freeBodyPositions(m, d));
    std::printf("%-14s %6d %4d/%-4d %6d %12.2f %12.2f %8.2f %8.3g/%-8.3g\n", sim->scene().name.c_str(), sim->model().nv,
                sim->contacts().n, d->ncon, apart, a, b, a / b, 1e3 * ours_went, 1e3 * theirs_went);
    rows.push_back({{"scene", sim->scene().name}, {"nv", sim->model().nv}, {"contacts_igms", sim->contacts().n},
                    {"contacts_mujoco", d->ncon}, {"igms_pairs_apart", apart}, {"igms_us", a}, {"mujoco_us", b}, {"ratio", a / b},
                    {"igms_rounds_us", ours}, {"mujoco_rounds_us", theirs}, {"igms_farthest_m", ours_went},
                    {"mujoco_farthest_m", theirs_went}});
    mj_deleteData(d);
    mj_deleteModel(m);
  }
  if (!json_path.empty()) std::ofstream(json_path) << rows.dump(1) << "\n";
  return 0;
}
