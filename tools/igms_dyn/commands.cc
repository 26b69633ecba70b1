#include "tools/igms_dyn/commands.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "core/dynamics/aba.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/external_force.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/geometry/shape_kind.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "tools/igms_dyn/json_io.h"
#include "tools/igms_dyn/median_time.h"

namespace igms::dyn {

int info(const Model& model, std::ostream& out) {
  JsonWriter w;
  w.beginObject().key("nq").integer(model.nq).key("nv").integer(model.nv).key("joints").beginArray();
  for (int i = 0; i < model.nb; ++i) {
    w.beginObject()
        .key("name").string(model.joint_name[i])
        .key("type").string(model.joint_continuous[i] ? "continuous" : jointTypeName(model.joint_type[i]))
        .key("q_index").integer(model.q_index[i])
        .key("v_index").integer(model.v_index[i]);
    if (!model.joint_mimic[static_cast<size_t>(i)].empty())
      w.key("mimic").string(model.joint_mimic[static_cast<size_t>(i)]).key("coupled").raw("false");
    w.endObject();
  }
  w.endArray().key("links").beginArray();
  for (const auto& f : model.frames) w.string(f.name);
  // Each link's geometry: what the tip can touch (collision; meshes with their distance field) and what a
  // viewer draws (visual).
  auto kinds = [&](const std::vector<CollisionShape>& shapes) {
    w.beginArray();
    for (const CollisionShape& c : shapes) {
      if (c.kind == CollisionShape::Kind::Mesh) w.string("mesh " + c.mesh_file);
      else w.string(shapeKindName(c.kind));
    }
    w.endArray();
  };
  w.endArray().key("geometry").beginArray();
  for (const auto& f : model.frames) {
    std::vector<CollisionShape> visual;
    for (const VisualShape& v : f.visuals) visual.push_back(v.geometry);
    bool touchable = false;
    for (const CollisionShape& c : f.collisions) touchable |= c.kind != CollisionShape::Kind::Mesh || c.field != nullptr;
    w.beginObject().key("link").string(f.name).key("collision");
    kinds(f.collisions);
    w.key("visual");
    kinds(visual);
    w.key("touchable").raw(touchable && f.body >= 0 ? "true" : "false").endObject();
  }
  w.endArray();
  // The environment's trees: each robot and each free body, and where its coordinates are.
  w.key("parts").beginArray();
  for (const ModelPart& p : model.parts) {
    w.beginObject()
        .key("name").string(p.name)
        .key("kind").string(p.free_body ? "free_body" : "robot")
        .key("mass").number([&] {
          double m = 0.0;
          for (int b = p.body_begin; b < p.body_end; ++b) m += model.inertia[static_cast<size_t>(b)].m;
          return m;
        }())
        .key("q_index").integer(p.q_begin).key("nq").integer(p.nq())
        .key("v_index").integer(p.dof_begin).key("nv").integer(p.nv())
        .endObject();
  }
  w.endArray().endObject();
  out << w.str() << '\n';
  return 0;
}

namespace {

// One input line -> one output object. Throws InputError on bad input.
std::string evalLine(const Model& model, Data& data, const std::string& text, std::vector<Force>& fext) {
  nlohmann::json line;
  try {
    line = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not valid JSON: ") + e.what());
  }
  if (!line.is_object()) throw InputError("expected a JSON object");
  VectorX q = readVector(line, "q", model.nq);
  const VectorX v = readVector(line, "v", model.nv);
  for (int i = 0; i < model.nb; ++i) {
    if (model.joint_type[i] != JointType::Floating) continue;
    const double n = q.segment<4>(model.q_index[i] + 3).norm();
    if (n < 1e-9) throw InputError("\"q\": the base quaternion is zero");
  }
  normalizeConfiguration(model, q);

  forwardKinematics(model, data, q);
  clearExternalForces(fext);
  bool has_fext = false;
  if (auto it = line.find("fext"); it != line.end()) {
    if (!it->is_array()) throw InputError("\"fext\" must be an array");
    for (size_t k = 0; k < it->size(); ++k) {
      const auto& e = (*it)[k];
      const std::string where = "\"fext\"[" + std::to_string(k) + "]";
      if (!e.is_object()) throw InputError(where + " must be an object");
      auto ln = e.find("link");
      if (ln == e.end() || !ln->is_string()) throw InputError(where + ": \"link\" must be a link name");
      const int frame = model.frameIndex(ln->get<std::string>());
      if (frame < 0) throw InputError(where + ": unknown link '" + ln->get<std::string>() + "'");
      addPointForce(model, data, PointForce{frame, readVector3(e, "point", where), readVector3(e, "force", where)},
                    fext);
      has_fext = true;
    }
  }
  const std::vector<Force>* f = has_fext ? &fext : nullptr;

  JsonWriter w;
  w.beginObject();
  if (line.contains("a")) {
    const VectorX a = readVector(line, "a", model.nv);
    w.key("tau").vector(rnea(model, data, q, v, a, f));
  }
  w.key("M").matrix(crba(model, data, q).dense());
  w.key("bias").vector(bias(model, data, q, v));
  if (line.contains("tau")) {
    const VectorX tau = readVector(line, "tau", model.nv);
    if (!forwardDynamics(model, data, q, v, tau, f))
      throw InputError("H is singular: joint '" + dofName(model, data.singular_dof) +
                       "' moves no mass or inertia along its axis");
    w.key("qdd").vector(data.qdd);
  }
  w.key("poses").beginObject();
  for (size_t k = 0; k < model.frames.size(); ++k) {
    const SE3& X = data.oMf[k];
    Eigen::Quaterniond quat(X.R);
    if (quat.w() < 0.0) quat.coeffs() *= -1.0;  // q and -q are one rotation: print w >= 0
    const double pose[7] = {X.p.x(), X.p.y(), X.p.z(), quat.w(), quat.x(), quat.y(), quat.z()};
    w.key(model.frames[k].name).vector(pose, 7);
  }
  w.endObject();
  w.endObject();
  return w.str();
}

}  // namespace

int eval(const Model& model, std::istream& in, std::ostream& out, std::ostream& err) {
  Data data(model);
  std::vector<Force> fext(static_cast<size_t>(model.nb));
  std::string text;
  int failed = 0;
  long line_no = 0;
  while (std::getline(in, text)) {
    ++line_no;
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      out << evalLine(model, data, text, fext) << '\n';
    } catch (const InputError& e) {
      ++failed;
      const std::string msg = "line " + std::to_string(line_no) + ": " + e.what();
      out << "{\"error\":" << quote(msg) << "}\n";
    }
  }
  out.flush();
  if (failed) err << "igms-dyn eval: " << failed << " line(s) failed\n";
  return failed ? 1 : 0;
}

