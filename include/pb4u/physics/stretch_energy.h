#pragma once
// StVK membrane stretch (SPEC 3.1).
#include "pb4u/physics/physics_term.h"

namespace pb4u {

// x: (n, 3) m. Per face F = Ds Dm^-1 (3 x 2), Green strain G = (F^T F - I) / 2,
// psi = mu tr(G^T G) + lambda / 2 tr(G)^2 (Pa), E = sum_f A_f h psi_f (J), rest area A_f,
// thickness h. 0-dim tensor of x's dtype.
torch::Tensor stretch_energy(const torch::Tensor& x, const ClothGeometry& cloth,
                             const Material& material);

class StretchTerm : public PhysicsTerm {
 public:
  std::string name() const override { return "stretch"; }
  torch::Tensor energy(const torch::Tensor& x_next, const FrameState& state,
                       const ClothGeometry& cloth, const BodyContact*) const override;
};

}  // namespace pb4u
