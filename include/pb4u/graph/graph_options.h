#pragma once
// Settings of the graph builder; no torch here, so configs can include it.
#include "pb4u/scene/material.h"

namespace pb4u {

// Coarse levels (mesh/coarse_levels.h) every garment topology has (graph/garment_topology.h):
// ContourCraft's 4; HOOD reads the first 3 (each level is built from the one below, so they are
// the same either way).
constexpr int kCoarseLevels = 4;
constexpr int kHoodCoarseLevels = 3;
// Cloth-to-cloth ("self") edges of the ccraft baseline: the features of one.
constexpr int64_t kClothEdgeFeatureDim = 12;

// How the graph is built (from ModelConfig::graph_options(), so a model always gets the graph
// it was trained on).
struct GraphOptions {
  double world_edge_radius = 0.03;  // m
  bool nearest_body_vertex_only = true;  // one world edge per garment vertex (else all in radius)
  MaterialRanges material_ranges;        // normalises the material inputs
  // World edges also carry (x - b).n_b now and (x + v dt - b').n_b' at the next pose: how far
  // the garment vertex is, and will be if it coasts, above the body's tangent plane (m).
  bool body_normal_distance = false;
  // > 0: the graph also carries this many of HOOD's coarse edge sets and each node's level,
  // capped at it (GraphBatch::coarse, vertex_level), for the hood and ccraft baselines.
  int coarse_levels = 0;
  // m, > 0: the graph also carries cloth-to-cloth edges (GraphBatch::cloth_edges), each vertex
  // to the nearest vertex of every face of its own cloth over which it lies within this distance
  // (ContourCraft's, for the ccraft baseline).
  double cloth_edge_radius = 0;
  // > 0: the graph also carries, per garment, this many geodesic anchors and every vertex's
  // distance to them (GraphBatch::anchor_sets), for the eslr baseline's attention. The garment's
  // topology must have been built with them (build_garment_topology).
  int geodesic_anchors = 0;

  int64_t world_edge_feature_dim() const { return body_normal_distance ? 10 : 8; }
};

}  // namespace pb4u
