// Files a robot description names (meshes): `package://PKG/path` through a
// search path, `file://` and plain paths relative to the description's folder.
// The search path is IGMS_PACKAGE_PATH, then ROS_PACKAGE_PATH (both
// colon-separated lists of folders that contain packages), then the
// description's ancestor folders (a model inside its package finds it).
#pragma once

#include <string>
#include <vector>

namespace igms {

struct ResourceResolution {
  std::string path;                // absolute, empty when not found
  std::vector<std::string> tried;  // every candidate looked at, in order
};

// `uri` as written in the file; `description_path` the file naming it.
ResourceResolution resolveResource(const std::string& uri, const std::string& description_path);

// The folders searched for `package://` URIs, in order (environment first).
std::vector<std::string> packageSearchPath(const std::string& description_path);

}  // namespace igms
