#pragma once
// How the cloth moves when the body moves into it (the intersection-free solve's body moves,
// reference_solver.h): every cloth vertex, and both ends of every cloth edge, that the body's
// motion brings closer than `keep` (m) moves with the body's closest point: all the way for
// pairs already nearer than `keep` (they ride on the body, the solve then lets them slide),
// else the fraction of the motion that would close the distance past `keep`. A point in
// several pairs takes the largest move. A body moving away drags nothing: contact only
// pushes. Linear in the motion, so CCD on the joint move still decides what is safe.
#include <Eigen/Core>

#include <vector>

#include "pb4u/physics/contact_candidates.h"

namespace pb4u {

// x: cloth (n x 3); body at its current pose with motion body_motion (nb x 3); excluded: cloth
// vertices out of contact (intersection_free_start.h), or empty. Returns the cloth's motion (n x 3).
Eigen::MatrixXd carried_by_body(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                const ContactSurface& body, const Eigen::MatrixXd& body_motion,
                                const std::vector<char>& excluded, double keep);

}  // namespace pb4u
