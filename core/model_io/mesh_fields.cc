#include "core/model_io/mesh_fields.h"

#include <cmath>
#include <limits>
#include <map>

#include "core/model_io/distance_field_builder.h"
#include "core/model_io/distance_field_cache.h"
#include "core/model_io/mesh_reader.h"
#include "core/model_io/resource_path.h"

namespace igms {

void attachDistanceFields(RobotDescription& description, const std::string& urdf_path,
                          const MeshFieldOptions& options) {
  // One field per file and scale, shared by every link that uses it.
  struct Built {
    std::shared_ptr<const DistanceField> field;
    std::shared_ptr<const TriangleMesh> triangles;
  };
  std::map<std::string, Built> built;
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
      const std::string key = found.path + "|" + std::to_string(shape.mesh_scale.x()) + "," +
                              std::to_string(shape.mesh_scale.y()) + "," + std::to_string(shape.mesh_scale.z());
      Built& done = built[key];
      if (!done.field) {
        TriangleMesh mesh;
        try {
          mesh = loadTriangleMesh(found.path, shape.mesh_scale);
        } catch (const ModelError& e) {
          throw ModelError(urdf_path + ": link '" + link.name + "': " + e.what());
        }
        Vector3 lo = Vector3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
        for (const Vector3& v : mesh.vertices) {
          lo = lo.cwiseMin(v);
          hi = hi.cwiseMax(v);
        }
        const Vector3 extent = hi - lo + Vector3::Constant(2 * options.band);
        double spacing = options.spacing;
        while ((extent.x() / spacing + 3) * (extent.y() / spacing + 3) * (extent.z() / spacing + 3) >
               static_cast<double>(options.max_points))
          spacing *= 1.25;
        const uint64_t key = distanceFieldKey(mesh, spacing, options.band);
        std::optional<DistanceField> cached = options.use_cache ? readCachedField(key) : std::nullopt;
        if (!cached) {
          cached = buildDistanceField(mesh, spacing, options.band);
          if (options.use_cache) writeCachedField(key, *cached);
        }
        done.field = std::make_shared<const DistanceField>(std::move(*cached));
        done.triangles = std::make_shared<const TriangleMesh>(std::move(mesh));
      }
      shape.field = done.field;
      shape.triangles = done.triangles;
    }
  }
}

}  // namespace igms
