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

// Lazy neighbour averaging of a per-vertex field f (n, c) over directed edges (both directions
// listed): f <- (f + mean of the neighbours' f) / 2, `iterations` times (mesh/lazy_averaging.h).
// n rounds spread the field over ~0.7 sqrt(n) edge lengths (rms), so n = (L / Lbar)^2 rounds
// reach ~0.7 L whatever the resolution. Linear and differentiable; isolated vertices keep their
// value.
torch::Tensor smooth_over_mesh(const torch::Tensor& f, const torch::Tensor& senders,
                               const torch::Tensor& receivers, int64_t iterations);

// Rounds of smooth_over_mesh that smooth over `distance` m on a mesh of mean edge length
// Lbar m: round((distance / Lbar)^2), at least 1.
int64_t smoothing_iterations(double distance, double mean_edge_length);

// Update scaling of the detail only: a = S(a~) + s (.) (a~ - S(a~)). The smooth part of the
// predicted acceleration (gravity, following the body, pushing a whole region out of it) keeps
// its size at every resolution; only what varies within ~distance (the mesh-scale corrections
// the scaling is for) shrinks with the edges. On the calibration mesh, s ~ 1 and this is a~.
torch::Tensor detail_update_scaling(const torch::Tensor& a, const torch::Tensor& s,
                                    const torch::Tensor& senders, const torch::Tensor& receivers,
                                    double mean_edge_length, double distance);

}  // namespace pb4u
