#pragma once
// The long-range half of the eslr baseline: ESLR's geodesic self-attention (Liu et al. 2025,
// "Extended Short- and Long-Range Mesh Learning for Fast and Generalised Garment Simulation"),
// reconstructed from the paper, whose code is not public. Each garment vertex attends to its
// garment's geodesic anchors (graph/graph_batch.h AnchorSet) with multi-head scaled dot-product
// attention, its logits biased per head by a learned function of the rest-mesh distance:
//   x = LayerNorm(v),  q_i = W_q x_i,  k_a = W_k x_a,  u_a = W_v x_a,
//   w_ia = softmax over a of (q_i . k_a / sqrt(H / heads) + b(d_ia)),  out_i = W_o sum_a w_ia u_a.
// b is piecewise linear in sqrt(d / d_max), through `bins` learned values per head that start at
// zero (a continuous form of Graphormer's distance encoding); distances past d_max, or across
// components (+inf), take the last value.
// Memory-bounded form: the keys are M anchors (farthest-point samples, mesh/geodesic_anchors.h),
// not every vertex, so a layer holds n x M x heads logits rather than n^2 x heads.
#include <torch/torch.h>

#include <vector>

#include "pb4u/graph/graph_batch.h"

namespace pb4u {

struct GeodesicAttentionImpl : torch::nn::Module {
  GeodesicAttentionImpl(int64_t latent, int64_t heads, int64_t bins, double max_distance);

  // (nodes, H): every node's attention output; rows in no anchor set (body nodes) are zero.
  torch::Tensor forward(const torch::Tensor& nodes, const std::vector<AnchorSet>& sets);

  // (n, M, heads): b(d) of distances (n, M), m.
  torch::Tensor distance_bias(const torch::Tensor& distance) const;

  // Matmul FLOPs of forward() on one set of n garment nodes and M anchors.
  double matmul_flops(double n, double anchors) const;

  int64_t heads;
  double max_distance;
  torch::nn::LayerNorm norm{nullptr};
  torch::nn::Linear query{nullptr}, key{nullptr}, value{nullptr}, output{nullptr};
  torch::Tensor bias_table;  // (bins, heads)
};
TORCH_MODULE(GeodesicAttention);

}  // namespace pb4u
