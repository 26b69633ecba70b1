// The ancestor dofs of a dof, run by run. Ancestors come in runs of consecutive
// dofs (chain segments: dof_parent[t] = t - 1 inside one), so each run is a
// plain loop over contiguous entries of a column; walking dof_parent one entry
// at a time would be a chain of dependent loads.
#pragma once

#include <vector>

namespace igms {

// f(r, j) for each run [r, j] of dof `from` and its ancestors, nearest first.
// dof_parent and run_start as Model::dof_parent and Model::dof_run_start.
template <typename F>
inline void forEachAncestorRun(const std::vector<int>& dof_parent, const std::vector<int>& run_start, int from, F&& f) {
  for (int j = from; j >= 0;) {
    const int r = run_start[j];
    f(r, j);
    j = dof_parent[r];
  }
}

}  // namespace igms
