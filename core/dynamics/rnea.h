// Recursive Newton-Euler inverse dynamics (Son et al. 2003, section IV.1).
#pragma once

#include <vector>

#include "core/model/data.h"

namespace igms {

// tau = H(q) a + C(q, v) v + G(q) - sum_i J_i^T f_E,i
// fext: wrench acting on each body, body coordinates (nullptr: none); see
// external_force.h. For a floating base the first 6 entries of tau are the
// base wrench [force; moment] in the base frame.
// \return data.tau
const VectorX& rnea(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX& a,
                    const std::vector<Force>* fext = nullptr);

// b(q, v) = C(q, v) v + G(q) (rnea with a = 0), minus J^T f_E when fext is given.
// \return data.bias
const VectorX& bias(const Model& model, Data& data, const VectorX& q, const VectorX& v,
                    const std::vector<Force>* fext = nullptr);

// The same with data.liMi already at q (bodyKinematics or another pass at this q placed them).
const VectorX& biasAtPlacements(const Model& model, Data& data, const VectorX& v,
                                const std::vector<Force>* fext = nullptr);

// A controller's inverse dynamics and the plant's bias at the same state, in one pass:
// data.tau = rnea(q, v, *a) (a null: bias(q, v), the hold's gravity and Coriolis compensation) and
// data.bias = bias(q, v, fext), bit for bit what the separate calls give, sharing the placements,
// the velocities and the velocity products (the server step's computed torque and forward dynamics).
void rneaAndBias(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX* a,
                 const std::vector<Force>* fext = nullptr);

// The same with data.liMi already at q.
void rneaAndBiasAtPlacements(const Model& model, Data& data, const VectorX& v, const VectorX* a,
                             const std::vector<Force>* fext = nullptr);

}  // namespace igms
