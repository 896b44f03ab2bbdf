#include "pb4u/physics/friction_energy.h"

#include <cmath>

#include "pb4u/util/error.h"

namespace pb4u {

namespace {
torch::Tensor tangential_slip(const torch::Tensor& x_next, const torch::Tensor& x,
                              const BodyContact& contact) {
  auto slip = (x_next - x) - contact.motion;
  return slip - (slip * contact.normal).sum(1, true) * contact.normal;
}
double gravity_norm(const FrameState& state) {
  const double* g = state.gravity;
  return std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
}
}  // namespace

torch::Tensor friction_energy(const torch::Tensor& x_next, const torch::Tensor& x,
                              const torch::Tensor& masses, const BodyContact& contact, double mu,
                              double gravity_norm, double smoothing) {
  auto tangential = tangential_slip(x_next, x, contact);
  auto length = (tangential.pow(2).sum(1) + smoothing * smoothing).sqrt() - smoothing;
  auto load = masses * (mu * gravity_norm);
  return (torch::where(contact.in_contact, load * length, torch::zeros_like(length))).sum();
}

torch::Tensor FrictionTerm::energy(const torch::Tensor& x_next, const FrameState& state,
                                   const ClothGeometry& cloth, const BodyContact* contact) const {
  check_positions(x_next, cloth);
  check_positions(state.x, cloth);
  if (!contact) throw Error("physics: the friction term needs the step's body contact");
  return friction_energy(x_next, state.x, cloth.vertex_masses(state.material.density), *contact,
                         config_.mu, gravity_norm(state), config_.slip_smoothing);
}

torch::Tensor FrictionTerm::contact_stiffness(const torch::Tensor& x_next, const FrameState& state,
                                              const ClothGeometry& cloth,
                                              const BodyContact* contact) const {
  if (!contact) return {};
  auto t = tangential_slip(x_next.detach(), state.x, *contact);
  const double d = config_.slip_smoothing;
  auto k = cloth.vertex_masses(state.material.density) * (config_.mu * gravity_norm(state)) /
           (t.pow(2).sum(1) + d * d).sqrt();
  return torch::where(contact->in_contact, k, torch::zeros_like(k));
}

PhysicsTerm::ContactDirection FrictionTerm::contact_direction(const FrameState&, const BodyContact* contact) const {
  if (!contact) return {};
  return {contact->normal, true};
}

}  // namespace pb4u
