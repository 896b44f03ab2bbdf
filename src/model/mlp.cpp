#include "pb4u/model/mlp.h"

#include <cmath>

namespace pb4u {

MLPImpl::MLPImpl(std::vector<int64_t> sizes, int64_t hidden, int64_t output, int hidden_layers,
                 bool layer_norm)
    : input_sizes(std::move(sizes)) {
  int64_t fan_in = 0;
  for (int64_t s : input_sizes) fan_in += s;
  // The split first layer is one Linear(fan_in, hidden) cut by columns: same init as torch's.
  const double bound = 1.0 / std::sqrt(static_cast<double>(fan_in));
  for (size_t i = 0; i < input_sizes.size(); ++i)
    first_weights.push_back(register_parameter(
        "first_weight" + std::to_string(i),
        torch::empty({hidden, input_sizes[i]}).uniform_(-bound, bound)));
  first_bias = register_parameter("first_bias", torch::empty({hidden}).uniform_(-bound, bound));
  rest = register_module("rest", torch::nn::Sequential());
  // In-place ReLUs: every activation here is a fresh tensor no one else holds, and on CPU
  // the saved allocation and memory pass matter as much as the matmuls.
  for (int l = 1; l < hidden_layers; ++l) {
    rest->push_back(torch::nn::Linear(hidden, hidden));
    rest->push_back(torch::nn::ReLU(torch::nn::ReLUOptions().inplace(true)));
  }
  rest->push_back(torch::nn::Linear(hidden, output));
  if (layer_norm)
    norm = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({output})));
}

torch::Tensor MLPImpl::first_layer(size_t part, const torch::Tensor& x, bool with_bias) const {
  const auto& w = first_weights[part];
  return with_bias ? torch::addmm(first_bias, x, w.t()) : torch::mm(x, w.t());
}

torch::Tensor MLPImpl::finish(torch::Tensor first_layer_sum) {
  auto y = rest->forward(first_layer_sum.relu_());
  return norm ? norm(y) : y;
}

double MLPImpl::first_layer_flops(size_t part, double rows) const {
  return 2.0 * rows * double(first_weights[part].size(0)) * double(first_weights[part].size(1));
}

double MLPImpl::finish_flops(double rows) const {
  double flops = 0;
  for (const auto& m : rest->children())
    if (const auto* linear = m->as<torch::nn::LinearImpl>())
      flops += 2.0 * rows * double(linear->weight.size(0)) * double(linear->weight.size(1));
  return flops;
}

double edge_mlp_flops(const MLPImpl& f, double nodes, double edges, bool with_edge_term) {
  return f.first_layer_flops(0, nodes) + f.first_layer_flops(1, nodes) +
         (with_edge_term ? f.first_layer_flops(2, edges) : 0.0) + f.finish_flops(edges);
}

torch::Tensor MLPImpl::forward(const std::vector<torch::Tensor>& inputs) {
  TORCH_CHECK(inputs.size() == input_sizes.size(), "MLP: expected ", input_sizes.size(),
              " inputs, got ", inputs.size());
  auto sum = first_layer(0, inputs[0], true);
  for (size_t i = 1; i < inputs.size(); ++i) sum.add_(first_layer(i, inputs[i]));
  return finish(sum);
}

torch::Tensor edge_mlp(MLPImpl& f, const torch::Tensor& nodes, const torch::Tensor& edges,
                       const RowIndex& senders, const RowIndex& receivers,
                       const torch::Tensor& edge_term, bool split) {
  if (!split) {
    auto in = torch::cat({gather_rows(nodes, receivers), gather_rows(nodes, senders), edges}, 1);
    auto w = torch::cat({f.first_weights[0], f.first_weights[1], f.first_weights[2]}, 1);
    return f.finish(torch::addmm(f.first_bias, in, w.t()));
  }
  // One matmul gives both node terms of every node; each edge then gathers its two.
  const int64_t h = f.first_weights[0].size(0);
  auto terms = torch::mm(nodes, torch::cat({f.first_weights[0], f.first_weights[1]}, 0).t());
  auto pre = gather_rows(terms.narrow(1, 0, h), receivers);
  pre.add_(gather_rows(terms.narrow(1, h, h), senders));
  pre.add_(edge_term.defined() ? edge_term : f.first_layer(2, edges, true));
  return f.finish(pre);
}

torch::Tensor sum_at_receivers(const torch::Tensor& values, const RowIndex& receivers, int64_t n) {
  return sum_rows_at(values, receivers, n);
}

}  // namespace pb4u
