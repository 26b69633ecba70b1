#include "core/model_io/mesh_samples.h"

#include <cmath>
#include <map>
#include <tuple>

namespace igms {

namespace {

std::vector<Vector3> samplesAt(const TriangleMesh& mesh, double spacing) {
  std::map<std::tuple<long, long, long>, int> taken;  // grid cell -> first point in it
  std::vector<Vector3> out;
  auto add = [&](const Vector3& p) {
    const auto cell = std::make_tuple(std::lround(std::floor(p.x() / spacing)), std::lround(std::floor(p.y() / spacing)),
                                      std::lround(std::floor(p.z() / spacing)));
    if (taken.emplace(cell, static_cast<int>(out.size())).second) out.push_back(p);
  };
  for (const Vector3& v : mesh.vertices) add(v);
  for (const auto& t : mesh.triangles) {
    const Vector3 &a = mesh.vertices[static_cast<size_t>(t[0])], &b = mesh.vertices[static_cast<size_t>(t[1])],
                  &c = mesh.vertices[static_cast<size_t>(t[2])];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int k = static_cast<int>(std::ceil(longest / spacing));
    if (k < 2) continue;
    for (int i = 1; i < k; ++i)
      for (int j = 1; i + j < k; ++j) add(a + (b - a) * (double(i) / k) + (c - a) * (double(j) / k));
  }
  return out;
}

}  // namespace

std::vector<Vector3> meshSurfaceSamples(const TriangleMesh& mesh, double spacing) {
  for (;; spacing *= 1.25) {
    std::vector<Vector3> out = samplesAt(mesh, spacing);
    if (static_cast<int>(out.size()) <= kMaxMeshSamples) return out;
  }
}

}  // namespace igms
