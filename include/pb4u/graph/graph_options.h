#pragma once
// Settings of the graph builder; no torch here, so configs can include it.
#include "pb4u/scene/material.h"

namespace pb4u {

// HOOD's coarse levels (its public configuration's n_coarse_levels): every garment topology
// has them (graph/garment_topology.h), a hood model reads them.
constexpr int kCoarseLevels = 3;

// How the graph is built (from ModelConfig::graph_options(), so a model always gets the graph
// it was trained on).
struct GraphOptions {
  double world_edge_radius = 0.03;  // m
  bool nearest_body_vertex_only = true;  // one world edge per garment vertex (else all in radius)
  MaterialRanges material_ranges;        // normalises the material inputs
  // World edges also carry (x - b).n_b now and (x + v dt - b').n_b' at the next pose: how far
  // the garment vertex is, and will be if it coasts, above the body's tangent plane (m).
  bool body_normal_distance = false;
  // > 0: the graph also carries this many of HOOD's coarse edge sets and each node's level
  // (GraphBatch::coarse, vertex_level), for the hood baseline.
  int coarse_levels = 0;

  int64_t world_edge_feature_dim() const { return body_normal_distance ? 10 : 8; }
};

}  // namespace pb4u
