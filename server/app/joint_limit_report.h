// Which joints went beyond their URDF position limits, and how far, over the
// run: counted by the publishing thread from every state it publishes (off
// the loop), reported in server_status_t. With the scene's joint_limits on, a
// joint sinks a little beyond a limit it is pushed against (the spring's
// give); with them off, this shows where a motion leaves the robot's range.
#pragma once

#include <string>
#include <vector>

#include "core/model/model.h"

namespace igms {

class JointLimitReport {
 public:
  explicit JointLimitReport(const Model& model);

  void observe(const std::vector<double>& q);

  struct Entry {
    std::string joint;
    int64_t steps = 0;
    double excess = 0.0;  // rad or m
  };
  // The joints that went beyond a limit, in model order.
  std::vector<Entry> hits() const;

 private:
  struct Joint {
    std::string name;
    int q = 0;
    double lower = 0.0, upper = 0.0;
    int64_t steps = 0;
    double excess = 0.0;
  };
  std::vector<Joint> joints_;
};

}  // namespace igms
