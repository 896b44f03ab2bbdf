#include "pb4u/mesh/coarse_levels.h"

#include <algorithm>
#include <limits>
#include <queue>

#include "pb4u/util/error.h"

namespace pb4u {

namespace {

using Adjacency = std::vector<std::vector<int>>;

// Breadth-first distances from `sources` (-1: not reached); returns the largest one.
int bfs(const Adjacency& adj, const std::vector<int>& sources, std::vector<int>& dist) {
  dist.assign(adj.size(), -1);
  std::queue<int> q;
  for (int s : sources) {
    dist[s] = 0;
    q.push(s);
  }
  int far = 0;
  while (!q.empty()) {
    const int v = q.front();
    q.pop();
    far = std::max(far, dist[v]);
    for (int w : adj[v])
      if (dist[w] < 0) {
        dist[w] = dist[v] + 1;
        q.push(w);
      }
  }
  return far;
}

bool adjacent(const Adjacency& adj, int a, int b) {
  return std::find(adj[a].begin(), adj[a].end(), b) != adj[a].end();
}

// Whether a and b are at most two hops apart.
bool within_two(const Adjacency& adj, int a, int b) {
  if (a == b || adjacent(adj, a, b)) return true;
  for (int c : adj[a])
    if (adjacent(adj, c, b)) return true;
  return false;
}

void join(Adjacency& adj, int a, int b) {
  if (a == b || adjacent(adj, a, b)) return;
  adj[a].push_back(b);
  adj[b].push_back(a);
}

// One HOOD level from the graph `g` and the distances `d` from its centres (header, steps 1-3).
Adjacency coarsen(const Adjacency& g, const std::vector<int>& d) {
  const int n = static_cast<int>(g.size());
  auto odd = [&](int v) { return d[v] >= 0 && d[v] % 2 == 1; };
  auto even = [&](int v) { return d[v] >= 0 && d[v] % 2 == 0; };
  auto at = [&](int v, int distance) {
    std::vector<int> out;
    for (int w : g[v])
      if (d[w] == distance) out.push_back(w);
    return out;
  };
  Adjacency two_hop(n);
  for (int i = 0; i < n; ++i) {
    if (!odd(i)) continue;
    for (int closer : at(i, d[i] - 1))
      for (int farther : at(i, d[i] + 1)) join(two_hop, closer, farther);
  }
  Adjacency out = two_hop;
  for (int i = 0; i < n; ++i) {
    if (!odd(i) || !at(i, d[i] + 1).empty()) continue;
    const std::vector<int> closer = at(i, d[i] - 1);
    for (int a : closer)
      for (int b : closer)
        if (a != b && !within_two(two_hop, a, b)) join(out, a, b);
  }
  for (int i = 0; i < n; ++i) {
    if (!even(i)) continue;
    for (int a : at(i, d[i]))
      if (!within_two(out, a, i)) join(out, a, i);
  }
  for (auto& neighbours : out) std::sort(neighbours.begin(), neighbours.end());
  return out;
}

Eigen::MatrixXi edge_list(const Adjacency& adj) {
  std::vector<std::pair<int, int>> e;
  for (int i = 0; i < static_cast<int>(adj.size()); ++i)
    for (int j : adj[i])
      if (i < j) e.emplace_back(i, j);
  std::sort(e.begin(), e.end());
  Eigen::MatrixXi out(static_cast<Eigen::Index>(e.size()), 2);
  for (size_t k = 0; k < e.size(); ++k) out.row(static_cast<Eigen::Index>(k)) << e[k].first, e[k].second;
  return out;
}

// Centres for this graph's components: a component keeps a centre it already holds, and one
// that holds none (a level that split its component) gets its own.
std::vector<int> centers_of(const Adjacency& g, const std::vector<int>& previous) {
  std::vector<int> centers, dist;
  for (int c : previous)
    if (!g[c].empty()) centers.push_back(c);
  if (centers.empty()) dist.assign(g.size(), -1);
  else bfs(g, centers, dist);
  for (int v = 0; v < static_cast<int>(g.size()); ++v) {
    if (g[v].empty() || dist[v] >= 0) continue;
    const int c = graph_center(g, v);
    centers.push_back(c);
    bfs(g, centers, dist);
  }
  return centers;
}

}  // namespace

int graph_center(const Adjacency& adj, int seed) {
  std::vector<int> dist;
  bfs(adj, {seed}, dist);
  std::vector<int> component;
  for (int v = 0; v < static_cast<int>(adj.size()); ++v)
    if (dist[v] >= 0) component.push_back(v);
  const int inf = std::numeric_limits<int>::max();
  std::vector<int> lower(adj.size(), 0), upper(adj.size(), inf), exact(adj.size(), -1);
  int best = inf;
  bool pick_low = true;
  for (;;) {
    // Vertices that may still be a centre: eccentricity not known, lower bound not above the best.
    int next = -1;
    for (int v : component) {
      if (exact[v] >= 0 || lower[v] > best) continue;
      if (lower[v] == upper[v]) {
        exact[v] = lower[v];
        best = std::min(best, exact[v]);
        continue;
      }
      if (next < 0 || (pick_low ? lower[v] < lower[next] : upper[v] > upper[next])) next = v;
    }
    if (next < 0) break;
    pick_low = !pick_low;
    const int ecc = bfs(adj, {next}, dist);
    exact[next] = ecc;
    best = std::min(best, ecc);
    for (int v : component) {
      lower[v] = std::max({lower[v], dist[v], ecc - dist[v]});
      upper[v] = std::min(upper[v], ecc + dist[v]);
    }
  }
  for (int v : component)
    if (exact[v] == best) return v;
  throw Error("graph_center: no centre found");  // unreachable: the seed's own search is exact
}

CoarseLevels coarse_levels(const Eigen::MatrixXi& edges, int num_vertices, int levels) {
  if (levels < 0) throw Error("coarse levels: the number of levels must be at least 0");
  Adjacency g(num_vertices);
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    const int a = edges(e, 0), b = edges(e, 1);
    if (a < 0 || b < 0 || a >= num_vertices || b >= num_vertices)
      throw Error("coarse levels: edge " + std::to_string(e) + " has a vertex outside [0, " +
                  std::to_string(num_vertices) + ")");
    join(g, a, b);
  }
  for (auto& neighbours : g) std::sort(neighbours.begin(), neighbours.end());
  CoarseLevels out;
  out.vertex_level = Eigen::VectorXi::Zero(num_vertices);
  out.centers = centers_of(g, {});
  std::vector<int> centers = out.centers, dist;
  for (int level = 0; level < levels; ++level) {
    centers = centers_of(g, centers);
    if (centers.empty()) dist.assign(g.size(), -1);
    else bfs(g, centers, dist);
    g = coarsen(g, dist);
    out.edges.push_back(edge_list(g));
    for (Eigen::Index e = 0; e < out.edges.back().rows(); ++e)
      for (int k = 0; k < 2; ++k) out.vertex_level(out.edges.back()(e, k)) = level + 1;
  }
  return out;
}

}  // namespace pb4u
