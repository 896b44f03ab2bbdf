#include "pb4u/physics/contact_projection.h"

#include <optional>
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
torch::Tensor project_to_surface_distance(const torch::Tensor& x_next, const ProjectionSurface& body, double gap,
                                          const torch::Tensor& pinned) {
  Eigen::MatrixXd x = tensor_to_matrix(x_next.to(torch::kCPU, torch::kFloat64));
  // Only vertices within `gap` of the body's bounding box can be within `gap` of the body.
  const Eigen::RowVector3d lo = body.lower().array() - gap;
  const Eigen::RowVector3d hi = body.upper().array() + gap;
  const torch::Tensor fixed = pinned.defined() ? pinned.to(torch::kCPU, torch::kBool).contiguous() : torch::Tensor();
  std::vector<Eigen::Index> near;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (fixed.defined() && fixed.data_ptr<bool>()[i]) continue;
    if ((x.row(i).array() >= lo.array()).all() && (x.row(i).array() <= hi.array()).all()) near.push_back(i);
  }
  if (near.empty()) return x_next;
  Eigen::MatrixXd points(near.size(), 3);
  for (size_t k = 0; k < near.size(); ++k) points.row(k) = x.row(near[k]);
  const SurfaceProjection p = body.query().project(points);
  bool moved = false;
  for (size_t k = 0; k < near.size(); ++k) {
    if (p.distance(k) >= gap) continue;
    x.row(near[k]) = p.closest.row(k) + gap * p.outward.row(k);
    moved = true;
  }
  return moved ? matrix_to_tensor(x).to(x_next.options()) : x_next;
}

// Pass 3: pass 1 again, kept only where the pushed vertex stays outside the body. In a slit
// narrower than the gap (between the legs, under an arm) the plane push would put it into the
// other side, which the exact pass had just moved it out of.
torch::Tensor reproject_along_matched_faces(const torch::Tensor& x_next, const BodyContact& contact,
                                            const ProjectionSurface& body, double gap, const torch::Tensor& pinned) {
  const torch::Tensor pushed = project_along_matched_faces(x_next, contact, gap, pinned);
  const torch::Tensor moved = (pushed != x_next).any(1).nonzero().squeeze(1);
  if (moved.numel() == 0) return x_next;
  const torch::Tensor candidates = pushed.index_select(0, moved);
  const SurfaceProjection p = body.query().project(tensor_to_matrix(candidates.to(torch::kCPU, torch::kFloat64)));
  const torch::Tensor outside =
      torch::from_blob(const_cast<double*>(p.distance.data()), {static_cast<int64_t>(p.distance.size())}, torch::kFloat64).ge(0).to(moved.device());
  torch::Tensor out = x_next.clone();
  out.index_copy_(0, moved.masked_select(outside), candidates.index({outside}));
  return out;
}

}  // namespace

ProjectionSurface::ProjectionSurface(const BodyFrame& body)
    : ProjectionSurface(tensor_to_matrix(body.next_vertices.to(torch::kCPU, torch::kFloat64)), body.faces) {}

ProjectionSurface::ProjectionSurface(const Eigen::MatrixXd& V, const torch::Tensor& faces)
    : query_(V, index_tensor_to_matrix(faces)),
      lower_(V.colwise().minCoeff()),
      upper_(V.colwise().maxCoeff()) {}

ProjectionSurface::~ProjectionSurface() = default;

torch::Tensor project_out_of_body(const torch::Tensor& x_next, const FrameState& state, const BodyContact* contact,
                                  double gap, const ProjectionSurface* surface) {
  if (!(gap > 0) || !state.body.defined() || !state.body.next_vertices.defined()) return x_next;
  const torch::Tensor pinned =
      state.pinned.defined() && state.pinned.numel() == x_next.size(0) ? state.pinned : torch::Tensor();
  std::optional<ProjectionSurface> prepared;
  if (!surface) surface = &prepared.emplace(state.body);
  const ProjectionSurface& body = *surface;
  if (!contact) return project_to_surface_distance(x_next, body, gap, pinned);
  const torch::Tensor along_faces = project_along_matched_faces(x_next, *contact, gap, pinned);
  const torch::Tensor outside = project_to_surface_distance(along_faces, body, gap, pinned);
  // Where the body is concave, pass 2 can move a vertex behind its matched face's plane again.
  return reproject_along_matched_faces(outside, *contact, body, gap, pinned);
}

}  // namespace pb4u
