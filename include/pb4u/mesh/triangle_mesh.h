#pragma once
// The mesh that crosses every stage boundary: vertex positions and triangles.
#include <Eigen/Core>

namespace pb4u {

// V: n x 3 vertex positions in metres (y up). F: m x 3 vertex indices, counter-clockwise
// seen from the side the normal points to.
struct TriMesh {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;

  int num_vertices() const { return static_cast<int>(V.rows()); }
  int num_faces() const { return static_cast<int>(F.rows()); }
};

}  // namespace pb4u
