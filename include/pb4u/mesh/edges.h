#pragma once
// Edge topology of a triangle mesh.
#include <Eigen/Core>

namespace pb4u {

// Unique undirected edges of F (m x 3), as an E x 2 matrix with row (i, j), i < j,
// sorted lexicographically.
Eigen::MatrixXi unique_edges(const Eigen::MatrixXi& F);

// Interior edges with their two incident faces, for bending. Row e of each matrix:
//   edge(e)     = (i, j): the shared vertices, ordered as in face(e, 0);
//   faces(e)    = (f0, f1): the incident faces (f0 traverses i -> j);
//   opposite(e) = (k0, k1): the vertex of f0 / f1 not on the edge.
// Edges with one face (boundary) or more than two (non-manifold) are skipped.
struct HingeSet {
  Eigen::MatrixXi edge, faces, opposite;
  int size() const { return static_cast<int>(edge.rows()); }
};
HingeSet interior_hinges(const Eigen::MatrixXi& F);

// Number of faces incident to each unique edge, aligned with unique_edges(F).
Eigen::VectorXi edge_face_counts(const Eigen::MatrixXi& F);

}  // namespace pb4u
