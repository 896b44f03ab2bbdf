#pragma once
// HOOD's long-range edges (Grigorev et al., CVPR 2023, as its public code builds them): each
// level keeps the vertices at an even breadth-first distance from a centre of the graph below
// it and joins kept vertices that were two hops apart there. A kept vertex is the fine vertex
// itself (no pooling), so every level's edges index the garment's own vertices.
//
// One level from the graph G below it (distances d from the centre, in G):
//   1. each vertex at odd d joins each neighbour at d - 1 to each neighbour at d + 1;
//   2. each vertex at odd d with no neighbour at d + 1 (the edge of the distance field) joins
//      pairs of its neighbours at d - 1 that are more than two hops apart in the graph of step 1;
//   3. each vertex at even d joins each neighbour at even d (the same distance) that is more
//      than two hops away in the graph built so far (vertices and neighbours in index order).
// Vertices at odd d are left without edges, and the next level starts from this one's graph.
//
// Where this differs from that code: each connected component has its own centre (it used one
// for the whole mesh, and a vertex it could not reach counted as distance 0), and the centre is
// the lowest-index vertex of least eccentricity (it drew one at random among them).
#include <Eigen/Core>

#include <vector>

namespace pb4u {

struct CoarseLevels {
  std::vector<int> centers;           // one per connected component of the mesh's edges
  std::vector<Eigen::MatrixXi> edges;  // per level: unique undirected edges (i, j), i < j, sorted
  // Per vertex: 0 if it is in no level's edges, else 1 + the coarsest level it belongs to.
  Eigen::VectorXi vertex_level;
};

// The `levels` coarse levels of the graph with `num_vertices` vertices and unique undirected
// `edges` (E x 2). A level may be empty when the one below it has no two vertices left to join.
CoarseLevels coarse_levels(const Eigen::MatrixXi& edges, int num_vertices, int levels);

// The lowest-index vertex of least eccentricity (longest shortest path to another vertex) of
// the connected component of `adjacency` that holds `seed`. Exact: eccentricity bounds from
// breadth-first searches (Takes and Kosters 2011) prune the vertices that cannot be the centre.
int graph_center(const std::vector<std::vector<int>>& adjacency, int seed);

}  // namespace pb4u
