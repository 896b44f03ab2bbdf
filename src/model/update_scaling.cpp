#include "pb4u/model/update_scaling.h"

#include <algorithm>
#include <cmath>

#include "pb4u/mesh/lazy_averaging.h"
#include "pb4u/util/error.h"

namespace pb4u {

torch::Tensor update_scale(const torch::Tensor& vertex_mean_edge_length, double base, bool enabled) {
  if (!enabled) return torch::ones({vertex_mean_edge_length.size(0), 1}, vertex_mean_edge_length.options());
  if (!(base > 0))
    throw Error("update scaling: the model is not calibrated (Lbar_base must be positive)");
  return (vertex_mean_edge_length / base).unsqueeze(1);
}

namespace {

// The same rounds with an Eigen sparse matrix: inference on the CPU (no gradient). On a Lv.5
// mesh (127 rounds) torch's index ops took ~330 ms, about a whole network step, on this VM;
// this path adds no measurable time to the step.
torch::Tensor smooth_over_mesh_eigen(const torch::Tensor& f, const torch::Tensor& senders,
                                     const torch::Tensor& receivers, int64_t iterations) {
  using Dense = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int64_t n = f.size(0);
  auto s = senders.to(torch::kInt64).contiguous(), r = receivers.to(torch::kInt64).contiguous();
  const auto P = lazy_averaging_matrix<float>(n, s.data_ptr<int64_t>(), r.data_ptr<int64_t>(), s.size(0));
  auto in = f.to(torch::kFloat32).contiguous();
  Dense g = Eigen::Map<const Dense>(in.data_ptr<float>(), n, f.size(1));
  Dense next(n, f.size(1));
  for (int64_t i = 0; i < iterations; ++i) {
    next.noalias() = P * g;
    g.swap(next);
  }
  auto out = torch::empty({n, f.size(1)}, torch::kFloat32);
  Eigen::Map<Dense>(out.data_ptr<float>(), n, f.size(1)) = g;
  return out.to(f.scalar_type());
}

}  // namespace

torch::Tensor smooth_over_mesh(const torch::Tensor& f, const torch::Tensor& senders,
                               const torch::Tensor& receivers, int64_t iterations) {
  if (iterations <= 0 || senders.numel() == 0) return f;
  if (f.device().is_cpu() && !f.requires_grad() && f.scalar_type() == torch::kFloat32)
    return smooth_over_mesh_eigen(f, senders, receivers, iterations);
  const int64_t n = f.size(0);
  auto degree = torch::zeros({n, 1}, f.options())
                    .index_add_(0, receivers, torch::ones({receivers.size(0), 1}, f.options()));
  auto has_neighbours = degree > 0;
  auto inv_degree = 1.0 / degree.clamp_min(1);
  auto g = f;
  for (int64_t i = 0; i < iterations; ++i) {
    auto mean = torch::zeros_like(g).index_add_(0, receivers, g.index_select(0, senders)) * inv_degree;
    g = torch::where(has_neighbours, 0.5 * (g + mean), g);
  }
  return g;
}

int64_t smoothing_iterations(double distance, double mean_edge_length) {
  if (!(distance > 0) || !(mean_edge_length > 0))
    throw Error("update scaling: the smoothing distance and the mean edge length must be positive");
  const double r = distance / mean_edge_length;
  return std::max<int64_t>(1, std::llround(r * r));
}

torch::Tensor detail_update_scaling(const torch::Tensor& a, const torch::Tensor& s,
                                    const torch::Tensor& senders, const torch::Tensor& receivers,
                                    double mean_edge_length, double distance) {
  auto smooth = smooth_over_mesh(a, senders, receivers, smoothing_iterations(distance, mean_edge_length));
  return smooth + s * (a - smooth);
}

}  // namespace pb4u
