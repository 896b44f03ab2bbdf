#pragma once
// Online mean / standard-deviation feature normaliser, as in MeshGraphNets: statistics
// accumulate over the first `max_accumulations` calls in training mode, then freeze. They are
// buffers, so torch::save / torch::load keep them with the model.
#include <torch/torch.h>

namespace pb4u {

struct OnlineNormalizerImpl : torch::nn::Module {
  // dim: feature width; std_epsilon: a feature whose standard deviation is below this never
  // varied in the data seen; it is centred but not scaled (std 1).
  OnlineNormalizerImpl(int64_t dim, int64_t max_accumulations, double std_epsilon);

  // x (rows, dim) -> (x - mean) / std, float. Accumulates x first while training and not
  // frozen (never under InferenceMode). Empty x passes through.
  torch::Tensor forward(const torch::Tensor& x);

  torch::Tensor mean() const;  // (dim) float64; 0 before any data
  torch::Tensor std() const;   // (dim) float64; 1 before any data and for constant features, else >= std_epsilon
  bool frozen() const { return accumulations.item<int64_t>() >= max_accumulations; }

  int64_t max_accumulations;
  double std_epsilon;
  torch::Tensor accumulations;         // () int64: calls accumulated
  torch::Tensor count;                 // () float64: rows accumulated
  torch::Tensor sum, sum_squares;      // (dim) float64
};
TORCH_MODULE(OnlineNormalizer);

}  // namespace pb4u
