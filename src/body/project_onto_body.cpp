#include "pb4u/body/project_onto_body.h"

#include "pb4u/body/outer_faces.h"

namespace pb4u {
namespace {

SurfaceQuery outer_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const WindingNumbers& wraps) {
  const Eigen::MatrixXi outer = outer_faces(V, F, &wraps);
  return SurfaceQuery(V, outer.rows() > 0 ? outer : F);
}

}  // namespace

BodyProjection::BodyProjection(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F)
    : wraps_(V, F), outer_(outer_surface(V, F, wraps_)) {}

SurfaceProjection BodyProjection::project(const Eigen::MatrixXd& points) const {
  SurfaceProjection p = outer_.project(points);
  if (points.rows() == 0) return p;
  const Eigen::VectorXi inside = wraps_.at(points);
  for (Eigen::Index k = 0; k < points.rows(); ++k) {
    const Eigen::RowVector3d d = points.row(k) - p.closest.row(k);
    const double length = d.norm();
    const double side = inside(k) >= 1 ? -1.0 : 1.0;
    p.distance(k) = side * length;
    if (length > 1e-12) p.outward.row(k) = side * d / length;  // on the surface: the pseudo-normal
  }
  return p;
}

SurfaceProjection project_onto_body(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return BodyProjection(V, F).project(points);
}

}  // namespace pb4u
