// Robots the tests run on: the committed models and random URDF robots.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/model/robot_description.h"
#include "core/model_io/urdf_loader.h"
#include "tests/support/random_urdf.h"

namespace igms::test {

inline std::string sourceDir() {
  const char* env = std::getenv("IGMS_SOURCE_DIR");
  return env ? env : IGMS_SOURCE_DIR;
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct NamedUrdf {
  std::string name;
  std::string xml;
};

inline Model modelFromUrdf(const std::string& xml, bool floating = false) {
  BuildOptions o;
  o.floating_base = floating;
  return buildModel(parseUrdfDescription(xml), o);
}

// The committed serial arms plus `random_count` random chains.
inline std::vector<NamedUrdf> serialRobots(int random_count) {
  std::vector<NamedUrdf> out{{"puma560", readFile(sourceDir() + "/models/puma560.urdf")},
                             {"arm7", readFile(sourceDir() + "/models/arm7.urdf")}};
  for (int s = 0; s < random_count; ++s) {
    RandomRobotOptions o;
    o.branches = false;
    o.moving_joints = 3 + s % 10;
    out.push_back({"random_chain_" + std::to_string(s), randomUrdf(o, 1000u + static_cast<unsigned>(s))});
  }
  return out;
}

// Random branched trees (and the quadruped, whose legs branch from the trunk).
inline std::vector<NamedUrdf> branchedRobots(int random_count) {
  std::vector<NamedUrdf> out{{"quadruped", readFile(sourceDir() + "/models/quadruped.urdf")}};
  for (int s = 0; s < random_count; ++s) {
    RandomRobotOptions o;
    o.branches = true;
    o.moving_joints = 4 + s % 12;
    out.push_back({"random_tree_" + std::to_string(s), randomUrdf(o, 2000u + static_cast<unsigned>(s))});
  }
  return out;
}

}  // namespace igms::test
