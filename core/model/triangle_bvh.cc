#include "core/model/triangle_bvh.h"

#include <algorithm>
#include <numeric>

#include "core/model/triangle_mesh.h"

namespace igms {
namespace {

struct Builder {
  const TriangleMesh& mesh;
  std::vector<Vector3> centre;  // per triangle
  TriangleBvh out;

  void bounds(int first, int count, Vector3& lo, Vector3& hi) const {
    lo = Vector3::Constant(INFINITY);
    hi = -lo;
    for (int k = first; k < first + count; ++k)
      for (int v : mesh.triangles[static_cast<size_t>(out.order[static_cast<size_t>(k)])]) {
        lo = lo.cwiseMin(mesh.vertices[static_cast<size_t>(v)]);
        hi = hi.cwiseMax(mesh.vertices[static_cast<size_t>(v)]);
      }
  }

  int build(int first, int count, int depth) {
    const int at = static_cast<int>(out.nodes.size());
    out.nodes.emplace_back();
    Vector3 lo, hi;
    bounds(first, count, lo, hi);
    out.nodes[static_cast<size_t>(at)].lo = lo;
    out.nodes[static_cast<size_t>(at)].hi = hi;
    if (count <= TriangleBvh::kLeafTriangles || depth + 1 >= TriangleBvh::kMaxDepth) {
      out.nodes[static_cast<size_t>(at)].first = first;
      out.nodes[static_cast<size_t>(at)].count = count;
      return at;
    }
    // Split at the median centre along the axis the centres spread most.
    Vector3 clo = Vector3::Constant(INFINITY), chi = -clo;
    for (int k = first; k < first + count; ++k) {
      clo = clo.cwiseMin(centre[static_cast<size_t>(out.order[static_cast<size_t>(k)])]);
      chi = chi.cwiseMax(centre[static_cast<size_t>(out.order[static_cast<size_t>(k)])]);
    }
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    const int half = count / 2;
    auto begin = out.order.begin() + first;
    std::nth_element(begin, begin + half, begin + count, [&](int a, int b) {
      return centre[static_cast<size_t>(a)][axis] < centre[static_cast<size_t>(b)][axis];
    });
    build(first, half, depth + 1);
    const int second = build(first + half, count - half, depth + 1);
    out.nodes[static_cast<size_t>(at)].second = second;
    return at;
  }
};

}  // namespace

TriangleBvh buildTriangleBvh(const TriangleMesh& mesh) {
  Builder b{mesh, {}, {}};
  const int n = static_cast<int>(mesh.triangles.size());
  if (n == 0) return {};
  b.centre.reserve(static_cast<size_t>(n));
  for (const auto& t : mesh.triangles)
    b.centre.push_back((mesh.vertices[static_cast<size_t>(t[0])] + mesh.vertices[static_cast<size_t>(t[1])] +
                        mesh.vertices[static_cast<size_t>(t[2])]) /
                       3.0);
  b.out.order.resize(static_cast<size_t>(n));
  std::iota(b.out.order.begin(), b.out.order.end(), 0);
  b.out.nodes.reserve(static_cast<size_t>(2 * n / TriangleBvh::kLeafTriangles + 2));
  b.build(0, n, 0);
  return std::move(b.out);
}

}  // namespace igms
