#pragma once
// Body friction (SPEC 3.5).
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/physics_term.h"

namespace pb4u {

// x_next, x: (n, 3) m at t + dt and t; masses (n) kg. Slip s = (x_next - x) - motion of the
// contact face, its tangential part s_t = s - (s . n) n with n the contact face's normal (the
// body surface, not a fixed axis). E = sum over in-contact vertices mu m_i |g| |s_t| (J),
// |g| (m/s^2) the magnitude of the scene's gravity (the normal load scale), |s_t| smoothed by
// `smoothing` (m, see FrictionConfig).
torch::Tensor friction_energy(const torch::Tensor& x_next, const torch::Tensor& x,
                              const torch::Tensor& masses, const BodyContact& contact, double mu,
                              double gravity_norm, double smoothing);

class FrictionTerm : public PhysicsTerm {
 public:
  explicit FrictionTerm(const FrictionConfig& config) : config_(config) {}
  std::string name() const override { return "friction"; }
  torch::Tensor energy(const torch::Tensor& x_next, const FrameState& state,
                       const ClothGeometry& cloth, const BodyContact* contact) const override;
  // mu m |g| / sqrt(|s_t|^2 + d^2): the smoothed slip norm's tangential curvature.
  torch::Tensor contact_stiffness(const torch::Tensor& x_next, const FrameState& state,
                                  const ClothGeometry& cloth,
                                  const BodyContact* contact) const override;
  // Along the contact face's normal (friction acts across it).
  ContactDirection contact_direction(const FrameState& state, const BodyContact* contact) const override;

 private:
  FrictionConfig config_;
};

}  // namespace pb4u
