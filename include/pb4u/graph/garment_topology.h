#pragma once
// What the graph needs from a garment's rest mesh, computed once per garment and reused every
// frame: the directed mesh edges and their rest geometry, lumped vertex areas (masses follow
// from the material's density), the rest edge lengths behind K and the update scaling, and
// HOOD's long-range edges (mesh/coarse_levels.h) for the hood baseline, and, when asked, the
// geodesic anchors of the eslr baseline (mesh/geodesic_anchors.h).
#include <torch/torch.h>

#include <string>
#include <vector>

#include "pb4u/graph/graph_options.h"
#include "pb4u/graph/row_index.h"
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// A set of directed garment edges (each in both directions) with its rest geometry.
struct GarmentEdgeSet {
  torch::Tensor senders, receivers;     // (2E) int64
  RowIndex sender_rows, receiver_rows;  // grouped by vertex (on the CPU)
  torch::Tensor rest_direction;         // (2E, 3) float, unit (X_receiver - X_sender)
  torch::Tensor rest_length;            // (2E) float, m
};

struct GarmentTopology {
  torch::Tensor faces;                    // (m, 3) int64
  torch::Tensor senders, receivers;       // (2E) int64: each unique edge in both directions
  RowIndex sender_rows, receiver_rows;    // the same, grouped by vertex (on the CPU)
  RowIndex corner_rows;                   // the faces' corners grouped by vertex (vertex normals)
  torch::Tensor rest_direction;           // (2E, 3) float, unit (X_receiver - X_sender)
  torch::Tensor rest_length;              // (2E) float, m
  torch::Tensor vertex_area;              // (n) float, m^2: each face gives area / 3
  torch::Tensor vertex_mean_edge_length;  // (n) float, m: mean rest length of incident edges
  double mean_edge_length = 0;            // m: Lbar, mean rest length of the unique edges
  int64_t num_vertices = 0;
  std::vector<GarmentEdgeSet> coarse;     // kCoarseLevels sets of long-range edges, finest first
  torch::Tensor vertex_level;             // (n) int64: 0, or 1 + the coarsest level a vertex is in
  // Built with geodesic_anchors > 0 only (else undefined): the anchors' vertex ids and every
  // vertex's edge-path distance to each, m (+inf across components).
  torch::Tensor anchors;                  // (M) int64
  torch::Tensor anchor_distance;          // (n, M) float

  int64_t num_mesh_edges() const { return senders.size(0); }
};

// Builds the topology of `rest` (n x 3 m, m x 3 faces). Throws pb4u::Error naming `where` for a
// mesh without faces, out-of-range indices or zero-length edges (relative features divide by
// rest lengths). geodesic_anchors > 0 also finds min(that, n) anchors (GraphOptions'
// geodesic_anchors: what the model's graph needs; 0.3 s for 256 on 5.5K vertices, 1 thread).
GarmentTopology build_garment_topology(const TriMesh& rest, const std::string& where = "garment",
                                       int geodesic_anchors = 0);

// The same topology with every tensor on `device` (built once, so a CUDA run builds graphs on
// the GPU without a host round trip per frame).
GarmentTopology garment_topology_to(const GarmentTopology& topology, torch::Device device);

}  // namespace pb4u
