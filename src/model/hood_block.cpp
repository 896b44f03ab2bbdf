#include "pb4u/model/hood_block.h"

#include <algorithm>

namespace pb4u {

HoodBlockImpl::HoodBlockImpl(std::vector<int> s, int64_t latent, int hidden_layers, bool cloth_edges)
    : sets(std::move(s)) {
  auto edge = [&](const std::string& name) {
    return register_module(name, MLP(std::vector<int64_t>{latent, latent, latent}, latent, latent, hidden_layers, true));
  };
  for (int set : sets) set_edge.push_back(edge(set == 0 ? "mesh_edge" : "coarse" + std::to_string(set - 1) + "_edge"));
  world_edge = edge("world_edge");
  if (cloth_edges) cloth_edge = edge("cloth_edge");
  node = register_module("node", MLP(std::vector<int64_t>(sets.size() + (cloth_edges ? 3 : 2), latent), latent, latent,
                                     hidden_layers, true));
}

int HoodBlockImpl::finest_set() const { return *std::min_element(sets.begin(), sets.end()); }

double HoodBlockImpl::matmul_flops(double n, const std::vector<double>& set_edges, double world_kept,
                                   double cloth) const {
  double flops = 0;
  for (size_t k = 0; k < sets.size(); ++k)
    flops += edge_mlp_flops(*set_edge[k], n, set_edges[static_cast<size_t>(sets[k])], true);
  if (world_kept > 0) flops += edge_mlp_flops(*world_edge, n, world_kept, true);
  if (cloth_edge && cloth > 0) flops += edge_mlp_flops(*cloth_edge, n, cloth, true);
  for (size_t part = 0; part < node->first_weights.size(); ++part) flops += node->first_layer_flops(part, n);
  return flops + node->finish_flops(n);
}

HoodLatents HoodBlockImpl::forward(const HoodLatents& g, const HoodIndices& ix) {
  const int64_t n = g.nodes.size(0);
  HoodLatents out = g;
  std::vector<torch::Tensor> node_inputs{g.nodes};
  for (size_t k = 0; k < sets.size(); ++k) {
    const size_t s = static_cast<size_t>(sets[k]);
    auto d = edge_mlp(*set_edge[k], g.nodes, g.edge_sets[s], ix.senders[s], ix.receivers[s]);
    out.edge_sets[s] = g.edge_sets[s] + d;
    node_inputs.push_back(sum_at_receivers(d, ix.receivers[s], n));
  }
  if (ix.world_kept.defined() && ix.world_kept.size(0) > 0) {
    auto kept = g.world_edges.index_select(0, ix.world_kept);
    auto d = edge_mlp(*world_edge, g.nodes, kept, ix.world_senders, ix.world_receivers);
    out.world_edges = g.world_edges.index_copy(0, ix.world_kept, kept + d);
    node_inputs.push_back(sum_at_receivers(d, ix.world_receivers, n));
  } else {
    node_inputs.push_back(torch::zeros_like(g.nodes));
  }
  if (cloth_edge) {
    if (g.cloth_edges.defined() && g.cloth_edges.size(0) > 0) {
      auto d = edge_mlp(*cloth_edge, g.nodes, g.cloth_edges, ix.cloth_senders, ix.cloth_receivers);
      out.cloth_edges = g.cloth_edges + d;
      node_inputs.push_back(sum_at_receivers(d, ix.cloth_receivers, n));
    } else {
      node_inputs.push_back(torch::zeros_like(g.nodes));
    }
  }
  out.nodes = g.nodes + node->forward(node_inputs);
  return out;
}

}  // namespace pb4u
