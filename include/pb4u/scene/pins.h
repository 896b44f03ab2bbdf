#pragma once
// Pins chosen by rule, the same wherever a garment is pinned (scenes, evaluation, tests).
#include <Eigen/Core>
#include <vector>

namespace pb4u {

// The vertices of x (n x 3, m) within `top_band` m below the highest one (y is up), in index
// order; top_band = 0 gives the vertices at the top height exactly.
std::vector<int> top_band_vertices(const Eigen::MatrixXd& x, double top_band);

}  // namespace pb4u
