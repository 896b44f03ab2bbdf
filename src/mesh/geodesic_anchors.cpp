#include "pb4u/mesh/geodesic_anchors.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include "pb4u/util/error.h"

namespace pb4u {

Eigen::VectorXd edge_path_distances(const std::vector<std::vector<std::pair<int, double>>>& adjacency, int source) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd d = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(adjacency.size()), inf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  d(source) = 0;
  open.push({0.0, source});
  while (!open.empty()) {
    auto [du, u] = open.top();
    open.pop();
    if (du > d(u)) continue;  // a stale entry
    for (const auto& [v, length] : adjacency[static_cast<size_t>(u)]) {
      const double dv = du + length;
      if (dv < d(v)) {
        d(v) = dv;
        open.push({dv, v});
      }
    }
  }
  return d;
}

GeodesicAnchors geodesic_anchors(const Eigen::MatrixXi& edges, const Eigen::VectorXd& lengths, int n, int count) {
  if (edges.rows() != lengths.size()) throw Error("geodesic anchors: one length per edge is needed");
  std::vector<std::vector<std::pair<int, double>>> adjacency(static_cast<size_t>(n));
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    const int i = edges(e, 0), j = edges(e, 1);
    if (i < 0 || j < 0 || i >= n || j >= n) throw Error("geodesic anchors: edge index outside the mesh");
    if (!(lengths(e) >= 0)) throw Error("geodesic anchors: negative or non-finite edge length");
    adjacency[static_cast<size_t>(i)].push_back({j, lengths(e)});
    adjacency[static_cast<size_t>(j)].push_back({i, lengths(e)});
  }
  GeodesicAnchors out;
  const int m = std::max(0, std::min(count, n));
  out.distance.resize(n, m);
  if (m == 0) return out;
  // Farthest from the anchors so far (+inf: a component none has reached); ties go to the
  // lowest index.
  auto farthest = [&](const Eigen::VectorXd& nearest) {
    int best = 0;
    for (int v = 1; v < n; ++v)
      if (nearest(v) > nearest(best)) best = v;
    return best;
  };
  Eigen::VectorXd from_zero = edge_path_distances(adjacency, 0);
  // Vertex 0's own component first: the vertex farthest from it there.
  int first = 0;
  for (int v = 1; v < n; ++v)
    if (std::isfinite(from_zero(v)) && from_zero(v) > from_zero(first)) first = v;
  Eigen::VectorXd nearest = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  int next = first;
  for (int k = 0; k < m; ++k) {
    out.anchors.push_back(next);
    out.distance.col(k) = edge_path_distances(adjacency, next);
    nearest = nearest.cwiseMin(out.distance.col(k));
    next = farthest(nearest);
  }
  return out;
}

}  // namespace pb4u
