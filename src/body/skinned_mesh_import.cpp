#include "pb4u/body/skinned_mesh_import.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "pb4u/body/forward_kinematics.h"
#include "pb4u/body/linear_blend_skinning.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return e;
}

Eigen::Quaterniond to_eigen(const aiQuaternion& q) {
  return Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized();
}

aiMatrix4x4 global_transform(const aiNode* node) {
  aiMatrix4x4 m;
  for (; node; node = node->mParent) m = node->mTransformation * m;
  return m;
}

std::vector<const aiNode*> path_from_root(const aiNode* node) {
  std::vector<const aiNode*> path;
  for (; node; node = node->mParent) path.push_back(node);
  std::reverse(path.begin(), path.end());
  return path;
}

// Piecewise-linear / slerp sampling of an assimp key track at `ticks`.
template <class Key, class Value, class Lerp>
Value sample(const Key* keys, unsigned count, double ticks, Value fallback, Lerp lerp) {
  if (count == 0) return fallback;
  if (ticks <= keys[0].mTime) return keys[0].mValue;
  for (unsigned k = 0; k + 1 < count; ++k)
    if (ticks < keys[k + 1].mTime) {
      const double a = (ticks - keys[k].mTime) / std::max(keys[k + 1].mTime - keys[k].mTime, 1e-12);
      return lerp(keys[k].mValue, keys[k + 1].mValue, a);
    }
  return keys[count - 1].mValue;
}

}  // namespace

