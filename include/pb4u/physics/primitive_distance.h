#pragma once
// Distances between the primitives that contact is made of (IPC, Li et al. 2020): a cloth
// vertex and a body triangle, a cloth edge and a body edge. Each comes with its gradient with
// respect to the 12 coordinates of its four points, so a barrier on the distance has exact
// derivatives. The closest points are parameters of a minimisation over the fixed
// (barycentric / segment) domain, so by the envelope theorem the gradient of the squared
// distance is 2 r times the closest points' weights, r the vector between them.
#include <Eigen/Core>

namespace pb4u {

struct PrimitiveDistance {
  double distance = 0;                   // m, >= 0
  Eigen::Matrix<double, 12, 1> gradient;  // d distance / d (x0, x1, x2, x3), each 3 coordinates;
                                          // zero where the distance is 0 (no direction)
  Eigen::Vector4d weights;               // of the four points in r = sum w_i x_i (closest-point
                                         // difference): p - (triangle point), or pa - pb
};

// Row i of an m x 3 point matrix as a point.
inline Eigen::Vector3d point_row(const Eigen::MatrixXd& points, int i) { return points.row(i).transpose(); }

// Vertex p and triangle (a, b, c), in that order in the gradient.
PrimitiveDistance point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Segment (a0, a1) and segment (b0, b1), in that order in the gradient. Parallel segments
// take the closest pair with the smallest parameter on the first segment; a zero-length
// segment is a point.
PrimitiveDistance edge_edge_distance(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                     const Eigen::Vector3d& b0, const Eigen::Vector3d& b1);

}  // namespace pb4u
