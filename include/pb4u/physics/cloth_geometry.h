#pragma once
// What the physics terms need from a garment's rest shape, computed once per garment
// (it does not change over a sequence) as tensors of one dtype on one device.
#include <torch/torch.h>

#include "pb4u/mesh/triangle_mesh.h"
#include "pb4u/physics/physics_config.h"

namespace pb4u {

struct ClothGeometry {
  int64_t num_vertices = 0;
  torch::Tensor faces;         // (m, 3) int64
  torch::Tensor dm_inverse;    // (m, 2, 2) 1/m: rest Dm^-1 in each face's local 2D frame
  torch::Tensor face_area;     // (m) m^2, rest
  torch::Tensor vertex_area;   // (n) m^2: a third of each incident face's rest area
  torch::Tensor hinges;        // (h, 4) int64: (i, j, k0, k1) shared edge i -> j as in face 0,
                               //   k0 / k1 the vertices opposite it in face 0 / face 1
  torch::Tensor hinge_weight;  // (h) 1: l_e^2 / (4 (A0 + A1)) at rest (SPEC 3.2)
  torch::Tensor rest_angle;    // (h) rad: zeros unless built with rest angles
  torch::Tensor edge_rest_length;  // (e) m: rest length of each edge of unique_edges(faces)

  // (n) kg: lumped masses density * vertex_area, so any sampled material reuses the geometry.
  // density in kg/m^2.
  torch::Tensor vertex_masses(double density) const { return vertex_area * density; }
  torch::Dtype dtype() const { return face_area.scalar_type(); }
  torch::Device device() const { return face_area.device(); }
};

// rest: the garment at rest (V n x 3 m, F m x 3). with_rest_angles: bend relative to the
// rest dihedral angles instead of flat (SPEC 3.2). degenerate_area (m^2): see PhysicsConfig.
// Throws pb4u::Error on an empty mesh or face indices out of range.
ClothGeometry make_cloth_geometry(const TriMesh& rest, torch::Dtype dtype = torch::kFloat64,
                                  torch::Device device = torch::kCPU,
                                  bool with_rest_angles = false,
                                  double degenerate_area = PhysicsConfig{}.degenerate_area);

}  // namespace pb4u
