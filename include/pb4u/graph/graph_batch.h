#pragma once
// The network's input: one garment's graph at one frame (raw, unnormalised features).
// Nodes are the garment vertices (first num_garment_nodes rows) followed by the body vertices
// that world edges touch. Mesh-edge index tensors are the cached topology's, shared, not copied.
#include <torch/torch.h>

#include <vector>

#include "pb4u/graph/row_index.h"

namespace pb4u {

// Feature widths (layout in docs/model.md and graph/features.h).
constexpr int64_t kVertexFeatureDim = 21;
constexpr int64_t kMeshEdgeFeatureDim = 7;
constexpr int64_t kWorldEdgeFeatureDim = 8;  // without the body-normal distances
// With GraphOptions::body_normal_distance: + the garment vertex's height over the body vertex's
// tangent plane, now and at the ballistic guess against the next pose.
constexpr int64_t kWorldEdgeNormalDistanceDim = 2;

// One set of garment edges in a graph: garment node ids, its features, its grouped indices.
struct GraphEdges {
  torch::Tensor senders, receivers;  // (E) int64
  torch::Tensor features;            // (E, 7) float, as the mesh edges' (cloth edges: their own)
  RowIndex sender_rows, receiver_rows;
};

// One garment's keys for the eslr baseline's attention: its nodes are rows
// [first_node, first_node + num_nodes) of the graph, and each attends to the anchor nodes.
struct AnchorSet {
  int64_t first_node = 0, num_nodes = 0;
  torch::Tensor nodes;     // (M) int64: the anchors' node ids
  torch::Tensor distance;  // (num_nodes, M) float, m: edge-path distance on the rest mesh
};

struct GraphBatch {
  torch::Tensor node_features;                   // (nodes, 21) float
  int64_t num_garment_nodes = 0;
  torch::Tensor mesh_senders, mesh_receivers;    // (Em) int64, garment node ids
  torch::Tensor mesh_features;                   // (Em, 7) float
  torch::Tensor world_senders, world_receivers;  // (Ew) int64, Ew may be 0
  torch::Tensor world_features;                  // (Ew, 8 or 10) float
  // The four indices above grouped by node (row_index.h), for the network's gathers and sums;
  // bare ones (torch's kernels) where a graph was put together without them.
  RowIndex mesh_sender_rows, mesh_receiver_rows, world_sender_rows, world_receiver_rows;
  torch::Tensor body_vertex_index;               // (nodes - n) int64: body vertex of each body node
  torch::Tensor vertex_mean_edge_length;         // (n) float, m: numerator of the update scaling
  double mean_edge_length = 0;                   // m: the garment's Lbar, which sets K
  // With GraphOptions::coarse_levels > 0 (the hood baseline): HOOD's long-range edge sets,
  // finest first, and every node's level (0 for body nodes; graph/garment_topology.h).
  std::vector<GraphEdges> coarse;
  torch::Tensor vertex_level;                    // (nodes) int64
  // With GraphOptions::cloth_edge_radius > 0 (ccraft): cloth-to-cloth edges
  // (graph/cloth_edges.h), features (E, kClothEdgeFeatureDim); else undefined.
  GraphEdges cloth_edges;
  // With GraphOptions::geodesic_anchors > 0 (eslr): one per garment, in node order.
  std::vector<AnchorSet> anchor_sets;

  int64_t num_nodes() const { return node_features.size(0); }
  int64_t num_world_edges() const { return world_senders.defined() ? world_senders.size(0) : 0; }
};

}  // namespace pb4u