SkinnedMeshFile read_skinned_mesh(const std::string& path, double fps) {
  if (!std::filesystem::exists(path)) fail_file(path, "no such file");
  if (!(fps > 0)) fail_file(path, "fps must be positive");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_LimitBoneWeights |
                aiProcess_ValidateDataStructure | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode) fail_file(path, std::string("cannot read: ") + importer.GetErrorString());

  // Bones and their nodes.
  std::map<std::string, aiMatrix4x4> inverse_bind;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    for (unsigned b = 0; b < scene->mMeshes[m]->mNumBones; ++b) {
      const aiBone* bone = scene->mMeshes[m]->mBones[b];
      inverse_bind[bone->mName.C_Str()] = bone->mOffsetMatrix;
    }
  if (inverse_bind.empty()) fail_file(path, "no skinned mesh (no bones); use it as a garment or mesh instead");
  std::vector<const aiNode*> common;
  for (const auto& [name, _] : inverse_bind) {
    const aiNode* node = scene->mRootNode->FindNode(name.c_str());
    if (!node) fail_file(path, "bone '" + name + "' has no node");
    std::vector<const aiNode*> p = path_from_root(node);
    if (common.empty()) {
      common = p;
    } else {
      size_t n = 0;
      while (n < common.size() && n < p.size() && common[n] == p[n]) ++n;
      common.resize(n);
    }
  }
  const aiNode* lca = common.back();

  // Skeleton: the subtree under the common ancestor, depth first (parents first).
  SkinnedMeshFile out;
  Body& body = out.body;
  body.name = std::filesystem::path(path).stem().string();
  Skeleton& s = body.skeleton;
  std::vector<const aiNode*> nodes;
  std::map<const aiNode*, int> index;
  std::vector<std::pair<const aiNode*, int>> stack = {{lca, -1}};
  while (!stack.empty()) {
    auto [node, parent] = stack.back();
    stack.pop_back();
    index[node] = static_cast<int>(nodes.size());
    nodes.push_back(node);
    s.names.push_back(node->mName.C_Str());
    s.parents.push_back(parent);
    for (int c = static_cast<int>(node->mNumChildren) - 1; c >= 0; --c)
      stack.push_back({node->mChildren[c], index[node]});
  }
  const int J = static_cast<int>(nodes.size());
  // The root carries everything above it; a uniform scale there (FBX centimetres) scales
  // every offset below it.
  aiVector3D scaling, position;
  aiQuaternion rotation;
  global_transform(lca).Decompose(scaling, rotation, position);
  const double scale = scaling.x;
  if (std::abs(scaling.y - scale) > 1e-4 * scale || std::abs(scaling.z - scale) > 1e-4 * scale)
    fail_file(path, "non-uniform scale above the skeleton is not supported");
  s.offsets.resize(J, 3);
  body.bind = rest_pose(s);
  for (int j = 0; j < J; ++j) {
    if (j == 0) {
      s.offsets.row(0) << position.x, position.y, position.z;
      body.bind.rotations[0] = to_eigen(rotation);
      continue;
    }
    aiVector3D sc, t;
    aiQuaternion q;
    nodes[j]->mTransformation.Decompose(sc, q, t);
    s.offsets.row(j) = scale * Eigen::RowVector3d(t.x, t.y, t.z);
    body.bind.rotations[j] = to_eigen(q);
  }
  validate_skeleton(s, path);

  // Mesh and weights, re-posed to the default node pose: v = sum_j w_j G_j S(scale) B_j v_mesh
  // with B_j the bone's inverse bind matrix.
  const JointTransforms G = forward_kinematics(s, body.bind);
  std::vector<Eigen::RowVector3d> verts;
  std::vector<Eigen::RowVector3i> faces;
  std::vector<std::vector<std::pair<int, double>>> influences;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (mesh->mNumBones == 0 || !(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const int base = static_cast<int>(verts.size());
    influences.resize(base + mesh->mNumVertices);
    for (unsigned b = 0; b < mesh->mNumBones; ++b) {
      const aiBone* bone = mesh->mBones[b];
      const int j = index.at(scene->mRootNode->FindNode(bone->mName));
      for (unsigned w = 0; w < bone->mNumWeights; ++w)
        if (bone->mWeights[w].mVertexId < mesh->mNumVertices)
          influences[base + bone->mWeights[w].mVertexId].push_back({j, bone->mWeights[w].mWeight});
    }
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const Eigen::Vector4d p(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z, 1.0);
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      double total = 0;
      for (const auto& [j, w] : influences[base + v]) {
        const Eigen::Matrix4d B = to_eigen(inverse_bind.at(s.names[j]));
        const Eigen::Vector4d local = B * p;
        x += w * (G[j] * (scale * local.head<3>()));
        total += w;
      }
      if (total <= 0) fail_file(path, "vertex " + std::to_string(v) + " of mesh " + std::to_string(m) + " has no bone weights");
      verts.push_back((x / total).transpose());
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f)
      if (mesh->mFaces[f].mNumIndices == 3)
        faces.emplace_back(base + mesh->mFaces[f].mIndices[0], base + mesh->mFaces[f].mIndices[1],
                           base + mesh->mFaces[f].mIndices[2]);
  }
  if (faces.empty()) fail_file(path, "the skinned meshes have no triangles");
  body.mesh.V.resize(verts.size(), 3);
  body.weights = Eigen::MatrixXd::Zero(verts.size(), J);
  for (size_t i = 0; i < verts.size(); ++i) {
    body.mesh.V.row(i) = verts[i];
    for (const auto& [j, w] : influences[i]) body.weights(i, j) += w;
  }
  body.mesh.F.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) body.mesh.F.row(f) = faces[f];
  if (!body.mesh.V.allFinite()) fail_file(path, "non-finite vertex positions after skinning");
  limit_and_normalize_weights(body.weights, 4);

  // Animations: rotations for every joint, translation for the root only.
  const aiMatrix4x4 above = lca->mParent ? global_transform(lca->mParent) : aiMatrix4x4();
  for (unsigned a = 0; a < scene->mNumAnimations; ++a) {
    const aiAnimation* anim = scene->mAnimations[a];
    const double tps = anim->mTicksPerSecond > 0 ? anim->mTicksPerSecond : 25.0;
    const double seconds = anim->mDuration / tps;
    std::vector<const aiNodeAnim*> channel(J, nullptr);
    for (unsigned c = 0; c < anim->mNumChannels; ++c) {
      const aiNode* node = scene->mRootNode->FindNode(anim->mChannels[c]->mNodeName);
      auto it = index.find(node);
      if (it != index.end()) channel[it->second] = anim->mChannels[c];
    }
    Motion motion;
    motion.fps = fps;
    const int frames = static_cast<int>(std::floor(seconds * fps + 1e-6)) + 1;
    for (int k = 0; k < frames; ++k) {
      const double ticks = k / fps * tps;
      Pose pose = body.bind;
      for (int j = 0; j < J; ++j) {
        const aiNodeAnim* ch = channel[j];
        if (!ch) continue;
        aiVector3D sc, t;
        aiQuaternion q;
        nodes[j]->mTransformation.Decompose(sc, q, t);
        q = sample(ch->mRotationKeys, ch->mNumRotationKeys, ticks, q,
                   [](const aiQuaternion& x, const aiQuaternion& y, double w) {
                     aiQuaternion r;
                     aiQuaternion::Interpolate(r, x, y, static_cast<float>(w));
                     return r;
                   });
        if (j > 0) {
          pose.rotations[j] = to_eigen(q);
          continue;
        }
        t = sample(ch->mPositionKeys, ch->mNumPositionKeys, ticks, t,
                   [](const aiVector3D& x, const aiVector3D& y, double w) {
                     return x + (y - x) * static_cast<float>(w);
                   });
        aiMatrix4x4 local(sc, q, t);
        aiVector3D gs, gt;
        aiQuaternion gq;
        (above * local).Decompose(gs, gq, gt);
        pose.rotations[0] = to_eigen(gq);
        pose.root = Eigen::Vector3d(gt.x, gt.y, gt.z) - s.offsets.row(0).transpose();
      }
      motion.frames.push_back(std::move(pose));
    }
    out.animation_names.push_back(anim->mName.length ? anim->mName.C_Str() : "animation_" + std::to_string(a + 1));
    out.motions.push_back(std::move(motion));
  }
  return out;
}

}  // namespace pb4u
