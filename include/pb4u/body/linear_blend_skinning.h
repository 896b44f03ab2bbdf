#pragma once
// Linear blend skinning: v' = sum_j w_ij M_j v.
#include <Eigen/Core>

#include "pb4u/body/forward_kinematics.h"

namespace pb4u {

// V: n x 3 bind-pose positions (m); W: n x J weights, rows summing to 1; M: J skinning
// matrices (skinning_transforms). Returns the n x 3 posed positions (m).
Eigen::MatrixXd linear_blend_skinning(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                      const JointTransforms& M);

// Normalises each row of W to sum 1 after dropping all but its `max_influences` largest
// entries (rows with no positive entry are left to `fallback_joint`).
void limit_and_normalize_weights(Eigen::MatrixXd& W, int max_influences, int fallback_joint = 0);

}  // namespace pb4u
