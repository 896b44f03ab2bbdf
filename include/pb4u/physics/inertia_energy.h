#pragma once
// Inertia (SPEC 3.6): the implicit-Euler kinetic term.
#include "pb4u/physics/physics_term.h"

namespace pb4u {

// x_next, x, x_prev: (n, 3) m at t + dt, t, t - dt; masses (n) kg; dt s.
// E = sum_i m_i |x_next_i - (x_i + v_i dt)|^2 / (2 dt^2) (J), v = (x - x_prev) / dt:
// zero on the ballistic prediction 2 x - x_prev.
torch::Tensor inertia_energy(const torch::Tensor& x_next, const torch::Tensor& x,
                             const torch::Tensor& x_prev, const torch::Tensor& masses, double dt);

class InertiaTerm : public PhysicsTerm {
 public:
  std::string name() const override { return "inertia"; }
  torch::Tensor energy(const torch::Tensor& x_next, const FrameState& state,
                       const ClothGeometry& cloth, const BodyContact*) const override;
};

}  // namespace pb4u
