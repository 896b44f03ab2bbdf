#pragma once
// Cutting a mesh along the zero level set of a per-vertex scalar.
#include <Eigen/Core>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// Keeps the part of the mesh where the linearly interpolated `g` (one value per vertex) is
// >= 0. Triangles crossing the level set are split at the crossing points (shared between
// neighbours, so the result stays a manifold with a clean border).
TriMesh clip_mesh(const TriMesh& mesh, const Eigen::VectorXd& g);

}  // namespace pb4u
