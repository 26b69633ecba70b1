// igms-ode-ref's two inputs, checked against igms: a recorded session (the
// paper's controlled straight line, and a push session) replayed on ODE, and a
// torque sequence computed by igms's inverse dynamics for a known motion,
// which ODE, integrating it, must follow.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/dynamics/rnea.h"
#include "core/model_io/model_loader.h"
#include "tests/support/test_models.h"
#include "tools/ode_ref/ode_replay.h"

namespace igms::test {
namespace {

OdeReplayResult replay(const std::string& log, bool tracking) {
  const auto contents = log::readAll(sourceDir() + "/tests/replay/data/" + log);
  EXPECT_FALSE(contents.damaged) << contents.error;
  return replayOnOde(contents.events, OdeSettings{}, sourceDir(), tracking);
}

struct Bound {
  const char* log;
  double link_max;        // m, over the whole session, tracking the recorded run
  double correction;      // tracking torque rms / recorded torque rms
  double first_second;    // m, open loop, within the first simulated second
};

class OdeReplay : public ::testing::TestWithParam<Bound> {};

TEST_P(OdeReplay, OdeReproducesTheRecordedIgmsRun) {
  const Bound& b = GetParam();
  const OdeReplayResult track = replay(b.log, true);
  ASSERT_TRUE(track.ok) << track.error;
  EXPECT_EQ(track.steps, static_cast<int64_t>(track.states.size()) - 1);
  const double rel = track.correction_rms / track.tau_rms;
  std::printf("%s, tracking: link origins max %.3g m, joints max %.3g rad, correction %.3g of the torque\n", b.log,
              track.link_max, track.q_max, rel);
  EXPECT_LT(track.link_max, b.link_max);
  EXPECT_LT(rel, b.correction);
  const OdeReplayResult open = replay(b.log, false);
  ASSERT_TRUE(open.ok) << open.error;
  ASSERT_FALSE(open.link_max_by_second.empty());
  std::printf("%s, open loop: link origins max %.3g m in the first second\n", b.log, open.link_max_by_second[0]);
  EXPECT_LT(open.link_max_by_second[0], b.first_second);
}

// Measured (1 ms, dWorldStep): nominal 7.6e-7 m / 1.7e-5 / 2.8e-5 m;
// paper push 1.3e-5 m / 1.5e-4 / 1.1e-4 m; short push 3.5e-5 m / 4e-4.
INSTANTIATE_TEST_SUITE_P(Sessions, OdeReplay,
                         ::testing::Values(Bound{"paper_nominal.lcmlog.gz", 5e-6, 1e-4, 2e-4},
                                           Bound{"paper_push.lcmlog.gz", 5e-5, 1e-3, 5e-4},
                                           Bound{"push.lcmlog", 1e-4, 2e-3, 5e-4}),
                         [](const auto& info) {
                           std::string n = info.param.log;
                           return n.substr(0, n.find('.'));
                         });

TEST(OdeReplay, ALogWithoutSessionInfoIsRefused) {
  auto contents = log::readAll(sourceDir() + "/tests/replay/data/push.lcmlog");
  std::vector<log::Event> states_only;
  for (auto& e : contents.events)
    if (e.channel == "IGMS_ROBOT_STATE") states_only.push_back(e);
  const OdeReplayResult r = replayOnOde(states_only, OdeSettings{});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("session info"), std::string::npos) << r.error;
}

// ODE integrates the torques igms's RNEA says produce q(t) = q0 + A sin(w t):
// it must follow q(t). Its error is first order (it halves with h), and the
// Richardson extrapolation 2 q_{h/2} - q_h, ODE's own limit h -> 0, meets
// q(t) far more closely: the two engines agree on the dynamics, not just
// to within ODE's step error.
TEST(OdeTorqueSequence, OdeFollowsTheMotionIgmsInverseDynamicsAskedFor) {
  const Model m = buildModel(loadDescription(sourceDir() + "/models/puma560.urdf"), {});
  Data d(m);
  VectorX q0(6), A(6);
  q0 << 0.3, 0.2, -0.6, 0.5, 1.0, 0.3;
  A << 0.4, 0.3, 0.5, 0.6, 0.5, 0.8;
  const double w = 2.0 * M_PI, T = 0.5, sample = 1e-3;
  auto at = [&](double t, VectorX& q, VectorX& qd, VectorX& qdd) {
    q = q0 + A * std::sin(w * t);
    qd = A * (w * std::cos(w * t));
    qdd = -A * (w * w * std::sin(w * t));
  };
  // ODE's q at every `sample`, for a step h.
  auto run = [&](double h) {
    const int n = static_cast<int>(std::lround(T / h));
    std::vector<VectorX> torques;
    VectorX q, qd, qdd;
    for (int k = 0; k < n; ++k) {
      // The mean of the torque over the step (Simpson), as a zero-order hold needs.
      VectorX tau = VectorX::Zero(6);
      const double ts[3] = {k * h, (k + 0.5) * h, (k + 1) * h}, ws[3] = {1.0 / 6, 4.0 / 6, 1.0 / 6};
      for (int s = 0; s < 3; ++s) {
        at(ts[s], q, qd, qdd);
        tau += ws[s] * rnea(m, d, q, qd, qdd);
      }
      torques.push_back(tau);
    }
    at(0.0, q, qd, qdd);
    const auto states = runTorquesOnOde(m, q, qd, torques, h, OdeSettings{});
    EXPECT_EQ(states.size(), static_cast<size_t>(n + 1));
    std::vector<VectorX> out;
    const int per = static_cast<int>(std::lround(sample / h));
    for (size_t k = 0; k < states.size(); k += static_cast<size_t>(per))
      out.push_back(Eigen::Map<const VectorX>(states[k].q.data(), 6));
    return out;
  };
  auto maxError = [&](const std::vector<VectorX>& qs) {
    double err = 0.0;
    VectorX q, qd, qdd;
    for (size_t k = 0; k < qs.size(); ++k) {
      at(k * sample, q, qd, qdd);
      err = std::max(err, (qs[k] - q).cwiseAbs().maxCoeff());
    }
    return err;
  };
  const auto coarse = run(5e-4), fine = run(2.5e-4);
  ASSERT_EQ(coarse.size(), fine.size());
  std::vector<VectorX> extrapolated;
  for (size_t k = 0; k < fine.size(); ++k) extrapolated.push_back(2.0 * fine[k] - coarse[k]);
  const double e_coarse = maxError(coarse), e_fine = maxError(fine), e_limit = maxError(extrapolated);
  std::printf("ODE's largest joint error against q(t) over %.1f s: %.3g rad at 0.5 ms, %.3g at 0.25 ms "
              "(ratio %.3f); Richardson-extrapolated %.3g rad\n", T, e_coarse, e_fine, e_coarse / e_fine, e_limit);
  EXPECT_NEAR(e_coarse / e_fine, 2.0, 0.2) << "first order";
  EXPECT_LT(e_fine, 0.03);
  EXPECT_LT(e_limit, 0.005 * e_fine) << "ODE's limit h -> 0 is the motion igms's inverse dynamics asked for";
}

}  // namespace
}  // namespace igms::test
