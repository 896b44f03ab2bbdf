#include "pb4u/graph/features.h"

#include <cmath>

#include "pb4u/graph/row_index.h"
#include "pb4u/util/error.h"

namespace pb4u {

RowIndex face_corner_rows(const torch::Tensor& faces, int64_t vertices) {
  return group_rows(torch::cat({faces.select(1, 0), faces.select(1, 1), faces.select(1, 2)}), vertices);
}

torch::Tensor vertex_normals(const torch::Tensor& x, const torch::Tensor& faces, const RowIndex& corners) {
  auto a = x.index_select(0, faces.select(1, 0)), b = x.index_select(0, faces.select(1, 1)),
       c = x.index_select(0, faces.select(1, 2));
  // Unnormalised face normals weigh each face by twice its area.
  auto fn = torch::cross(b - a, c - a, 1);
  // Each vertex sums its faces' normals corner by corner (all first corners in face order, then
  // the second, then the third), grouped by vertex (row_index.h): the order, and so the bits,
  // of three index_add_ calls, without their row-at-a-time cost.
  const RowIndex grouped = corners.index.defined() ? corners : face_corner_rows(faces, x.size(0));
  auto n = sum_rows_at(torch::cat({fn, fn, fn}), grouped, x.size(0));
  auto norm = n.norm(2, 1, true);
  return torch::where(norm > 0, n / norm.clamp_min(1e-30), torch::zeros_like(n));
}

std::array<double, 4> normalised_material(const Material& material, const MaterialRanges& ranges,
                                          const std::string& where) {
  auto unit = [&](const char* key, const std::vector<double>& range, double value, bool log) {
    if (range.size() != 2 || !(range[0] < range[1]) || (log && range[0] <= 0))
      fail_file(where + "." + key, log ? "expected an increasing pair of positive numbers [lo, hi]"
                                       : "expected an increasing pair [lo, hi]");
    if (log) {
      if (value <= 0) fail_file(std::string("material.") + key, "must be positive");
      return (std::log(value) - std::log(range[0])) / (std::log(range[1]) - std::log(range[0]));
    }
    return (value - range[0]) / (range[1] - range[0]);
  };
  return {unit("density", ranges.density, material.density, false),
          unit("mu", ranges.mu, material.mu, true),
          unit("lambda", ranges.lambda, material.lambda, false),
          unit("bending", ranges.bending, material.bending, true)};
}

namespace {
torch::Tensor relative_edge_features(const torch::Tensor& x, const torch::Tensor& senders,
                                     const torch::Tensor& receivers, const torch::Tensor& rest_direction,
                                     const torch::Tensor& rest_length) {
  auto d = x.index_select(0, receivers) - x.index_select(0, senders);
  auto len = d.norm(2, 1, true);
  auto rest_len = rest_length.unsqueeze(1);
  return torch::cat({d / len.clamp_min(1e-12), rest_direction, len / rest_len}, 1);
}
}  // namespace

torch::Tensor mesh_edge_features(const torch::Tensor& x, const GarmentTopology& topology) {
  return relative_edge_features(x, topology.senders, topology.receivers, topology.rest_direction,
                                topology.rest_length);
}

torch::Tensor edge_set_features(const torch::Tensor& x, const GarmentEdgeSet& edges) {
  return relative_edge_features(x, edges.senders, edges.receivers, edges.rest_direction, edges.rest_length);
}

torch::Tensor world_edge_features(const torch::Tensor& p, const torch::Tensor& q,
                                  const torch::Tensor& senders, const torch::Tensor& receivers) {
  auto dp = p.index_select(0, receivers) - p.index_select(0, senders);
  auto dq = q.index_select(0, receivers) - q.index_select(0, senders);
  return torch::cat({dp, dp.norm(2, 1, true), dq, dq.norm(2, 1, true)}, 1);
}

torch::Tensor body_normal_distances(const torch::Tensor& x, const torch::Tensor& x_coast,
                                    const torch::Tensor& b, const torch::Tensor& b_next,
                                    const torch::Tensor& n, const torch::Tensor& n_next) {
  return torch::stack({((x - b) * n).sum(1), ((x_coast - b_next) * n_next).sum(1)}, 1);
}

}  // namespace pb4u
