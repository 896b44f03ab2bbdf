#pragma once
// Global topology of a triangle mesh: boundaries, components, manifoldness.
#include <Eigen/Core>
#include <vector>

namespace pb4u {

// Closed loops of boundary edges (edges with exactly one face), each an ordered list of
// vertex indices following the faces' orientation. A t-shirt has four: neck, waist, sleeves.
std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixXi& F);

// Connected components over shared vertices. Returns a label per vertex (-1 for vertices no
// face references) and writes the number of components to *count.
Eigen::VectorXi connected_components(const Eigen::MatrixXi& F, int num_vertices, int* count);

struct ManifoldReport {
  int nonmanifold_edges = 0;     // edges with more than two faces
  int nonmanifold_vertices = 0;  // vertices whose faces form more than one fan
  int misoriented_edges = 0;     // interior edges both faces traverse the same way
  bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  bool oriented() const { return misoriented_edges == 0; }
};
ManifoldReport check_manifold(const Eigen::MatrixXi& F, int num_vertices);

}  // namespace pb4u
