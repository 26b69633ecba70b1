// The exchange with the independent ground truth (scripts/reports/accuracy_peers.py:
// SciPy's DOP853 on Pinocchio's articulated-body algorithm, and MuJoCo's
// integrators on the same axes). igms writes each case as a URDF plus a JSON
// description in its own coordinate order; the script writes back the truth
// sampled every 32 ms in that order, which igms reads as a Run.
#pragma once

#include <string>

#include "tools/accuracy/accuracy.h"

namespace igms::accuracy {

// <dir>/<case>.urdf and <dir>/<case>.json: joints by name in igms's q order
// (a floating base first: position, quaternion w first; body-frame velocity,
// linear first), q0, v0, per-dof damping when the case has it, gravity,
// duration, the 32 ms sample period and the end-effector frame.
void writeCaseFiles(const Case& c, const std::string& dir);

// <dir>/<case>.truth.json: q, v and the end-effector position at every sample.
// The energy and momentum of each sample are igms's own (used only to
// normalise drifts). Throws naming the file when it is missing, malformed, or
// does not fit the case (sample count, coordinate count).
struct Reference {
  Run run;
  std::string method;          // how the truth was computed, as the file says
  double self_check_q_max = 0; // the truth against itself at 10x tighter tolerance
};
Reference readReference(const Case& c, const std::string& dir);
// Whether <dir>/<case>.truth.json exists (without it igms measures against
// its own truth, RK4 at 1/64 ms, and says so).
bool hasReference(const Case& c, const std::string& dir);

}  // namespace igms::accuracy
