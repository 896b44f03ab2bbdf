#include "pb4u/physics/inertia_energy.h"

namespace pb4u {

torch::Tensor inertia_energy(const torch::Tensor& x_next, const torch::Tensor& x,
                             const torch::Tensor& x_prev, const torch::Tensor& masses, double dt) {
  auto predicted = 2 * x - x_prev;  // x + v dt with v = (x - x_prev) / dt
  return (masses * (x_next - predicted).pow(2).sum(1)).sum() / (2 * dt * dt);
}

torch::Tensor InertiaTerm::energy(const torch::Tensor& x_next, const FrameState& state,
                                  const ClothGeometry& cloth, const BodyContact*) const {
  check_positions(x_next, cloth);
  return inertia_energy(x_next, state.x, state.x_prev,
                        cloth.vertex_masses(state.material.density), state.dt);
}

}  // namespace pb4u
