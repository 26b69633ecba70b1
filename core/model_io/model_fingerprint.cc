#include "core/model_io/model_fingerprint.h"

#include <algorithm>
#include <set>

#include "core/model/robot_description.h"
#include "core/model_io/resource_path.h"

namespace igms {

std::vector<MeshFingerprint> meshFingerprints(const Model& model, const std::string& model_path) {
  return meshFingerprints(model, model_path, 0, static_cast<int>(model.frames.size()));
}

std::vector<MeshFingerprint> meshFingerprints(const Model& model, const std::string& model_path, int frame_begin,
                                              int frame_end) {
  std::vector<MeshFingerprint> out;
  std::set<std::string> seen;
  auto add = [&](const CollisionShape& s) {
    if (s.kind != CollisionShape::Kind::Mesh || s.mesh_file.empty() || !seen.insert(s.mesh_file).second) return;
    MeshFingerprint f{s.mesh_file, "missing"};
    const ResourceResolution found = resolveResource(s.mesh_file, model_path);
    if (!found.path.empty()) {
      try {
        f.hash = textHash(readModelFile(found.path));
      } catch (const std::exception&) {
      }
    }
    out.push_back(std::move(f));
  };
  for (int f = std::max(frame_begin, 0); f < std::min(frame_end, static_cast<int>(model.frames.size())); ++f) {
    const Frame& frame = model.frames[static_cast<size_t>(f)];
    for (const CollisionShape& c : frame.collisions) add(c);
    for (const VisualShape& v : frame.visuals) add(v.geometry);
  }
  return out;
}

}  // namespace igms
