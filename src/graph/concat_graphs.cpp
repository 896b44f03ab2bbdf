#include "pb4u/graph/concat_graphs.h"

#include "pb4u/util/error.h"

namespace pb4u {

GraphBatch concat_graphs(const std::vector<GraphBatch>& graphs) {
  if (graphs.empty()) throw Error("concat_graphs: no graphs to batch");
  if (graphs.size() == 1) return graphs[0];
  int64_t total_garment = 0;
  for (const auto& g : graphs) total_garment += g.num_garment_nodes;

  std::vector<torch::Tensor> garment_nodes, body_nodes, ms, mr, mf, ws, wr, wf, body_index, scale;
  std::vector<torch::Tensor> garment_levels, body_levels, cloth_s, cloth_r, cloth_f;
  const bool cloth = graphs[0].cloth_edges.senders.defined();
  const size_t levels = graphs[0].coarse.size();
  std::vector<std::vector<torch::Tensor>> cs(levels), cr(levels), cf(levels);
  int64_t garment_offset = 0, body_offset = total_garment;
  std::vector<AnchorSet> anchor_sets;
  double length_sum = 0, edge_count = 0;
  for (const auto& g : graphs) {
    const int64_t n = g.num_garment_nodes, nb = g.num_nodes() - n;
    garment_nodes.push_back(g.node_features.narrow(0, 0, n));
    body_nodes.push_back(g.node_features.narrow(0, n, nb));
    ms.push_back(g.mesh_senders + garment_offset);
    mr.push_back(g.mesh_receivers + garment_offset);
    mf.push_back(g.mesh_features);
    // Garment node v keeps its rank among garments; body node v moves to the body block.
    auto renumber = [&](const torch::Tensor& v) {
      return torch::where(v < n, v + garment_offset, v - n + body_offset);
    };
    ws.push_back(renumber(g.world_senders));
    wr.push_back(renumber(g.world_receivers));
    wf.push_back(g.world_features);
    body_index.push_back(g.body_vertex_index);
    if (g.coarse.size() != levels) throw Error("concat_graphs: graphs with different numbers of coarse levels");
    for (size_t l = 0; l < levels; ++l) {
      cs[l].push_back(g.coarse[l].senders + garment_offset);
      cr[l].push_back(g.coarse[l].receivers + garment_offset);
      cf[l].push_back(g.coarse[l].features);
    }
    if (g.cloth_edges.senders.defined() != cloth) throw Error("concat_graphs: graphs with and without cloth edges");
    if (cloth) {
      cloth_s.push_back(g.cloth_edges.senders + garment_offset);
      cloth_r.push_back(g.cloth_edges.receivers + garment_offset);
      cloth_f.push_back(g.cloth_edges.features);
    }
    if (levels > 0) {
      garment_levels.push_back(g.vertex_level.narrow(0, 0, n));
      body_levels.push_back(g.vertex_level.narrow(0, n, nb));
    }
    if (g.anchor_sets.empty() != graphs[0].anchor_sets.empty())
      throw Error("concat_graphs: graphs with and without geodesic anchors");
    for (const AnchorSet& set : g.anchor_sets)
      anchor_sets.push_back({set.first_node + garment_offset, set.num_nodes, set.nodes + garment_offset, set.distance});
    scale.push_back(g.vertex_mean_edge_length);
    length_sum += g.mean_edge_length * static_cast<double>(g.mesh_senders.size(0));
    edge_count += static_cast<double>(g.mesh_senders.size(0));
    garment_offset += n;
    body_offset += nb;
  }
  GraphBatch out;
  garment_nodes.insert(garment_nodes.end(), body_nodes.begin(), body_nodes.end());
  out.node_features = torch::cat(garment_nodes, 0);
  out.num_garment_nodes = total_garment;
  out.mesh_senders = torch::cat(ms);
  out.mesh_receivers = torch::cat(mr);
  out.mesh_features = torch::cat(mf, 0);
  out.world_senders = torch::cat(ws);
  out.world_receivers = torch::cat(wr);
  out.world_features = torch::cat(wf, 0);
  out.mesh_sender_rows = group_rows(out.mesh_senders, out.num_garment_nodes);
  out.mesh_receiver_rows = group_rows(out.mesh_receivers, out.num_garment_nodes);
  out.world_sender_rows = group_rows(out.world_senders, out.num_nodes());
  out.world_receiver_rows = group_rows(out.world_receivers, out.num_nodes());
  out.body_vertex_index = torch::cat(body_index);
  for (size_t l = 0; l < levels; ++l) {
    GraphEdges set{torch::cat(cs[l]), torch::cat(cr[l]), torch::cat(cf[l], 0), {}, {}};
    set.sender_rows = group_rows(set.senders, out.num_garment_nodes);
    set.receiver_rows = group_rows(set.receivers, out.num_garment_nodes);
    out.coarse.push_back(set);
  }
  if (cloth) {
    out.cloth_edges = {torch::cat(cloth_s), torch::cat(cloth_r), torch::cat(cloth_f, 0), {}, {}};
    out.cloth_edges.sender_rows = group_rows(out.cloth_edges.senders, out.num_garment_nodes);
    out.cloth_edges.receiver_rows = group_rows(out.cloth_edges.receivers, out.num_garment_nodes);
  }
  if (levels > 0) {
    garment_levels.insert(garment_levels.end(), body_levels.begin(), body_levels.end());
    out.vertex_level = torch::cat(garment_levels);
  }
  out.anchor_sets = std::move(anchor_sets);
  out.vertex_mean_edge_length = torch::cat(scale);
  out.mean_edge_length = edge_count > 0 ? length_sum / edge_count : 0;
  return out;
}

}  // namespace pb4u
