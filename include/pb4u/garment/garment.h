#pragma once
// A garment mesh at one resolution with the skinning weights that pose it like the body.
#include <Eigen/Core>
#include <string>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

struct Garment {
  std::string name;         // template name or source file stem
  TriMesh mesh;             // rest shape around the body's bind pose, metres
  Eigen::MatrixXd weights;  // n x J skinning weights (transfer_skin_weights), rows sum to 1
};

}  // namespace pb4u
