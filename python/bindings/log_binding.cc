// igms.Log, igms.resimulate and igms.run_scenario: a recorded session read
// back (tools/replay/recorded_session.h), re-simulated bit for bit
// (tools/replay/resimulate.h), and a scene with a device script run in
// process as igms-scenario runs it (tools/scenario/scenario_run.h): what a
// sweep's run is. Both long calls run without the GIL.
#include <nanobind/stl/map.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <map>
#include <optional>

#include "python/bindings/array_args.h"
#include "python/bindings/bindings.h"
#include "python/bindings/solve_figures.h"
#include "tools/replay/recorded_session.h"
#include "tools/replay/resimulate.h"
#include "tools/scenario/scenario_run.h"

namespace igms::python {

namespace {

class PyLog {
 public:
  // A file that cannot be opened, or holds no event before its damage, raises LogError; a damaged one
  // keeps the events before the damage (damaged, error say where).
  explicit PyLog(const std::string& path) : path_(path) {
    log::LogContents contents = log::readAll(path);
    if (contents.damaged && contents.events.empty()) throw log::LogError(contents.error, contents.error_offset);
    events_ = std::move(contents.events);
    damaged_ = contents.damaged;
    error_ = contents.error;
    session_ = readRecordedSession(events_);
    for (const log::Event& e : events_) ++counts_[e.channel];
  }
  const std::string& path() const { return path_; }
  const std::vector<log::Event>& events() const { return events_; }
  const RecordedSession& session() const { return session_; }
  bool damaged() const { return damaged_; }
  const std::string& error() const { return error_; }
  const std::map<std::string, int64_t>& counts() const { return counts_; }

  // The haptic inputs as columns, by (client, seq).
  nb::dict inputs() const {
    const size_t n = session_.inputs.size();
    VectorX client(n), seq(n), mode(n), utime(n), radius(n);
    MatrixX tip(n, 3), velocity(n, 3);
    size_t k = 0;
    for (const auto& [key, m] : session_.inputs) {
      client[k] = m.client_id;
      seq[k] = static_cast<double>(m.seq);
      mode[k] = m.mode;
      utime[k] = static_cast<double>(m.utime);
      radius[k] = m.tip_radius;
      for (int i = 0; i < 3; ++i) {
        tip(k, i) = m.tip_position[i];
        velocity(k, i) = m.tip_velocity[i];
      }
      ++k;
    }
    nb::dict d;
    d["client"] = newVector(client.data(), n);
    d["seq"] = newVector(seq.data(), n);
    d["mode"] = newVector(mode.data(), n);
    d["utime"] = newVector(utime.data(), n);
    d["tip_position"] = newMatrix(tip);
    d["tip_velocity"] = newMatrix(velocity);
    d["tip_radius"] = newVector(radius.data(), n);
    return d;
  }

  // The robot states in step order as columns: seq, t, mode (N,); q (N, nq); v, qdd, tau (N, nv); force (N, 3).
  nb::dict states() const {
    const auto& st = session_.states;
    const size_t n = st.size();
    const size_t nq = n ? static_cast<size_t>(st[0].nq) : 0, nv = n ? static_cast<size_t>(st[0].nv) : 0;
    MatrixX q(n, nq), v(n, nv), qdd(n, nv), tau(n, nv), force(n, 3);
    VectorX seq(n), t(n), mode(n);
    for (size_t k = 0; k < n; ++k) {
      const robot_state_t& s = st[k];
      if (static_cast<size_t>(s.nq) != nq || static_cast<size_t>(s.nv) != nv)
        throw std::runtime_error(path_ + ": the states change size at seq " + std::to_string(s.seq));
      seq[k] = static_cast<double>(s.seq);
      t[k] = s.sim_time;
      mode[k] = s.mode;
      for (size_t i = 0; i < nq; ++i) q(k, i) = s.q[i];
      for (size_t i = 0; i < nv; ++i) {
        v(k, i) = s.v[i];
        qdd(k, i) = s.qdd[i];
        tau(k, i) = s.tau[i];
      }
      for (size_t i = 0; i < 3; ++i) force(k, i) = s.interaction_force[i];
    }
    nb::dict d;
    d["seq"] = newVector(seq.data(), n);
    d["t"] = newVector(t.data(), n);
    d["mode"] = newVector(mode.data(), n);
    d["q"] = newMatrix(q);
    d["v"] = newMatrix(v);
    d["qdd"] = newMatrix(qdd);
    d["tau"] = newMatrix(tau);
    d["interaction_force"] = newMatrix(force);
    return d;
  }

