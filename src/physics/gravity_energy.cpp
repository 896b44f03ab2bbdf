#include "pb4u/physics/gravity_energy.h"

namespace pb4u {

torch::Tensor gravity_energy(const torch::Tensor& x, const torch::Tensor& masses,
                             const double gravity[3]) {
  auto g = torch::tensor({gravity[0], gravity[1], gravity[2]}, torch::kFloat64).to(x.options());
  return -(masses * torch::mv(x, g)).sum();
}

torch::Tensor GravityTerm::energy(const torch::Tensor& x_next, const FrameState& state,
                                  const ClothGeometry& cloth, const BodyContact*) const {
  check_positions(x_next, cloth);
  return gravity_energy(x_next, cloth.vertex_masses(state.material.density), state.gravity);
}

}  // namespace pb4u
