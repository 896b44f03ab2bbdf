#pragma once
// Which segments pass through a triangle surface: the test behind "a cloth edge through the
// body" (physics/penetration.h counts them per frame, the barrier solver's start frees them,
// a garment's rest mesh is cleared of them at its bind pose).
#include <Eigen/Core>

#include <vector>

namespace pb4u {

// Whether segment (p, q) crosses triangle (a, b, c), endpoints on it included (Moller-Trumbore).
// A segment parallel to the triangle's plane never crosses its interior: false.
bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// The rows of `segments` (k x 2 rows of `points`, n x 3 m) that cross a face of the surface
// (V, F), ascending. Broad phase: a KD-tree over the face centroids; a face a segment crosses
// has its centroid within half the segment plus the face's radius of the segment's midpoint.
std::vector<int> segments_through_surface(const Eigen::MatrixXd& points, const Eigen::MatrixXi& segments,
                                          const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace pb4u
