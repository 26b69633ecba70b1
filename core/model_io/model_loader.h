// One door for model files: *.urdf through urdfdom, *.yaml / *.yml as a DH table.
#pragma once

#include <string>
#include <vector>

#include "core/model/robot_description.h"

namespace igms {

RobotDescription loadDescription(const std::string& path);
Model loadModel(const std::string& path, const BuildOptions& options = {},
                std::vector<std::string>* warnings = nullptr);

// The same from the file's content (a log's copy): `path` picks the format and
// is where the file was, from which a URDF's meshes resolve.
RobotDescription parseDescription(const std::string& text, const std::string& path);
Model parseModel(const std::string& text, const std::string& path, const BuildOptions& options = {},
                 std::vector<std::string>* warnings = nullptr);

}  // namespace igms
