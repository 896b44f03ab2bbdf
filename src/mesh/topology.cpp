#include "pb4u/mesh/topology.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

#include "pb4u/mesh/edges.h"

namespace pb4u {
namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

int64_t key(int a, int b) {
  return (static_cast<int64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

}  // namespace

std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixXi& F) {
  std::unordered_map<int64_t, int> uses;
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) ++uses[key(F(f, c), F(f, (c + 1) % 3))];
  // Directed boundary sides a -> b; a vertex may start several (pinched boundaries).
  std::multimap<int, int> next;
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      int a = F(f, c), b = F(f, (c + 1) % 3);
      if (uses[key(a, b)] == 1) next.emplace(a, b);
    }
  std::vector<std::vector<int>> loops;
  while (!next.empty()) {
    auto it = next.begin();
    int start = it->first;
    std::vector<int> loop{start};
    int cur = it->second;
    next.erase(it);
    while (cur != start) {
      loop.push_back(cur);
      auto nx = next.find(cur);
      if (nx == next.end()) break;  // open chain (inconsistent orientation): stop here
      cur = nx->second;
      next.erase(nx);
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

Eigen::VectorXi connected_components(const Eigen::MatrixXi& F, int num_vertices, int* count) {
  UnionFind uf(num_vertices);
  std::vector<char> used(num_vertices, 0);
  for (int f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) used[F(f, c)] = 1;
    uf.join(F(f, 0), F(f, 1));
    uf.join(F(f, 1), F(f, 2));
  }
  Eigen::VectorXi label = Eigen::VectorXi::Constant(num_vertices, -1);
  std::unordered_map<int, int> root_label;
  for (int v = 0; v < num_vertices; ++v) {
    if (!used[v]) continue;
    auto [it, inserted] = root_label.emplace(uf.find(v), static_cast<int>(root_label.size()));
    label(v) = it->second;
  }
  if (count) *count = static_cast<int>(root_label.size());
  return label;
}

ManifoldReport check_manifold(const Eigen::MatrixXi& F, int num_vertices) {
  ManifoldReport report;
  // Edge uses and orientation: +1 for a -> b with a < b, -1 otherwise.
  std::unordered_map<int64_t, std::pair<int, int>> edge;  // key -> (count, orientation sum)
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      int a = F(f, c), b = F(f, (c + 1) % 3);
      auto& e = edge[key(a, b)];
      e.first += 1;
      e.second += a < b ? 1 : -1;
    }
  for (const auto& [k, e] : edge) {
    if (e.first > 2) ++report.nonmanifold_edges;
    if (e.first == 2 && e.second != 0) ++report.misoriented_edges;
  }
  // Vertex fans: faces around v are connected when they share an edge through v.
  std::vector<std::vector<int>> vf(num_vertices);
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) vf[F(f, c)].push_back(f);
  for (int v = 0; v < num_vertices; ++v) {
    const auto& faces = vf[v];
    if (faces.size() < 2) continue;
    UnionFind uf(static_cast<int>(faces.size()));
    std::unordered_map<int, int> by_other;  // other vertex -> first local face
    for (int i = 0; i < static_cast<int>(faces.size()); ++i)
      for (int c = 0; c < 3; ++c) {
        int w = F(faces[i], c);
        if (w == v) continue;
        auto [it, inserted] = by_other.emplace(w, i);
        if (!inserted) uf.join(i, it->second);
      }
    int roots = 0;
    for (int i = 0; i < static_cast<int>(faces.size()); ++i) roots += uf.find(i) == i;
    if (roots > 1) ++report.nonmanifold_vertices;
  }
  return report;
}

}  // namespace pb4u
