#pragma once
// Where a predicted garment meets the posed body, seen from the body's surface itself: for the
// collision term that cannot be fooled (physics.collision.measure: surface).
//
// SPEC 3.3's term measures each vertex against the plane of the body face with the nearest
// centroid at t. A vertex pushed deeper than a limb's middle is nearer the far side's faces,
// and one beside a small face is off its plane: both measure as outside and pay nothing (the
// penalty solver sits 11 mm inside at zero collision energy). Here the side comes from the
// body's winding number at the vertex (spatial/winding_number.h: right also where the body
// crosses itself) and the distance from the closest point of the faces no other part of the
// body covers (body/outer_faces.h), both at t + dt.
#include <torch/torch.h>

#include "pb4u/scene/frame_state.h"

namespace pb4u {

// For the garment vertices within `reach` of the body's bounding box (the others are farther
// than `reach` from the body): their indices, the closest outer surface point and the unit
// outward direction there. The signed distance of a vertex x is (x - point) . outward,
// negative inside, and its gradient is the outward direction (the point held fixed).
struct SurfaceContact {
  torch::Tensor vertex;   // (k) int64
  torch::Tensor point;    // (k, 3) m, x_next's dtype and device
  torch::Tensor outward;  // (k, 3) unit
};

// x_next: (n, 3) m; body: its next_vertices and faces (closed, outward). Throws pb4u::Error
// on a body without faces or non-finite positions.
SurfaceContact query_surface_contact(const torch::Tensor& x_next, const BodyFrame& body, double reach);

}  // namespace pb4u
