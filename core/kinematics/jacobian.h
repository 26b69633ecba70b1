// Jacobians of points and frames, and the bias acceleration Jdot v.
//
// All are world-aligned: rows [linear velocity of the point; angular velocity],
// expressed in world axes, the point moving with its link.
#pragma once

#include "core/model/data.h"

namespace igms {

// J (6 x nv) of a point given in frame f's coordinates. Needs data.oMi at the
// current q (bodyKinematics or forwardKinematics). Columns of joints that do
// not move the frame are zero.
void pointJacobian(const Model& model, const Data& data, int frame, const Vector3& point_in_frame, Matrix6X& J);

// J (6 x nv) of frame f's origin, kinematics included: the poses of the bodies
// that support the frame (its body and that body's ancestors), no others.
void frameJacobian(const Model& model, Data& data, const VectorX& q, int frame, Matrix6X& J);

// Jdot v of a point of frame f: the point's classical acceleration (linear) and
// the frame's angular acceleration when qdd = 0, world axes. Leaves data.v,
// data.a (without gravity) and data.oMi at (q, v).
Vector6 pointBiasAcceleration(const Model& model, Data& data, const VectorX& q, const VectorX& v, int frame,
                              const Vector3& point_in_frame = Vector3::Zero());

}  // namespace igms
