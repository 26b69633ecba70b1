// A symmetric nv x nv matrix with the kinematic tree's sparsity: the joint-space inertia H, its
// L^T D L factors, the implicit step's matrix. Entry (r, c) can be non-zero only where r and c lie on
// one chain of dofs, so dofs under different root dofs (the bodies of a pile, a robot and the box it
// pushes) never share one. It is stored as one dense column-major block per root dof's subtree: a
// pile of 1000 free bodies takes 1000 blocks of 6 x 6 (288 kB) where the dense matrix took 288 MB,
// and reading a dof's column touched a page of its own. A single tree (one robot) is one block: the
// dense matrix's own layout.
//
// Columns are addressed by global row: column(c)[r] is entry (r, c) for r in c's block, so the tree
// algorithms (crba.h, ltdl.h) index it as they would a dense column.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/model/model.h"

namespace igms {

using VectorX = Eigen::VectorXd;
using MatrixX = Eigen::MatrixXd;

class TreeMatrix {
 public:
  TreeMatrix() = default;
  explicit TreeMatrix(const Model& model);  // zero

  int size() const { return static_cast<int>(column_.size()); }
  int blocks() const { return static_cast<int>(block_begin_.size()) - 1; }
  size_t storedEntries() const { return values_.size(); }
  // Block b's dofs [blockBegin, blockEnd); the block of dof c.
  int blockBegin(int b) const { return block_begin_[static_cast<size_t>(b)]; }
  int blockEnd(int b) const { return block_begin_[static_cast<size_t>(b) + 1]; }
  int blockOf(int c) const { return block_of_[static_cast<size_t>(c)]; }

  // Column c, by global row: column(c)[r] is (r, c) for r in c's block (only those rows exist).
  double* column(int c) { return values_.data() + column_[static_cast<size_t>(c)]; }
  const double* column(int c) const { return values_.data() + column_[static_cast<size_t>(c)]; }
  double& diagonal(int c) { return column(c)[c]; }
  double diagonal(int c) const { return column(c)[c]; }
  // Entry (r, c): zero where r and c are in different blocks. A write must stay within a block.
  double operator()(int r, int c) const { return sameBlock(r, c) ? column(c)[r] : 0.0; }
  double& operator()(int r, int c) { return column(c)[r]; }
  bool sameBlock(int r, int c) const { return blockOf(r) == blockOf(c); }

  // Every stored entry of `from` (a matrix of the same model): no allocation.
  void assign(const TreeMatrix& from) { values_ = from.values_; }
  // Block b's stored entries, column-major (n x n, n its dofs).
  double* blockValues(int b) { return column(blockBegin(b)) + blockBegin(b); }
  const double* blockValues(int b) const { return column(blockBegin(b)) + blockBegin(b); }
  size_t blockEntries(int b) const {
    const size_t n = static_cast<size_t>(blockEnd(b) - blockBegin(b));
    return n * n;
  }
  // The square sub-block [begin, begin + n) of one block, as an Eigen view (both triangles as stored).
  Eigen::Map<const MatrixX, 0, Eigen::OuterStride<>> block(int begin, int n) const;

  // y[range] += scale * S x[range] on dofs [begin, end), S the symmetric matrix of the stored upper
  // triangle restricted to those dofs (its entries with dofs outside the range are left out).
  void addSymmetricUpperTimes(int begin, int end, double scale, const VectorX& x, VectorX& y) const;
  // S x over every dof (allocates the result: for tools and tests).
  VectorX symmetricUpperTimes(const VectorX& x) const;
  // The dense nv x nv matrix, both triangles as stored (crba() fills both), zero between blocks
  // (allocates: for tools and tests).
  MatrixX dense() const;
  // The same with the lower triangle mirrored from the upper one.
  MatrixX denseFromUpper() const;

 private:
  std::vector<double> values_;
  std::vector<std::ptrdiff_t> column_;  // per dof c: values_ index of (0, c) as if global rows were local
  std::vector<int> block_begin_;        // per block, and one past the last dof
  std::vector<int> block_of_;           // per dof
};

}  // namespace igms
