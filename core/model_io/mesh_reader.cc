#include "core/model_io/mesh_reader.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "core/model/robot_description.h"

namespace igms {
namespace {

void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, const Vector3& scale,
             TriangleMesh* out) {
  const aiMatrix4x4 X = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const int base = static_cast<int>(out->vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = X * mesh.mVertices[v];
      out->vertices.emplace_back(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      out->triangles.push_back({base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
                                base + static_cast<int>(face.mIndices[2])});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) collect(scene, *node.mChildren[c], X, scale, out);
}

}  // namespace

TriangleMesh loadTriangleMesh(const std::string& path, const Vector3& scale) {
  Assimp::Importer importer;
  // URDF meshes are in the link's frame: keep Collada's Z up (its unit still applies).
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode) throw ModelError(path + ": cannot read the mesh: " + importer.GetErrorString());
  TriangleMesh out;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), scale, &out);
  if (out.triangles.empty()) throw ModelError(path + ": the mesh has no triangles");
  return out;
}

}  // namespace igms
