// igms.Scene and igms.Simulation: a scene file loaded and checked, and the
// server's own step on it, driven from Python. step(n) runs n steps without
// the GIL (several simulations on several threads use several cores), with the
// hands' inputs as the bus would bring them: each hand's last push or pull is
// validated by the server's input gate (server/transport/input_gate.h) when it
// is set, and sent again every step with the next seq, as a device holding still.
// q and v are read-only views of the simulation's own vectors (no copy);
// set_state writes them.
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <optional>

#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "python/bindings/array_args.h"
#include "python/bindings/bindings.h"
#include "python/bindings/diverged_error.h"
#include "python/bindings/solve_figures.h"
#include "server/transport/input_gate.h"

namespace igms::python {

namespace {

// One hand's stretch of push or pull, as the session summary lists them (scripts/reports/session_summary.py).
struct Interaction {
  int32_t client = -1;
  InteractionMode mode = InteractionMode::None;
  double start = 0.0, end = 0.0, max_force = 0.0;  // s, s, N on the robot or body
};

// The running figures summary() reports, kept as the steps go.
struct Tally {
  int max_contacts = 0;
  double max_penetration = 0.0;
  int max_sweeps = 0;
  double max_residual = 0.0;
  int64_t polish_rounds = 0;
  double max_slip_angle = 0.0;
  double max_linearised_angle = 0.0;
  double max_robot_force = 0.0;
  int64_t steps_with_several_hands = 0;
  std::vector<Interaction> interactions;            // in order of start (reserved: a push or pull is rare)
  std::array<int, kMaxHands> open;  // per client: its interaction going on (-1: none; the constructor fills it)
};

class PySimulation {
 public:
  explicit PySimulation(const Scene& scene)
      : sim_(scene), frames_(sim_.model()), bodies_(freeBodyNames()), zero_qdd_(VectorX::Zero(sim_.model().nv)), q_in_(sim_.model().nq),
        v_in_(sim_.model().nv), q_start_(sim_.q()) {
    tally_.interactions.reserve(256);
    tally_.open.fill(-1);
  }

  Simulation& sim() { return sim_; }
  const Simulation& sim() const { return sim_; }
  const std::vector<std::string>& bodies() const { return bodies_; }

  // Runs without the GIL: touches no Python object.
  void step(int n) {
    if (n < 0) throw nb::value_error("step(n): n must be >= 0");
    if (busy_.exchange(true)) throw std::runtime_error("this Simulation is already stepping on another thread");
    struct Release {
      std::atomic<bool>& b;
      ~Release() { b = false; }
    } release{busy_};
    for (int k = 0; k < n; ++k) {
      inputs_.clear();
      for (Hand& h : hands_)
        if (h.active) {
          h.input.seq = ++seq_;
          inputs_.add(h.input);
        }
      if (!sim_.step(inputs_)) throw DivergedError(sim_.divergenceReport());
      tally();
    }
  }

  void setState(nb::handle q, nb::handle v) {
    readVector(q, sim_.model().nq, "q", q_in_);
    readVector(v, sim_.model().nv, "v", v_in_);
    sim_.setState(sim_.time(), q_in_, v_in_, zero_qdd_, false);
  }

  // A hand's push or pull from now on, until released (client: 0..3, kMaxHands hands at once).
  void setHand(int client, haptic_input_t& msg) {
    if (client < 0 || client >= kMaxHands)
      throw nb::value_error(("client must be 0.." + std::to_string(kMaxHands - 1)).c_str());
    msg.client_id = client;
    msg.seq = seq_ + 1;
    InteractionInput input;
    RejectReason why;
    if (!toInteractionInput(msg, frames_, &input, &why))
      throw nb::value_error(("the server's input gate rejects this input: " + std::string(rejectReasonName(why)) +
                             (why == RejectReason::UnknownLink ? " (no link '" + msg.contact_link + msg.attach_link +
                                                                     "' in the scene)"
                                                               : ""))
                                .c_str());
    Hand& h = hands_[static_cast<size_t>(client)];
    h.active = true;
    h.input = input;
  }
  void release(int client) {
    if (client < 0 || client >= kMaxHands)
      throw nb::value_error(("client must be 0.." + std::to_string(kMaxHands - 1)).c_str());
    hands_[static_cast<size_t>(client)].active = false;
  }
  std::vector<int> activeHands() const {
    std::vector<int> out;
    for (int c = 0; c < kMaxHands; ++c)
      if (hands_[static_cast<size_t>(c)].active) out.push_back(c);
    return out;
  }

