// URDF -> KDL::Tree, written for the cross-checks from urdfdom's parse tree
// (not from igms's RobotDescription), so KDL sees the robot independently of
// igms's model builder. Fixed joints stay as KDL segments.
#pragma once

#include <kdl/tree.hpp>
#include <map>
#include <string>
#include <vector>

namespace igms::test {

struct KdlRobot {
  KDL::Tree tree;
  std::vector<std::string> leaves;               // link names without children
  std::map<std::string, unsigned> q_nr_of_joint; // moving joint name -> KDL tree q index
};

KdlRobot kdlFromUrdf(const std::string& urdf_xml);

}  // namespace igms::test
