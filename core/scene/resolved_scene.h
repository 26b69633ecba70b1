// A scene resolved against its model, once: the one value the server, the
// client, the tools and the tests build a run from. It holds the loaded model
// and every per-joint and per-link setting the scene names by size or by
// name, checked: the initial state, the computed-torque gains, the pull link.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace igms {

struct ResolvedScene {
  Scene scene;
  std::shared_ptr<const Model> model;
  VectorX q0, v0;      // nq, nv (neutral and at rest when the scene gives none); q0 normalised
  VectorX kp, kd;      // nv: per-joint computed-torque gains
  int pull_frame = -1; // interaction.pull.link (default: the model's last link); -1 when pull is off
  // What the scene cannot do as written, one line each (the programs print them at start): with push
  // on, every moving link with mass but nothing the tip can touch; mimic joints treated as independent.
  std::vector<std::string> warnings;
};

// Loads the model and checks the scene against it. Throws SceneError naming
// the scene file and the key, or ModelError naming the model file.
ResolvedScene resolveScene(const Scene& scene);

}  // namespace igms
