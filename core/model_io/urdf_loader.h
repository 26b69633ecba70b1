// URDF -> RobotDescription -> Model, through urdfdom.
#pragma once

#include <string>
#include <vector>

#include "core/model/robot_description.h"

namespace igms {

// Throws ModelError naming the file and the problem (urdfdom's own message
// included when it rejects the XML).
RobotDescription loadUrdfDescription(const std::string& path);
RobotDescription parseUrdfDescription(const std::string& xml, const std::string& source = "<string>");

Model loadUrdfModel(const std::string& path, const BuildOptions& options = {},
                    std::vector<std::string>* warnings = nullptr);

}  // namespace igms
