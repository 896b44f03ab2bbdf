#pragma once
// Small scenes shared by the physics tests.
#include <torch/torch.h>

#include "pb4u/mesh/triangle_mesh.h"
#include "pb4u/scene/frame_state.h"

namespace pb4u::test {

// Rows of V as a (n, 3) tensor of `dtype`, and faces as (m, 3) int64.
torch::Tensor positions_tensor(const Eigen::MatrixXd& V, torch::Dtype dtype = torch::kFloat64);
torch::Tensor faces_tensor(const Eigen::MatrixXi& F);

// A closed, outward-oriented icosphere (radius in m) around `center`, `subdivisions` times
// refined (20 * 4^s faces).
TriMesh icosphere(double radius, int subdivisions, const Eigen::RowVector3d& center);

// A static body (the same pose at t and t + dt).
BodyFrame static_body(const TriMesh& body, torch::Dtype dtype = torch::kFloat64);

// The garment at rest at positions `x`, at rest in time (x_prev = x), all effects off.
FrameState resting_state(const torch::Tensor& x);

}  // namespace pb4u::test
