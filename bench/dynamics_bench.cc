// igms-bench: median time per call of igms's algorithms and of KDL's
// equivalents, measured in the same run with interleaved samples, and their
// ratio (igms / KDL: below 1 is faster). Robots: PUMA 560, the 7-dof arm, the
// quadruped (floating base for igms; KDL has none, so its fixed-trunk tree is
// the peer for RNEA), serial chains of 30 and 100 links.
//   igms-bench [--quick] [--json FILE]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainhdsolver_vereshchagin.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <memory>
#include <string>
#include <vector>

#include "core/cli/command_line.h"
#include "core/dynamics/aba.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "core/model_io/urdf_loader.h"
#include "tests/support/kdl_from_urdf.h"
#include "tools/synthetic/random_urdf.h"

namespace {

using namespace igms;
using Clock = std::chrono::steady_clock;

int g_samples = 201;
volatile double g_sink = 0.0;

// Calls per sample so that one sample lasts about 100 us.
int callsPerSample(const std::function<void(int)>& f) {
  int n = 1;
  for (;;) {
    const auto t0 = Clock::now();
    for (int k = 0; k < n; ++k) f(k);
    if (std::chrono::duration<double, std::micro>(Clock::now() - t0).count() > 100.0 || n > (1 << 20)) return n;
    n *= 2;
  }
}

// Median microseconds per call of a and b, sampled alternately so that drift
// of a noisy machine hits both alike.
std::pair<double, double> medianPair(const std::function<void(int)>& a, const std::function<void(int)>& b) {
  const int na = callsPerSample(a), nb = callsPerSample(b);
  std::vector<double> sa, sb;
  for (int s = 0; s < g_samples; ++s) {
    auto t0 = Clock::now();
    for (int k = 0; k < na; ++k) a(s + k);
    sa.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / na);
    t0 = Clock::now();
    for (int k = 0; k < nb; ++k) b(s + k);
    sb.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / nb);
  }
  auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  return {median(sa), median(sb)};
}

struct Row {
  std::string robot, op, peer;
  double igms_us, kdl_us;
};

struct Robot {
  std::string name;
  std::string xml;
  bool floating = false;
};

constexpr int kStates = 32;

