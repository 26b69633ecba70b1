// A scene resolved against its models, once: the one value the server, the
// client, the tools and the tests build a run from. It holds the environment
// model (every robot and free body, each a tree: environment_model.h) and
// every per-joint and per-link setting the scene names by size or by name,
// checked: the initial state, the gains, the pull link, the materials.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/geometry/geometry_model.h"
#include "core/scene/scene.h"

namespace igms {

// One robot of the scene, where it sits in the environment model.
struct ResolvedRobot {
  std::string name;     // "" for the short form robot:
  int part = -1;        // its tree: model->parts[part]
  int spec = -1;        // scene.robots[spec]
  VectorX kp, kd;       // its nv: per-joint gains
};

struct ResolvedScene {
  Scene scene;                          // mesh obstacles carry their fields here
  std::shared_ptr<const Model> model;   // the environment: robots first, then free bodies
  VectorX q0, v0;      // nq, nv (neutral and at rest when the scene gives none); q0 normalised
  VectorX kp, kd;      // nv: per-joint gains (zero on free bodies)
  int pull_frame = -1; // interaction.pull.link (default: the first robot's last link); -1 when pull is off
  std::vector<ResolvedRobot> robots;
  std::vector<int> part_material;       // per model part: its material's index in material_names
  std::vector<std::string> material_names;  // the scene's materials, "default" first
  // What the scene cannot do as written, one line each (the programs print them at start): with push
  // on, every moving link with mass but nothing the tip can touch; mimic joints treated as independent.
  std::vector<std::string> warnings;
  // The geometry world (core/geometry/geometry_model.h): the model's collision shapes, then the
  // scene's obstacles in its order (solid and ghost) and the ground. What the contact layer, the
  // hands' proxies and the obstacle monitor all index into.
  std::shared_ptr<const GeometryModel> geometry;

  int materialIndex(const std::string& name) const;  // "" : default
};

// Loads the models and checks the scene against them. Throws SceneError naming
// the scene file and the key, or ModelError naming the model file.
ResolvedScene resolveScene(const Scene& scene);

}  // namespace igms
