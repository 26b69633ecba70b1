#include "core/model_io/mesh_fields.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <optional>
#include <thread>
#include <vector>

#include "core/model_io/distance_field_builder.h"
#include "core/model_io/distance_field_cache.h"
#include "core/model_io/mesh_reader.h"
#include "core/model_io/mesh_samples.h"
#include "core/model_io/resource_path.h"

namespace igms {

void attachDistanceFields(RobotDescription& description, const std::string& urdf_path,
                          const MeshFieldOptions& options) {
  // One field per file and scale, shared by every link that uses it.
  struct Built {
    TriangleMesh mesh;
    double spacing = 0.0;
    uint64_t key = 0;
    std::optional<DistanceField> field;
    std::shared_ptr<const DistanceField> shared_field;
    std::shared_ptr<const TriangleMesh> triangles;
    std::shared_ptr<const std::vector<Vector3>> samples;
  };
  std::map<std::string, Built> built;
  std::vector<std::pair<CollisionShape*, Built*>> uses;
  // Find and read every mesh (assimp), and take what the cache has.
  for (LinkDescription& link : description.links) {
    for (CollisionShape& shape : link.collisions) {
      if (shape.kind != CollisionShape::Kind::Mesh) continue;
      const ResourceResolution found = resolveResource(shape.mesh_file, urdf_path);
      if (found.path.empty()) {
        std::string tried;
        for (const auto& t : found.tried) tried += (tried.empty() ? "" : ", ") + t;
        throw ModelError(urdf_path + ": link '" + link.name + "': collision mesh '" + shape.mesh_file +
                         "' not found (tried: " + (tried.empty() ? "nothing" : tried) +
                         "; set IGMS_PACKAGE_PATH to the folder that holds its package)");
      }
      const std::string name = found.path + "|" + std::to_string(shape.mesh_scale.x()) + "," +
                               std::to_string(shape.mesh_scale.y()) + "," + std::to_string(shape.mesh_scale.z());
      const auto [it, is_new] = built.try_emplace(name);
      uses.emplace_back(&shape, &it->second);
      if (!is_new) continue;
      Built& b = it->second;
      try {
        b.mesh = loadTriangleMesh(found.path, shape.mesh_scale);
        b.mesh.bvh = buildTriangleBvh(b.mesh);
      } catch (const ModelError& e) {
        throw ModelError(urdf_path + ": link '" + link.name + "': " + e.what());
      }
      Vector3 lo = Vector3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (const Vector3& v : b.mesh.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
      const Vector3 extent = hi - lo + Vector3::Constant(2 * options.band);
      b.spacing = options.spacing;
      while ((extent.x() / b.spacing + 3) * (extent.y() / b.spacing + 3) * (extent.z() / b.spacing + 3) >
             static_cast<double>(options.max_points))
        b.spacing *= 1.25;
      b.key = distanceFieldKey(b.mesh, b.spacing, options.band);
      if (options.use_cache) b.field = readCachedField(b.key);
    }
  }
  // Build the rest on every core (Talos: 52 meshes), largest first.
  std::vector<Built*> todo;
  for (auto& [name, b] : built)
    if (!b.field) todo.push_back(&b);
  std::sort(todo.begin(), todo.end(), [](const Built* a, const Built* b) {
    return a->mesh.triangles.size() > b->mesh.triangles.size();
  });
  std::atomic<size_t> next{0};
  std::vector<std::exception_ptr> failures(todo.size());
  auto work = [&] {
    for (size_t k = next++; k < todo.size(); k = next++) {
      try {
        todo[k]->field = buildDistanceField(todo[k]->mesh, todo[k]->spacing, options.band);
        if (options.use_cache) writeCachedField(todo[k]->key, *todo[k]->field);
      } catch (...) {
        failures[k] = std::current_exception();
      }
    }
  };
  const size_t workers = std::min<size_t>(todo.size(), std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (size_t w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : failures)
    if (e) std::rethrow_exception(e);
  for (auto& [shape, b] : uses) {
    if (!b->shared_field) {
      b->shared_field = std::make_shared<const DistanceField>(std::move(*b->field));
      b->samples = std::make_shared<const std::vector<Vector3>>(meshSurfaceSamples(b->mesh));
      b->triangles = std::make_shared<const TriangleMesh>(std::move(b->mesh));
    }
    shape->field = b->shared_field;
    shape->triangles = b->triangles;
    shape->samples = b->samples;
  }
}

}  // namespace igms
