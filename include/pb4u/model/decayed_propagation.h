#pragma once
// Propagation-before-update (SPEC 4): h^0 = v; for k = 1..K
//   h~^k = LayerNorm(sum_j f_m(h_i^{k-1}, h_j^{k-1}, e_ij)),  h^k = gamma h^{k-1} + h~^k,
// with one message MLP f_m shared by all K steps, so K can change at inference without new
// weights. The decay gamma < 1 keeps h bounded however large K grows.
#include <torch/torch.h>

#include "pb4u/model/mlp.h"

namespace pb4u {

struct DecayedPropagationImpl : torch::nn::Module {
  DecayedPropagationImpl(int64_t latent, int hidden_layers, double gamma);

  // v (n, H) node latents, e (E, H) edge latents over (senders, receivers) -> h^K (n, H).
  // K = 0 returns v.
  torch::Tensor forward(const torch::Tensor& v, const torch::Tensor& e, const RowIndex& senders,
                        const RowIndex& receivers, int64_t K);

  // Matmul FLOPs of forward() on n nodes and E edges.
  double matmul_flops(double n, double E, int64_t K) const;

  double gamma;
  bool split_first_layer = true;  // runtime switch for the benchmark; same weights either way
  MLP message{nullptr};           // f_m(h_i, h_j, e_ij), no LayerNorm of its own
  torch::nn::LayerNorm norm{nullptr};
};
TORCH_MODULE(DecayedPropagation);

}  // namespace pb4u
