#pragma once
// Resolution-aware propagation control (SPEC 4): a fixed propagation distance
// D = K_base * Lbar_base (m), calibrated on the training resolution, covered by
// K = max(1, floor(D / Lbar)) steps on a mesh of mean rest edge length Lbar, so a finer mesh
// propagates over the same physical distance.
#include <cstdint>
#include <random>

#include "pb4u/model/model_config.h"

namespace pb4u {

// K for a mesh of mean rest edge length `mean_edge_length` (m) given D (m).
// Throws pb4u::Error unless both are positive.
int64_t propagation_steps(double propagation_distance, double mean_edge_length);

// K the configured model uses at inference: 0 for kind mgn, K_base with propagation control
// off, else propagation_steps(D, Lbar).
int64_t inference_propagation_steps(const ModelConfig& config, double propagation_distance,
                                    double mean_edge_length);

// K for one training step: uniform integer in [lo * K_base * depth, hi * K_base * depth]
// (config train_k_range) with control on; K_base with control off; 0 for mgn. depth > 0: how
// many times the calibration's K the sample's mesh takes (1 / c for a scene scaled by c).
int64_t sample_propagation_steps(const ModelConfig& config, std::mt19937_64& rng, double depth = 1.0);

}  // namespace pb4u
