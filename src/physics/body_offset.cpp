#include "pb4u/physics/body_offset.h"

#include "pb4u/mesh/geometry.h"
#include "pb4u/spatial/signed_distance_to_surface.h"

namespace pb4u {

Eigen::MatrixXd offset_where_room(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double offset) {
  const Eigen::MatrixXd normals = vertex_normals(V, F);
  const Eigen::VectorXd room = signed_distance_to_surface(V + 2 * offset * normals, V, F);
  const Eigen::VectorXd moved = (0.5 * room.array()).max(0.0).min(offset).matrix();
  return V + moved.asDiagonal() * normals;
}

}  // namespace pb4u
