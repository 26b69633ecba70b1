// The PUMA 560 (standard DH) and the 7-dof arm (modified DH) described both as
// DH tables and as URDFs give the same model: same H, bias and link poses.
#include <gtest/gtest.h>

#include "core/dynamics/crba.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/model/configuration.h"
#include "core/model_io/model_loader.h"
#include "tests/support/test_models.h"
#include "tests/support/tolerances.h"

namespace igms::test {
namespace {

class DhModel : public ::testing::TestWithParam<std::string> {};

TEST_P(DhModel, DhTableAndUrdfAgree) {
  const Model dh = loadModel(sourceDir() + "/models/" + GetParam() + ".dh.yaml");
  const Model urdf = loadModel(sourceDir() + "/models/" + GetParam() + ".urdf");
  ASSERT_EQ(dh.nv, urdf.nv);
  ASSERT_EQ(dh.frames.size(), urdf.frames.size());
  Data a(dh), b(urdf);
  std::mt19937 rng(9);
  for (int s = 0; s < 100; ++s) {
    const VectorX q = randomConfiguration(dh, rng), v = randomVector(dh.nv, rng);
    EXPECT_LE(relError(crba(dh, a, q).dense(), crba(urdf, b, q).dense()), 1e-12);
    EXPECT_LE(relError(bias(dh, a, q, v), bias(urdf, b, q, v)), 1e-12);
    forwardKinematics(dh, a, q);
    forwardKinematics(urdf, b, q);
    for (size_t f = 0; f < dh.frames.size(); ++f) {
      const int g = urdf.frameIndex(dh.frames[f].name);
      ASSERT_GE(g, 0) << dh.frames[f].name;
      EXPECT_LE((a.oMf[f].p - b.oMf[static_cast<size_t>(g)].p).norm(), 1e-12);
      EXPECT_LE((a.oMf[f].R - b.oMf[static_cast<size_t>(g)].R).norm(), 1e-12);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Arms, DhModel, ::testing::Values("puma560", "arm7"));

TEST(DhModel, PumaKeepsThePublishedOddities) {
  std::vector<std::string> warnings;
  const Model m = loadModel(sourceDir() + "/models/puma560.dh.yaml", {}, &warnings);
  EXPECT_NEAR(m.totalMass(), 0.0 + 17.4 + 4.8 + 0.82 + 0.34 + 0.09, 1e-12);
  bool link3 = false;
  for (const auto& w : warnings) link3 |= w.find("link 'link3'") != std::string::npos;
  EXPECT_TRUE(link3) << "link 3 breaks the triangle inequality and must be flagged";
}

}  // namespace
}  // namespace igms::test
