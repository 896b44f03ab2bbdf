#pragma once
// Where one network frame's time goes (bench's per-stage table): graph build, world-edge
// query, encoders, propagation, blocks, decoder, Euler step, contact query and physics terms,
// each a median over repeats, beside a dense matmul's FLOP rate on the same machine load.
#include <torch/torch.h>

#include <vector>

#include "pb4u/eval/bench.h"
#include "pb4u/graph/garment_topology.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/rollout/rollout.h"

namespace pb4u {

// Dense float matmul of an m x k by k x n product, timed one product at a time.
class DenseMatmul {
 public:
  // size: [m, k, n]; pb4u::Error naming matmul_size otherwise. Runs one warm-up product.
  explicit DenseMatmul(const std::vector<int>& size);
  // GFLOP/s of one product.
  double gflops();
  double median_gflops(int repeats);

 private:
  torch::Tensor a_, b_, c_;
  double flops_ = 0;
};

// One network frame split into its stages, median over `repeats` (after one warm-up).
// The dense matmul is timed in each repeat too, so the FLOP-rate ratio compares the two under
// the same machine load. The message passing's FLOPs come from the network's own layers
// (Pb4uNetImpl::message_passing_flops).
StageRow time_stages(Pb4uNet& net, const GarmentTopology& topology, const RolloutInput& in,
                     const PhysicsConfig& physics, int repeats, DenseMatmul& matmul);

}  // namespace pb4u
