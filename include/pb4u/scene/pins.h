#pragma once
// Pins chosen by rule, the same wherever a garment is pinned (scenes, evaluation, tests).
#include <Eigen/Core>
#include <vector>

namespace pb4u {

// The vertices of x (n x 3, m) within `top_band` m below the highest one (y is up), in index
// order; top_band = 0 gives the vertices at the top height exactly.
std::vector<int> top_band_vertices(const Eigen::MatrixXd& x, double top_band);

// Pin targets riding on a body known only as a mesh sequence (no skeleton to skin the garment
// with): every vertex of x0 (n x 3, m) keeps its offset to its nearest body vertex of frame 0.
// body: nb x 3 positions per frame, m. Returns n x 3 targets per body frame.
std::vector<Eigen::MatrixXd> nearest_body_vertex_pin_targets(const Eigen::MatrixXd& x0,
                                                             const std::vector<Eigen::MatrixXd>& body);

}  // namespace pb4u
