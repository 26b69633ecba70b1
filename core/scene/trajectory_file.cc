#include "core/scene/trajectory_file.h"

#include <yaml-cpp/yaml.h>

#include <stdexcept>

namespace igms {

std::string trajectoryFileText(const std::string& source, const std::vector<std::string>& joints,
                               const std::vector<double>& times, const std::vector<VectorX>& q) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);  // a re-read file gives the same doubles
  out << YAML::Comment("Edited trajectory. Load it as a scene's nominal trajectory: trajectory: {kind: file, file: THIS_FILE}");
  out << YAML::BeginMap;
  out << YAML::Key << "source" << YAML::Value << source;
  out << YAML::Key << "joints" << YAML::Value << YAML::Flow << joints;
  out << YAML::Key << "waypoints" << YAML::Value << YAML::BeginSeq;
  for (size_t k = 0; k < times.size(); ++k) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "t" << YAML::Value << times[k] << YAML::Key << "q"
        << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (Eigen::Index j = 0; j < q[k].size(); ++j) out << q[k][j];
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  if (!out.good()) throw std::runtime_error("trajectory file: " + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

}  // namespace igms