  int frameOf(const std::string& name) const {
    const int f = sim_.model().frameIndex(name);
    if (f < 0) {
      std::string known;
      for (const std::string& b : bodies_) known += (known.empty() ? "" : ", ") + b;
      throw nb::key_error(("no body or link '" + name + "' in the scene (its free bodies: " +
                           (known.empty() ? "none" : known) + ")")
                              .c_str());
    }
    return f;
  }

  nb::dict summary() const {
    nb::dict d;
    const ContactSolveStats& s = sim_.contactStats();
    d["time"] = sim_.time();
    d["steps"] = sim_.steps();
    d["diverged"] = sim_.diverged();
    d["divergence"] = sim_.divergenceReport();
    d["max_contacts"] = tally_.max_contacts;
    d["max_penetration"] = tally_.max_penetration;
    d["max_robot_force"] = tally_.max_robot_force;
    d["forces_clamped"] = sim_.forcesClamped();
    d["resume_ramps"] = sim_.resumeRamps();
    d["contacts_dropped"] = sim_.contacts().dropped;
    d["steps_with_several_hands"] = tally_.steps_with_several_hands;
    nb::list interactions;
    for (const Interaction& i : tally_.interactions) {
      nb::dict x;
      x["client"] = i.client;
      x["mode"] = i.mode == InteractionMode::Push ? "push" : "pull";
      x["start"] = i.start;
      x["end"] = i.end;
      x["max_force"] = i.max_force;
      interactions.append(x);
    }
    d["interactions"] = interactions;
    ScenarioSolveStats solve;
    solve.solves = s.solves;
    solve.unconverged = s.unconverged;
    solve.max_sweeps = tally_.max_sweeps;
    solve.max_residual = tally_.max_residual;
    solve.polish_rounds = tally_.polish_rounds;
    solve.warm_dropped = s.warm_dropped;
    solve.restitution_scaled = s.restitution_scaled;
    solve.energy_capped = s.energy_capped;
    solve.position_unconverged = s.position_unconverged;
    solve.slips_unturned = s.slips_unturned;
    solve.polish_cycles = s.polish_cycles;
    solve.large_solves = s.large_solves;
    solve.large_iterations = s.large_iterations;
    solve.max_slip_angle = tally_.max_slip_angle;
    solve.linearised_exact = s.linearised_exact;
    solve.linearised = s.linearised;
    solve.linearised_failed = s.linearised_failed;
    solve.max_linearised_angle = tally_.max_linearised_angle;
    d["contact_solve"] = solveFigures(solve);
    nb::dict poses;
    const Model& model = sim_.model();
    for (const ModelPart& part : model.parts)
      if (part.free_body) {
        nb::dict body;
        body["start"] = newVector(q_start_.data() + part.q_begin, 7);
        body["end"] = newVector(sim_.q().data() + part.q_begin, 7);
        poses[part.name.c_str()] = body;
      }
    d["bodies"] = poses;
    return d;
  }

