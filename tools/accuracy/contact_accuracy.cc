#include "tools/accuracy/contact_accuracy.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "core/cli/round_trip.h"
#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tools/ode_ref/ode_contact_scene.h"

namespace igms::accuracy {
namespace {

constexpr double kG = 9.81;
const double kTheta20 = 20.0 * M_PI / 180.0, kTheta15 = 15.0 * M_PI / 180.0;

// One body's world pose and velocity, whichever engine moves it.
struct Sample {
  Vector3 p, v;
  Matrix3 R = Matrix3::Identity();
  Vector3 w = Vector3::Zero();  // angular velocity, world
};

// An engine stepping one case's scene: igms's Simulation or ODE's dWorldStep.
class Engine {
 public:
  virtual ~Engine() = default;
  virtual bool step() = 0;
  virtual Sample body() const = 0;
};

class IgmsEngine : public Engine {
 public:
  explicit IgmsEngine(const Scene& scene) : sim_(scene) {}
  bool step() override { return sim_.step(nullptr); }
  Sample body() const override {
    const FreeBodyState b = freeBodyState(sim_.model().parts.front(), sim_.q(), sim_.v());
    return {b.p, b.v, b.R, b.w};
  }

 private:
  Simulation sim_;
};

class OdeEngine : public Engine {
 public:
  explicit OdeEngine(const Scene& scene) : ode_(resolveScene(scene)), h_(scene.dt) {}
  bool step() override {
    ode_.step(h_);
    return std::isfinite(ode_.pose(0).p.x());
  }
  Sample body() const override {
    const SE3 pose = ode_.pose(0);
    return {pose.p, ode_.velocity(0), pose.R, ode_.angularVelocity(0)};
  }

 private:
  OdeContactScene ode_;
  double h_;
};

// A case's measurement over a run: fed every step's end, then asked for the error.
class Measurement {
 public:
  explicit Measurement(const std::string& name) : name_(name) {}

  void observe(double t, const Sample& b) {
    if (name_ == "box_slide" || name_ == "sphere_roll" || name_ == "free_top" || name_ == "ball_on_mesh") {
      last_ = b;
    } else if (name_ == "box_slope") {
      if (t <= 0.5 + 1e-9) from_ = b.p;
      else creep_ = (b.p - from_).norm() / (t - 0.5);
    } else if (!fell_again_) {  // ball_bounce: the first rebound's apex
      bounced_ = bounced_ || b.v.z() > 0.0;
      if (bounced_) {
        apex_ = std::max(apex_, b.p.z() - 0.05);
        fell_again_ = b.v.z() < 0.0;
      }
    }
  }

  double error() const {
    if (name_ == "box_slide") return std::abs(last_.p.x() - 1.0 / (2.0 * 0.5 * kG));  // v0^2 / (2 mu g)
    if (name_ == "box_slope") return creep_;                                         // the truth is 0
    if (name_ == "free_top") {  // |E(10 s) - E(0)| / E(0): I = (1, 1, 0.3), w = (2, 0, 50), 377 J
      const Vector3 w = last_.R.transpose() * last_.w;
      const double energy = 0.5 * (w.x() * w.x() + w.y() * w.y() + 0.3 * w.z() * w.z()) + 0.5 * last_.v.squaredNorm();
      return std::abs(energy - 377.0) / 377.0;
    }
    if (name_ == "ball_on_mesh") return std::abs(last_.p.z() - (0.4 + 0.03));  // on the cube's top, r above it
    if (name_ == "sphere_roll") {
      const double a = 5.0 / 7.0 * kG * std::sin(kTheta15);  // from rest, rolling without slip, at 1 s
      return std::abs(last_.v.norm() - a) / a;
    }
    return std::abs(apex_ - 0.25) / 0.25;  // dropped from 1 m, e = 0.5: e^2 m
  }

 private:
  std::string name_;
  Sample last_{Vector3::Zero(), Vector3::Zero()};
  Vector3 from_ = Vector3::Zero();
  double creep_ = 0.0, apex_ = 0.0;
  bool bounced_ = false, fell_again_ = false;
};

struct RunResult {
  double error = NAN;
  double wall = 0.0;  // s, the steps alone
  bool failed = false;
};

RunResult runOnce(const ContactCase& c, bool ode, double h) {
  Scene scene = parseScene(c.yaml, c.name + ".yaml", ".");
  scene.dt = h;
  scene.rate_hz = 1.0 / h;
  std::unique_ptr<Engine> engine;
  if (ode) engine = std::make_unique<OdeEngine>(scene);
  else engine = std::make_unique<IgmsEngine>(scene);
  Measurement m(c.name);
  const int steps = static_cast<int>(std::lround(c.seconds / h));
  RunResult r;
  double wall = 0.0;
  for (int k = 1; k <= steps; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = engine->step();
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!ok) {
      r.failed = true;
      break;
    }
    m.observe(k * h, engine->body());
  }
  r.error = r.failed ? NAN : m.error();
  r.wall = wall;
  return r;
}

}  // namespace

