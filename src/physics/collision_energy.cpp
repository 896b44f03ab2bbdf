#include "pb4u/physics/collision_energy.h"

#include "pb4u/util/error.h"

namespace pb4u {

namespace {
torch::Tensor penetration(const torch::Tensor& x_next, const BodyContact& contact, double eps) {
  return (eps - ((x_next - contact.point) * contact.normal).sum(1)).clamp_min(0);
}
}  // namespace

torch::Tensor collision_energy(const torch::Tensor& x_next, const BodyContact& contact,
                               double eps, double weight) {
  return weight * penetration(x_next, contact, eps).pow(3).sum();
}

CollisionTerm::CollisionTerm(const CollisionConfig& config, double weight)
    : eps_(config.eps), weight_(weight) {}

torch::Tensor CollisionTerm::energy(const torch::Tensor& x_next, const FrameState&,
                                    const ClothGeometry& cloth, const BodyContact* contact) const {
  check_positions(x_next, cloth);
  if (!contact) throw Error("physics: the collision term needs the step's body contact");
  return collision_energy(x_next, *contact, eps_, weight_);
}

}  // namespace pb4u

namespace pb4u {

torch::Tensor CollisionTerm::contact_stiffness(const torch::Tensor& x_next, const FrameState&,
                                               const ClothGeometry&, const BodyContact* contact) const {
  if (!contact) return {};
  return 6 * weight_ * penetration(x_next.detach(), *contact, eps_);
}

}  // namespace pb4u
