#include "pb4u/physics/collision_energy.h"

#include "pb4u/util/error.h"

namespace pb4u {

torch::Tensor collision_energy(const torch::Tensor& x_next, const BodyContact& contact,
                               double eps, double weight) {
  auto d = ((x_next - contact.point) * contact.normal).sum(1);
  return weight * (eps - d).clamp_min(0).pow(3).sum();
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
