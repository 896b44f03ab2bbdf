#pragma once
// Garment <-> body world edges (SPEC 4), found with a KD-tree over the body vertices.
#include <torch/torch.h>

namespace pb4u {

// Garment vertices x (n, 3) within `radius` (m) of body vertices (nb, 3): (P, 2) int64 rows
// (garment vertex, body vertex), sorted by garment then body vertex.
torch::Tensor garment_body_pairs(const torch::Tensor& x, const torch::Tensor& body_vertices,
                                 double radius);

}  // namespace pb4u
