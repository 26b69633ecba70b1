// Tolerances of the tests, in one place. Relative to the size of the quantity.
#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace igms::test {

// Two independent implementations of the same exact formula (igms vs KDL).
constexpr double kCrossCheckRel = 1e-9;
// Identities evaluated by one implementation (FD(ID(a)) = a, ABA = LDL^T).
constexpr double kIdentityRel = 1e-9;
// Central finite differences with step 1e-6: truncation ~1e-12, round-off ~1e-10.
constexpr double kFiniteDifferenceRel = 1e-6;

// max |a - b| / max(1, max |b|)
template <typename A, typename B>
double relError(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  return (a - b).cwiseAbs().maxCoeff() / scale;
}

}  // namespace igms::test
