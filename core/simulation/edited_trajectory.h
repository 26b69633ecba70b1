// The executed motion of the first robot, the paper's edited trajectory:
// its q sampled every kPeriod (and whenever generation replans), up to ten
// minutes, into storage preallocated at construction (sampling allocates
// nothing). Saved as a scene-loadable waypoint file ({waypoints: [{t, q}]}),
// which a scene can then take as its nominal trajectory.
#pragma once

#include <string>
#include <vector>

#include "core/model/tree_matrix.h"

namespace igms {

class EditedTrajectory {
 public:
  static constexpr double kPeriod = 0.01;   // s
  static constexpr int kCapacity = 60000;  // 10 minutes at 100 Hz

  EditedTrajectory() = default;
  // Records q[q_begin, q_begin + nq); joints: the robot's joint names for the saved file; source: the
  // scene file the saved file names. nq 0: nothing to record (a scene of free bodies).
  EditedTrajectory(int q_begin, int nq, std::vector<std::string> joints, std::string source);

  void clear();
  // Samples q at t, if a period has passed since the last sample or `force`d (every step asks).
  void sample(double t, const VectorX& q, bool force) {
    if (!force && t + 1e-12 < next_t_) return;
    if (count_ >= kCapacity || t_.empty()) return;
    t_[static_cast<size_t>(count_)] = t;
    q_.row(count_) = q.segment(q_begin_, q_.cols()).transpose();
    ++count_;
    next_t_ = t + kPeriod;
  }

  int count() const { return count_; }
  double time(int k) const { return t_[static_cast<size_t>(k)]; }
  auto point(int k) const { return q_.row(k).transpose(); }
  // Throws std::runtime_error naming the path: no robot, fewer than two samples, a file not written.
  void save(const std::string& path) const;

 private:
  int q_begin_ = 0;
  std::vector<std::string> joints_;
  std::string source_;
  std::vector<double> t_;
  MatrixX q_;  // kCapacity x the robot's nq
  int count_ = 0;
  double next_t_ = 0.0;
};

}  // namespace igms
