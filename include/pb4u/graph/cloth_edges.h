#pragma once
// Cloth-to-cloth edges (ContourCraft, as its public code builds them), for the ccraft
// baseline: each garment vertex v to the nearest vertex of every face of the same cloth over
// which v lies within a radius (spatial/points_over_faces.h, faces holding v left out), one
// direction, v the sender. They let a network see cloth about to pass through itself.
#include <torch/torch.h>

#include "pb4u/graph/graph_batch.h"

namespace pb4u {

// Edges among the first n = x.size(0) nodes, from positions x (n, 3) and the positions
// expected at t + dt, x_coast (n, 3), faces (m, 3) int64. Features (E, kClothEdgeFeatureDim):
// x_r - x_s, |x_r - x_s|, x_coast_r - x_coast_s, |x_coast_r - x_coast_s|, |d| n_f, |d|, with d
// the sender's signed distance to the face's plane and n_f its unit normal at t (m). Grouped
// over the first `rows` node rows (the garment's).
GraphEdges build_cloth_edges(const torch::Tensor& x, const torch::Tensor& x_coast, const torch::Tensor& faces,
                             double radius, int64_t rows);

}  // namespace pb4u
