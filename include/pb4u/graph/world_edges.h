#pragma once
// Garment <-> body world edges (SPEC 4), found with a KD-tree over the body vertices.
#include <torch/torch.h>

namespace pb4u {

// (P, 2) int64 rows (garment vertex, body vertex), sorted by garment then body vertex, for
// garment vertices x (n, 3) and body vertices (nb, 3) closer than `radius` (m).
// nearest_only: at most one row per garment vertex, its nearest body vertex (SPEC 4: "the
// distance to the nearest body vertex is below a radius"); else every pair within the radius.
torch::Tensor garment_body_pairs(const torch::Tensor& x, const torch::Tensor& body_vertices,
                                 double radius, bool nearest_only);

}  // namespace pb4u
