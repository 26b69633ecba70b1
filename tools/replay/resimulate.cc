#include "tools/replay/resimulate.h"

#include <cmath>
#include <algorithm>
#include <cstring>

#include "core/simulation/simulation.h"
#include "core/model/robot_description.h"
#include "server/transport/input_gate.h"
#include "tools/replay/recorded_session.h"

namespace igms {
namespace {

void track(FieldDeviation& d, double recorded, double now, int64_t seq, bool& identical) {
  if (std::memcmp(&recorded, &now, sizeof(double)) != 0) identical = false;
  const double e = std::abs(recorded - now);
  if (e > d.max_abs || std::isnan(e)) {
    d.max_abs = std::isnan(e) ? INFINITY : e;
    d.at_seq = seq;
  }
}

}  // namespace

ResimResult resimulate(const std::vector<log::Event>& events, const std::string& base_dir,
                       const std::function<void(const Simulation&)>& each_step) {
  ResimResult out;
  const RecordedSession session = readRecordedSession(events);
  const std::string versions =
      session.undecodable ? " (" + std::to_string(session.undecodable) +
                                " messages did not decode: damaged, or recorded by another igms version whose message "
                                "types differ)"
                          : "";
  if (!session.has_info) {
    out.error = "the log has no session info (record it with igms-logger while igms-server runs)" + versions;
    return out;
  }
  const session_info_t& info = session.info;
  const auto& inputs = session.inputs;
  out.scene_path = info.scene_path;
  out.model_hash_logged = info.model_hash;
  out.build_logged = info.build_version;
  std::unique_ptr<Simulation> sim;
  try {
    sim = std::make_unique<Simulation>(recordedScene(session, base_dir));
    const RobotSpec* robot = sim->scene().robot();
    out.model_from_log = robot && !robot->model_text.empty();
    out.robots = static_cast<int>(sim->scene().robots.size());
    for (const RobotSpec& r : sim->scene().robots) out.models_from_log += !r.model_text.empty();
    try {
      out.model_hash_now = robot ? textHash(readModelFile(robot->model_path)) : "none";
    } catch (const std::exception&) {
      if (!out.model_from_log) throw;
      out.model_hash_now = "absent";  // the log's copy stands in
    }
    out.mesh_differences = meshDifferences(session, sim->model());
  } catch (const std::exception& e) {
    out.error = std::string("cannot rebuild the scene: ") + e.what();
    return out;
  }
  const Model& model = sim->model();
  const FrameNames frames(model);
  FieldDeviation dq{"q"}, dv{"v"}, dqdd{"qdd"}, dtau{"tau"}, dforce{"interaction_force"}, dpose{"link_poses"};
  bool identical = true;
  // States in step order; the first state is the initial one (seq 0).
  InteractionInput input;
  HandInputs hands;
  int64_t previous_utime = 0;
  for (const auto& st : session.states) {
    // The server's stall test (server/loop/stepper.cc): from the last state to this step's start.
    const bool stalled = previous_utime > 0 && st.utime - st.step_us - previous_utime > Simulation::kStallGapUs;
    previous_utime = st.utime;
    if (st.seq == 0) continue;  // the initial state, before any step
    if (st.seq != sim->steps() + 1) {
      out.error = "state seq " + std::to_string(st.seq) + " follows " + std::to_string(sim->steps()) +
                  ": states are missing from the log (dropped by the logger?) or the session was reset";
      break;
    }
    // Every input the step consumed (one per hand), as the server's gate converted it.
    hands.clear();
    const int nhands = std::min<int>(st.nhands, kMaxHands);
    bool missing = false;
    for (int h = 0; h < nhands; ++h) {
      const auto it = inputs.find({st.hand_client[static_cast<size_t>(h)], st.hand_input_seq[static_cast<size_t>(h)]});
      RejectReason why;
      if (it == inputs.end() || !toInteractionInput(it->second, frames, &input, &why)) {
        out.error = "state " + std::to_string(st.seq) + " consumed input " +
                    std::to_string(st.hand_input_seq[static_cast<size_t>(h)]) + " of client " +
                    std::to_string(st.hand_client[static_cast<size_t>(h)]) + ", which the log does not hold";
        missing = true;
        break;
      }
      hands.add(input);
    }
    if (missing) break;
    if (stalled) sim->noteStall();
    sim->step(hands);
    if (each_step) each_step(*sim);
    if (st.nq != model.nq || st.nv != model.nv) {
      out.error = "the recorded states do not match the scene's model";
      break;
    }
    for (int j = 0; j < model.nq; ++j) track(dq, st.q[j], sim->q()[j], st.seq, identical);
    for (int j = 0; j < model.nv; ++j) {
      track(dv, st.v[j], sim->v()[j], st.seq, identical);
      track(dqdd, st.qdd[j], sim->qdd()[j], st.seq, identical);
      track(dtau, st.tau[j], sim->tau()[j], st.seq, identical);
    }
    for (int k = 0; k < 3; ++k) {
      track(dforce, st.interaction_force[k], sim->outcome().force_on_robot[k], st.seq, identical);
      track(dforce, st.interaction_torque[k], sim->outcome().torque_on_robot[k], st.seq, identical);
    }
    for (int h = 0; h < nhands && h < sim->outcome().nhands; ++h)
      for (int k = 0; k < 3; ++k)
        track(dforce, st.hand_force[static_cast<size_t>(h)][static_cast<size_t>(k)],
              sim->outcome().hands[static_cast<size_t>(h)].applied.force[k], st.seq, identical);
    const auto& poses = sim->linkPoses();
    for (int l = 0; l < st.nlinks && l < static_cast<int>(poses.size()); ++l)
      for (int k = 0; k < 3; ++k) track(dpose, st.link_poses[l][k], poses[static_cast<size_t>(l)].p[k], st.seq, identical);
    ++out.steps;
  }
  out.deviations = {dq, dv, dqdd, dtau, dforce, dpose};
  for (const auto& d : out.deviations) out.max_deviation = std::max(out.max_deviation, d.max_abs);
  out.identical = identical && out.steps > 0;
  out.final_q.assign(sim->q().data(), sim->q().data() + sim->q().size());
  out.ok = out.steps > 0;
  if (!out.ok && out.error.empty()) out.error = "the log holds no robot states to compare" + versions;
  return out;
}

}  // namespace igms
