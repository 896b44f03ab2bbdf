#include "pb4u/physics/contact_projection.h"

#include <vector>

#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {
namespace {

// Pass 1: out along the matched face's normal to `gap` in front of its plane.
torch::Tensor project_along_matched_faces(const torch::Tensor& x_next, const BodyContact& contact, double gap,
                                          const torch::Tensor& pinned) {
  const torch::Tensor normal = contact.normal.to(x_next.options());
  const torch::Tensor d = ((x_next - contact.point.to(x_next.options())) * normal).sum(1);
  torch::Tensor push = (gap - d).clamp_min(0);
  if (pinned.defined()) push = push.masked_fill(pinned.to(push.device()), 0);
  return x_next + push.unsqueeze(1) * normal;
}

// Pass 2: out to `gap` from the closest point of the body surface.
torch::Tensor project_to_surface_distance(const torch::Tensor& x_next, const BodyFrame& body, double gap,
                                          const torch::Tensor& pinned) {
  const Eigen::MatrixXd body_V = tensor_to_matrix(body.next_vertices.to(torch::kCPU, torch::kFloat64));
  const torch::Tensor faces = body.faces.to(torch::kCPU, torch::kInt32).contiguous();
  const Eigen::MatrixXi body_F =
      Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(faces.data_ptr<int>(), faces.size(0), 3);
  Eigen::MatrixXd x = tensor_to_matrix(x_next.to(torch::kCPU, torch::kFloat64));
  // Only vertices within `gap` of the body's bounding box can be within `gap` of the body.
  const Eigen::RowVector3d lo = body_V.colwise().minCoeff().array() - gap;
  const Eigen::RowVector3d hi = body_V.colwise().maxCoeff().array() + gap;
  const torch::Tensor fixed = pinned.defined() ? pinned.to(torch::kCPU, torch::kBool).contiguous() : torch::Tensor();
  std::vector<Eigen::Index> near;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (fixed.defined() && fixed.data_ptr<bool>()[i]) continue;
    if ((x.row(i).array() >= lo.array()).all() && (x.row(i).array() <= hi.array()).all()) near.push_back(i);
  }
  if (near.empty()) return x_next;
  Eigen::MatrixXd points(near.size(), 3);
  for (size_t k = 0; k < near.size(); ++k) points.row(k) = x.row(near[k]);
  const SurfaceProjection p = project_onto_surface(points, body_V, body_F);
  bool moved = false;
  for (size_t k = 0; k < near.size(); ++k) {
    if (p.distance(k) >= gap) continue;
    x.row(near[k]) = p.closest.row(k) + gap * p.outward.row(k);
    moved = true;
  }
  return moved ? matrix_to_tensor(x).to(x_next.options()) : x_next;
}

}  // namespace

torch::Tensor project_out_of_body(const torch::Tensor& x_next, const FrameState& state, const BodyContact* contact,
                                  double gap) {
  if (!(gap > 0) || !state.body.defined() || !state.body.next_vertices.defined()) return x_next;
  const torch::Tensor pinned =
      state.pinned.defined() && state.pinned.numel() == x_next.size(0) ? state.pinned : torch::Tensor();
  if (!contact) return project_to_surface_distance(x_next, state.body, gap, pinned);
  const torch::Tensor along_faces = project_along_matched_faces(x_next, *contact, gap, pinned);
  const torch::Tensor outside = project_to_surface_distance(along_faces, state.body, gap, pinned);
  // Where the body is concave, pass 2 can move a vertex behind its matched face's plane again.
  return project_along_matched_faces(outside, *contact, gap, pinned);
}

}  // namespace pb4u