void benchRobot(const Robot& r, std::vector<Row>& rows) {
  BuildOptions options;
  options.floating_base = r.floating;
  const Model model = buildModel(parseUrdfDescription(r.xml, r.name), options);
  Data data(model);
  const test::KdlRobot kdl = test::kdlFromUrdf(r.xml);
  std::mt19937 rng(3);
  const RandomStates states = randomStates(model, kStates, rng);
  const auto &q = states.q, &v = states.v, &a = states.a, &tau = states.tau;
  // KDL states: the same random numbers in KDL's joint order are not needed
  // for timing; any states of the right size will do.
  const unsigned nj = kdl.tree.getNrOfJoints();
  std::vector<KDL::JntArray> kq, kv, ka, kt;
  for (int k = 0; k < kStates; ++k) {
    KDL::JntArray x(nj), y(nj), z(nj), w(nj);
    x.data = randomVector(static_cast<int>(nj), rng, 1.0);
    y.data = randomVector(static_cast<int>(nj), rng, 1.0);
    z.data = randomVector(static_cast<int>(nj), rng, 1.0);
    w.data = randomVector(static_cast<int>(nj), rng, 10.0);
    kq.push_back(x); kv.push_back(y); ka.push_back(z); kt.push_back(w);
  }
  KDL::JntArray kout(nj);
  const KDL::Vector g(0, 0, -9.81);
  auto add = [&](const std::string& op, const std::string& peer, const std::function<void(int)>& ours,
                 const std::function<void(int)>& theirs) {
    const auto [us, them] = medianPair(ours, theirs);
    rows.push_back({r.name, op, peer, us, them});
    std::printf("  %-12s %-10s %-34s igms %9.3f us   KDL %9.3f us   ratio %5.2f\n", r.name.c_str(), op.c_str(),
                peer.c_str(), us, them, us / them);
    std::fflush(stdout);
  };
  auto S = [](int k) { return k % kStates; };

  if (kdl.leaves.size() != 1) {  // a tree: KDL's tree RNEA is the only peer
    KDL::TreeIdSolver_RNE id(kdl.tree, g);
    KDL::WrenchMap none;
    add("rnea", "TreeIdSolver_RNE (fixed trunk)",
        [&](int k) { g_sink = g_sink + rnea(model, data, q[S(k)], v[S(k)], a[S(k)])[0]; },
        [&](int k) { id.CartToJnt(kq[S(k)], kv[S(k)], ka[S(k)], none, kout); g_sink = g_sink + kout(0); });
    return;
  }
  KDL::Chain chain;
  kdl.tree.getChain(model.root_link, kdl.leaves[0], chain);
  KDL::ChainIdSolver_RNE id(chain, g);
  KDL::ChainDynParam dyn(chain, g);
  KDL::ChainFdSolver_RNE fd(chain, g);
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  KDL::Wrenches none(chain.getNrOfSegments(), KDL::Wrench::Zero());
  KDL::JntSpaceInertiaMatrix kH(nj);
  std::vector<KDL::Frame> frames(chain.getNrOfSegments());
  KDL::Jacobian kJ(nj);
  const int tip = model.frameIndex(kdl.leaves[0]);

  add("rnea", "ChainIdSolver_RNE", [&](int k) { g_sink = g_sink + rnea(model, data, q[S(k)], v[S(k)], a[S(k)])[0]; },
      [&](int k) { id.CartToJnt(kq[S(k)], kv[S(k)], ka[S(k)], none, kout); g_sink = g_sink + kout(0); });
  add("crba", "ChainDynParam::JntToMass", [&](int k) { g_sink = g_sink + crba(model, data, q[S(k)])(0, 0); },
      [&](int k) { dyn.JntToMass(kq[S(k)], kH); g_sink = g_sink + kH(0, 0); });
  add("fd_ldlt", "ChainFdSolver_RNE",
      [&](int k) { forwardDynamics(model, data, q[S(k)], v[S(k)], tau[S(k)]); g_sink = g_sink + data.qdd[0]; },
      [&](int k) { fd.CartToJnt(kq[S(k)], kv[S(k)], kt[S(k)], none, kout); g_sink = g_sink + kout(0); });
  add("aba", "ChainFdSolver_RNE",
      [&](int k) { aba(model, data, q[S(k)], v[S(k)], tau[S(k)]); g_sink = g_sink + data.qdd[0]; },
      [&](int k) { fd.CartToJnt(kq[S(k)], kv[S(k)], kt[S(k)], none, kout); g_sink = g_sink + kout(0); });
  add("fk+jac", "ChainFkSolverPos (all) + JntToJac",
      [&](int k) {
        forwardKinematics(model, data, q[S(k)]);
        pointJacobian(model, data, tip, Vector3::Zero(), data.J);
        g_sink = g_sink + data.J(0, 0);
      },
      [&](int k) {
        fk.JntToCart(kq[S(k)], frames);
        jac.JntToJac(kq[S(k)], kJ);
        g_sink = g_sink + kJ(0, 0);
      });
  if (model.nv >= 30) {
    // KDL's O(n) hybrid-dynamics solver, without constraints (it wants +g).
    KDL::ChainHdSolver_Vereshchagin hd(chain, KDL::Twist(KDL::Vector(0, 0, 9.81), KDL::Vector::Zero()), 0);
    KDL::Jacobian alpha(0);
    KDL::JntArray beta(0), ff(nj), ct(nj);
    add("aba", "ChainHdSolver_Vereshchagin (O(n))",
        [&](int k) { aba(model, data, q[S(k)], v[S(k)], tau[S(k)]); g_sink = g_sink + data.qdd[0]; },
        [&](int k) {
          hd.CartToJnt(kq[S(k)], kv[S(k)], kout, alpha, beta, none, kt[S(k)], ct);
          g_sink = g_sink + kout(0);
        });
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string json_path;
  bool quick = false;
  CLI::App app{"", "igms-bench"};
  igms::cli::describe(app, "igms against KDL in one interleaved run: median microseconds per call and the ratio.");
  app.add_flag("--quick", quick, "31 samples instead of 201");
  app.add_option("--json", json_path, "also write the rows here as JSON");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  if (quick) g_samples = 31;
  const char* src = std::getenv("IGMS_SOURCE_DIR");
  const std::string dir = std::string(src ? src : IGMS_SOURCE_DIR) + "/models/";
  auto read = [](const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::vector<Robot> robots = {{"puma560", read(dir + "puma560.urdf")},
                                     {"arm7", read(dir + "arm7.urdf")},
                                     {"quadruped", read(dir + "quadruped.urdf"), true},
                                     {"chain30", synthetic::serialChainUrdf(30)},
                                     {"chain100", synthetic::serialChainUrdf(100)}};
  std::printf("igms-bench: median microseconds per call, %d interleaved samples; ratio = igms / KDL\n", g_samples);
  std::vector<Row> rows;
  for (const auto& r : robots) benchRobot(r, rows);
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << "[\n";
    for (size_t i = 0; i < rows.size(); ++i) {
      char line[512];
      std::snprintf(line, sizeof line,
                    "  {\"robot\": \"%s\", \"op\": \"%s\", \"peer\": \"%s\", \"igms_us\": %.6g, \"kdl_us\": %.6g, "
                    "\"ratio\": %.4g}%s\n",
                    rows[i].robot.c_str(), rows[i].op.c_str(), rows[i].peer.c_str(), rows[i].igms_us,
                    rows[i].kdl_us, rows[i].igms_us / rows[i].kdl_us, i + 1 < rows.size() ? "," : "");
      out << line;
    }
    out << "]\n";
  }
  return 0;
}
