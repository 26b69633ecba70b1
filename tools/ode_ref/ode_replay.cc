#include "tools/ode_ref/ode_replay.h"

#include <chrono>
#include <cmath>

#include "channels.h"
#include "core/dynamics/crba.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/model_io/model_loader.h"
#include "core/scene/resolved_scene.h"
#include "tools/replay/recorded_session.h"

namespace igms {
namespace {

// ODE's state as a state message (interaction fields from the recorded step).
robot_state_t stateMessage(const Model& m, Data& d, int64_t seq, double t, const VectorX& q, const VectorX& v,
                           const VectorX& qdd, const VectorX& tau) {
  robot_state_t s{};
  s.utime = static_cast<int64_t>(std::llround(t * 1e6));
  s.seq = seq;
  s.sim_time = t;
  s.input_seq = -1;
  s.input_client = -1;
  s.nq = m.nq;
  s.nv = m.nv;
  s.q.assign(q.data(), q.data() + m.nq);
  s.v.assign(v.data(), v.data() + m.nv);
  s.qdd.assign(qdd.data(), qdd.data() + m.nv);
  s.tau.assign(tau.data(), tau.data() + m.nv);
  forwardKinematics(m, d, q);
  s.nlinks = static_cast<int32_t>(m.frames.size());
  s.link_poses.resize(m.frames.size());
  for (size_t f = 0; f < m.frames.size(); ++f) {
    const SE3& X = d.oMf[f];
    const Eigen::Quaterniond r(X.R);
    s.link_poses[f] = {X.p.x(), X.p.y(), X.p.z(), r.w(), r.x(), r.y(), r.z()};
  }
  s.min_obstacle_distance = 1e9;  // not computed for the reference run
  s.in_collision = false;
  s.closest_link = -1;
  return s;
}

}  // namespace

std::vector<robot_state_t> runTorquesOnOde(const Model& model, const VectorX& q0, const VectorX& v0,
                                           const std::vector<VectorX>& torques, double h,
                                           const OdeSettings& settings) {
  Data d(model);
  OdeRobot ode(model, q0, v0, settings);
  VectorX q = q0, v = v0, v_prev = v0, qdd = VectorX::Zero(model.nv);
  std::vector<robot_state_t> out;
  out.push_back(stateMessage(model, d, 0, 0.0, q, v, qdd, VectorX::Zero(model.nv)));
  for (size_t k = 0; k < torques.size(); ++k) {
    ode.step(torques[k], h);
    ode.state(q, v);
    qdd = (v - v_prev) / h;
    v_prev = v;
    out.push_back(stateMessage(model, d, static_cast<int64_t>(k + 1), (k + 1) * h, q, v, qdd, torques[k]));
  }
  return out;
}

OdeReplayResult replayOnOde(const std::vector<log::Event>& events, const OdeSettings& base_settings,
                            const std::string& base_dir, bool tracking) {
  OdeReplayResult out;
  const RecordedSession session = readRecordedSession(events);
  if (!session.has_info) {
    out.error = "the log has no session info (record it with igms-logger while igms-server runs)";
    return out;
  }
  out.info = session.info;
  ResolvedScene resolved;
  try {
    resolved = resolveScene(recordedScene(session, base_dir));
  } catch (const std::exception& e) {
    out.error = std::string("cannot rebuild the scene: ") + e.what();
    return out;
  }
  const Scene& scene = resolved.scene;
  const Model& m = *resolved.model;
  const auto& states = session.states;
  if (states.empty() || states.front().seq != 0) {
    out.error = "the log does not start with the initial state (seq 0): the logger started late";
    return out;
  }
  if (states.front().nq != m.nq || states.front().nv != m.nv) {
    out.error = "the recorded states do not match the scene's model";
    return out;
  }
  if (tracking && m.floating_base) {
    out.error = "tracking needs a fixed base (a floating base is not actuated, so there is no PD to add)";
    return out;
  }
  OdeSettings settings = base_settings;
  settings.joint_damping = scene.joint_damping;
  const double h = scene.dt;
  out.dt = h;
  if (scene.robots.size() != 1 || m.parts.size() != 1 || scene.hasContact()) {
    out.error = "the ODE replay takes one robot in empty space (no free bodies, ground or contact)";
    return out;
  }
  const RobotSpec& robot = scene.robots.front();
  const bool has_trajectory = robot.trajectory.kind != TrajectorySpec::Kind::None;
  const int pull_frame = resolved.pull_frame;
  const VectorX& kp = resolved.kp;
  const VectorX& kd = resolved.kd;
  double correction_sq = 0.0, tau_sq = 0.0;
  Data d(m);
  VectorX q = Eigen::Map<const VectorX>(states[0].q.data(), m.nq);
  VectorX v = Eigen::Map<const VectorX>(states[0].v.data(), m.nv);
  OdeRobot ode(m, q, v, settings);
  VectorX tau(m.nv), v_prev = v;
  out.states.push_back(stateMessage(m, d, 0, 0.0, q, v, VectorX::Zero(m.nv), VectorX::Zero(m.nv)));
  double sum = 0.0;
  int64_t n = 0;
  double wall = 0.0;
  for (size_t k = 1; k < states.size(); ++k) {
    const robot_state_t& st = states[k];
    if (st.seq != static_cast<int64_t>(k)) {
      out.error = "state seq " + std::to_string(st.seq) + " follows " + std::to_string(k - 1) +
                  ": states are missing from the log";
      return out;
    }
    tau = Eigen::Map<const VectorX>(st.tau.data(), m.nv);
    tau_sq += tau.squaredNorm();
    const bool hold = st.mode != 0 && has_trajectory;
    if (hold || tracking) crba(m, d, q);  // H at ODE's state, once per step
    if (hold) tau -= robot.hold_damping * d.H.symmetricUpperTimes(v);  // the hold: -c H v
    if (tracking) {
      const auto& rec_q = states[k - 1].q;  // the recorded state this step starts from
      const auto& rec_v = states[k - 1].v;
      const VectorX a = kp.cwiseProduct(Eigen::Map<const VectorX>(rec_q.data(), m.nq) - q) +
                        kd.cwiseProduct(Eigen::Map<const VectorX>(rec_v.data(), m.nv) - v);
      const VectorX correction = d.H.symmetricUpperTimes(a);
      correction_sq += correction.squaredNorm();
      tau += correction;
    }
    // Each hand's recorded force (and 6-D pull torque) on the link its input names.
    for (size_t h = 0; h < static_cast<size_t>(st.nhands); ++h) {
      const Vector3 force(st.hand_force[h][0], st.hand_force[h][1], st.hand_force[h][2]);
      const Vector3 torque(st.hand_torque[h][0], st.hand_torque[h][1], st.hand_torque[h][2]);
      const int8_t mode = st.hand_mode[h];
      if (mode == 0 || (force.norm() == 0.0 && torque.norm() == 0.0)) continue;
      int frame = -1;
      const auto in = session.inputs.find({st.hand_client[h], st.hand_input_seq[h]});
      if (in != session.inputs.end())
        frame = m.frameIndex(mode == 1 ? in->second.contact_link : in->second.attach_link);
      if (frame < 0 && mode == 2) frame = pull_frame;
      if (frame < 0) {
        out.error = "state " + std::to_string(st.seq) + ": a force with no link to apply it to (input " +
                    std::to_string(st.hand_input_seq[h]) + " of client " + std::to_string(st.hand_client[h]) +
                    " is not in the log)";
        return out;
      }
      const int body = m.frame(frame).body;
      if (body < 0) continue;
      ode.addForceAtPoint(body, Vector3(st.hand_point[h][0], st.hand_point[h][1], st.hand_point[h][2]), force);
      ode.addTorque(body, torque);
    }
    const auto t0 = std::chrono::steady_clock::now();
    ode.step(tau, h);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ode.state(q, v);
    robot_state_t s = stateMessage(m, d, st.seq, st.sim_time, q, v, (v - v_prev) / h, tau);
    v_prev = v;
    s.input_seq = st.input_seq;
    s.input_client = st.input_client;
    s.mode = st.mode;
    for (int i = 0; i < 3; ++i) {
      s.interaction_force[i] = st.interaction_force[i];
      s.interaction_point[i] = st.interaction_point[i];
      s.interaction_torque[i] = st.interaction_torque[i];
    }
    s.nhands = st.nhands;
    s.hand_client = st.hand_client;
    s.hand_input_seq = st.hand_input_seq;
    s.hand_mode = st.hand_mode;
    s.hand_force = st.hand_force;
    s.hand_torque = st.hand_torque;
    s.hand_point = st.hand_point;
    // Deviation from the recorded igms run.
    for (int i = 0; i < m.nb; ++i) {
      if (m.joint_type[i] == JointType::Floating) continue;  // compared through the link poses
      const double e = std::abs(q[m.q_index[i]] - st.q[static_cast<size_t>(m.q_index[i])]);
      out.q_max = std::max(out.q_max, e);
      sum += e * e;
      ++n;
    }
    double link = 0.0;
    for (int f = 0; f < st.nlinks && f < s.nlinks; ++f)
      link = std::max(link, std::hypot(s.link_poses[f][0] - st.link_poses[f][0], s.link_poses[f][1] - st.link_poses[f][1],
                                       s.link_poses[f][2] - st.link_poses[f][2]));
    out.link_max = std::max(out.link_max, link);
    const size_t second = static_cast<size_t>(std::max(0.0, st.sim_time - 1e-9));
    if (out.link_max_by_second.size() <= second) out.link_max_by_second.resize(second + 1, 0.0);
    out.link_max_by_second[second] = std::max(out.link_max_by_second[second], link);
    out.states.push_back(std::move(s));
    if (!q.allFinite() || !v.allFinite()) {
      out.error = "ODE diverged at t = " + std::to_string(st.sim_time) + " s";
      return out;
    }
  }
  out.steps = static_cast<int64_t>(out.states.size()) - 1;
  out.q_rms = std::sqrt(sum / std::max<int64_t>(1, n));
  out.correction_rms = std::sqrt(correction_sq / std::max<int64_t>(1, out.steps));
  out.tau_rms = std::sqrt(tau_sq / std::max<int64_t>(1, out.steps));
  out.wall_seconds = wall;
  out.ok = out.steps > 0;
  if (!out.ok) out.error = "the log holds no steps to replay";
  return out;
}

void writeStateLog(const std::string& path, const session_info_t* info, const std::vector<robot_state_t>& states) {
  log::LogWriter w(path);
  std::vector<uint8_t> buf;
  if (info) {
    buf.resize(static_cast<size_t>(info->getEncodedSize()));
    info->encode(buf.data(), 0, static_cast<int>(buf.size()));
    w.write(info->utime, channels::kSessionInfo, buf.data(), buf.size());
  }
  for (const auto& s : states) {
    buf.resize(static_cast<size_t>(s.getEncodedSize()));
    s.encode(buf.data(), 0, static_cast<int>(buf.size()));
    w.write(s.utime, channels::kRobotState, buf.data(), buf.size());
  }
  w.flush();
}

}  // namespace igms
