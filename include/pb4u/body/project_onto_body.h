#pragma once
// Where points lie against a posed body, with the side told by the body's winding number.
//
// spatial/signed_distance_to_surface.h reads the side from the pseudo-normal of the closest
// feature, which is exact for a closed manifold that neither folds nor crosses itself. A
// skinned body does both: an arm raised high folds the shoulder's faces flat onto each other
// (two faces sharing an edge with opposite normals; the pseudo-normal of that edge is the sum
// of two opposite vectors, and its sign is rounding), and a forearm swung into a hip puts one
// part inside another. There a point 23 mm outside the body read as inside it, and a start
// that "pushed it out" along that direction pushed it in. Here the side comes from the
// winding number (spatial/winding_number.h), right in both cases, and the distance from the
// closest point of the faces no other part covers (outer_faces.h).
#include <Eigen/Core>

#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/spatial/winding_number.h"

namespace pb4u {

// One posed body prepared for many queries (its winding numbers, outer faces and their
// KD-tree built once): the rounds of a start push the same cloth out of the same body.
class BodyProjection {
 public:
  // V: nb x 3 (m); F: mb x 3, closed and outward. Throws pb4u::Error on an empty body.
  BodyProjection(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  // project_onto_body(points, V, F), below.
  SurfaceProjection project(const Eigen::MatrixXd& points) const;

 private:
  WindingNumbers wraps_;
  SurfaceQuery outer_;
};

// points: n x 3 (m); V: nb x 3 (m); F: mb x 3, closed and outward. Per point: the signed
// distance to the outer faces (negative where the body wraps the point at least once), the
// closest point of those faces, and the unit outward direction: from the point to the closest
// point when inside, away from it when outside, the surface's pseudo-normal when the point
// lies on it. Throws pb4u::Error as signed_distance_to_surface does.
SurfaceProjection project_onto_body(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace pb4u
