#include "core/model_io/distance_field_builder.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "core/model/closest_point_on_triangle.h"

namespace igms {
namespace {

// Nearest distance so far, the first triangle at it, and the summed sidedness of the triangles that share it.
struct Nearest {
  double distance = std::numeric_limits<double>::infinity();
  double side = 0.0;
  int triangle = -1;
  void offer(double d, double s, int t) {
    constexpr double kTie = 1e-9;
    if (d < distance - kTie) {
      distance = d;
      side = s;
      triangle = t;
    } else if (d <= distance + kTie) {
      side += s;
    }
  }
};

// How much p lies on the outer side of triangle t, weighted by its angle at
// the nearest point's corner (a stand-in for the angle-weighted pseudo-normal).
double sidedness(const Vector3& p, const Vector3& q, const Vector3& n) {
  const Vector3 d = p - q;
  const double len = d.norm();
  return len > 0 ? n.dot(d) / len : 0.0;
}

}  // namespace

double exactSignedDistance(const TriangleMesh& mesh, const Vector3& p) {
  Nearest best;
  for (const auto& t : mesh.triangles) {
    const Vector3 &a = mesh.vertices[static_cast<size_t>(t[0])], &b = mesh.vertices[static_cast<size_t>(t[1])],
                  &c = mesh.vertices[static_cast<size_t>(t[2])];
    const Vector3 n = (b - a).cross(c - a);
    if (n.squaredNorm() == 0) continue;
    const Vector3 q = closestPointOnTriangle(p, a, b, c).point;
    best.offer((p - q).norm(), sidedness(p, q, n.normalized()), 0);
  }
  return best.side >= 0 ? best.distance : -best.distance;
}

DistanceField buildDistanceField(const TriangleMesh& mesh, double spacing, double band) {
  Vector3 lo = Vector3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vector3& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  DistanceField f;
  f.spacing = spacing;
  f.band = band;
  f.origin = lo - Vector3::Constant(band + spacing);
  const Vector3 extent = hi - lo + Vector3::Constant(2 * (band + spacing));
  f.nx = static_cast<int>(std::ceil(extent.x() / spacing)) + 1;
  f.ny = static_cast<int>(std::ceil(extent.y() / spacing)) + 1;
  f.nz = static_cast<int>(std::ceil(extent.z() / spacing)) + 1;
  const size_t n = static_cast<size_t>(f.nx) * static_cast<size_t>(f.ny) * static_cast<size_t>(f.nz);
  std::vector<Nearest> nearest(n);
  auto index = [&](int i, int j, int k) {
    return static_cast<size_t>(i) + static_cast<size_t>(f.nx) * (static_cast<size_t>(j) + static_cast<size_t>(f.ny) * static_cast<size_t>(k));
  };
  // Narrow band: each triangle updates the grid points within `band` of its bounding box.
  for (size_t ti = 0; ti < mesh.triangles.size(); ++ti) {
    const auto& t = mesh.triangles[ti];
    const Vector3 &a = mesh.vertices[static_cast<size_t>(t[0])], &b = mesh.vertices[static_cast<size_t>(t[1])],
                  &c = mesh.vertices[static_cast<size_t>(t[2])];
    Vector3 normal = (b - a).cross(c - a);
    if (normal.squaredNorm() == 0) continue;
    normal.normalize();
    const Vector3 tlo = a.cwiseMin(b).cwiseMin(c) - Vector3::Constant(band), thi = a.cwiseMax(b).cwiseMax(c) + Vector3::Constant(band);
    const Eigen::Vector3i i0 = ((tlo - f.origin) / spacing).array().floor().cast<int>().max(0);
    const Eigen::Vector3i i1 = ((thi - f.origin) / spacing).array().ceil().cast<int>().min(Eigen::Array3i(f.nx - 1, f.ny - 1, f.nz - 1));
    for (int k = i0.z(); k <= i1.z(); ++k)
      for (int j = i0.y(); j <= i1.y(); ++j)
        for (int i = i0.x(); i <= i1.x(); ++i) {
          const Vector3 p = f.origin + spacing * Vector3(i, j, k);
          const Vector3 q = closestPointOnTriangle(p, a, b, c).point;
          const double d = (p - q).norm();
          if (d < band) nearest[index(i, j, k)].offer(d, sidedness(p, q, normal), static_cast<int>(ti));
        }
  }
  // Beyond the band: outside if reachable from the boundary without crossing a point inside the band
  // that lies inside the mesh.
  std::vector<char> outside(n, 0);
  std::deque<std::array<int, 3>> todo;
  auto seed = [&](int i, int j, int k) {
    const size_t at = index(i, j, k);
    if (outside[at] || (std::isfinite(nearest[at].distance) && nearest[at].side < 0)) return;
    outside[at] = 1;
    todo.push_back({i, j, k});
  };
  for (int k = 0; k < f.nz; ++k)
    for (int j = 0; j < f.ny; ++j)
      for (int i = 0; i < f.nx; ++i)
        if (i == 0 || j == 0 || k == 0 || i == f.nx - 1 || j == f.ny - 1 || k == f.nz - 1) seed(i, j, k);
  while (!todo.empty()) {
    const auto [i, j, k] = todo.front();
    todo.pop_front();
    const size_t at = index(i, j, k);
    if (std::isfinite(nearest[at].distance)) continue;  // the band's own signs stop the fill
    if (i > 0) seed(i - 1, j, k);
    if (i < f.nx - 1) seed(i + 1, j, k);
    if (j > 0) seed(i, j - 1, k);
    if (j < f.ny - 1) seed(i, j + 1, k);
    if (k > 0) seed(i, j, k - 1);
    if (k < f.nz - 1) seed(i, j, k + 1);
  }
  f.values.resize(n);
  f.nearest.resize(n);
  for (size_t at = 0; at < n; ++at) {
    const Nearest& c = nearest[at];
    f.nearest[at] = c.triangle;
    if (std::isfinite(c.distance)) f.values[at] = static_cast<float>(c.side >= 0 ? c.distance : -c.distance);
    else f.values[at] = static_cast<float>(outside[at] ? band : -band);
  }
  return f;
}

}  // namespace igms
