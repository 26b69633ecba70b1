#include "core/model_io/model_loader.h"

#include "core/model_io/dh_loader.h"
#include "core/model_io/urdf_loader.h"

namespace igms {
namespace {
bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
}  // namespace

RobotDescription loadDescription(const std::string& path) {
  if (endsWith(path, ".yaml") || endsWith(path, ".yml")) return loadDhDescription(path);
  return loadUrdfDescription(path);
}

Model loadModel(const std::string& path, const BuildOptions& options, std::vector<std::string>* warnings) {
  return buildModel(loadDescription(path), options, warnings);
}

}  // namespace igms
