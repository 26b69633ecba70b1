// igms-peer-bench: Pinocchio and MuJoCo on one URDF, the kernels that
// `igms-dyn bench` times for igms, with the same sampling (a median over
// samples of about 50 us), as JSON. It links no igms library: Pinocchio's URDF
// parser brings urdfdom 6 from its wheel, igms links Debian's urdfdom 3, and
// one process cannot hold both. scripts/bench/peer_table.py runs it and igms-dyn bench
// in turn, round after round, and prints igms / the best peer.
// Kernels, each library's fastest public path from (q, v, a or tau):
//   rnea_us      Pinocchio rnea; MuJoCo mj_kinematics + mj_comPos + mj_comVel + mj_rne (with qacc)
//   crba_us      Pinocchio crba; MuJoCo mj_kinematics + mj_comPos + mj_crb + mj_makeM
//   fd_us        Pinocchio aba; MuJoCo mj_forward
//   fk_us        Pinocchio forwardKinematics + updateFramePlacements (every URDF frame, as igms); MuJoCo mj_kinematics
//   jacobian_us  Pinocchio computeFrameJacobian; MuJoCo mj_kinematics + mj_comPos + mj_jacBody
//   step_us      Pinocchio aba + semi-implicit Euler + integrate; MuJoCo mj_step (Euler), 1 ms
// MuJoCo reads the URDF without its visual and collision geometry (dynamics
// only; its compiler fuses fixed joints), contacts and constraints disabled.
// Built with the CMake option IGMS_PEER_BENCH (off by default: it needs PyPI
// pin and mujoco, whose wheels carry Pinocchio's C++ headers and MuJoCo's C
// library; scripts/bench/bench.sh --peers does all of it).
//   igms-peer-bench --model ROBOT.urdf [--floating-base] [--frame NAME]
//   igms-peer-bench --write-chain N FILE      the serial chain igms-bench uses, as a URDF file
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/parsers/urdf.hpp>

#include <nlohmann/json.hpp>

#include "core/cli/command_line.h"
#include "tools/igms_dyn/median_time.h"
#include "tools/synthetic/random_urdf.h"

