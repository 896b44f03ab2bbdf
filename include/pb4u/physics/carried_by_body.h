#pragma once
// How the cloth moves when the body moves into it (the intersection-free solve's body moves,
// reference_solver.h; solver.body_carry). `push`: every cloth vertex, and both ends of every
// cloth edge, that the body's motion brings closer than `keep` (m), to first order, moves with
// the body's closest point: all the way for pairs already nearer than `keep` (they ride on the
// body, the solve then lets them slide), else the fraction of the motion that would close the
// distance past `keep`; a point in several pairs takes the largest move. `ride` adds: pairs
// nearer than `keep` ride also where the body slides or turns under them (unless it leaves
// them faster than a quarter of its motion) and are lifted back to `keep`; each end of a cloth
// edge moves with the body edge where it projects onto it, so an edge turns as the body edge
// does; a point in several pairs takes the largest move, then what each other pair still
// needs along its normal. A body leaving the cloth drags nothing: contact only pushes. Linear
// in the motion, so CCD on the joint move still decides what is safe.
#include <Eigen/Core>

#include <vector>

#include "pb4u/physics/contact_candidates.h"

namespace pb4u {

// x: cloth (n x 3); body at its current pose with motion body_motion (nb x 3); excluded: cloth
// vertices out of contact (intersection_free_start.h), or empty; ride: the `ride` rule (above),
// else `push`. Returns the cloth's motion (n x 3).
Eigen::MatrixXd carried_by_body(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                const ContactSurface& body, const Eigen::MatrixXd& body_motion,
                                const std::vector<char>& excluded, double keep, bool ride = false);

}  // namespace pb4u
