#include "core/simulation/edited_trajectory.h"

#include <fstream>
#include <stdexcept>
#include <utility>

#include "core/scene/trajectory_file.h"

namespace igms {

EditedTrajectory::EditedTrajectory(int q_begin, int nq, std::vector<std::string> joints, std::string source)
    : q_begin_(q_begin),
      joints_(std::move(joints)),
      source_(std::move(source)),
      t_(kCapacity, 0.0),
      q_(MatrixX::Zero(kCapacity, nq)) {}

void EditedTrajectory::clear() {
  count_ = 0;
  next_t_ = 0.0;
}

void EditedTrajectory::save(const std::string& path) const {
  if (q_.cols() == 0) throw std::runtime_error(path + ": the scene has no robot whose motion could be saved");
  std::vector<double> times;
  std::vector<VectorX> rows;
  double last_t = -1.0;
  for (int k = 0; k < count_; ++k) {
    if (t_[static_cast<size_t>(k)] <= last_t + 1e-9) continue;  // a spline needs increasing times
    last_t = t_[static_cast<size_t>(k)];
    times.push_back(last_t);
    rows.push_back(q_.row(k).transpose());
  }
  if (times.size() < 2) throw std::runtime_error(path + ": fewer than two samples recorded");
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write the edited trajectory");
  out << trajectoryFileText(source_, joints_, times, rows);
  if (!out) throw std::runtime_error(path + ": cannot write the edited trajectory");
}

}  // namespace igms
