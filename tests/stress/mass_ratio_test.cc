// Extreme masses along a chain: from root to tip the masses fall by 1e3 and by
// 1e6, and chains of 1 g and of 1 t links. Forward dynamics keeps its digits within
// what cond(H) allows, and ABA agrees with the LDL^T path.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/forward_dynamics.h"
#include "server/dynamics/rnea.h"
#include "server/model/configuration.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

// A 12-link chain tapering from base (at the root) to base / ratio (at the
// tip) geometrically, inertia scaled alike: the light tip makes H ill-conditioned.
std::string chain(double base, double ratio) {
  std::ostringstream out;
  out.precision(17);
  out << "<robot name=\"masses\"><link name=\"l0\"/>";
  for (int i = 1; i <= 12; ++i) {
    const double m = base * std::pow(ratio, -(i - 1) / 11.0), I = 0.01 * m;
    out << "<link name=\"l" << i << "\"><inertial><origin xyz=\"0 0 0.05\"/><mass value=\"" << m
        << "\"/><inertia ixx=\"" << I << "\" ixy=\"0\" ixz=\"0\" iyy=\"" << I << "\" iyz=\"0\" izz=\"" << 0.5 * I
        << "\"/></inertial></link><joint name=\"j" << i << "\" type=\"revolute\"><parent link=\"l" << i - 1
        << "\"/><child link=\"l" << i << "\"/><origin xyz=\"0 0 " << (i == 1 ? 0.0 : 0.1) << "\"/><axis xyz=\""
        << (i % 2 ? "0 1 0" : "1 0 0") << "\"/><limit lower=\"-3\" upper=\"3\" effort=\"1\" velocity=\"1\"/></joint>";
  }
  out << "</robot>";
  return out.str();
}

struct Masses {
  const char* name;
  double base, ratio;
};

class MassRatio : public ::testing::TestWithParam<Masses> {};

TEST_P(MassRatio, ForwardDynamicsKeepsTheDigitsConditioningAllows) {
  const Model m = modelFromUrdf(chain(GetParam().base, GetParam().ratio));
  Data d(m);
  std::mt19937 rng(9);
  double worst_fd = 0, worst_aba = 0, worst_cond = 0;
  for (int s = 0; s < 10; ++s) {
    const VectorX q = randomConfiguration(m, rng), v = randomVector(m.nv, rng), a = randomVector(m.nv, rng);
    const VectorX tau = rnea(m, d, q, v, a);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<MatrixX>(crba(m, d, q)).eigenvalues();
    const double cond = ev.maxCoeff() / ev.minCoeff();
    ASSERT_TRUE(forwardDynamics(m, d, q, v, tau));
    const VectorX ldlt = d.qdd;
    ASSERT_TRUE(aba(m, d, q, v, tau));
    const double fd = (ldlt - a).norm() / a.norm(), ab = (d.qdd - ldlt).norm() / ldlt.norm();
    EXPECT_LE(fd, std::max(1e-12, cond * 1e-13)) << GetParam().name << " cond " << cond;
    EXPECT_LE(ab, std::max(1e-12, cond * 1e-13)) << GetParam().name << " cond " << cond;
    worst_fd = std::max(worst_fd, fd);
    worst_aba = std::max(worst_aba, ab);
    worst_cond = std::max(worst_cond, cond);
  }
  std::printf("%-22s cond(H) up to %.3g; FD(ID(a)) relative error %.3g; ABA vs LDL^T %.3g\n", GetParam().name,
              worst_cond, worst_fd, worst_aba);
}

INSTANTIATE_TEST_SUITE_P(Chains, MassRatio,
                         ::testing::Values(Masses{"ratio_1e3", 1.0, 1e3}, Masses{"ratio_1e6", 1.0, 1e6},
                                           Masses{"links_of_1_g", 1e-3, 1.0}, Masses{"links_of_1_t", 1e3, 1.0}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace igms::test
