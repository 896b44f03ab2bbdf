#include "pb4u/mesh/edges.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace pb4u {
namespace {

// A directed face side: the undirected key, the face and which corner it starts at.
struct Side {
  int64_t key;  // (min << 32) | max
  int face, corner;
};

std::vector<Side> sorted_sides(const Eigen::MatrixXi& F) {
  std::vector<Side> sides;
  sides.reserve(static_cast<size_t>(F.rows()) * 3);
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      int64_t a = F(f, c), b = F(f, (c + 1) % 3);
      sides.push_back({(std::min(a, b) << 32) | std::max(a, b), f, c});
    }
  std::sort(sides.begin(), sides.end(), [](const Side& l, const Side& r) {
    return l.key != r.key ? l.key < r.key : l.face < r.face;
  });
  return sides;
}

// Calls fn(first, last) for every run of sides sharing one undirected edge.
template <class Fn>
void for_each_edge(const std::vector<Side>& sides, Fn fn) {
  for (size_t i = 0; i < sides.size();) {
    size_t j = i + 1;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    fn(i, j);
    i = j;
  }
}

}  // namespace

Eigen::MatrixXi unique_edges(const Eigen::MatrixXi& F) {
  auto sides = sorted_sides(F);
  std::vector<int64_t> keys;
  for_each_edge(sides, [&](size_t i, size_t) { keys.push_back(sides[i].key); });
  Eigen::MatrixXi E(keys.size(), 2);
  for (size_t e = 0; e < keys.size(); ++e) {
    E(e, 0) = static_cast<int>(keys[e] >> 32);
    E(e, 1) = static_cast<int>(keys[e] & 0xffffffff);
  }
  return E;
}

Eigen::VectorXi edge_face_counts(const Eigen::MatrixXi& F) {
  auto sides = sorted_sides(F);
  std::vector<int> counts;
  for_each_edge(sides, [&](size_t i, size_t j) { counts.push_back(static_cast<int>(j - i)); });
  return Eigen::Map<Eigen::VectorXi>(counts.data(), counts.size());
}

HingeSet interior_hinges(const Eigen::MatrixXi& F) {
  auto sides = sorted_sides(F);
  std::vector<std::array<int, 6>> rows;
  for_each_edge(sides, [&](size_t i, size_t j) {
    if (j - i != 2) return;
    const Side& s0 = sides[i];
    const Side& s1 = sides[i + 1];
    int a = F(s0.face, s0.corner), b = F(s0.face, (s0.corner + 1) % 3);
    int k0 = F(s0.face, (s0.corner + 2) % 3);
    int k1 = F(s1.face, (s1.corner + 2) % 3);
    rows.push_back({a, b, s0.face, s1.face, k0, k1});
  });
  HingeSet h;
  int n = static_cast<int>(rows.size());
  h.edge.resize(n, 2);
  h.faces.resize(n, 2);
  h.opposite.resize(n, 2);
  for (int e = 0; e < n; ++e) {
    h.edge.row(e) << rows[e][0], rows[e][1];
    h.faces.row(e) << rows[e][2], rows[e][3];
    h.opposite.row(e) << rows[e][4], rows[e][5];
  }
  return h;
}

}  // namespace pb4u
