#pragma once
// Brute-force distances for small test meshes: exact point-triangle distance, winding-number
// inside test and symmetric Hausdorff distance over vertices.
#include <Eigen/Core>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u::test {

// Unsigned distance (m) from p to the nearest triangle of m.
double point_mesh_distance(const Eigen::Vector3d& p, const TriMesh& m);

// Signed distance to a closed mesh: negative inside (generalised winding number > 0.5).
double signed_distance(const Eigen::Vector3d& p, const TriMesh& closed);

// max over the vertices of each mesh of the distance to the other mesh (m).
double hausdorff_distance(const TriMesh& a, const TriMesh& b);

}  // namespace pb4u::test