std::vector<ContactCase> contactCases(const std::string& source_dir) {
  char slope[640], roll[640];
  std::snprintf(slope, sizeof slope,
                "name: box_slope\nground: {height: 0, rpy: [0, %.17g, 0], material: rough}\n"
                "materials: {rough: {friction: 1.0}}\n"
                "bodies: [{name: box, shape: box, size: [0.2, 0.2, 0.2], mass: 1.0, material: rough, "
                "xyz: [%.17g, 0, %.17g], rpy: [0, %.17g, 0]}]\n",
                kTheta20, 0.1 * std::sin(kTheta20), 0.1 * std::cos(kTheta20), kTheta20);
  std::snprintf(roll, sizeof roll,
                "name: sphere_roll\nground: {height: 0, rpy: [0, %.17g, 0], material: m}\n"
                "materials: {m: {friction: 1.0}}\n"
                "bodies: [{name: ball, shape: sphere, radius: 0.05, mass: 1.0, material: m, xyz: [%.17g, 0, %.17g]}]\n",
                kTheta15, 0.05 * std::sin(kTheta15), 0.05 * std::cos(kTheta15));
  return {
      {"box_slide",
       "name: box_slide\nground: {height: 0, material: wood}\nmaterials: {wood: {friction: 0.5}}\n"
       "bodies: [{name: box, shape: box, size: [0.2, 0.2, 0.2], mass: 1.0, xyz: [0, 0, 0.1], v: [1, 0, 0], "
       "material: wood}]\n",
       "a box launched at 1 m/s, mu 0.5: |stop - 101.937 mm|", "m", 0.4, 0.5e-3 + 1e-6},
      {"box_slope", slope, "a box on 20 deg, mu 1: creep after 0.5 s (truth 0)", "m/s", 3.0, 1e-6},
      {"sphere_roll", roll, "a sphere rolling down 15 deg: |v(1 s) - (5/7) g sin 15 deg| relative", "1", 1.0, 5.5e-4},
      {"ball_bounce",
       "name: ball_bounce\nground: {height: 0, material: m}\nmaterials: {m: {friction: 0.5, restitution: 0.5}}\n"
       "bodies: [{name: ball, shape: sphere, radius: 0.05, mass: 0.2, xyz: [0, 0, 1.05], material: m}]\n",
       "a ball dropped 1 m, e = 0.5: |apex - e^2 m| relative", "1", 1.6, 0.01},
      {"free_top",
       "name: free_top\ngravity: [0, 0, 0]\nground: {height: -5}\n"
       "bodies: [{name: top, shape: cylinder, radius: 0.2, length: 0.05, mass: 1, inertia: [1, 1, 0.3, 0, 0, 0], "
       "w: [2, 0, 50]}]\n",
       "a free top, I (1, 1, 0.3), 50 rad/s spin and 2 rad/s wobble, 10 s: |E - E0| / E0", "1", 10.0, 1e-3},
      {"ball_on_mesh",
       "name: ball_on_mesh\nobstacles: [{name: block, shape: mesh, file: " + source_dir +
           "/models/meshes/cube.obj, xyz: [0, 0, 0.2], solid: true}]\n"
           "bodies: [{name: ball, shape: sphere, radius: 0.03, mass: 1, xyz: [0.01, 0.02, 0.432]}]\n",
       "a 3 cm ball released 2 mm above a mesh cube: |rest height - r| after 1 s", "m", 1.0, 1e-4},
  };
}

int contactAccuracy(const ContactAccuracyOptions& o) {
  const std::vector<ContactCase> cases = contactCases(o.source_dir);
  if (!o.write_cases.empty()) {
    std::filesystem::create_directories(o.write_cases);
    // The scenes, and what the peer needs to run and measure them alike: each case's duration and unit.
    std::ofstream index(o.write_cases + "/cases.json");
    index << "{";
    for (size_t k = 0; k < cases.size(); ++k) {
      const ContactCase& c = cases[k];
      std::ofstream(o.write_cases + "/" + c.name + ".yaml") << c.yaml;
      index << (k ? ",\n " : "\n ") << "\"" << c.name << "\": {\"seconds\": " << c.seconds << ", \"unit\": \"" << c.unit
            << "\"}";
    }
    index << "\n}\n";
    std::printf("wrote %zu contact cases into %s\n", cases.size(), o.write_cases.c_str());
    return 0;
  }
  std::vector<double> steps;
  for (double h = o.quick ? 0.5e-3 : 0.25e-3; h <= (o.quick ? 2e-3 : 4e-3) * 1.0001; h *= 2) steps.push_back(h);
  std::ofstream out(o.csv.empty() ? "/dev/null" : o.csv);
  cli::roundTripDigits(out);
  out << "case,engine,h_ms,error,unit,wall_s_per_sim_s,failed\n";
  int status = 0;
  for (const ContactCase& c : cases) {
    std::printf("%s: %s [%s], %.2f s\n", c.name.c_str(), c.measure.c_str(), c.unit.c_str(), c.seconds);
    for (const bool ode : {false, true}) {
      const char* engine = ode ? "ode_dworldstep" : "igms";
      for (double h : steps) {
        const RunResult r = runOnce(c, ode, h);
        std::vector<double> walls{r.wall};
        while (static_cast<int>(walls.size()) < (o.quick ? 1 : o.repeats)) walls.push_back(runOnce(c, ode, h).wall);
        std::sort(walls.begin(), walls.end());
        const double cost = walls[walls.size() / 2] / c.seconds;
        out << c.name << "," << engine << "," << h * 1e3 << "," << r.error << "," << c.unit << "," << cost << ","
            << r.failed << "\n";
        const bool goal = !ode && std::abs(h - 1e-3) < 1e-12;
        const bool missed = goal && !(r.error <= c.goal_at_1ms);
        std::printf("  %-15s h=%6.3f ms  error %-10.3g %s  %.3g s per s%s\n", engine, h * 1e3, r.error, c.unit.c_str(),
                    cost, goal ? (missed ? "  MISSES its goal" : "  (meets its goal)") : "");
        if (missed) status = 1;
      }
    }
  }
  return status;
}

}  // namespace igms::accuracy
