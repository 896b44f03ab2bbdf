#pragma once
// Resolution-aware update scaling (SPEC 4): a = s (.) a~ with s_i = (mean rest length of the
// edges at vertex i) / Lbar_base, so a finer mesh's smaller cells take proportionally smaller
// corrections.
#include <torch/torch.h>

namespace pb4u {

// (n, 1) s from the per-vertex mean rest edge length (n) m and Lbar_base (m); all ones when
// `enabled` is false. Throws pb4u::Error if enabled and Lbar_base <= 0 (uncalibrated).
torch::Tensor update_scale(const torch::Tensor& vertex_mean_edge_length, double mean_edge_length_base,
                           bool enabled);

}  // namespace pb4u