int bench(const Model& model, bool json, std::ostream& out) {
  Data data(model);
  std::mt19937 rng(42);
  const int states = 64;
  const RandomStates random = randomStates(model, states, rng);
  const auto &q = random.q, &v = random.v, &a = random.a, &tau = random.tau;
  // The Jacobian of the frame of the last body (a leaf of the tree).
  const int frame = std::max(0, model.frameIndex(model.body_name.empty() ? model.root_link : model.body_name.back()));
  volatile double sink = 0.0;  // keeps the calls from being optimised away
  const struct { const char* name; std::function<void(int)> call; } cases[] = {
      {"rnea_us", [&](int k) { sink = sink + rnea(model, data, q[k], v[k], a[k])[0]; }},
      {"crba_us", [&](int k) { sink = sink + crba(model, data, q[k])(0, 0); }},
      {"bias_us", [&](int k) { sink = sink + bias(model, data, q[k], v[k])[0]; }},
      {"fd_us", [&](int k) { forwardDynamics(model, data, q[k], v[k], tau[k]); sink = sink + data.qdd[0]; }},
      {"aba_us", [&](int k) { aba(model, data, q[k], v[k], tau[k]); sink = sink + data.qdd[0]; }},
      {"fk_us", [&](int k) { forwardKinematics(model, data, q[k]); sink = sink + data.oMf.back().p[0]; }},
      {"jacobian_us", [&](int k) { frameJacobian(model, data, q[k], frame, data.J); sink = sink + data.J(0, 0); }},
  };
  JsonWriter w;
  w.beginObject();
  w.key("jacobian_frame").string(model.frames[static_cast<size_t>(frame)].name);
  if (!json) {
    out << "igms-dyn bench: " << (model.name.empty() ? model.source : model.name) << " (nq " << model.nq << ", nv "
        << model.nv << ", bodies " << model.nb << "), median microseconds per call\n";
  }
  auto report = [&](const char* name, double us) {
    w.key(name).number(us);
    if (!json) {
      char line[96];
      std::snprintf(line, sizeof line, "  %-12s %10.3f\n", name, us);
      out << line;
    }
  };
  double fd_us = 0.0, aba_us = 0.0;
  for (const auto& c : cases) {
    if (model.nv == 0) break;
    const double us = medianMicroseconds(c.call, states);
    if (std::string(c.name) == "fd_us") fd_us = us;
    if (std::string(c.name) == "aba_us") aba_us = us;
    report(c.name, us);
  }
  if (model.nv > 0) {
    // One 1 ms semi-implicit Euler step through the faster forward dynamics of the two, as a peer's bare step.
    const bool use_aba = aba_us < fd_us;
    VectorX v_next(model.nv), q_next(model.nq);
    report("step_us", medianMicroseconds(
                          [&](int k) {
                            if (use_aba) aba(model, data, q[k], v[k], tau[k]);
                            else forwardDynamics(model, data, q[k], v[k], tau[k]);
                            v_next = v[k] + 0.001 * data.qdd;
                            integrateConfiguration(model, q[k], v_next, 0.001, q_next);
                            sink = sink + q_next[0];
                          },
                          states));
  }
  w.endObject();
  if (json) out << w.str() << '\n';
  return 0;
}

}  // namespace igms::dyn
