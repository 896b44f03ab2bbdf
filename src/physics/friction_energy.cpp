#include "pb4u/physics/friction_energy.h"

#include <cmath>

#include "pb4u/util/error.h"

namespace pb4u {

torch::Tensor friction_energy(const torch::Tensor& x_next, const torch::Tensor& x,
                              const torch::Tensor& masses, const BodyContact& contact, double mu,
                              double gravity_norm, double smoothing) {
  auto slip = (x_next - x) - contact.motion;
  auto tangential = slip - (slip * contact.normal).sum(1, true) * contact.normal;
  auto length = (tangential.pow(2).sum(1) + smoothing * smoothing).sqrt() - smoothing;
  auto load = masses * (mu * gravity_norm);
  return (torch::where(contact.in_contact, load * length, torch::zeros_like(length))).sum();
}

torch::Tensor FrictionTerm::energy(const torch::Tensor& x_next, const FrameState& state,
                                   const ClothGeometry& cloth, const BodyContact* contact) const {
  check_positions(x_next, cloth);
  if (!contact) throw Error("physics: the friction term needs the step's body contact");
  const double* g = state.gravity;
  double g_norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  return friction_energy(x_next, state.x, cloth.vertex_masses(state.material.density), *contact,
                         config_.mu, g_norm, config_.slip_smoothing);
}

}  // namespace pb4u
