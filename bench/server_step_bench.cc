// igms-step-bench: time of one full server step (trajectory point, computed
// torque, forward dynamics, integration; or the coupling), median and p99 over
// 20000 steps, per scene and interaction (the environment's scenes, contact
// included, after 1 s of settling); and the FCL collision check that
// runs beside the step on the publishing thread. Then one tip-link query on
// each Panda collision mesh (the push's contact: distance, normal, point), at
// random tips within 12 mm of the surface, against FCL's exact point-to-mesh
// distance on the same triangles in the same run. Also the contact detection alone on the mesh scenes
// (panda_channel, ball_on_mesh).
//   igms-step-bench [--quick] [--only TEXT] [--steps N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <filesystem>
#include <random>

#include <fcl/fcl.h>

#include "core/cli/command_line.h"
#include "core/geometry/tip_contact.h"
#include "server/collision/collision_world.h"
#include "core/contact/contact_detection.h"
#include "core/geometry/deepest_contact.h"
#include "core/kinematics/forward_kinematics.h"
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

volatile double g_sink = 0;  // keeps the timed calls from being optimised away

// Per query, each timed alone (the clock's own ~20 ns included), interleaved with the peer.
void benchTipQueries(int n) {
  const std::string dir = std::string(IGMS_SOURCE_DIR) + "/scenes/";
  Scene scene;
  try {
    scene = loadScene(dir + "panda_obstacle.yaml");
  } catch (const std::exception& e) {
    std::printf("tip-link queries on the Panda's meshes skipped: %s\n", e.what());
    return;
  }
  const Simulation sim(scene);
  const Model& model = sim.model();
  std::mt19937 rng(11);
  std::vector<double> ours, peer;
  ours.reserve(static_cast<size_t>(n));
  peer.reserve(static_cast<size_t>(n));
  std::printf("tip-link query (tip 1 cm) on each Panda collision mesh, %d random tips within 12 mm of it:\n", n);
  std::vector<double> all_ours, all_peer;
  for (const Frame& frame : model.frames) {
    for (const CollisionShape& shape : frame.collisions) {
      if (shape.kind != CollisionShape::Kind::Mesh || !shape.field || !shape.triangles) continue;
      const TriangleMesh& mesh = *shape.triangles;
      auto bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
      std::vector<fcl::Vector3d> vs(mesh.vertices.begin(), mesh.vertices.end());
      std::vector<fcl::Triangle> ts;
      for (const auto& t : mesh.triangles) ts.emplace_back(t[0], t[1], t[2]);
      bvh->beginModel();
      bvh->addSubModel(vs, ts);
      bvh->endModel();
      const fcl::CollisionObjectd mesh_object(bvh, fcl::Transform3d::Identity());
      auto point_shape = std::make_shared<fcl::Sphered>(0.0);
      std::uniform_int_distribution<size_t> pick(0, mesh.triangles.size() - 1);
      std::uniform_real_distribution<double> unit(0.0, 1.0), offset(-0.012, 0.012);
      ours.clear();
      peer.clear();
      while (static_cast<int>(ours.size()) < n) {
        const auto& t = mesh.triangles[pick(rng)];
        const Vector3 &a = mesh.vertices[static_cast<size_t>(t[0])], &b = mesh.vertices[static_cast<size_t>(t[1])],
                      &c = mesh.vertices[static_cast<size_t>(t[2])];
        const Vector3 normal = (b - a).cross(c - a);
        if (normal.norm() < 1e-12) continue;
        double u = unit(rng), v = unit(rng);
        if (u + v > 1) { u = 1 - u; v = 1 - v; }
        const Vector3 tip = a + u * (b - a) + v * (c - a) + offset(rng) * normal.normalized();
        auto t0 = Clock::now();
        g_sink = g_sink + tipContact(shape, SE3(), tip, 0.01).depth;
        ours.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        const fcl::CollisionObjectd point(point_shape, fcl::Transform3d(Eigen::Translation3d(tip)));
        fcl::DistanceRequestd request(true);
        fcl::DistanceResultd result;
        t0 = Clock::now();
        fcl::distance(&point, &mesh_object, request, result);
        peer.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        g_sink = g_sink + result.min_distance;
      }
      all_ours.insert(all_ours.end(), ours.begin(), ours.end());
      all_peer.insert(all_peer.end(), peer.begin(), peer.end());
      const Stats o = stats(ours), p = stats(peer);
      std::printf("  %-14s %5zu triangles: igms median %6.3f us p99 %6.3f us | FCL (exact, BVH) median %6.3f us "
                  "p99 %6.3f us | ratio %.2f\n",
                  frame.name.c_str(), mesh.triangles.size(), o.median, o.p99, p.median, p.p99, o.median / p.median);
    }
  }
  if (all_ours.empty()) return;
  const Stats o = stats(all_ours), p = stats(all_peer);
  std::printf("  %-14s %5s           igms median %6.3f us p99 %6.3f us | FCL (exact, BVH) median %6.3f us "
              "p99 %6.3f us | ratio %.2f\n", "all meshes", "", o.median, o.p99, p.median, p.p99, o.median / p.median);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  CLI::App app{"", "igms-step-bench"};
  igms::cli::describe(app, "One server step (the paper's loop) on the committed scenes: median and p99.");
  std::string only;
  int steps = 0;
  app.add_flag("--quick", quick, "3000 steps per row instead of 20000");
  app.add_option("--only", only, "only the rows whose label contains this text (e.g. Talos, 'PUMA, pull')");
  app.add_option("--steps", steps, "steps per row (default 20000; 3000 with --quick)")->check(CLI::PositiveNumber);
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  const int n = steps > 0 ? steps : quick ? 3000 : 20000;
  const auto wanted = [&](const std::string& label) { return only.empty() || label.find(only) != std::string::npos; };
  const std::string dir = std::string(IGMS_SOURCE_DIR) + "/scenes/";
  std::printf("igms-step-bench: one simulation step, %d steps each (1 kHz scenes)\n", n);
  for (const char* integrator : {"linearly_implicit", "semi_implicit_euler", "rk4"}) {
    const std::string label = "PUMA, trajectory + computed torque + FD, " + std::string(integrator);
    if (!wanted(label)) continue;
    Scene scene = loadScene(dir + "puma_wall.yaml");
    parseIntegrator(integrator, &scene.integrator);
    Simulation sim(scene);
    auto us = timeSteps(sim, nullptr, n);
    report(label.c_str(), us);
  }
  if (wanted("PUMA, push coupling (hold + contact), linearly_implicit")) {
    Simulation sim(loadScene(dir + "puma_wall.yaml"));
    sim.step(nullptr);
    const auto& poses = sim.linkPoses();
    InteractionInput push;
    push.mode = InteractionMode::Push;
    const int link3 = sim.model().frameIndex("link3");
    push.tip_position = poses[static_cast<size_t>(link3)].p + Vector3(0, 0, 0.055);
    auto us = timeSteps(sim, &push, n);
    report("PUMA, push coupling (hold + contact), linearly_implicit", us);
  }
  if (wanted("PUMA, pull coupling (hold + spring-damper), linearly_implicit")) {
    Simulation sim(loadScene(dir + "puma_wall.yaml"));
    InteractionInput pull;
    pull.mode = InteractionMode::Pull;
    pull.tip_position = sim.linkPoses()[static_cast<size_t>(sim.pullFrame())].p + Vector3(0.02, 0, 0);
    auto us = timeSteps(sim, &pull, n);
    report("PUMA, pull coupling (hold + spring-damper), linearly_implicit", us);
  }
  if (wanted("PUMA, 6-D pull coupling (force and torque), linearly_implicit") ||
      wanted("PUMA, two hands: 6-D pull + push on link 2, linearly_implicit")) {
    // The 6-D pull (eq. 4 with X a pose): the rotational spring-damper too.
    Simulation sim(loadScene(dir + "puma_obstacle.yaml"));
    const SE3 X = sim.linkPoses()[static_cast<size_t>(sim.pullFrame())];
    InteractionInput pull;
    pull.mode = InteractionMode::Pull;
    pull.tip_position = X.p + Vector3(0.02, 0, 0);
    pull.has_orientation = true;
    pull.tip_orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Vector3::UnitZ()).toRotationMatrix() * X.R);
    auto us = timeSteps(sim, &pull, n);
    report("PUMA, 6-D pull coupling (force and torque), linearly_implicit", us);
    // Two hands: that pull (client 1) and a push on link 2 (client 2), summed.
    HandInputs two;
    pull.client = 1;
    two.add(pull);
    InteractionInput push;
    push.mode = InteractionMode::Push;
    push.client = 2;
    const int link2 = sim.model().frameIndex("link2");
    push.tip_position = sim.linkPoses()[static_cast<size_t>(link2)].act(Vector3(0.2159, 0, 0.15));
    two.add(push);
    std::vector<double> hands_us;
    for (int k = 0; k < n; ++k) {
      const auto t0 = Clock::now();
      sim.step(two);
      hands_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    }
    report("PUMA, two hands: 6-D pull + push on link 2, linearly_implicit", hands_us);
  }
  if (wanted("PUMA + FCL obstacles: FK + collision check (publisher)") || wanted("PUMA + FCL obstacles: step + check")) {
    Simulation sim(loadScene(dir + "puma_obstacle.yaml"));
    CollisionWorld world(sim.model(), sim.geometry());
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
  // The floating robots as the earlier rows timed them: in empty space (no gravity, ground or contact; the
  // scenes now stand on the ground, timed below).
  auto inEmptySpace = [](Scene s) {
    s.gravity = Vector3::Zero();
    s.ground.enabled = false;
    for (RobotSpec& r : s.robots) r.controller = ControllerKind::ComputedTorque;
    return s;
  };
  if (wanted("quadruped, floating base (18 dof), linearly_implicit")) {
    Simulation sim(inEmptySpace(loadScene(dir + "quadruped_float.yaml")));
    auto us = timeSteps(sim, nullptr, n);
    report("quadruped, floating base (18 dof), linearly_implicit", us);
  }
  // The environment: robots standing on the ground, free bodies at rest, contact in every step.
  for (const auto& [file, label] : std::vector<std::pair<const char*, const char*>>{
           {"go1_stand.yaml", "Go1 standing, 4 foot contacts (environment)"},
           {"talos_stand.yaml", "Talos standing on box soles, 8 contacts (environment)"},
           {"puma_table.yaml", "PUMA line past a table with 3 boxes (environment)"},
           {"box_tower.yaml", "10-box tower, 40 contacts (environment)"},
           {"sphere_pile.yaml", "216-sphere pile, nv 1296, 216 contacts (environment)"}}) {
    if (!wanted(label)) continue;
    try {
      Simulation sim(loadScene(dir + file));
      for (int k = 0; k < 1000; ++k) sim.step(nullptr);  // settled
      const int steps = std::string(file) == "sphere_pile.yaml" || std::string(file) == "box_tower.yaml" ? n / 10 : n;
      auto us = timeSteps(sim, nullptr, steps);
      report(label, us);
    } catch (const std::exception& e) {
      std::printf("%-62s skipped: %s\n", label, e.what());
    }
  }
  // Contact detection alone on meshes: the scene stepped, and at each step's state the detection timed by
  // itself (its own Data and ContactDetection on the scene's contact model).
  for (const auto& [file, label] : std::vector<std::pair<const char*, const char*>>{
           {"panda_channel.yaml", "contact detection: Panda meshes pressed into a mesh channel"},
           {"ball_on_mesh.yaml", "contact detection: balls on a mesh cube and in a mesh bowl"}}) {
    if (!wanted(label)) continue;
    try {
      Simulation sim(loadScene(dir + file));
      for (int k = 0; k < 1000; ++k) sim.step(nullptr);  // pressed in, settled
      Data data(sim.model());
      GeometryData placed(sim.geometry());
      ContactDetection detection(*sim.contactModel());
      ContactSet set(sim.contactModel()->capacity());
      std::vector<double> us;
      int points = 0;
      for (int k = 0; k < n; ++k) {
        sim.step(nullptr);
        bodyKinematics(sim.model(), data, sim.q());
        const auto t0 = Clock::now();
        placed.place(sim.geometry(), sim.model(), data);
        detection.detect(placed, set);
        us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        points = std::max(points, set.n);
      }
      char what[160];
      std::snprintf(what, sizeof what, "%s (%d points)", label, points);
      report(what, us);
    } catch (const std::exception& e) {
      std::printf("%-62s skipped: %s\n", label, e.what());
    }
  }
  // Robots from example-robot-data (scripts/setup/fetch_robots.sh), pushed on a collision mesh and pulled.
  struct RealRobot {
    const char* scene;
    const char* label;
    const char* pushed;
  };
  for (const RealRobot& r : {RealRobot{"panda_obstacle.yaml", "Panda (9 dof, meshes)", "panda_link4"},
                             RealRobot{"ur5_line.yaml", "UR5 (6 dof, meshes)", "forearm_link"},
                             RealRobot{"talos_float.yaml", "Talos (44 dof + floating base, meshes)", "torso_2_link"}}) {
    const std::string push_label = std::string(r.label) + ", push on a mesh link";
    const std::string pull_label = std::string(r.label) + ", pull";
    if (!wanted(push_label) && !wanted(pull_label)) continue;
    Scene scene;
    try {
      scene = inEmptySpace(loadScene(dir + r.scene));
      Simulation probe(scene);
    } catch (const std::exception& e) {
      std::printf("%-62s skipped: %s\n", r.label, e.what());
      continue;
    }
    if (wanted(push_label)) {
      Simulation sim(scene);
      sim.step(nullptr);
      // A tip just touching the link's mesh (2 mm in: a push engages at most 5 mm deep, proxy.h),
      // marched in from 30 cm above its origin.
      const int f = sim.model().frameIndex(r.pushed);
      InteractionInput push;
      push.mode = InteractionMode::Push;
      const auto& poses = sim.linkPoses();
      Vector3 tip = poses[static_cast<size_t>(f)].p + Vector3(0, 0, 0.3);
      for (int k = 0; k < 3000; ++k, tip.z() -= 1e-4) {
        const LinkContact c = deepestContact(sim.model(), [&](int g) { return poses[static_cast<size_t>(g)]; }, tip,
                                             sim.scene().push.tip_radius, f);
        if (c.contact.touching && c.contact.depth > 0.002) break;
      }
      push.tip_position = tip;
      auto us = timeSteps(sim, &push, n);
      report(push_label.c_str(), us);
    }
    if (wanted(pull_label)) {
      Simulation sim(scene);
      InteractionInput pull;
      pull.mode = InteractionMode::Pull;
      pull.tip_position = sim.linkPoses()[static_cast<size_t>(std::max(0, sim.pullFrame()))].p + Vector3(0.02, 0, 0);
      auto us = timeSteps(sim, &pull, n);
      report(pull_label.c_str(), us);
    }
  }
  if (wanted("tip-link query")) benchTipQueries(quick ? 2000 : 20000);
  return 0;
}
