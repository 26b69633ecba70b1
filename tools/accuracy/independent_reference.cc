#include "tools/accuracy/independent_reference.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/kinematics/forward_kinematics.h"

namespace igms::accuracy {
namespace {

const char* typeName(JointType t) {
  switch (t) {
    case JointType::Revolute: return "revolute";
    case JointType::Prismatic: return "prismatic";
    case JointType::Floating: return "floating";
  }
  return "?";
}

std::vector<double> toVector(const VectorX& x) { return {x.data(), x.data() + x.size()}; }

VectorX fromJson(const nlohmann::json& j, long size, const std::string& what) {
  if (!j.is_array() || static_cast<long>(j.size()) != size)
    throw std::runtime_error(what + ": expected " + std::to_string(size) + " numbers");
  VectorX x(size);
  for (long k = 0; k < size; ++k) x[k] = j[static_cast<size_t>(k)].get<double>();
  if (!x.allFinite()) throw std::runtime_error(what + ": not finite");
  return x;
}

}  // namespace

void writeCaseFiles(const Case& c, const std::string& dir) {
  const Model& m = *c.model;
  const std::string urdf_path = dir + "/" + c.name + ".urdf";
  std::ofstream urdf(urdf_path);
  urdf << c.urdf;
  if (!urdf) throw std::runtime_error(urdf_path + ": cannot write");
  nlohmann::json j;
  j["name"] = c.name;
  j["urdf"] = c.name + ".urdf";
  j["floating_base"] = m.floating_base;
  j["gravity"] = {m.gravity.x(), m.gravity.y(), m.gravity.z()};
  j["duration"] = c.duration;
  j["sample"] = kSamplePeriod;
  j["ee_frame"] = c.ee_frame;
  j["nq"] = m.nq;
  j["nv"] = m.nv;
  nlohmann::json joints = nlohmann::json::array();
  for (int i = 0; i < m.nb; ++i)
    joints.push_back({{"name", m.joint_name[static_cast<size_t>(i)]},
                      {"child_link", m.body_name[static_cast<size_t>(i)]},
                      {"type", typeName(m.joint_type[static_cast<size_t>(i)])},
                      {"q_index", m.q_index[static_cast<size_t>(i)]},
                      {"v_index", m.v_index[static_cast<size_t>(i)]}});
  j["joints"] = joints;
  j["q0"] = toVector(c.q0);
  j["v0"] = toVector(c.v0);
  std::vector<double> damping(static_cast<size_t>(m.nv), 0.0);
  if (c.damping)
    for (size_t k = 0; k < damping.size() && k < m.damping.size(); ++k) damping[k] = m.damping[k];
  j["damping"] = damping;
  if (c.hand.mode != InteractionMode::None) {
    const HandCoupling& h = c.hand;
    j["hand"] = {{"mode", h.mode == InteractionMode::Pull ? "pull" : "push"}, {"link", h.link},
                 {"point", {h.point.x(), h.point.y(), h.point.z()}}, {"tip", {h.tip.x(), h.tip.y(), h.tip.z()}},
                 {"k", h.k}, {"b", h.b}, {"tip_radius", h.tip_radius}};
  }
  const std::string json_path = dir + "/" + c.name + ".json";
  std::ofstream out(json_path);
  out << j.dump(1) << "\n";
  if (!out) throw std::runtime_error(json_path + ": cannot write");
}

bool hasReference(const Case& c, const std::string& dir) {
  return std::ifstream(dir + "/" + c.name + ".truth.json").good();
}

Reference readReference(const Case& c, const std::string& dir) {
  const std::string path = dir + "/" + c.name + ".truth.json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open (run scripts/reports/accuracy_peers.py first)");
  const Model& m = *c.model;
  Reference ref;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    ref.method = j.at("method").get<std::string>();
    ref.self_check_q_max = j.at("self_check_q_max").get<double>();
    const auto& q = j.at("q");
    const auto& v = j.at("v");
    const auto& ee = j.at("ee");
    const size_t samples = static_cast<size_t>(std::lround(c.duration / kSamplePeriod)) + 1;
    if (q.size() != samples || v.size() != samples || ee.size() != samples)
      throw std::runtime_error("expected " + std::to_string(samples) + " samples of q, v and ee");
    Data d(m);
    for (size_t k = 0; k < samples; ++k) {
      const VectorX qk = fromJson(q[k], m.nq, "q[" + std::to_string(k) + "]");
      const VectorX vk = fromJson(v[k], m.nv, "v[" + std::to_string(k) + "]");
      ref.run.q.push_back(qk);
      ref.run.ee.push_back(fromJson(ee[k], 3, "ee[" + std::to_string(k) + "]"));
      forwardKinematics(m, d, qk);
      const double spring = handEnergy(c, d);
      ref.run.energy.push_back(mechanicalEnergy(m, d, qk, vk) + spring);
      ref.run.momentum.push_back(spatialMomentum(m, d, qk, vk));
    }
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  return ref;
}

}  // namespace igms::accuracy
