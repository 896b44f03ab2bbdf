#pragma once
// Cubic body-penetration penalty (SPEC 3.3), with d measured against the matched face's plane
// (SPEC) or against the body's own surface (collision.measure: surface, surface_contact.h).
#include <string>

#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/physics_term.h"
#include "pb4u/physics/surface_contact.h"

namespace pb4u {

// x_next: (n, 3) m. Signed distance d = (x_next - c) . n to each vertex's contact face at
// t + dt; E = weight * sum max(eps - d, 0)^3 (J). eps in m, weight in J/m^3.
torch::Tensor collision_energy(const torch::Tensor& x_next, const BodyContact& contact,
                               double eps, double weight);
// The same penalty with d = (x_next - point) . outward over the surface contact's vertices.
torch::Tensor collision_energy(const torch::Tensor& x_next, const SurfaceContact& contact,
                               double eps, double weight);

class CollisionTerm : public PhysicsTerm {
 public:
  CollisionTerm(const CollisionConfig& config, double weight);
  std::string name() const override { return "collision"; }
  torch::Tensor energy(const torch::Tensor& x_next, const FrameState& state,
                       const ClothGeometry& cloth, const BodyContact* contact) const override;
  // 6 w max(eps - d, 0): the penalty's second derivative along the normal.
  torch::Tensor contact_stiffness(const torch::Tensor& x_next, const FrameState& state,
                                  const ClothGeometry& cloth,
                                  const BodyContact* contact) const override;
  // Along the contact face's normal (the penalty acts along it; isotropic with the surface measure).
  ContactDirection contact_direction(const FrameState& state, const BodyContact* contact) const override;
  double weight() const { return weight_; }
  double eps() const { return eps_; }

 private:
  // max(eps - d, 0) per measured vertex (all of them with the plane measure).
  torch::Tensor penetration(const torch::Tensor& x_next, const FrameState& state, const BodyContact& contact) const;
  double eps_, weight_;
  std::string measure_;
};

}  // namespace pb4u
