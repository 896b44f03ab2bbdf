#pragma once
// A skinned, animated mesh from any file assimp reads with bones (glTF/GLB, FBX, DAE) as a
// Body, with its animations as Motions.
#include <string>
#include <vector>

#include "pb4u/body/body.h"

namespace pb4u {

struct SkinnedMeshFile {
  Body body;                    // mesh at the file's default node pose (= body.bind)
  std::vector<std::string> animation_names;
  std::vector<Motion> motions;  // one per animation, resampled to the requested fps
};

// The skeleton is the node tree under the lowest common ancestor of the bones; joint offsets
// are the nodes' translations (a uniform scale above the skeleton, e.g. FBX centimetres, is
// folded in), their default rotations form the bind pose, and the mesh is re-posed to it
// with the bones' inverse bind matrices. Animated rotations drive every joint; animated
// translation drives the root only. Throws pb4u::Error naming `path` when the file cannot
// be read or has no bones.
SkinnedMeshFile read_skinned_mesh(const std::string& path, double fps = 30.0);

}  // namespace pb4u
