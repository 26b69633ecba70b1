// A signed distance field of one collision mesh: the exact distance to the
// mesh at the points of a regular grid (negative inside), within a band
// around the surface; beyond it the values are clamped to ±band. Built once
// when the model loads (core/model_io/distance_field_builder.h), immutable,
// shared by every copy of the model; the tip query (core/geometry) reads it
// with trilinear interpolation in constant time, allocation-free.
#pragma once

#include <vector>

#include "core/model/spatial.h"

namespace igms {

struct DistanceField {
  Vector3 origin = Vector3::Zero();  // grid point (0, 0, 0), in the shape's frame, m
  double spacing = 0.0;              // m between grid points
  int nx = 0, ny = 0, nz = 0;        // grid points per axis
  double band = 0.0;                 // |values| ≤ band; exact where |d| < band
  std::vector<float> values;         // signed distance, m; x fastest, then y, then z

  float at(int i, int j, int k) const {
    return values[static_cast<size_t>(i) + static_cast<size_t>(nx) * (static_cast<size_t>(j) + static_cast<size_t>(ny) * static_cast<size_t>(k))];
  }
};

}  // namespace igms
