#pragma once
// The body as the intersection-free solver's barrier sees it under a contact offset
// (physics.solver.barrier_offset, after C-IPC's thickness): each vertex moved out along its
// normal, so that the cloth rests that far off the real body, but only as far as the body has
// room in front of it, so that the offset closes no gap between parts that nearly meet.
#include <Eigen/Core>

namespace pb4u {

// V (nb x 3, m) moved out along the area-weighted vertex normals of the outward faces F by
// `offset` (m), or less where another part of the body lies in front: a probe 2 x offset out
// measures the room (its signed distance to the body), and the vertex moves half of it, at most
// `offset`. Two flat facing surfaces g apart keep at least min(g, 2 x offset) between them:
// closer than 2 x offset neither moves.
Eigen::MatrixXd offset_where_room(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double offset);

}  // namespace pb4u
