#include "pb4u/model/geodesic_attention.h"

#include <cmath>

namespace pb4u {

GeodesicAttentionImpl::GeodesicAttentionImpl(int64_t latent, int64_t h, int64_t bins, double d_max)
    : heads(h), max_distance(d_max) {
  TORCH_CHECK(latent % heads == 0, "geodesic attention: heads must divide the latent width");
  TORCH_CHECK(bins >= 2, "geodesic attention: at least two bins");
  norm = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({latent})));
  auto linear = [&](const char* name) { return register_module(name, torch::nn::Linear(latent, latent)); };
  query = linear("query");
  key = linear("key");
  value = linear("value");
  output = linear("output");
  bias_table = register_parameter("distance_bias", torch::zeros({bins, heads}));
}

torch::Tensor GeodesicAttentionImpl::distance_bias(const torch::Tensor& distance) const {
  const int64_t bins = bias_table.size(0);
  // +inf / d_max clamps to 1 like any distance past d_max.
  auto u = (distance / max_distance).clamp(0.0, 1.0).sqrt() * double(bins - 1);
  auto lo = u.floor().clamp_max(double(bins - 2));
  auto w = (u - lo).unsqueeze(-1);
  auto index = lo.to(torch::kInt64).flatten();
  std::vector<int64_t> shape = distance.sizes().vec();
  shape.push_back(heads);
  auto below = bias_table.index_select(0, index).view(shape);
  auto above = bias_table.index_select(0, index + 1).view(shape);
  return below + (above - below) * w;
}

torch::Tensor GeodesicAttentionImpl::forward(const torch::Tensor& nodes, const std::vector<AnchorSet>& sets) {
  const int64_t H = nodes.size(1), dh = H / heads;
  auto x = norm(nodes);
  std::vector<torch::Tensor> pieces;
  int64_t next_row = 0;
  for (const AnchorSet& set : sets) {
    if (set.first_node > next_row) pieces.push_back(torch::zeros({set.first_node - next_row, H}, nodes.options()));
    const int64_t n = set.num_nodes, m = set.nodes.size(0);
    auto q = query(x.narrow(0, set.first_node, n)).view({n, heads, dh}).permute({1, 0, 2});
    auto anchors = x.index_select(0, set.nodes);
    auto k = key(anchors).view({m, heads, dh}).permute({1, 2, 0});      // (heads, dh, M)
    auto u = value(anchors).view({m, heads, dh}).permute({1, 0, 2});    // (heads, M, dh)
    auto logits = torch::bmm(q, k) / std::sqrt(double(dh)) + distance_bias(set.distance).permute({2, 0, 1});
    auto mixed = torch::bmm(torch::softmax(logits, -1), u);            // (heads, n, dh)
    pieces.push_back(output(mixed.permute({1, 0, 2}).reshape({n, H})));
    next_row = set.first_node + n;
  }
  if (nodes.size(0) > next_row) pieces.push_back(torch::zeros({nodes.size(0) - next_row, H}, nodes.options()));
  return torch::cat(pieces, 0);
}

double GeodesicAttentionImpl::matmul_flops(double n, double m) const {
  const double H = double(query->weight.size(0));
  // q and the output on n rows, k and v on M; the logits and the weighted sum, n x M x H each.
  return 2.0 * H * H * (2.0 * n + 2.0 * m) + 2.0 * 2.0 * n * m * H;
}

}  // namespace pb4u
