#include "core/model/tree_matrix.h"

#include <algorithm>
#include <cassert>

namespace igms {

TreeMatrix::TreeMatrix(const Model& model) {
  const int nv = model.nv;
  column_.resize(static_cast<size_t>(nv));
  block_of_.resize(static_cast<size_t>(nv));
  // A block per root dof's subtree (depth-first: contiguous), in dof order.
  size_t values = 0;
  for (int begin = 0; begin < nv;) {
    assert(model.dof_parent[static_cast<size_t>(begin)] < 0);
    const int end = model.dof_subtree_end[static_cast<size_t>(begin)];
    const int n = end - begin;
    const int b = static_cast<int>(block_begin_.size());
    block_begin_.push_back(begin);
    // (r, c) at values + (c - begin) n + (r - begin); values >= begin (each block before holds at least
    // one entry per dof), so the offset stored is never negative.
    for (int c = begin; c < end; ++c) {
      column_[static_cast<size_t>(c)] =
          static_cast<std::ptrdiff_t>(values) + static_cast<std::ptrdiff_t>(c - begin) * n - begin;
      block_of_[static_cast<size_t>(c)] = b;
    }
    values += static_cast<size_t>(n) * static_cast<size_t>(n);
    begin = end;
  }
  block_begin_.push_back(nv);
  values_.assign(values, 0.0);
}

Eigen::Map<const MatrixX, 0, Eigen::OuterStride<>> TreeMatrix::block(int begin, int n) const {
  const int b = blockOf(begin);
  assert(n == 0 || blockOf(begin + n - 1) == b);
  return {column(begin) + begin, n, n, Eigen::OuterStride<>(blockEnd(b) - blockBegin(b))};
}

void TreeMatrix::addSymmetricUpperTimes(int begin, int end, double scale, const VectorX& x, VectorX& y) const {
  for (int from = begin; from < end;) {
    const int to = std::min(end, blockEnd(blockOf(from)));
    const int n = to - from;
    y.segment(from, n).noalias() += scale * (block(from, n).selfadjointView<Eigen::Upper>() * x.segment(from, n));
    from = to;
  }
}

VectorX TreeMatrix::symmetricUpperTimes(const VectorX& x) const {
  VectorX y = VectorX::Zero(size());
  addSymmetricUpperTimes(0, size(), 1.0, x, y);
  return y;
}

MatrixX TreeMatrix::dense() const {
  MatrixX M = MatrixX::Zero(size(), size());
  for (int b = 0; b < blocks(); ++b) {
    const int begin = blockBegin(b), n = blockEnd(b) - begin;
    M.block(begin, begin, n, n) = block(begin, n);
  }
  return M;
}

MatrixX TreeMatrix::denseFromUpper() const {
  MatrixX M = dense();
  M.triangularView<Eigen::StrictlyLower>() = M.transpose();
  return M;
}

}  // namespace igms
