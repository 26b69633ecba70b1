#include "core/model_io/model_loader.h"

#include "core/model_io/dh_loader.h"
#include "core/model_io/mesh_fields.h"
#include "core/model_io/urdf_loader.h"

namespace igms {
namespace {
bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool isDhTable(const std::string& path) { return endsWith(path, ".yaml") || endsWith(path, ".yml"); }
}  // namespace

RobotDescription loadDescription(const std::string& path) {
  if (isDhTable(path)) return loadDhDescription(path);
  return loadUrdfDescription(path);
}

RobotDescription parseDescription(const std::string& text, const std::string& path) {
  if (isDhTable(path)) return parseDhDescription(text, path);
  RobotDescription d = parseUrdfDescription(text, path);
  attachDistanceFields(d, path);
  return d;
}

Model parseModel(const std::string& text, const std::string& path, const BuildOptions& options,
                 std::vector<std::string>* warnings) {
  return buildModel(parseDescription(text, path), options, warnings);
}

Model loadModel(const std::string& path, const BuildOptions& options, std::vector<std::string>* warnings) {
  return buildModel(loadDescription(path), options, warnings);
}

}  // namespace igms
