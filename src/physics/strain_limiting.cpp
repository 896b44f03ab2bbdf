#include "pb4u/physics/strain_limiting.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pb4u/graph/garment_topology.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {

StrainLimitResult limit_edge_strain(const torch::Tensor& x, const GarmentTopology& topology,
                                    const torch::Tensor& pinned, double limit, int max_iterations) {
  StrainLimitResult result;
  result.x = x;
  if (!(limit > 0)) return result;
  // Gauss-Seidel sweeps over the edges on the host: a few thousand edges per sweep, where a
  // Jacobi (averaged) update needs hundreds of sweeps to pull a far-flung vertex back.
  Eigen::MatrixXd pos = tensor_to_matrix(x.detach().to(torch::kCPU, torch::kFloat64));
  const int64_t n = pos.rows();
  // Each unique edge once: the topology lists every edge in both directions.
  const int64_t ne = topology.senders.size(0) / 2;
  const torch::Tensor senders = topology.senders.slice(0, 0, ne).to(torch::kCPU).contiguous();
  const torch::Tensor receivers = topology.receivers.slice(0, 0, ne).to(torch::kCPU).contiguous();
  const torch::Tensor rest = topology.rest_length.slice(0, 0, ne).to(torch::kCPU, torch::kFloat64).contiguous();
  const int64_t* a = senders.data_ptr<int64_t>();
  const int64_t* b = receivers.data_ptr<int64_t>();
  const double* L = rest.data_ptr<double>();
  // Inverse masses: a pinned vertex does not move, so its edge's free end takes the whole
  // correction; an edge between two pinned vertices is left as it is.
  std::vector<double> w(n, 1.0);
  if (pinned.defined() && pinned.numel() == n) {
    const torch::Tensor p = pinned.to(torch::kCPU, torch::kBool).contiguous();
    for (int64_t i = 0; i < n; ++i)
      if (p.data_ptr<bool>()[i]) w[i] = 0;
  }
  auto max_strain = [&] {
    double m = -1;
    for (int64_t e = 0; e < ne; ++e) m = std::max(m, (pos.row(b[e]) - pos.row(a[e])).norm() / L[e] - 1);
    return m;
  };
  const double tolerance = 0.01 * limit;
  result.max_strain = max_strain();
  while (result.max_strain > limit + tolerance && result.iterations < max_iterations) {
    // Alternate the sweep direction so that no end of the mesh is always corrected last.
    const bool forward = result.iterations % 2 == 0;
    for (int64_t k = 0; k < ne; ++k) {
      const int64_t e = forward ? k : ne - 1 - k;
      const double wsum = w[a[e]] + w[b[e]];
      if (wsum == 0) continue;
      const Eigen::RowVector3d d = pos.row(b[e]) - pos.row(a[e]);
      const double length = d.norm(), longest = (1 + limit) * L[e];
      if (length <= longest) continue;
      const Eigen::RowVector3d shift = (length - longest) / length * d;
      pos.row(a[e]) += w[a[e]] / wsum * shift;
      pos.row(b[e]) -= w[b[e]] / wsum * shift;
    }
    ++result.iterations;
    result.max_strain = max_strain();
  }
  if (result.iterations > 0) result.x = matrix_to_tensor(pos).to(x.options());
  return result;
}

}  // namespace pb4u
