#pragma once
// The short-range half of the eslr baseline: ESLR's Laplacian-smoothed dual message passing
// (Liu et al. 2025), reconstructed from the paper. One layer is a MeshGraphNet step
// (graph_net_block.h: edge updates e^a, then the node update v^a), then Laplacian smoothing of
// the node latents over the mesh edges,
//   p_i = mean over the edges e = (j -> i) of (v^a_j + e^a_e),
// and an MLP of the smoothed latent, added as a residual: v_i <- v^a_i + f'(p_i).
#include <torch/torch.h>

#include "pb4u/model/graph_net_block.h"
#include "pb4u/model/mlp.h"

namespace pb4u {

// (n, H): p_i above for nodes (n, H) and edge latents (E, H) along senders -> receivers; a node
// no edge reaches (a body node) keeps its own row.
torch::Tensor laplacian_smoothing(const torch::Tensor& nodes, const torch::Tensor& edges, const RowIndex& senders,
                                  const RowIndex& receivers);

struct LsdmpBlockImpl : torch::nn::Module {
  LsdmpBlockImpl(int64_t latent, int hidden_layers);

  LatentGraph forward(const LatentGraph& g, const RowIndex& mesh_senders, const RowIndex& mesh_receivers,
                      const RowIndex& world_senders, const RowIndex& world_receivers);

  // Matmul FLOPs of forward() on n nodes, Em mesh and Ew world edges.
  double matmul_flops(double n, double Em, double Ew) const;

  GraphNetBlock message_passing{nullptr};
  MLP smoothed{nullptr};  // f'
};
TORCH_MODULE(LsdmpBlock);

}  // namespace pb4u
