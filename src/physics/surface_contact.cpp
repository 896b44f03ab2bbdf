#include "pb4u/physics/surface_contact.h"

#include <vector>

#include "pb4u/body/project_onto_body.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"

namespace pb4u {

SurfaceContact query_surface_contact(const torch::Tensor& x_next, const BodyFrame& body, double reach) {
  if (!body.next_vertices.defined() || !body.faces.defined() || body.faces.size(0) == 0)
    throw Error("surface contact: the body has no faces");
  const Eigen::MatrixXd x = tensor_to_matrix(x_next.detach());
  if (!x.allFinite()) throw Error("surface contact: garment positions are not finite");
  const Eigen::MatrixXd V = tensor_to_matrix(body.next_vertices);
  const Eigen::MatrixXi F = index_tensor_to_matrix(body.faces);
  const Eigen::RowVector3d lo = V.colwise().minCoeff().array() - reach, hi = V.colwise().maxCoeff().array() + reach;
  std::vector<int64_t> near;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if ((x.row(i).array() >= lo.array()).all() && (x.row(i).array() <= hi.array()).all()) near.push_back(i);
  const auto options = x_next.options().requires_grad(false);
  SurfaceContact out;
  out.vertex = torch::tensor(near, torch::kInt64).to(x_next.device());
  if (near.empty()) {
    out.point = torch::zeros({0, 3}, options);
    out.outward = torch::zeros({0, 3}, options);
    return out;
  }
  Eigen::MatrixXd points(near.size(), 3);
  for (size_t k = 0; k < near.size(); ++k) points.row(Eigen::Index(k)) = x.row(near[k]);

  // The side from the body's winding number, the distance to its outer faces
  // (body/project_onto_body.h).
  const SurfaceProjection p = project_onto_body(points, V, F);
  out.point = matrix_to_tensor(p.closest, x_next.scalar_type(), x_next.device());
  out.outward = matrix_to_tensor(p.outward, x_next.scalar_type(), x_next.device());
  return out;
}

}  // namespace pb4u
