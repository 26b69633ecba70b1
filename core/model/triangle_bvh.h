// A bounding-volume hierarchy over a triangle mesh's triangles: axis-aligned boxes, split at the
// median of the longest axis, up to kLeafTriangles per leaf, stored depth-first in one array (a
// node's first child follows it; `second` names the other). Built once with the mesh (immutable);
// core/geometry/mesh_query.h walks it without allocating. What it answers that a distance field
// kept in a narrow band cannot: the exact nearest surface from any point, however far (a large
// sphere's centre, a point deep inside).
#pragma once

#include <vector>

#include "core/model/spatial.h"

namespace igms {

struct TriangleMesh;

struct TriangleBvh {
  static constexpr int kLeafTriangles = 4;
  static constexpr int kMaxDepth = 64;  // the query's stack; the build splits at the median: depth ~ log2(n)
  struct Node {
    Vector3 lo, hi;   // the box of its triangles
    int first = 0;    // a leaf: its triangles are order[first, first + count)
    int count = 0;    // 0: an inner node, children at this + 1 and `second`
    int second = -1;
  };
  std::vector<Node> nodes;
  std::vector<int> order;  // triangle indices, leaf by leaf
  bool empty() const { return nodes.empty(); }
};

TriangleBvh buildTriangleBvh(const TriangleMesh& mesh);

}  // namespace igms
