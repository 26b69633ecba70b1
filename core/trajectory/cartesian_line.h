// The paper's nominal motion (Fig. 5): a frame's origin moves on a straight
// line to a target while its orientation is held, rest to rest with a quintic
// time scaling; solved by damped least-squares inverse kinematics at samples
// and joined by a C2 cubic spline in joint space.
#pragma once

#include <string>

#include "core/trajectory/piecewise_polynomial.h"

namespace igms {

struct CartesianLine {
  int frame = -1;
  Vector3 target = Vector3::Zero();  // world, m
  double duration = 1.0;             // s
  double sample_dt = 0.02;           // IK sample spacing, s
};

// Throws std::runtime_error naming the sample where IK fails to converge.
PiecewisePolynomial cartesianLineTrajectory(const Model& model, const VectorX& q0, const CartesianLine& line);

// Damped least-squares IK of frame f to pose target (6-D when the model has at
// least 6 dof, else position only), starting from q. Returns the final error norm.
double solveIk(const Model& model, Data& data, int frame, const SE3& target, VectorX& q, int max_iterations = 100);

}  // namespace igms
