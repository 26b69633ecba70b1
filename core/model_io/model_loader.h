// One door for model files: *.urdf through urdfdom, *.yaml / *.yml as a DH table.
#pragma once

#include <string>
#include <vector>

#include "core/model/robot_description.h"

namespace igms {

RobotDescription loadDescription(const std::string& path);
Model loadModel(const std::string& path, const BuildOptions& options = {},
                std::vector<std::string>* warnings = nullptr);

}  // namespace igms
