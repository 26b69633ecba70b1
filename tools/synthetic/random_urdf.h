// Synthetic robots as URDF text (random trees and chains, tapered chains): for
// the tests, the benchmarks and the accuracy tool. Each test so also exercises the URDF path
// and KDL can be built from the same file independently of igms's builder.
#pragma once

#include <string>

namespace igms::synthetic {

struct RandomRobotOptions {
  int moving_joints = 8;
  bool branches = true;        // false: a serial chain
  double p_prismatic = 0.2;
  double p_continuous = 0.15;
  double p_fixed = 0.15;       // fixed joints mid-chain (merged by igms, kept by KDL)
  double p_massless = 0.15;    // links without <inertial> (never a leaf)
  double p_axis_aligned = 0.3; // else a random unit axis
  bool damping = true;
};

// Deterministic in (options, seed). Every link with mass satisfies the
// triangle inequality; the root link "root" has mass. Origins and inertial frames are rotated.
std::string randomUrdf(const RandomRobotOptions& options, unsigned seed);

// A serial chain of n revolute joints along alternating axes (bench models).
std::string serialChainUrdf(int n);

// A 12-link chain whose masses taper geometrically from `base` kg at the root
// to base / ratio at the tip, inertia scaled alike: a light tip makes H
// ill-conditioned (the mass-ratio stress cases).
std::string taperedChainUrdf(double base, double ratio);

}  // namespace igms::synthetic
