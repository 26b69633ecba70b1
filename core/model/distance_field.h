// A signed distance field of one collision mesh: the exact distance to the
// mesh at the points of a regular grid (negative inside), within a band
// around the surface; beyond it the values are clamped to ±band. Built once
// when the model loads (core/model_io/distance_field_builder.h), immutable,
// shared by every copy of the model. The tip query (core/geometry) reads it
// in constant time, allocation-free: trilinear interpolation for the side and
// for points far from the surface; near it, the exact distance and normal to
// the triangles nearest the query's cell corners (`nearest`).
#pragma once

#include <cstdint>
#include <vector>

#include "core/model/spatial.h"

namespace igms {

struct DistanceField {
  Vector3 origin = Vector3::Zero();  // grid point (0, 0, 0), in the shape's frame, m
  double spacing = 0.0;              // m between grid points
  int nx = 0, ny = 0, nz = 0;        // grid points per axis
  double band = 0.0;                 // |values| ≤ band; exact where |d| < band
  std::vector<float> values;         // signed distance, m; x fastest, then y, then z
  std::vector<int32_t> nearest;      // per grid point: the nearest triangle of the mesh, -1 beyond the band

  size_t index(int i, int j, int k) const {
    return static_cast<size_t>(i) + static_cast<size_t>(nx) * (static_cast<size_t>(j) + static_cast<size_t>(ny) * static_cast<size_t>(k));
  }
  float at(int i, int j, int k) const { return values[index(i, j, k)]; }
};

}  // namespace igms
