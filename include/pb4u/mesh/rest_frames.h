#pragma once
// Rest-shape reference frames for StVK stretch (SPEC 3.1).
#include <Eigen/Core>

namespace pb4u {

// For each face (x0, x1, x2) the rest edges e1 = x1 - x0, e2 = x2 - x0 are expressed in a
// local orthonormal 2D frame (u along e1, v in the face plane), giving
// Dm = [[e1.u, e2.u], [e1.v, e2.v]] (metres). Returns m x 4 rows of Dm^-1 in row-major
// order (a, b, c, d) = [[a, b], [c, d]] (1/m). Degenerate faces get a zero row.
Eigen::MatrixXd rest_dm_inverse(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace pb4u
