#pragma once
// Exact closest point on a triangle (Ericson, Real-Time Collision Detection, 5.1.5), with the
// feature it lies on: what picks the pseudo-normal that signs a distance to a closed mesh.
#include <Eigen/Core>

namespace pb4u {

// Where on triangle (a, b, c) the closest point lies: the interior, an edge (ab, bc, ca) or a
// corner (a, b, c).
enum class TriangleFeature { interior, edge_ab, edge_bc, edge_ca, corner_a, corner_b, corner_c };

struct ClosestPointOnTriangle {
  Eigen::Vector3d point;    // m
  TriangleFeature feature;
  Eigen::Vector3d weights;  // barycentric weights of a, b, c: point = w0 a + w1 b + w2 c
};

// The point of triangle (a, b, c) nearest to p (all in m). A degenerate triangle is handled
// as its edges / corners are (the result is on them).
ClosestPointOnTriangle closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                                 const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace pb4u
