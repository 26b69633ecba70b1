// Identities that tie the algorithms to each other and to finite differences:
// H symmetric positive definite, FD(ID(a)) = a, ABA = LDL^T path, external
// forces = -J^T f, Coriolis from Christoffel symbols of H, v^T (Hdot - 2C) v = 0,
// Jacobians and Jdot v against finite differences of forward kinematics.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "core/dynamics/aba.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/external_force.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "tests/support/test_models.h"
#include "tests/support/tolerances.h"

namespace igms::test {
namespace {

struct Robot {
  std::string name;
  std::string xml;
  bool floating;
};

std::vector<Robot> robots() {
  std::vector<Robot> out;
  for (const auto& r : serialRobots(4)) {
    out.push_back({r.name, r.xml, false});
    if (r.name.rfind("random", 0) == 0) out.push_back({r.name + "_floating", r.xml, true});
  }
  for (const auto& r : branchedRobots(6)) {
    out.push_back({r.name, r.xml, false});
    out.push_back({r.name + "_floating", r.xml, true});
  }
  return out;
}

class Identities : public ::testing::TestWithParam<Robot> {
 protected:
  void SetUp() override {
    model = modelFromUrdf(GetParam().xml, GetParam().floating);
    data = std::make_unique<Data>(model);
  }
  // Random external point forces on two links.
  std::vector<PointForce> randomForces(std::mt19937& rng) {
    std::vector<PointForce> out;
    for (int e = 0; e < 2; ++e)
      out.push_back({static_cast<int>(rng() % model.frames.size()), randomVector(3, rng, 0.3),
                     randomVector(3, rng, 20.0)});
    return out;
  }
  Model model;
  std::unique_ptr<Data> data;
};

TEST_P(Identities, InertiaMatrixIsSymmetricPositiveDefinite) {
  std::mt19937 rng(1);
  for (int s = 0; s < 50; ++s) {
    const MatrixX H = crba(model, *data, randomConfiguration(model, rng)).dense();
    EXPECT_LE((H - H.transpose()).cwiseAbs().maxCoeff(), 1e-14 * H.cwiseAbs().maxCoeff());
    EXPECT_EQ(Eigen::LLT<MatrixX>(H).info(), Eigen::Success);
  }
}

TEST_P(Identities, ForwardDynamicsInvertsInverseDynamics) {
  std::mt19937 rng(2);
  std::vector<Force> fext(static_cast<size_t>(model.nb));
  double worst = 0.0, worst_aba = 0.0, worst_ldlt_vs_aba = 0.0;
  for (int s = 0; s < 100; ++s) {
    const VectorX q = randomConfiguration(model, rng), v = randomVector(model.nv, rng, 2.0);
    const VectorX a = randomVector(model.nv, rng, 5.0);
    bodyKinematics(model, *data, q);
    clearExternalForces(fext);
    for (const auto& pf : randomForces(rng)) addPointForce(model, *data, pf, fext);
    const VectorX tau = rnea(model, *data, q, v, a, &fext);
    ASSERT_TRUE(forwardDynamics(model, *data, q, v, tau, &fext));
    const VectorX qdd_ldlt = data->qdd;
    worst = std::max(worst, relError(qdd_ldlt, a));
    ASSERT_TRUE(aba(model, *data, q, v, tau, &fext));
    worst_aba = std::max(worst_aba, relError(data->qdd, a));
    worst_ldlt_vs_aba = std::max(worst_ldlt_vs_aba, relError(data->qdd, qdd_ldlt));
  }
  EXPECT_LE(worst, kIdentityRel);
  EXPECT_LE(worst_aba, kIdentityRel);
  EXPECT_LE(worst_ldlt_vs_aba, kIdentityRel);
}

TEST_P(Identities, ExternalForcesEnterAsMinusJacobianTranspose) {
  std::mt19937 rng(3);
  std::vector<Force> fext(static_cast<size_t>(model.nb));
  for (int s = 0; s < 50; ++s) {
    const VectorX q = randomConfiguration(model, rng), v = randomVector(model.nv, rng);
    const VectorX a = randomVector(model.nv, rng);
    const VectorX tau_free = rnea(model, *data, q, v, a);
    bodyKinematics(model, *data, q);
    clearExternalForces(fext);
    VectorX expected = tau_free;
    for (const auto& pf : randomForces(rng)) {
      addPointForce(model, *data, pf, fext);
      pointJacobian(model, *data, pf.frame, pf.point, data->J);
      expected -= data->J.topRows<3>().transpose() * pf.force;
    }
    EXPECT_LE(relError(rnea(model, *data, q, v, a, &fext), expected), kIdentityRel);
  }
}

// The server step's fused pass gives, bit for bit, what the controller's rnea (or bias) and the
// plant's bias with external forces give alone: the replay suites' identity rests on it.
TEST_P(Identities, RneaAndBiasEqualTheSeparateCallsBitForBit) {
  std::mt19937 rng(13);
  std::vector<Force> fext(static_cast<size_t>(model.nb));
  Data separate(model);
  for (int s = 0; s < 50; ++s) {
    const VectorX q = randomConfiguration(model, rng), v = randomVector(model.nv, rng, 2.0);
    const VectorX a = randomVector(model.nv, rng, 5.0);
    bodyKinematics(model, *data, q);
    clearExternalForces(fext);
    for (const auto& pf : randomForces(rng)) addPointForce(model, *data, pf, fext);
    const bool with_fext = s % 2 == 0, at_placements = s % 3 == 0;
    const std::vector<Force>* f = with_fext ? &fext : nullptr;
    for (const VectorX* acc : {&a, static_cast<const VectorX*>(nullptr)}) {
      const VectorX tau = acc ? rnea(model, separate, q, v, *acc) : bias(model, separate, q, v);
      const VectorX b = bias(model, separate, q, v, f);
      if (at_placements) {
        bodyKinematics(model, *data, q);
        rneaAndBiasAtPlacements(model, *data, v, acc, f);
      } else {
        rneaAndBias(model, *data, q, v, acc, f);
      }
      for (int k = 0; k < model.nv; ++k) {
        ASSERT_EQ(data->tau[k], tau[k]) << "tau, dof " << k << (acc ? " (rnea)" : " (bias)");
        ASSERT_EQ(data->bias[k], b[k]) << "bias, dof " << k << (with_fext ? " with fext" : "");
      }
      // and the forward dynamics from that bias (with the world poses bodyKinematics left, or
      // composing its own) is forwardDynamics's, as is forwardDynamicsAtPoses's
      ASSERT_TRUE(forwardDynamics(model, separate, q, v, tau, f));
      ASSERT_TRUE(forwardDynamicsAtBias(model, *data, tau, at_placements));
      for (int k = 0; k < model.nv; ++k) ASSERT_EQ(data->qdd[k], separate.qdd[k]) << "qdd, dof " << k;
      bodyKinematics(model, *data, q);
      ASSERT_TRUE(forwardDynamicsAtPoses(model, *data, v, tau, f));
      for (int k = 0; k < model.nv; ++k) ASSERT_EQ(data->qdd[k], separate.qdd[k]) << "qdd at poses, dof " << k;
    }
  }
}

TEST_P(Identities, PowerBalanceHoldsAlongMotion) {
  // v^T Hdot v = 2 v^T C(q, v) v: the kinetic energy changes only through work.
  std::mt19937 rng(4);
  const double h = 1e-6;
  for (int s = 0; s < 30; ++s) {
    const VectorX q = randomConfiguration(model, rng), v = randomVector(model.nv, rng);
    VectorX qp(model.nq), qm(model.nq);
    integrateConfiguration(model, q, v, h, qp);
    integrateConfiguration(model, q, v, -h, qm);
    const MatrixX Hdot = (crba(model, *data, qp).dense() - crba(model, *data, qm).dense()) / (2 * h);
    const VectorX G = bias(model, *data, q, VectorX::Zero(model.nv));
    const VectorX Cv = bias(model, *data, q, v) - G;
    const double lhs = v.dot(Hdot * v), rhs = 2.0 * v.dot(Cv);
    EXPECT_NEAR(lhs, rhs, kFiniteDifferenceRel * std::max(1.0, std::abs(rhs)));
  }
}

// Fixed bases only: with a quaternion base, q has no coordinate derivatives of H.
class FixedBaseIdentities : public Identities {};

TEST_P(FixedBaseIdentities, CoriolisMatchesChristoffelSymbolsOfH) {
  // C_ij = sum_k Gamma_ijk v_k, Gamma_ijk = (dH_ij/dq_k + dH_ik/dq_j - dH_jk/dq_i) / 2,
  // and Hdot - 2C is skew-symmetric.
  std::mt19937 rng(5);
  const int n = model.nv;
  const double h = 1e-6;
  for (int s = 0; s < 10; ++s) {
    const VectorX q = randomConfiguration(model, rng), v = randomVector(n, rng);
    std::vector<MatrixX> dH(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) {
      VectorX qp = q, qm = q;
      qp[k] += h;
      qm[k] -= h;
      dH[static_cast<size_t>(k)] = (crba(model, *data, qp).dense() - crba(model, *data, qm).dense()) / (2 * h);
    }
    MatrixX C = MatrixX::Zero(n, n), Hdot = MatrixX::Zero(n, n);
    for (int k = 0; k < n; ++k) Hdot += dH[static_cast<size_t>(k)] * v[k];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k)
          C(i, j) += 0.5 * (dH[k](i, j) + dH[j](i, k) - dH[i](j, k)) * v[k];
    const VectorX G = bias(model, *data, q, VectorX::Zero(n));
    const VectorX Cv = bias(model, *data, q, v) - G;
    EXPECT_LE(relError(C * v, Cv), kFiniteDifferenceRel);
    const MatrixX N = Hdot - 2.0 * C;
    EXPECT_LE(relError(N + N.transpose(), MatrixX::Zero(n, n)), kFiniteDifferenceRel);
  }
}

TEST_P(Identities, JacobianMatchesFiniteDifferencesOfKinematics) {
  std::mt19937 rng(6);
  const double h = 1e-6;
  for (int s = 0; s < 30; ++s) {
    const VectorX q = randomConfiguration(model, rng), v = randomVector(model.nv, rng);
    const int f = static_cast<int>(rng() % model.frames.size());
    const Vector3 point = randomVector(3, rng, 0.3);
    bodyKinematics(model, *data, q);
    pointJacobian(model, *data, f, point, data->J);
    const Vector6 Jv = data->J * v;
    VectorX qp(model.nq), qm(model.nq);
    integrateConfiguration(model, q, v, h, qp);
    integrateConfiguration(model, q, v, -h, qm);
    bodyKinematics(model, *data, qp);
    const SE3 Xp = framePose(model, *data, f);
    bodyKinematics(model, *data, qm);
    const SE3 Xm = framePose(model, *data, f);
    const Vector3 dp = (Xp.act(point) - Xm.act(point)) / (2 * h);
    const Eigen::AngleAxisd dR(Xp.R * Xm.R.transpose());
    const Vector3 w = dR.axis() * dR.angle() / (2 * h);
    EXPECT_LE(relError(Jv.head<3>(), dp), kFiniteDifferenceRel);
    EXPECT_LE(relError(Jv.tail<3>(), w), kFiniteDifferenceRel);
  }
}

TEST_P(Identities, BiasAccelerationIsJdotV) {
  std::mt19937 rng(7);
  const double h = 1e-6;
  Matrix6X Jp(6, model.nv), Jm(6, model.nv);
  for (int s = 0; s < 30; ++s) {
    const VectorX q = randomConfiguration(model, rng), v = randomVector(model.nv, rng);
    const int f = static_cast<int>(rng() % model.frames.size());
    const Vector3 point = randomVector(3, rng, 0.3);
    const Vector6 Jdv = pointBiasAcceleration(model, *data, q, v, f, point);
    VectorX qp(model.nq), qm(model.nq);
    integrateConfiguration(model, q, v, h, qp);
    integrateConfiguration(model, q, v, -h, qm);
    bodyKinematics(model, *data, qp);
    pointJacobian(model, *data, f, point, Jp);
    bodyKinematics(model, *data, qm);
    pointJacobian(model, *data, f, point, Jm);
    const Vector6 fd = (Jp - Jm) * v / (2 * h);
    EXPECT_LE(relError(Jdv, fd), kFiniteDifferenceRel);
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, Identities, ::testing::ValuesIn(robots()),
                         [](const auto& info) { return info.param.name; });

std::vector<Robot> fixedBaseRobots() {
  std::vector<Robot> out;
  for (const auto& r : robots())
    if (!r.floating) out.push_back(r);
  return out;
}
INSTANTIATE_TEST_SUITE_P(Robots, FixedBaseIdentities, ::testing::ValuesIn(fixedBaseRobots()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace igms::test
