#pragma once
// Inference-time strain limiting of a network's step (model.strain_limit > 0), after Provot
// (1995): an edge longer than (1 + limit) times its rest length is shortened to that length by
// moving its two ends towards each other, the pinned end staying put. Gauss-Seidel sweeps over
// the edges, alternating direction, until no edge exceeds the limit by more than 1% of it or
// the sweeps run out. Edges may compress freely (buckling cloth shortens edges). Forward Euler takes the next velocity from positions,
// so the correction also removes the stretching velocity. Not differentiable; training never
// limits.
#include <torch/torch.h>

namespace pb4u {

struct GarmentTopology;

struct StrainLimitResult {
  torch::Tensor x;        // (n, 3): the limited positions (the input itself if nothing was long)
  double max_strain = 0;  // largest edge strain |x_i - x_j| / L - 1 after the last iteration
  int iterations = 0;     // sweeps run (0: no edge exceeded the limit)
};

// x: (n, 3) m. pinned: (n) bool or undefined. limit: the largest edge strain kept (0.1: 10%
// longer than at rest); limit <= 0 returns x as is.
StrainLimitResult limit_edge_strain(const torch::Tensor& x, const GarmentTopology& topology,
                                    const torch::Tensor& pinned, double limit, int max_iterations = 100);

}  // namespace pb4u
