#pragma once
// Gravitational potential (SPEC 3.4).
#include "pb4u/physics/physics_term.h"

namespace pb4u {

// x: (n, 3) m; masses: (n) kg; gravity: m/s^2. E = - sum_i m_i g . x_i (J): with
// g = (0, -9.81, 0), sum m_i 9.81 y_i.
torch::Tensor gravity_energy(const torch::Tensor& x, const torch::Tensor& masses,
                             const double gravity[3]);

class GravityTerm : public PhysicsTerm {
 public:
  std::string name() const override { return "gravity"; }
  torch::Tensor energy(const torch::Tensor& x_next, const FrameState& state,
                       const ClothGeometry& cloth, const BodyContact*) const override;
};

}  // namespace pb4u
