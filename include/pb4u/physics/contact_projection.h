#pragma once
// Inference-time contact projection of a network's step (model.contact_projection > 0): the
// predicted garment is moved out of the body at t + dt, in three passes.
//  1. The collision term's own measure (SPEC 3.3, body_queries.h): a free vertex closer than
//     `gap` to the plane of its matched body face, or behind it, moves along that face's normal
//     to `gap` in front of it.
//  2. Exact signed distance (spatial/signed_distance_to_surface.h, as the penetration figures
//     measure it): a free vertex still inside the body, or within `gap` of its surface, moves to
//     `gap` outside the closest surface point. Pass 1 alone leaves vertices inside where the
//     matched face's plane is not the nearest surface (armpits, a limb that moved since t).
//  3. Pass 1 again: where the body is concave, pass 2 can put a vertex behind its matched
//     face's plane. A push is kept only where the vertex stays outside the body (exact signed
//     distance >= 0): in a slit (between the legs, under an arm) the plane push could put it
//     into the other side. Elsewhere the collision term then measures nothing.
// Forward Euler takes the next velocity from positions, so a push also becomes velocity. Not
// differentiable; training never projects.
#include <torch/torch.h>

#include "pb4u/physics/body_queries.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/scene/frame_state.h"

namespace pb4u {

// x_next: (n, 3) m. state: the step's state (its body at t + dt; its pinned vertices are not
// moved). contact: the step's body contact, or null to skip pass 1. Returns x_next (same dtype
// and device) with the projected rows moved; gap <= 0 or a state without a body returns it as is.
// With gap >= the collision term's eps the returned step has zero collision energy, except
// where that would take a vertex into the body (pass 3).
// The body at t + dt prepared for passes 2 and 3 (spatial/signed_distance_to_surface.h). A
// step that projects several times (step_constraints.h) prepares it once.
class ProjectionSurface {
 public:
  explicit ProjectionSurface(const BodyFrame& body);  // body.next_vertices must be defined
  ~ProjectionSurface();
  const SurfaceQuery& query() const { return query_; }
  const Eigen::RowVector3d& lower() const { return lower_; }  // m: bounding box of the body
  const Eigen::RowVector3d& upper() const { return upper_; }

 private:
  ProjectionSurface(const Eigen::MatrixXd& V, const torch::Tensor& faces);
  SurfaceQuery query_;
  Eigen::RowVector3d lower_, upper_;
};

// surface: the state's body prepared, or null to prepare it here.
torch::Tensor project_out_of_body(const torch::Tensor& x_next, const FrameState& state,
                                  const BodyContact* contact, double gap,
                                  const ProjectionSurface* surface = nullptr);

}  // namespace pb4u
