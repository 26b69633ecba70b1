// frameVelocities (core/kinematics/forward_kinematics.h): every frame's world velocity at (q, v), which
// the client's estimate carries for the push coupling's damper. Checked two independent ways on serial,
// branched and floating robots: against the frame Jacobian times v, and against central differences
// of the frames' poses along q(t) = q (+) t v.
#include <gtest/gtest.h>

#include <random>

#include "core/kinematics/forward_kinematics.h"
#include "core/interaction/pull.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

TEST(FrameVelocities, AgreeWithTheJacobianAndWithFiniteDifferences) {
  std::vector<std::pair<std::string, Model>> robots;
  for (const auto& r : test::serialRobots(3)) robots.emplace_back(r.name, test::modelFromUrdf(r.xml));
  for (const auto& r : test::branchedRobots(3)) robots.emplace_back(r.name + " (floating)", test::modelFromUrdf(r.xml, true));
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  for (const auto& [name, model] : robots) {
    Data data(model);
    const VectorX q = randomConfiguration(model, rng);
    VectorX v(model.nv);
    for (int i = 0; i < model.nv; ++i) v[i] = n(rng);
    std::vector<Motion> w(model.frames.size());
    bodyKinematics(model, data, q);
    frameVelocities(model, data, v, w);
    // Finite differences of the poses, h = 1e-6.
    const double h = 1e-6;
    VectorX qp(model.nq), qm(model.nq);
    integrateConfiguration(model, q, v, h, qp);
    integrateConfiguration(model, q, v, -h, qm);
    Data dp(model), dm(model), dj(model);
    forwardKinematics(model, dp, qp);
    forwardKinematics(model, dm, qm);
    Matrix6X J(6, model.nv);
    double worst_fd = 0.0, worst_j = 0.0;
    for (int f = 0; f < static_cast<int>(model.frames.size()); ++f) {
      const SE3 P = framePose(model, dp, f), M = framePose(model, dm, f);
      const Vector3 lin = (P.p - M.p) / (2 * h);
      const Vector3 ang = rotationLog(P.R * M.R.transpose()) / (2 * h);
      worst_fd = std::max({worst_fd, (lin - w[f].v).norm(), (ang - w[f].w).norm()});
      frameJacobian(model, dj, q, f, J);  // world axes, at the frame's origin
      const Vector6 jv = J * v;
      worst_j = std::max({worst_j, (jv.head<3>() - w[f].v).norm(), (jv.tail<3>() - w[f].w).norm()});
    }
    EXPECT_LT(worst_fd, 1e-6) << name;
    EXPECT_LT(worst_j, 1e-12 * std::max(1.0, v.norm() * 10)) << name;
  }
}

}  // namespace
}  // namespace igms
