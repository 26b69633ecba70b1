// RobotDescription: a robot as links and joints, the common ground of the URDF
// loader, the DH loader and the random-tree generator. buildModel() turns it
// into a Model (fixed joints merged, bodies ordered, everything validated).
#pragma once

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model/model.h"

namespace igms {

// Raised for any model that cannot be built; the message names the file and
// the element ("models/x.urdf: link 'l3': inertia is not positive semi-definite").
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LinkDescription {
  std::string name;
  double mass = 0.0;                  // 0 for a link without <inertial>
  Vector3 com = Vector3::Zero();      // in the link frame
  Matrix3 inertia = Matrix3::Zero();  // about the com, axes of the link frame
  std::vector<CollisionShape> collisions;
  std::vector<VisualShape> visuals;
};

struct JointDescription {
  enum class Type { Revolute, Continuous, Prismatic, Fixed, Floating, Planar };
  std::string name;
  Type type = Type::Fixed;
  std::string parent, child;
  SE3 origin;                               // joint frame in the parent link frame
  Vector3 axis = Vector3(1.0, 0.0, 0.0);    // URDF default
  double damping = 0.0, friction = 0.0;
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  double effort = std::numeric_limits<double>::infinity();
  double velocity = std::numeric_limits<double>::infinity();
  std::string mimic;                        // <mimic joint="..."/>: the leader ("" : none)
  double mimic_multiplier = 1.0, mimic_offset = 0.0;
};

struct RobotDescription {
  std::string name;
  std::string source;  // file name for messages ("<string>" when built in memory)
  std::vector<LinkDescription> links;
  std::vector<JointDescription> joints;
};

struct BuildOptions {
  bool floating_base = false;
  Vector3 gravity = Vector3(0.0, 0.0, -9.81);
};

// The whole text of a model file; ModelError "PATH: cannot open the file".
std::string readModelFile(const std::string& path);

// FNV-1a 64 of a text, as 16 hex digits: identifies a model file in logs.
std::string textHash(const std::string& text);

// Warnings (valid but suspicious data) are appended to *warnings when given.
Model buildModel(const RobotDescription& description, const BuildOptions& options,
                 std::vector<std::string>* warnings = nullptr);

}  // namespace igms