 private:
  std::string path_;
  std::vector<log::Event> events_;
  bool damaged_ = false;
  std::string error_;
  RecordedSession session_;
  std::map<std::string, int64_t> counts_;
};

nb::dict resimulated(const ResimResult& r) {
  nb::dict d;
  d["ok"] = r.ok;
  d["error"] = r.error;
  d["steps"] = r.steps;
  d["identical"] = r.identical;
  d["max_deviation"] = r.max_deviation;
  d["scene_path"] = r.scene_path;
  d["model_from_log"] = r.model_from_log;
  nb::list deviations;
  for (const FieldDeviation& f : r.deviations) {
    nb::dict x;
    x["field"] = f.field;
    x["max_abs"] = f.max_abs;
    x["at_seq"] = f.at_seq;
    deviations.append(x);
  }
  d["deviations"] = deviations;
  d["final_q"] = newVector(r.final_q.data(), r.final_q.size());
  return d;
}

// igms-scenario's JSON fields, and every step's columns.
nb::dict scenarioResult(const ScenarioResult& r) {
  nb::dict d;
  d["diverged"] = r.diverged;
  d["max_contacts"] = r.max_contacts;
  d["max_penetration"] = r.max_penetration;
  d["collision_steps"] = r.collision_steps;
  d["collision_steps_all"] = r.collision_steps_all;
  d["first_collision"] = r.first_collision;
  d["first_collision_what"] = r.first_collision_what;
  d["min_distance_all"] = r.min_distance;
  d["min_distance_excluding_wall"] = r.min_distance_excluding_goal;
  d["reached_wall_time"] = r.reached_wall_time;
  d["final_ee"] = newVector(r.final_ee.data(), 3);
  d["max_user_force"] = r.max_user_force;
  d["max_robot_force"] = r.max_robot_force;
  d["max_force_step"] = r.max_force_step;
  d["max_proxy_penetration"] = r.max_proxy_penetration;
  d["max_device_behind_proxy"] = r.max_device_behind_proxy;
  d["contact_solve"] = solveFigures(r.solve);
  nb::list interactions;
  for (size_t i = 0; i < r.interactions.size(); ++i) {
    nb::dict x;
    x["mode"] = r.interaction_modes[i] == 1 ? "push" : "pull";
    x["start"] = r.interactions[i].first;
    x["end"] = r.interactions[i].second;
    interactions.append(x);
  }
  d["interactions"] = interactions;
  const size_t n = r.samples.size(), nq = r.q_columns.size();
  MatrixX q(n, nq), force(n, 3), ee(n, 3);
  VectorX t(n), contacts(n), penetration(n), mode(n);
  for (size_t k = 0; k < n; ++k) {
    const ScenarioSample& s = r.samples[k];
    t[k] = s.t;
    mode[k] = s.mode;
    contacts[k] = s.contacts;
    penetration[k] = s.max_penetration;
    for (size_t i = 0; i < nq; ++i) q(k, i) = s.q[i];
    force.row(k) = s.force_on_robot.transpose();
    ee.row(k) = s.ee.transpose();
  }
  nb::dict bodies;
  for (const std::string& name : r.bodies) {
    std::vector<double> pose;
    for (size_t c = 0; c < nq && n > 0; ++c)
      if (r.q_columns[c].rfind(name + ".", 0) == 0) pose.push_back(r.samples.back().q[c]);
    bodies[name.c_str()] = newVector(pose.data(), pose.size());
  }
  d["bodies"] = bodies;
  d["q_columns"] = r.q_columns;
  nb::dict steps;
  steps["t"] = newVector(t.data(), n);
  steps["mode"] = newVector(mode.data(), n);
  steps["q"] = newMatrix(q);
  steps["force_on_robot"] = newMatrix(force);
  steps["ee"] = newMatrix(ee);
  steps["contacts"] = newVector(contacts.data(), n);
  steps["max_penetration"] = newVector(penetration.data(), n);
  d["samples"] = steps;
  return d;
}

}  // namespace

void bindLog(nb::module_& m) {
  nb::class_<PyLog>(m, "Log", "A session log (.lcmlog or .lcmlog.gz) read back: the session, its states, its inputs.")
      .def(nb::init<const std::string&>(), nb::arg("path"))
      .def_prop_ro("path", &PyLog::path)
      .def_prop_ro("damaged", &PyLog::damaged, "The file is damaged; the events before the damage were read.")
      .def_prop_ro("error", &PyLog::error)
      .def_prop_ro("counts", &PyLog::counts, "Events per channel.")
      .def_prop_ro("events", [](const PyLog& l) { return l.events().size(); })
      .def_prop_ro("undecodable", [](const PyLog& l) { return l.session().undecodable; })
      .def_prop_ro("has_session", [](const PyLog& l) { return l.session().has_info; })
      .def_prop_ro("scene_path", [](const PyLog& l) { return l.session().info.scene_path; })
      .def_prop_ro("scene_text", [](const PyLog& l) { return l.session().info.scene_text; })
      .def_prop_ro("build_version", [](const PyLog& l) { return l.session().info.build_version; })
      .def_prop_ro("clock", [](const PyLog& l) { return l.session().info.clock; })
      .def_prop_ro("dt", [](const PyLog& l) { return l.session().info.dt; })
      .def_prop_ro("inputs", &PyLog::inputs,
                   "The haptic inputs, by client and seq: client, seq, mode, utime (N,); tip_position, "
                   "tip_velocity (N, 3); tip_radius (N,).")
      .def_prop_ro("states", &PyLog::states,
                   "The robot states in step order: seq, t, mode (N,); q (N, nq); v, qdd, tau (N, nv); "
                   "interaction_force (N, 3).");

  m.def(
      "resimulate",
      [](const PyLog& log, const std::string& base_dir) {
        ResimResult r;
        {
          nb::gil_scoped_release unlocked;
          r = resimulate(log.events(), base_dir);
        }
        return resimulated(r);
      },
      nb::arg("log"), nb::arg("base_dir") = ".",
      "Re-simulates a log's session from its recorded inputs and compares every state: identical, max_deviation, "
      "deviations per field. base_dir resolves a relative scene path (where the server ran).");

  m.def(
      "run_scenario",
      [](const Scene& scene, std::optional<std::string> script, double seconds, bool device_limits) {
        if (!(seconds > 0.0) || seconds > 1e6) throw nb::value_error("seconds must be > 0");
        ScenarioResult r;
        {
          nb::gil_scoped_release unlocked;
          r = runScenario(scene, script ? *script : std::string(), seconds, "", 0.01, device_limits);
        }
        return scenarioResult(r);
      },
      nb::arg("scene"), nb::arg("script").none() = nb::none(), nb::arg("seconds") = 1.0,
      nb::arg("device_limits") = false,
      "A scene and a scripted device file run in process, as igms-scenario --device scripted:FILE runs them: "
      "its summary and every step's columns (samples).");
}

}  // namespace igms::python
