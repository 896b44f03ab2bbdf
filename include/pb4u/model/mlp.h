#pragma once
// The MLP every learned part is made of (SPEC 4): Linear -> ReLU, `hidden_layers` times, then a
// Linear output, then LayerNorm unless disabled (the decoder). Its input is a list of parts
// (e.g. receiver latent, sender latent, edge latent) and the first Linear is split per part,
// W [a, b, c] = W_a a + W_b b + W_c c, so a per-edge MLP can apply W_a, W_b once per node and
// gather the results instead of multiplying every edge's concatenated input.
#include <torch/torch.h>

#include <vector>

#include "pb4u/graph/row_index.h"

namespace pb4u {

struct MLPImpl : torch::nn::Module {
  MLPImpl(std::vector<int64_t> input_sizes, int64_t hidden, int64_t output, int hidden_layers,
          bool layer_norm);

  // inputs[i]: (rows, input_sizes[i]) -> (rows, output).
  torch::Tensor forward(const std::vector<torch::Tensor>& inputs);

  // W_part x: (rows, hidden), with the first layer's bias added when with_bias (exactly one
  // part of a sum carries it). Summed over parts, then finish().
  torch::Tensor first_layer(size_t part, const torch::Tensor& x, bool with_bias = false) const;
  // ReLU of the summed first-layer terms (in place: callers pass a fresh tensor), then the
  // remaining layers: (rows, output).
  torch::Tensor finish(torch::Tensor first_layer_sum);

  // Multiply-add FLOPs (2 per multiply-add) of the matmuls above, read off the layers' shapes:
  // first_layer(part) on `rows` rows, and finish() on `rows` rows.
  double first_layer_flops(size_t part, double rows) const;
  double finish_flops(double rows) const;

  std::vector<int64_t> input_sizes;
  std::vector<torch::Tensor> first_weights;  // per part, (hidden, input_sizes[i])
  torch::Tensor first_bias;                  // (hidden)
  torch::nn::Sequential rest{nullptr};
  torch::nn::LayerNorm norm{nullptr};
};
TORCH_MODULE(MLP);

// f(x_receiver, x_sender, e) for every edge, with f an MLP of parts {node, node, edge}.
// nodes (n, d), senders / receivers (E) indices (grouped or bare, row_index.h), edges (E, de). `edge_term`, if defined, is
// f->first_layer(2, edges, true) computed by the caller (propagation reuses it over K steps).
// split = false concatenates the gathered inputs and multiplies once per edge (the slower
// textbook form, kept for the benchmark and as a reference in tests).
torch::Tensor edge_mlp(MLPImpl& f, const torch::Tensor& nodes, const torch::Tensor& edges,
                       const RowIndex& senders, const RowIndex& receivers,
                       const torch::Tensor& edge_term = {}, bool split = true);

// Matmul FLOPs of edge_mlp (split form) over `nodes` nodes and `edges` edges; the edge part's
// first layer is counted only when with_edge_term (propagation computes it once for K steps).
double edge_mlp_flops(const MLPImpl& f, double nodes, double edges, bool with_edge_term);

// (n, d): sum of the edge values (E, d) at their receivers.
torch::Tensor sum_at_receivers(const torch::Tensor& values, const RowIndex& receivers, int64_t n);

}  // namespace pb4u
