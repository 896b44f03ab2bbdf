#pragma once
// Exact signed distance from points to a closed, outward-oriented triangle surface (a body):
// candidate faces from a KD-tree over face centroids (PointKdTree), exact point-triangle
// distance on them, the sign from the angle-weighted pseudo-normal of the closest feature
// (face, edge or corner; Baerentzen & Aanaes 2005), which is exact for a closed manifold.
#include <Eigen/Core>
#include <memory>

namespace pb4u {

// points: n x 3 (m); V: nb x 3 (m); F: mb x 3, outward. Returns n signed distances (m):
// negative inside. Faces of zero area are skipped (on a closed mesh their points lie on
// their neighbours' edges). Throws pb4u::Error on non-finite input, an empty surface or an
// out-of-range face index.
//
// Why the candidates are exact: the face c0 with the nearest centroid bounds the distance by
// D = dist(p, c0); the closest face has a point within D of p, so its centroid lies within
// D + r_max (r_max: the largest centroid-to-corner distance) and the radius query finds it.
// Far from the surface that radius covers many faces: callers that only need points near or
// inside it should filter first (garment_penetration() skips points outside the bounding box).
Eigen::VectorXd signed_distance_to_surface(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V,
                                           const Eigen::MatrixXi& F);

// The same query with where it lands: per point the signed distance (m, negative inside),
// the closest surface point and the unit outward direction there (from the closest point
// towards an outside point, away from an inside one; the pseudo-normal where the point lies
// on the surface).
struct SurfaceProjection {
  Eigen::VectorXd distance;  // n
  Eigen::MatrixXd closest;   // n x 3 m
  Eigen::MatrixXd outward;   // n x 3 unit
};
SurfaceProjection project_onto_surface(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V,
                                       const Eigen::MatrixXi& F);

// One surface prepared for many queries: its normals, pseudo-normals and the KD-tree of its
// face centroids are built once (a body of 13776 faces: a few ms, more than a query of a
// thousand points). The rounds of a step's constraints ask about the same body each time.
class SurfaceQuery {
 public:
  // V, F as above (copied); throws pb4u::Error as above.
  SurfaceQuery(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  ~SurfaceQuery();
  SurfaceQuery(SurfaceQuery&&) noexcept;
  SurfaceQuery& operator=(SurfaceQuery&&) noexcept;

  // project_onto_surface(points, V, F), without rebuilding the surface.
  SurfaceProjection project(const Eigen::MatrixXd& points) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pb4u
