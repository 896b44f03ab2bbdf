#include "pb4u/physics/collision_energy.h"

#include "pb4u/util/error.h"

namespace pb4u {

namespace {
torch::Tensor penetration(const torch::Tensor& x_next, const BodyContact& contact, double eps) {
  return (eps - ((x_next - contact.point) * contact.normal).sum(1)).clamp_min(0);
}
torch::Tensor penetration(const torch::Tensor& x_next, const SurfaceContact& contact, double eps) {
  return (eps - ((x_next.index_select(0, contact.vertex) - contact.point) * contact.outward).sum(1)).clamp_min(0);
}
}  // namespace

torch::Tensor collision_energy(const torch::Tensor& x_next, const BodyContact& contact,
                               double eps, double weight) {
  return weight * penetration(x_next, contact, eps).pow(3).sum();
}

torch::Tensor collision_energy(const torch::Tensor& x_next, const SurfaceContact& contact,
                               double eps, double weight) {
  return weight * penetration(x_next, contact, eps).pow(3).sum();
}

CollisionTerm::CollisionTerm(const CollisionConfig& config, double weight)
    : eps_(config.eps), weight_(weight), measure_(config.measure) {}

torch::Tensor CollisionTerm::penetration(const torch::Tensor& x_next, const FrameState& state,
                                         const BodyContact& contact) const {
  if (measure_ == "surface")
    return pb4u::penetration(x_next, query_surface_contact(x_next, state.body, eps_), eps_);
  return pb4u::penetration(x_next, contact, eps_);
}

torch::Tensor CollisionTerm::energy(const torch::Tensor& x_next, const FrameState& state,
                                    const ClothGeometry& cloth, const BodyContact* contact) const {
  check_positions(x_next, cloth);
  if (!contact) throw Error("physics: the collision term needs the step's body contact");
  return weight_ * penetration(x_next, state, *contact).pow(3).sum();
}

}  // namespace pb4u

namespace pb4u {

torch::Tensor CollisionTerm::contact_stiffness(const torch::Tensor& x_next, const FrameState& state,
                                               const ClothGeometry&, const BodyContact* contact) const {
  if (!contact) return {};
  if (measure_ == "surface") {
    const SurfaceContact surface = query_surface_contact(x_next, state.body, eps_);
    return torch::zeros({x_next.size(0)}, x_next.options().requires_grad(false))
        .index_put_({surface.vertex}, 6 * weight_ * pb4u::penetration(x_next.detach(), surface, eps_));
  }
  return 6 * weight_ * pb4u::penetration(x_next.detach(), *contact, eps_);
}

PhysicsTerm::ContactDirection CollisionTerm::contact_direction(const FrameState&, const BodyContact* contact) const {
  if (!contact || measure_ == "surface") return {};
  return {contact->normal, false};
}

}  // namespace pb4u
