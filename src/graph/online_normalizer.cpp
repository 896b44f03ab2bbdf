#include "pb4u/graph/online_normalizer.h"

#include "pb4u/util/error.h"

namespace pb4u {

OnlineNormalizerImpl::OnlineNormalizerImpl(int64_t dim, int64_t max_acc, double eps)
    : max_accumulations(max_acc), std_epsilon(eps) {
  accumulations = register_buffer("accumulations", torch::zeros({}, torch::kInt64));
  count = register_buffer("count", torch::zeros({}, torch::kFloat64));
  sum = register_buffer("sum", torch::zeros({dim}, torch::kFloat64));
  sum_squares = register_buffer("sum_squares", torch::zeros({dim}, torch::kFloat64));
}

torch::Tensor OnlineNormalizerImpl::mean() const {
  return count.item<double>() > 0 ? sum / count : torch::zeros_like(sum);
}

torch::Tensor OnlineNormalizerImpl::std() const {
  if (!(count.item<double>() > 0)) return torch::ones_like(sum);
  auto m = sum / count;
  auto s = (sum_squares / count - m * m).clamp_min(0).sqrt();
  // A feature that never varied while the statistics were gathered (a vertex type or an
  // effect the training data lacked) would be scaled by 1 / std_epsilon, ~1e8, the first time
  // it takes another value. It passes through centred instead; the training data, where it
  // is constant, maps to 0 either way.
  return torch::where(s < std_epsilon, torch::ones_like(s), s);
}

torch::Tensor OnlineNormalizerImpl::forward(const torch::Tensor& x) {
  if (x.dim() != 2 || x.size(1) != sum.size(0))
    throw Error("normaliser: expected features of width " + std::to_string(sum.size(0)) +
                ", got " + c10::str(x.sizes()));
  if (x.size(0) == 0) return x.to(torch::kFloat32);
  if (is_training() && !c10::InferenceMode::is_enabled() && !frozen()) {
    torch::NoGradGuard no_grad;
    auto xd = x.detach().to(torch::kFloat64);
    sum.add_(xd.sum(0));
    sum_squares.add_((xd * xd).sum(0));
    count.add_(static_cast<double>(x.size(0)));
    accumulations.add_(1);
  }
  return (x.to(torch::kFloat32) - mean().to(torch::kFloat32)) / std().to(torch::kFloat32);
}

}  // namespace pb4u