  // The contacts at the last step's start as columns; igms.Simulation.contacts() makes them a structured array.
  nb::dict contactColumns() const {
    const ContactSet& set = sim_.hasContacts() ? sim_.contacts() : empty_;
    const Model& model = sim_.model();
    const GeometryModel& geometry = sim_.geometry();
    const size_t n = static_cast<size_t>(set.n);
    std::vector<std::string> body_a(n), body_b(n), geom_a(n), geom_b(n);
    MatrixX point(n, 3), normal(n, 3), impulse(n, 3);
    VectorX depth(n);
    auto bodyName = [&](int b) { return b < 0 ? std::string("world") : model.body_name[static_cast<size_t>(b)]; };
    for (int k = 0; k < set.n; ++k) {
      const Contact& c = set[k];
      body_a[k] = bodyName(c.body_a);
      body_b[k] = bodyName(c.body_b);
      geom_a[k] = geometry.object(c.geom_a).name;
      geom_b[k] = geometry.object(c.geom_b).name;
      point.row(k) = c.point.transpose();
      normal.row(k) = c.normal.transpose();
      impulse.row(k) = c.impulse.transpose();
      depth[k] = -c.distance;
    }
    nb::dict d;
    d["body_a"] = body_a;
    d["body_b"] = body_b;
    d["geom_a"] = geom_a;
    d["geom_b"] = geom_b;
    d["point"] = newMatrix(point);
    d["normal"] = newMatrix(normal);
    d["impulse"] = newMatrix(impulse);
    d["depth"] = newVector(depth.data(), n);
    return d;
  }

  // Each hand's part of the last step: client, mode, force, torque, point.
  nb::list handOutcomes() const {
    nb::list out;
    const StepOutcome& o = sim_.outcome();
    for (int k = 0; k < o.nhands; ++k) {
      const HandOutcome& h = o.hands[static_cast<size_t>(k)];
      nb::dict d;
      d["client"] = h.client;
      d["mode"] = h.mode == InteractionMode::Push ? "push" : h.mode == InteractionMode::Pull ? "pull" : "none";
      d["force"] = newVector(h.applied.force.data(), 3);
      d["torque"] = newVector(h.applied.torque.data(), 3);
      d["point"] = newVector(h.applied.point.data(), 3);
      d["clamped"] = h.applied.clamped;
      out.append(d);
    }
    return out;
  }

 private:
  struct Hand {
    bool active = false;
    InteractionInput input;
  };

  std::vector<std::string> freeBodyNames() const {
    std::vector<std::string> names;
    for (const ModelPart& part : sim_.model().parts)
      if (part.free_body) names.push_back(part.name);
    return names;
  }

  void tally() {
    const ContactSet& c = sim_.contacts();
    const int n = sim_.hasContacts() ? c.n : 0;
    tally_.max_contacts = std::max(tally_.max_contacts, n);
    if (n > 0) {
      tally_.max_penetration = std::max(tally_.max_penetration, c.maxPenetration());
      tally_.max_sweeps = std::max(tally_.max_sweeps, sim_.contactStats().iterations);
      tally_.max_residual = std::max(tally_.max_residual, sim_.contactStats().residual);
      tally_.polish_rounds += sim_.contactStats().polish_rounds;
      tally_.max_slip_angle = std::max(tally_.max_slip_angle, sim_.contactStats().slip_angle);
      tally_.max_linearised_angle = std::max(tally_.max_linearised_angle, sim_.contactStats().linearised_angle);
    }
    const StepOutcome& o = sim_.outcome();
    tally_.max_robot_force = std::max(tally_.max_robot_force, o.force_on_robot.norm());
    int acting = 0;
    std::array<bool, kMaxHands> seen{};
    for (int k = 0; k < o.nhands; ++k) {
      const HandOutcome& h = o.hands[static_cast<size_t>(k)];
      if (h.mode == InteractionMode::None || h.client < 0 || h.client >= kMaxHands) continue;
      ++acting;
      seen[static_cast<size_t>(h.client)] = true;
      int& open = tally_.open[static_cast<size_t>(h.client)];
      if (open < 0 || tally_.interactions[static_cast<size_t>(open)].mode != h.mode) {
        open = static_cast<int>(tally_.interactions.size());
        tally_.interactions.push_back(Interaction{h.client, h.mode, sim_.time(), sim_.time(), 0.0});
      }
      Interaction& i = tally_.interactions[static_cast<size_t>(open)];
      i.end = sim_.time();
      i.max_force = std::max(i.max_force, h.applied.force.norm());
    }
    for (int c = 0; c < kMaxHands; ++c)
      if (!seen[static_cast<size_t>(c)]) tally_.open[static_cast<size_t>(c)] = -1;
    if (acting > 1) ++tally_.steps_with_several_hands;
  }

