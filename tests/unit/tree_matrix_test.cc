// The tree matrix (tree_matrix.h): H, its factors and the step's matrix stored one block per root
// dof's subtree. A scene's bodies and robots are separate blocks, a robot is one; the tree
// factorisation and solve on it agree with a dense LDL^T of the same matrix; and a pile of a
// thousand bodies holds 36 entries a body, not nv^2.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "core/dynamics/crba.h"
#include "core/dynamics/ltdl.h"
#include "core/model/configuration.h"
#include "core/scene/resolved_scene.h"
#include "core/scene/scene.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

ResolvedScene shipped(const char* name) { return resolveScene(loadScene(test::sourceDir() + "/scenes/" + name)); }

TEST(TreeMatrix, EachRootDofsSubtreeIsABlockOfItsOwn) {
  const ResolvedScene r = shipped("workcell.yaml");  // a PUMA, a Go1 and free bodies
  const Model& m = *r.model;
  const TreeMatrix H(m);
  ASSERT_EQ(H.size(), m.nv);
  ASSERT_GT(H.blocks(), 1);
  EXPECT_EQ(H.blockBegin(0), 0);
  EXPECT_EQ(H.blockEnd(H.blocks() - 1), m.nv);
  for (int b = 0; b < H.blocks(); ++b) {
    EXPECT_LT(m.dof_parent[H.blockBegin(b)], 0) << "a block starts at a root dof";
    for (int k = H.blockBegin(b) + 1; k < H.blockEnd(b); ++k)
      EXPECT_GE(m.dof_parent[k], H.blockBegin(b)) << "no dof's parent outside its block";
  }
  // The Go1 (a floating base) is one block; each free body is its own 6 x 6.
  for (const ModelPart& p : m.parts) {
    if (!p.free_body && p.name != "go1") continue;
    EXPECT_EQ(H.blockOf(p.dof_begin), H.blockOf(p.dof_end - 1)) << p.name;
    EXPECT_EQ(H.blockBegin(H.blockOf(p.dof_begin)), p.dof_begin) << p.name;
    EXPECT_EQ(H.blockEnd(H.blockOf(p.dof_begin)), p.dof_end) << p.name;
  }
}

TEST(TreeMatrix, APileStoresItsBodiesBlocksAlone) {
  // 216 free bodies, nv 1296: the dense matrix held 1.7 million entries (13 MB); a thousand, 288 MB.
  const ResolvedScene r = shipped("sphere_pile.yaml");
  const Model& m = *r.model;
  const TreeMatrix H(m);
  int free_bodies = 0;
  for (const ModelPart& p : m.parts) free_bodies += p.free_body ? 1 : 0;
  ASSERT_GE(free_bodies, 200);
  EXPECT_EQ(H.blocks(), free_bodies);
  EXPECT_EQ(H.storedEntries(), static_cast<size_t>(36 * free_bodies));
}

TEST(TreeMatrix, TheTreeFactorisationSolvesAsADenseOneOnAScene) {
  // A scene's inertia matrix (a PUMA, a Go1, free bodies) at a random state: the tree's L^T D L solve
  // against Eigen's dense LDL^T of the dense matrix.
  const ResolvedScene r = shipped("workcell.yaml");
  const Model& m = *r.model;
  Data d(m);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 5; ++trial) {
    const TreeMatrix& H = crba(m, d, randomConfiguration(m, rng));
    const MatrixX dense = H.dense();
    EXPECT_LE((dense - H.denseFromUpper()).norm(), 1e-12 * dense.norm()) << "crba fills both triangles alike";
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    VectorX b(m.nv);
    for (int k = 0; k < m.nv; ++k) b[k] = u(rng);
    TreeMatrix LD(m);
    LD.assign(H);
    VectorX diag(m.nv);
    ASSERT_LT(ltdlFactor(m.dof_parent, m.dof_run_start, LD, diag), 0);
    VectorX x = b;
    ltdlSolve(m.dof_parent, m.dof_run_start, LD, x);
    const VectorX expected = dense.ldlt().solve(b);
    EXPECT_LE((x - expected).norm(), 1e-9 * expected.norm());
    EXPECT_LE((H.symmetricUpperTimes(x) - b).norm(), 1e-9 * b.norm());
    // A held range's product (a robot's dofs alone) equals the dense sub-block's.
    const ModelPart& puma = m.parts[0];
    const int n = puma.dof_end - puma.dof_begin;
    VectorX y = VectorX::Zero(m.nv);
    H.addSymmetricUpperTimes(puma.dof_begin, puma.dof_end, -2.0, x, y);
    const VectorX want = -2.0 * dense.block(puma.dof_begin, puma.dof_begin, n, n) * x.segment(puma.dof_begin, n);
    EXPECT_LE((y.segment(puma.dof_begin, n) - want).norm(), 1e-12 * want.norm());
    EXPECT_EQ(y.head(puma.dof_begin).norm() + y.tail(m.nv - puma.dof_end).norm(), 0.0) << "outside the range: untouched";
  }
}

TEST(TreeMatrix, EntriesBetweenBlocksAreZero) {
  const ResolvedScene r = shipped("workcell.yaml");
  const Model& m = *r.model;
  Data d(m);
  const TreeMatrix& H = crba(m, d, r.q0);
  const int last = m.nv - 1;
  ASSERT_FALSE(H.sameBlock(0, last));
  EXPECT_EQ(H(0, last), 0.0);
  EXPECT_EQ(H(last, 0), 0.0);
  EXPECT_GT(H(0, 0), 0.0);
  EXPECT_EQ(H(last, last), H.diagonal(last));
}

}  // namespace
}  // namespace igms
