#pragma once
// HOOD's message passing (Grigorev et al., CVPR 2023, as its public code builds it), the hood
// baseline's update stack. Each block passes messages over the world edges and one or two
// garment edge sets, `f` (the mesh edges) or `cL` (coarse level L, graph/garment_topology.h),
// each with its own edge MLP; its node MLP reads the node and, per edge set, the sum of the
// set's updated edges at it (zero where a node has none). A block on coarse sets only keeps
// the world edges whose garment vertex is in them (HOOD's down-sampling); the others keep
// their latents until a finer block uses them again (its up-sampling).
#include <torch/torch.h>

#include <vector>

#include "pb4u/model/hood_schedule.h"
#include "pb4u/model/mlp.h"

namespace pb4u {

// Latent garment edges of every set (index 0 the mesh edges, L + 1 coarse level L).
struct HoodLatents {
  torch::Tensor nodes;                   // (nodes, H)
  std::vector<torch::Tensor> edge_sets;  // (E_s, H)
  torch::Tensor world_edges;             // (Ew, H)
  torch::Tensor cloth_edges;             // (Ec, H): ccraft's cloth-to-cloth edges, else undefined
};

// The indices a block reads: per garment edge set, and the world edges it keeps.
struct HoodIndices {
  std::vector<RowIndex> senders, receivers;  // per garment edge set
  RowIndex world_senders, world_receivers;   // the kept world edges
  torch::Tensor world_kept;                  // (Ew') int64: which world edges those are
  RowIndex cloth_senders, cloth_receivers;   // ccraft's cloth edges (all of them, every block)
};

struct HoodBlockImpl : torch::nn::Module {
  // cloth_edges: the block also passes messages over ccraft's cloth-to-cloth edges (one more
  // edge MLP, one more node MLP part).
  HoodBlockImpl(std::vector<int> sets, int64_t latent, int hidden_layers, bool cloth_edges = false);

  HoodLatents forward(const HoodLatents& g, const HoodIndices& ix);

  // The finest level of this block's sets (0: the mesh edges): the world edges it keeps are
  // those whose garment vertex's level is at least this.
  int finest_set() const;

  // Matmul FLOPs of forward() on n nodes, `set_edges[s]` edges in garment set s (all sets,
  // index as HoodLatents::edge_sets), `world_kept` world edges and `cloth` cloth edges.
  double matmul_flops(double n, const std::vector<double>& set_edges, double world_kept, double cloth = 0) const;

  std::vector<int> sets;
  std::vector<MLP> set_edge;  // per entry of `sets`
  MLP world_edge{nullptr}, node{nullptr};
  MLP cloth_edge{nullptr};  // ccraft only
};
TORCH_MODULE(HoodBlock);

}  // namespace pb4u
