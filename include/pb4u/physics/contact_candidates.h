#pragma once
// The broad phase of intersection-free contact: which cloth-vertex / body-face and
// cloth-edge / body-edge pairs can come within a distance of each other during a step. Only
// candidates: the narrow phase (primitive_distance.h, additive_ccd.h) decides. Grids over the
// body's face and edge boxes (spatial/box_grid.h), queried with boxes grown by the motion of the
// step, then each pair's centroid reach and swept boxes, so no pair that can meet is missed.
#include <Eigen/Core>

#include <array>
#include <memory>
#include <vector>

namespace pb4u {

struct SurfaceIndex;

// A body surface as contact sees it: vertices (nb x 3, m), outward faces (mb x 3) and its
// unique edges (eb x 2). `index` caches the grids over its face and edge boxes between
// queries; contact_candidates rebuilds it whenever V differs from the
// positions it was built at (so V may be assigned freely). Not to be queried from two
// threads at once.
struct ContactSurface {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F, E;
  mutable std::shared_ptr<const SurfaceIndex> index;
};
ContactSurface make_contact_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

struct ContactCandidates {
  std::vector<std::array<int, 2>> vertex_face;  // (cloth vertex, body face)
  std::vector<std::array<int, 2>> edge_edge;    // (cloth edge row, body edge row)
  size_t size() const { return vertex_face.size() + edge_edge.size(); }
};

// Pairs that may come within `distance` (m) of each other while the cloth x (n x 3) moves by
// dx (n x 3, or empty: still) and the body by body_motion (nb x 3, or empty: still).
// cloth_edges: e x 2 vertex rows of x.
ContactCandidates contact_candidates(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx,
                                     const Eigen::MatrixXi& cloth_edges, const ContactSurface& body,
                                     const Eigen::MatrixXd& body_motion, double distance);

// The candidates without the pairs of excluded cloth vertices (excluded[i] != 0): their
// vertex-face pairs and the edge-edge pairs of the edges they end.
void drop_pairs_of(const std::vector<char>& excluded, const Eigen::MatrixXi& cloth_edges,
                   ContactCandidates* candidates);

}  // namespace pb4u
