#include "pb4u/model/graph_net_block.h"

namespace pb4u {

GraphNetBlockImpl::GraphNetBlockImpl(int64_t latent, int hidden_layers) {
  auto mlp = [&](const char* name) {
    return register_module(name, MLP(std::vector<int64_t>{latent, latent, latent}, latent, latent,
                                     hidden_layers, true));
  };
  mesh_edge = mlp("mesh_edge");
  world_edge = mlp("world_edge");
  node = mlp("node");
}

double GraphNetBlockImpl::matmul_flops(double n, double Em, double Ew) const {
  double flops = edge_mlp_flops(*mesh_edge, n, Em, true);
  if (Ew > 0) flops += edge_mlp_flops(*world_edge, n, Ew, true);
  for (size_t part = 0; part < node->first_weights.size(); ++part) flops += node->first_layer_flops(part, n);
  return flops + node->finish_flops(n);
}

LatentGraph GraphNetBlockImpl::forward(const LatentGraph& g, const RowIndex& ms, const RowIndex& mr,
                                       const RowIndex& ws, const RowIndex& wr) {
  const int64_t n = g.nodes.size(0);
  LatentGraph out;
  auto dm = edge_mlp(*mesh_edge, g.nodes, g.mesh_edges, ms, mr, {}, split_first_layer);
  out.mesh_edges = g.mesh_edges + dm;
  torch::Tensor world_sum;
  if (g.world_edges.size(0) > 0) {
    auto dw = edge_mlp(*world_edge, g.nodes, g.world_edges, ws, wr, {}, split_first_layer);
    out.world_edges = g.world_edges + dw;
    world_sum = sum_at_receivers(dw, wr, n);
  } else {
    out.world_edges = g.world_edges;
    world_sum = torch::zeros_like(g.nodes);
  }
  // Nodes aggregate the updated edge latents (MeshGraphNets), before the edge residual.
  out.nodes = g.nodes + node->forward({g.nodes, sum_at_receivers(dm, mr, n), world_sum});
  return out;
}

}  // namespace pb4u
