#include "pb4u/model/update_scaling.h"

#include "pb4u/util/error.h"

namespace pb4u {

torch::Tensor update_scale(const torch::Tensor& vertex_mean_edge_length, double base, bool enabled) {
  if (!enabled) return torch::ones({vertex_mean_edge_length.size(0), 1}, vertex_mean_edge_length.options());
  if (!(base > 0))
    throw Error("update scaling: the model is not calibrated (Lbar_base must be positive)");
  return (vertex_mean_edge_length / base).unsqueeze(1);
}

}  // namespace pb4u
