// What identifies a model's files, for a log: the FNV-1a 64 hash of each mesh
// file the model names (collision and visual), as written in the model. A
// replay on another machine compares them with the meshes it resolves.
#pragma once

#include <string>
#include <vector>

#include "core/model/model.h"

namespace igms {

struct MeshFingerprint {
  std::string uri;   // as written in the model file
  std::string hash;  // textHash of the file's bytes; "missing" when it does not resolve
};

// Each distinct mesh once, in the order the model's frames name them.
std::vector<MeshFingerprint> meshFingerprints(const Model& model, const std::string& model_path);
// The same for frames [frame_begin, frame_end) (one part of an environment: a robot, resolved beside
// its own model file; the free bodies, beside the scene).
std::vector<MeshFingerprint> meshFingerprints(const Model& model, const std::string& model_path, int frame_begin,
                                              int frame_end);

}  // namespace igms
