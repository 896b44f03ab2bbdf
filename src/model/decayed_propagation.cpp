#include "pb4u/model/decayed_propagation.h"

namespace pb4u {

DecayedPropagationImpl::DecayedPropagationImpl(int64_t latent, int hidden_layers, double g)
    : gamma(g) {
  message = register_module("message", MLP(std::vector<int64_t>{latent, latent, latent}, latent,
                                           latent, hidden_layers, false));
  norm = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({latent})));
}

double DecayedPropagationImpl::matmul_flops(double n, double E, int64_t K) const {
  if (K <= 0) return 0;
  // The edge term once (as forward computes it), then K node-term + remaining-layer passes.
  return message->first_layer_flops(2, E) + double(K) * edge_mlp_flops(*message, n, E, false);
}

torch::Tensor DecayedPropagationImpl::forward(const torch::Tensor& v, const torch::Tensor& e,
                                              const RowIndex& senders, const RowIndex& receivers,
                                              int64_t K) {
  if (K <= 0) return v;
  // The edge latents do not change across steps: their first-layer term is computed once.
  torch::Tensor edge_term = split_first_layer ? message->first_layer(2, e, true) : torch::Tensor();
  auto h = v;
  for (int64_t k = 0; k < K; ++k) {
    auto m = edge_mlp(*message, h, e, senders, receivers, edge_term, split_first_layer);
    h = gamma * h + norm(sum_at_receivers(m, receivers, h.size(0)));
  }
  return h;
}

}  // namespace pb4u
