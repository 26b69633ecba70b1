// Conversions between igms's vectors and KDL's joint arrays, by joint name.
#pragma once

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <map>
#include <vector>

#include "core/model/data.h"

namespace igms::test {

// kdl index k -> igms v index.
using JointMap = std::vector<int>;

inline JointMap jointMap(const Model& model, const KDL::Chain& chain) {
  JointMap map;
  for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) {
    const KDL::Joint& j = chain.getSegment(s).getJoint();
    if (j.getType() == KDL::Joint::Fixed) continue;
    map.push_back(model.v_index[static_cast<size_t>(model.jointIndex(j.getName()))]);
  }
  return map;
}

inline JointMap jointMap(const Model& model, const std::map<std::string, unsigned>& q_nr_of_joint) {
  JointMap map(q_nr_of_joint.size());
  for (const auto& [name, k] : q_nr_of_joint) map[k] = model.v_index[static_cast<size_t>(model.jointIndex(name))];
  return map;
}

inline KDL::JntArray toKdl(const VectorX& x, const JointMap& map) {
  KDL::JntArray out(static_cast<unsigned>(map.size()));
  for (size_t k = 0; k < map.size(); ++k) out(static_cast<unsigned>(k)) = x[map[k]];
  return out;
}

inline VectorX fromKdl(const KDL::JntArray& x, const JointMap& map) {
  VectorX out = VectorX::Zero(static_cast<int>(map.size()));
  for (size_t k = 0; k < map.size(); ++k) out[map[k]] = x(static_cast<unsigned>(k));
  return out;
}

// Columns (and rows, when row_map is given) from KDL order to igms order.
inline MatrixX fromKdl(const MatrixX& M, const JointMap& col_map, const JointMap& row_map = {}) {
  const bool square = !row_map.empty();
  MatrixX out = MatrixX::Zero(square ? static_cast<int>(row_map.size()) : M.rows(), static_cast<int>(col_map.size()));
  for (int r = 0; r < M.rows(); ++r)
    for (size_t c = 0; c < col_map.size(); ++c) out(square ? row_map[r] : r, col_map[c]) = M(r, static_cast<int>(c));
  return out;
}

inline double poseError(const SE3& X, const KDL::Frame& F) {
  double e = 0.0;
  for (int r = 0; r < 3; ++r) {
    e = std::max(e, std::abs(X.p[r] - F.p(r)));
    for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(X.R(r, c) - F.M(r, c)));
  }
  return e;
}

// A world-frame force at a point of a segment, as KDL wants it: the wrench on
// the segment, in the segment frame, about its origin.
inline KDL::Wrench wrenchOnSegment(const KDL::Frame& oMs, const Vector3& point, const Vector3& force_world) {
  const KDL::Vector f = oMs.M.Inverse(KDL::Vector(force_world.x(), force_world.y(), force_world.z()));
  const KDL::Vector r(point.x(), point.y(), point.z());
  return KDL::Wrench(f, r * f);
}

}  // namespace igms::test
