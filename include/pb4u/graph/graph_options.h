#pragma once
// Settings of the graph builder; no torch here, so configs can include it.
#include "pb4u/physics/material.h"

namespace pb4u {

// How the graph is built (from ModelConfig::graph_options(), so a model always gets the graph
// it was trained on).
struct GraphOptions {
  double world_edge_radius = 0.03;  // m
  bool nearest_body_vertex_only = true;  // one world edge per garment vertex (else all in radius)
  MaterialRanges material_ranges;        // normalises the material inputs
};

}  // namespace pb4u
