// The joint trajectory file a scene reads (trajectory: {kind: file, file: F})
// and the server writes (the edited trajectory, --save-edited): YAML with the
// joint names the columns belong to, written by yaml-cpp's emitter.
//   source: scenes/puma_obstacle.yaml
//   joints: [joint1, ..., joint6]
//   waypoints:
//     - {t: 0, q: [..]}
#pragma once

#include <string>
#include <vector>

#include "core/model/data.h"

namespace igms {

// Rows of q (one per time) as the file's text; doubles round-trip exactly.
std::string trajectoryFileText(const std::string& source, const std::vector<std::string>& joints,
                               const std::vector<double>& times, const std::vector<VectorX>& q);

}  // namespace igms
