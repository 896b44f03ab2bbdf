#pragma once
// Feature building blocks of SPEC 4: what goes into the network, one function per feature
// group. Positions are float tensors in metres; directions "receiver - sender".
#include <torch/torch.h>

#include <array>
#include <string>

#include "pb4u/graph/garment_topology.h"
#include "pb4u/graph/row_index.h"
#include "pb4u/scene/material.h"

namespace pb4u {

// The face corners of faces (m, 3) int64 over `vertices` vertices grouped by vertex, first
// corners in face order, then second, then third (row_index.h): what vertex_normals sums.
RowIndex face_corner_rows(const torch::Tensor& faces, int64_t vertices);

// (n, 3) unit area-weighted vertex normals of positions x (n, 3) with faces (m, 3) int64;
// zero for isolated or fully degenerate vertices. `corners`: face_corner_rows(faces, n) when
// the caller keeps it (a garment's topology, a body posed twice), else built here.
torch::Tensor vertex_normals(const torch::Tensor& x, const torch::Tensor& faces, const RowIndex& corners = {});

// Material as 4 numbers in [0, 1] over `ranges`: density and lambda linear, mu and bending on
// a log scale. Values outside a range extrapolate linearly. Throws pb4u::Error naming
// `where`.<key> when a range is not an increasing pair (positive for the log ones).
std::array<double, 4> normalised_material(const Material& material, const MaterialRanges& ranges,
                                          const std::string& where = "model.material_ranges");

// (2E, 7) relative mesh-edge features at current positions x (n, 3): current unit direction
// (3), rest unit direction (3), current / rest length (1). No absolute lengths, so a uniform
// scaling of the garment leaves them unchanged.
torch::Tensor mesh_edge_features(const torch::Tensor& x, const GarmentTopology& topology);
// The same 7 features for any set of garment edges (HOOD's coarse edges).
torch::Tensor edge_set_features(const torch::Tensor& x, const GarmentEdgeSet& edges);

// (Ew, 8) world-edge features from node positions p (nodes, 3) at time t and q (nodes, 3) the
// positions expected at t + dt (body: its next pose; garment: x + v dt): p_r - p_s, |p_r - p_s|,
// q_r - q_s, |q_r - q_s| (m).
torch::Tensor world_edge_features(const torch::Tensor& p, const torch::Tensor& q,
                                  const torch::Tensor& senders, const torch::Tensor& receivers);

// (P, 2) per garment/body vertex pair (rows gathered per pair): the garment vertex's signed
// height over the body vertex's tangent plane now, (x - b).n, and if it coasts, against the
// next pose, (x + v dt - b').n' (m; negative = behind the surface).
torch::Tensor body_normal_distances(const torch::Tensor& x, const torch::Tensor& x_coast,
                                    const torch::Tensor& b, const torch::Tensor& b_next,
                                    const torch::Tensor& n, const torch::Tensor& n_next);

}  // namespace pb4u
