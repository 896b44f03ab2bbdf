#include "pb4u/model/lsdmp_block.h"

namespace pb4u {

torch::Tensor laplacian_smoothing(const torch::Tensor& nodes, const torch::Tensor& edges, const RowIndex& senders,
                                  const RowIndex& receivers) {
  const int64_t n = nodes.size(0);
  auto sum = sum_at_receivers(gather_rows(nodes, senders) + edges, receivers, n);
  auto count = sum_at_receivers(torch::ones({edges.size(0), 1}, nodes.options()), receivers, n);
  return torch::where(count > 0, sum / count.clamp_min(1.0), nodes);
}

LsdmpBlockImpl::LsdmpBlockImpl(int64_t latent, int hidden_layers) {
  message_passing = register_module("message_passing", GraphNetBlock(latent, hidden_layers));
  smoothed = register_module("smoothed", MLP(std::vector<int64_t>{latent}, latent, latent, hidden_layers, true));
}

LatentGraph LsdmpBlockImpl::forward(const LatentGraph& g, const RowIndex& ms, const RowIndex& mr, const RowIndex& ws,
                                    const RowIndex& wr) {
  LatentGraph out = message_passing(g, ms, mr, ws, wr);
  out.nodes = out.nodes + smoothed->forward({laplacian_smoothing(out.nodes, out.mesh_edges, ms, mr)});
  return out;
}

double LsdmpBlockImpl::matmul_flops(double n, double Em, double Ew) const {
  return message_passing->matmul_flops(n, Em, Ew) + smoothed->first_layer_flops(0, n) + smoothed->finish_flops(n);
}

}  // namespace pb4u