  Simulation sim_;
  FrameNames frames_;  // the gate's link names, resolved once
  std::vector<std::string> bodies_;
  VectorX zero_qdd_, q_in_, v_in_;
  const VectorX q_start_;  // the scene's initial q (each body's start in summary())
  std::array<Hand, kMaxHands> hands_;
  HandInputs inputs_;
  int64_t seq_ = 0;
  Tally tally_;
  std::atomic<bool> busy_{false};
  const ContactSet empty_{};
};

haptic_input_t baseInput(nb::handle tip, nb::handle velocity) {
  haptic_input_t msg{};
  const Vector3 p = readVector3(tip, "tip"), u = readVector3(velocity, "velocity");
  for (int i = 0; i < 3; ++i) {
    msg.tip_position[i] = p[i];
    msg.tip_velocity[i] = u[i];
  }
  msg.tip_orientation[0] = msg.attach_orientation[0] = 1.0;
  return msg;
}

void setQuaternion(const nb::handle& in, const char* what, double out[4]) {
  if (!in) return;
  VectorX q(4);
  readVector(*in, 4, what, q);
  for (int i = 0; i < 4; ++i) out[i] = q[i];
}

}  // namespace

void bindSimulation(nb::module_& m) {
  nb::class_<Scene>(m, "Scene", "A scene file, loaded and checked (models resolve when a Simulation is built).")
      .def_static("load", &loadScene, nb::arg("path"),
                  "Loads a scene (YAML). Errors name the file, the line and the key (igms.SceneError).")
      .def_static(
          "from_yaml",
          [](const std::string& text, const std::string& base_dir, const std::string& source) {
            return parseScene(text, source, base_dir);
          },
          nb::arg("text"), nb::arg("base_dir") = ".", nb::arg("source") = "<string>",
          "A scene from YAML text; base_dir resolves its relative paths, source names it in errors.")
      .def_prop_ro("name", [](const Scene& s) { return s.name; })
      .def_prop_ro("source", [](const Scene& s) { return s.source; })
      .def_prop_ro("dt", [](const Scene& s) { return s.dt; })
      .def("__repr__", [](const Scene& s) { return "<igms.Scene '" + s.name + "' from " + s.source + ">"; });

  nb::class_<PySimulation>(m, "Simulation", "The server's step on a scene (one thread at a time per Simulation).")
      .def(nb::init<const Scene&>(), nb::arg("scene"))
      .def("step", &PySimulation::step, nb::arg("n") = 1, nb::call_guard<nb::gil_scoped_release>(),
           "n steps of the scene's dt, without the GIL. Raises igms.SimulationDiverged when the state diverges "
           "(it stays at the last good one).")
      .def("reset", [](PySimulation& p) { p.sim().reset(); })
      .def_prop_ro("time", [](const PySimulation& p) { return p.sim().time(); })
      .def_prop_ro("steps", [](const PySimulation& p) { return p.sim().steps(); })
      .def_prop_ro("dt", [](const PySimulation& p) { return p.sim().scene().dt; })
      .def_prop_ro(
          "q", [](const PySimulation& p) { return VectorView(p.sim().q().data(), {static_cast<size_t>(p.sim().q().size())}); },
          nb::rv_policy::reference_internal, "The configuration, a read-only view (set_state writes it).")
      .def_prop_ro(
          "v", [](const PySimulation& p) { return VectorView(p.sim().v().data(), {static_cast<size_t>(p.sim().v().size())}); },
          nb::rv_policy::reference_internal, "The velocity, a read-only view.")
      .def_prop_ro(
          "qdd", [](const PySimulation& p) { return VectorView(p.sim().qdd().data(), {static_cast<size_t>(p.sim().qdd().size())}); },
          nb::rv_policy::reference_internal, "The last step's acceleration, a read-only view.")
      .def_prop_ro(
          "tau", [](const PySimulation& p) { return VectorView(p.sim().tau().data(), {static_cast<size_t>(p.sim().tau().size())}); },
          nb::rv_policy::reference_internal, "The controller's joint torques over the last step, a read-only view.")
      .def("set_state", &PySimulation::setState, nb::arg("q"), nb::arg("v"),
           "Puts the scene in the state (q, v) at the current time; the trajectories are kept.")
      .def_prop_ro("nq", [](const PySimulation& p) { return p.sim().model().nq; })
      .def_prop_ro("nv", [](const PySimulation& p) { return p.sim().model().nv; })
      .def_prop_ro("coordinate_names", [](const PySimulation& p) { return coordinateNames(p.sim().model()); })
      .def_prop_ro("bodies", &PySimulation::bodies, "The free bodies' names, in q order.")
      .def_prop_ro("frames",
                   [](const PySimulation& p) {
                     std::vector<std::string> names;
                     for (const Frame& f : p.sim().model().frames) names.push_back(f.name);
                     return names;
                   })
      .def_prop_ro("diverged", [](const PySimulation& p) { return p.sim().diverged(); })
      .def(
          "_body",
          [](PySimulation& p, const std::string& name) {
            const int f = p.frameOf(name);
            const SE3 X = p.sim().linkPoses()[static_cast<size_t>(f)];
            const Motion u = p.sim().linkVelocities()[static_cast<size_t>(f)];
            const Vector6 velocity = (Vector6() << u.v, u.w).finished();
            return std::make_pair(newPose(X), newVector(velocity.data(), 6));
          },
          nb::arg("name"))
      .def("_contact_columns", &PySimulation::contactColumns)
      .def("_hand_outcomes", &PySimulation::handOutcomes)
      .def(
          "_push",
          [](PySimulation& p, int client, nb::handle tip, nb::handle velocity, double radius,
             const std::string& link) {
            haptic_input_t msg = baseInput(tip, velocity);
            msg.mode = haptic_input_t::MODE_PUSH;
            msg.tip_radius = radius;
            msg.contact_link = link;
            p.setHand(client, msg);
          },
          nb::arg("client"), nb::arg("tip"), nb::arg("velocity"), nb::arg("radius"), nb::arg("link"))
      .def(
          "_pull",
          [](PySimulation& p, int client, nb::handle tip, nb::handle velocity, const std::string& link,
             nb::handle point, nb::handle orientation, nb::handle angular_velocity,
             nb::handle grasp) {
            haptic_input_t msg = baseInput(tip, velocity);
            msg.mode = haptic_input_t::MODE_PULL;
            msg.attach_link = link;
            const Vector3 a = readVector3(point, "point");
            for (int i = 0; i < 3; ++i) msg.attach_point[i] = a[i];
            if (!orientation.is_none()) {
              msg.has_orientation = true;
              setQuaternion(orientation, "orientation", msg.tip_orientation);
              setQuaternion(grasp, "grasp", msg.attach_orientation);
              if (!angular_velocity.is_none()) {
                const Vector3 w = readVector3(angular_velocity, "angular_velocity");
                for (int i = 0; i < 3; ++i) msg.tip_angular_velocity[i] = w[i];
              }
            }
            p.setHand(client, msg);
          },
          nb::arg("client"), nb::arg("tip"), nb::arg("velocity"), nb::arg("link"), nb::arg("point"),
          nb::arg("orientation").none(), nb::arg("angular_velocity").none(), nb::arg("grasp").none())
      .def("_release", &PySimulation::release, nb::arg("client"))
      .def("_active_hands", &PySimulation::activeHands)
      .def("summary", &PySimulation::summary,
           "The run so far, as the session summary has it: time, steps, divergence, the most contacts and the deepest "
           "overlap, the contact solve's figures, the largest force on a robot or body, each hand's interactions "
           "(client, mode, start, end, max_force) and the steps with several hands, each free body's start and end "
           "pose [x y z qw qx qy qz].");
}

}  // namespace igms::python
