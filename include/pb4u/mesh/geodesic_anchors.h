#pragma once
// Distances along a garment's rest mesh to a few spread-out vertices, the keys of the eslr
// baseline's geodesic self-attention (model/geodesic_attention.h). A geodesic distance is
// approximated by the shortest path along the mesh's edges (Dijkstra over rest lengths), which
// is exact along edge paths and at most ~15% long across a regular triangulation.
//
// The anchors are picked by farthest-point sampling on those distances: the first is the vertex
// farthest from vertex 0, each next one the vertex farthest from the anchors picked so far. A
// component the anchors have not reached is infinitely far, so each connected component gets an
// anchor before any gets a second.
#include <Eigen/Core>

#include <vector>

namespace pb4u {

struct GeodesicAnchors {
  std::vector<int> anchors;  // vertex ids, in the order they were picked
  Eigen::MatrixXd distance;  // (n, anchors) m: edge-path distance; +inf across components
};

// Shortest edge-path distances (m) from `source` over a graph given as, per vertex, its
// (neighbour, edge length) pairs; +inf where it cannot reach.
Eigen::VectorXd edge_path_distances(const std::vector<std::vector<std::pair<int, double>>>& adjacency, int source);

// min(count, num_vertices) anchors of the graph of unique undirected `edges` (E x 2) with rest
// `lengths` (E, m). Throws pb4u::Error on a negative length or an
// edge index outside [0, num_vertices).
GeodesicAnchors geodesic_anchors(const Eigen::MatrixXi& edges, const Eigen::VectorXd& lengths, int num_vertices,
                                 int count);

}  // namespace pb4u
