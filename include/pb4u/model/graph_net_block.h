#pragma once
// One MeshGraphNet block (SPEC 4 update stack): mesh-edge and world-edge updates from their
// end nodes, then a node update from the summed incoming edges, each with a residual.
#include <torch/torch.h>

#include "pb4u/model/mlp.h"

namespace pb4u {

// Latent state of a graph as it flows through the blocks.
struct LatentGraph {
  torch::Tensor nodes;        // (nodes, H)
  torch::Tensor mesh_edges;   // (Em, H)
  torch::Tensor world_edges;  // (Ew, H), Ew may be 0
};

struct GraphNetBlockImpl : torch::nn::Module {
  GraphNetBlockImpl(int64_t latent, int hidden_layers);

  LatentGraph forward(const LatentGraph& g, const RowIndex& mesh_senders,
                      const RowIndex& mesh_receivers, const RowIndex& world_senders,
                      const RowIndex& world_receivers);

  // Matmul FLOPs of forward() on n nodes, Em mesh and Ew world edges.
  double matmul_flops(double n, double Em, double Ew) const;

  bool split_first_layer = true;  // runtime switch for the benchmark; same weights either way
  MLP mesh_edge{nullptr}, world_edge{nullptr}, node{nullptr};
};
TORCH_MODULE(GraphNetBlock);

}  // namespace pb4u