namespace {

volatile double g_sink = 0.0;
constexpr int kStates = 64;  // as igms-dyn bench
constexpr double kDt = 0.001;

struct Robot {
  std::string name;  // for messages
  std::string urdf;  // text
  bool floating = false;
};

std::string readText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// MuJoCo's URDF importer, dynamics only: no geometry (its meshes may be formats it cannot read), inertias
// as written (balanced where a URDF's violate the triangle inequality), no contacts or constraints.
mjModel* mujocoModel(const Robot& r) {
  std::string xml = std::regex_replace(r.urdf, std::regex("<visual[\\s\\S]*?</visual>"), "");
  xml = std::regex_replace(xml, std::regex("<collision[\\s\\S]*?</collision>"), "");
  xml = std::regex_replace(xml, std::regex("<robot([^>]*)>"),
                           "<robot$1><mujoco><compiler inertiafromgeom=\"false\" balanceinertia=\"true\" "
                           "boundmass=\"1e-6\" boundinertia=\"1e-10\" discardvisual=\"true\"/></mujoco>",
                           std::regex_constants::format_first_only);
  char error[1024] = "";
  mjSpec* spec = mj_parseXMLString(xml.c_str(), nullptr, error, sizeof error);
  if (!spec) throw std::runtime_error(r.name + ": MuJoCo cannot read the URDF: " + error);
  if (r.floating) {
    mjsBody* world = mjs_findBody(spec, "world");
    mjsElement* root = world ? mjs_firstChild(world, mjOBJ_BODY, 0) : nullptr;
    if (!root) throw std::runtime_error(r.name + ": MuJoCo: no root body to float");
    mjs_addFreeJoint(mjs_asBody(root));
  }
  mjModel* m = mj_compile(spec, nullptr);
  if (!m) throw std::runtime_error(r.name + ": MuJoCo cannot compile the URDF: " + mjs_getError(spec));
  mj_deleteSpec(spec);
  m->opt.disableflags |= mjDSBL_CONTACT | mjDSBL_CONSTRAINT | mjDSBL_EQUALITY;
  m->opt.integrator = mjINT_EULER;
  m->opt.timestep = kDt;
  return m;
}

nlohmann::json benchRobot(const std::string& path, bool floating, const std::string& frame_name) {
  const Robot r{path, readText(path), floating};
  std::mt19937 rng(42);
  // Pinocchio
  pinocchio::Model pm;
  if (floating) pinocchio::urdf::buildModel(path, pinocchio::JointModelFreeFlyer(), pm);
  else pinocchio::urdf::buildModel(path, pm);
  pinocchio::Data pd(pm);
  // The Jacobian's frame: the one named (igms-dyn bench's, from scripts/bench/peer_table.py), else the last body's.
  pinocchio::FrameIndex pframe = pm.frames.size() - 1;
  if (!frame_name.empty()) {
    if (!pm.existFrame(frame_name)) throw std::runtime_error(path + ": Pinocchio has no frame '" + frame_name + "'");
    pframe = pm.getFrameId(frame_name);
  } else {
    for (pinocchio::FrameIndex f = 0; f < pm.frames.size(); ++f)
      if (pm.frames[f].type == pinocchio::BODY) pframe = f;
  }
  // MuJoCo: the body of that name (a link on a moving joint keeps its name), else the deepest body.
  mjModel* mm = mujocoModel(r);
  mjData* md = mj_makeData(mm);
  int mbody = frame_name.empty() ? -1 : mj_name2id(mm, mjOBJ_BODY, frame_name.c_str());
  const bool mbody_named = mbody >= 0;
  if (mbody < 0) mbody = mm->nbody - 1;
  if (pm.nv != mm->nv)
    throw std::runtime_error(path + ": Pinocchio has nv " + std::to_string(pm.nv) + ", MuJoCo " + std::to_string(mm->nv));
  const int nv = pm.nv;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::VectorXd> pq, pv, pa, ptau;
  std::vector<std::vector<double>> mq;
  for (int k = 0; k < kStates; ++k) {
    pq.push_back(pinocchio::randomConfiguration(pm, -Eigen::VectorXd::Ones(pm.nq), Eigen::VectorXd::Ones(pm.nq)));
    pv.push_back(Eigen::VectorXd::NullaryExpr(nv, [&] { return u(rng); }));
    pa.push_back(Eigen::VectorXd::NullaryExpr(nv, [&] { return u(rng); }));
    ptau.push_back(Eigen::VectorXd::NullaryExpr(nv, [&] { return 10.0 * u(rng); }));
    std::vector<double> x(static_cast<size_t>(mm->nq));
    for (int i = 0; i < mm->nq; ++i) x[static_cast<size_t>(i)] = mm->qpos0[i] + 0.5 * u(rng);
    if (floating) {  // the free joint's unit quaternion (w x y z at 3..6)
      double n = 0;
      for (size_t i = 3; i < 7; ++i) n += x[i] * x[i];
      for (size_t i = 3; i < 7; ++i) x[i] /= std::sqrt(n);
    }
    mq.push_back(x);
  }
  auto S = [](int k) { return static_cast<size_t>(k % kStates); };
  auto setM = [&](int k) {
    std::copy(mq[S(k)].begin(), mq[S(k)].end(), md->qpos);
    std::copy(pv[S(k)].data(), pv[S(k)].data() + nv, md->qvel);
  };
  pinocchio::Data::Matrix6x PJ = pinocchio::Data::Matrix6x::Zero(6, nv);
  std::vector<double> jacp(3 * static_cast<size_t>(nv)), jacr(3 * static_cast<size_t>(nv));
  std::vector<double> result(static_cast<size_t>(nv));
  Eigen::VectorXd pqn(pm.nq), pvn(nv);
  const struct { const char* name; std::function<void(int)> pin, mj; } cases[] = {
      {"rnea_us", [&](int k) { g_sink = g_sink + pinocchio::rnea(pm, pd, pq[S(k)], pv[S(k)], pa[S(k)])[0]; },
       [&](int k) {
         setM(k);
         std::copy(pa[S(k)].data(), pa[S(k)].data() + nv, md->qacc);
         mj_kinematics(mm, md);
         mj_comPos(mm, md);
         mj_comVel(mm, md);
         mj_rne(mm, md, 1, result.data());
         g_sink = g_sink + result[0];
       }},
      {"crba_us", [&](int k) { g_sink = g_sink + pinocchio::crba(pm, pd, pq[S(k)])(0, 0); },
       [&](int k) {
         setM(k);
         mj_kinematics(mm, md);
         mj_comPos(mm, md);
         mj_crb(mm, md);
         mj_makeM(mm, md);
         g_sink = g_sink + md->M[0];
       }},
      {"fd_us", [&](int k) { g_sink = g_sink + pinocchio::aba(pm, pd, pq[S(k)], pv[S(k)], ptau[S(k)])[0]; },
       [&](int k) {
         setM(k);
         std::copy(ptau[S(k)].data(), ptau[S(k)].data() + nv, md->qfrc_applied);
         mj_forward(mm, md);
         g_sink = g_sink + md->qacc[0];
       }},
      {"fk_us",
       [&](int k) {
         pinocchio::forwardKinematics(pm, pd, pq[S(k)]);
         pinocchio::updateFramePlacements(pm, pd);
         g_sink = g_sink + pd.oMf.back().translation()[0];
       },
       [&](int k) {
         setM(k);
         mj_kinematics(mm, md);
         g_sink = g_sink + md->xpos[3 * mbody];
       }},
      {"jacobian_us",
       [&](int k) {
         pinocchio::computeFrameJacobian(pm, pd, pq[S(k)], pframe, pinocchio::LOCAL_WORLD_ALIGNED, PJ);
         g_sink = g_sink + PJ(0, 0);
       },
       [&](int k) {
         setM(k);
         mj_kinematics(mm, md);
         mj_comPos(mm, md);
         mj_jacBody(mm, md, jacp.data(), jacr.data(), mbody);
         g_sink = g_sink + jacp[0];
       }},
      {"step_us",
       [&](int k) {
         pinocchio::aba(pm, pd, pq[S(k)], pv[S(k)], ptau[S(k)]);
         pvn = pv[S(k)] + kDt * pd.ddq;
         pqn = pinocchio::integrate(pm, pq[S(k)], kDt * pvn);
         g_sink = g_sink + pqn[0];
       },
       [&](int k) {
         setM(k);
         std::copy(ptau[S(k)].data(), ptau[S(k)].data() + nv, md->qfrc_applied);
         mj_step(mm, md);
         g_sink = g_sink + md->qpos[0];
       }},
  };
  // The same robot? The trace of H at the neutral configuration does not depend on the joints' order.
  pinocchio::crba(pm, pd, pinocchio::neutral(pm));
  const double pin_trace = pd.M.trace();
  std::copy(mm->qpos0, mm->qpos0 + mm->nq, md->qpos);
  std::fill(md->qvel, md->qvel + nv, 0.0);
  mj_forward(mm, md);
  std::vector<double> dense(static_cast<size_t>(nv) * static_cast<size_t>(nv));
  mj_fullM(mm, md, dense.data());
  double mj_trace = 0.0;
  for (int i = 0; i < nv; ++i) mj_trace += dense[static_cast<size_t>(i) * static_cast<size_t>(nv + 1)];
  nlohmann::json out, pin, mj;
  out["trace_H_neutral"] = {{"pinocchio", pin_trace}, {"mujoco", mj_trace}};
  out["jacobian_frame"] = {{"pinocchio", pm.frames[pframe].name},
                           {"mujoco", mbody_named ? std::string(frame_name) : std::string(mj_id2name(mm, mjOBJ_BODY, mbody))}};
  for (const auto& c : cases) {
    pin[c.name] = igms::dyn::medianMicroseconds(c.pin, kStates);
    mj[c.name] = igms::dyn::medianMicroseconds(c.mj, kStates);
  }
  out["model"] = path;
  out["nq"] = pm.nq;
  out["nv"] = nv;
  out["mujoco_nq"] = mm->nq;
  out["pinocchio"] = pin;
  out["mujoco"] = mj;
  out["versions"] = {{"pinocchio", PINOCCHIO_VERSION}, {"mujoco", mj_versionString()}};
  mj_deleteData(md);
  mj_deleteModel(mm);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string model, frame, chain_file;
  bool floating = false;
  int chain = 0;
  CLI::App app{"", "igms-peer-bench"};
  igms::cli::describe(app, "Pinocchio and MuJoCo on one URDF: median microseconds per call of the kernels igms-dyn "
                           "bench times, as one JSON object (scripts/bench/peer_table.py compares).");
  app.add_option("--model", model, "ROBOT.urdf")->check(CLI::ExistingFile);
  app.add_flag("--floating-base", floating, "a free root");
  app.add_option("--frame", frame, "the Jacobian's frame (default: the last body's)");
  app.add_option("--write-chain", chain, "write the serial chain of N links igms-bench uses ...")
      ->check(CLI::PositiveNumber);
  app.add_option("FILE", chain_file, "... to this file");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  try {
    if (chain > 0) {
      if (chain_file.empty()) throw std::runtime_error("--write-chain N needs the FILE to write");
      std::ofstream(chain_file) << igms::synthetic::serialChainUrdf(chain);
      return 0;
    }
    if (model.empty()) throw std::runtime_error("--model ROBOT.urdf is required");
    std::printf("%s\n", benchRobot(model, floating, frame).dump().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-peer-bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
