// DH-parameter description of a serial chain (the paper's DHparameters), read
// from YAML, built into the same RobotDescription as a URDF.
//
//   name: puma560
//   convention: standard        # standard: T_i = Rz(theta) Tz(d) Tx(a) Rx(alpha)
//                               # modified (Craig): T_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)
//   base: {xyz: [0, 0, 0], rpy: [0, 0, 0]}     # optional
//   tool: ee_link                               # optional frame at the last DH frame,
//   tool_xyz: [0, 0, 0.107]                     # offset by this (in the last DH frame)
//   links:
//     - {joint: joint1, link: link1, type: revolute, a: 0, alpha: 1.5708, d: 0, offset: 0,
//        mass: 0, com: [0, 0, 0], inertia: [Ixx, Iyy, Izz, Ixy, Ixz, Iyz],
//        damping: 0, limits: [lower, upper]}
//
// Revolute rows: theta = q + offset. Prismatic rows give `theta` and
// d = q + offset. com and inertia (about the com) are in the DH link frame i.
// Each URDF-style link frame is the DH frame {i-1} after the joint motion (the
// standard convention's constant part Tz(d) Tx(a) Rx(alpha) moves into the
// next joint's origin), so the PUMA's URDF and DH descriptions name the same frames.
#pragma once

#include <string>
#include <vector>

#include "core/model/robot_description.h"

namespace igms {

// Throws ModelError naming the file, line and key.
RobotDescription loadDhDescription(const std::string& path);
RobotDescription parseDhDescription(const std::string& yaml, const std::string& source = "<string>");

Model loadDhModel(const std::string& path, const BuildOptions& options = {},
                  std::vector<std::string>* warnings = nullptr);

}  // namespace igms
