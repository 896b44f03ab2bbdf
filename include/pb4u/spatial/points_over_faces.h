#pragma once
// Which faces of a triangle mesh a point lies over, closely: the pairs behind cloth-to-cloth
// proximity (ContourCraft's repulsion term and its cloth edges).
#include <Eigen/Core>

#include <vector>

namespace pb4u {

struct PointOverFace {
  int point = -1, face = -1;
  double distance = 0;  // signed, m: (p - V(F(face, 0))) . the face's unit normal
};

// Pairs (point i, face f): the projection of point i onto f's plane lies inside f (barycentric
// coordinates in [0, 1]), |distance| < radius, and f is not degenerate. With points that are
// the mesh's own vertices (same_mesh), a face that holds point i is left out. Sorted by point,
// then face. Broad phase: a KD-tree over the face centroids.
std::vector<PointOverFace> points_over_faces(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V,
                                             const Eigen::MatrixXi& F, double radius, bool same_mesh);

}  // namespace pb4u
