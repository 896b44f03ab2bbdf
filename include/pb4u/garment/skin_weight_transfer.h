#pragma once
// Skinning weights for a garment, copied from the nearest body vertex at the bind pose.
#include <Eigen/Core>

#include "pb4u/body/body.h"

namespace pb4u {

// V: n x 3 garment positions around body's bind pose (m). Returns n x J weights.
Eigen::MatrixXd transfer_skin_weights(const Eigen::MatrixXd& V, const Body& body);

}  // namespace pb4u
