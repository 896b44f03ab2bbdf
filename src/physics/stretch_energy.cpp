#include "pb4u/physics/stretch_energy.h"

namespace pb4u {

torch::Tensor stretch_energy(const torch::Tensor& x, const ClothGeometry& cloth,
                             const Material& material) {
  const auto& F = cloth.faces;
  auto x0 = x.index_select(0, F.select(1, 0));
  auto Ds = torch::stack({x.index_select(0, F.select(1, 1)) - x0,
                          x.index_select(0, F.select(1, 2)) - x0}, 2);  // (m, 3, 2)
  auto Fd = torch::bmm(Ds, cloth.dm_inverse);                          // (m, 3, 2)
  auto I = torch::eye(2, x.options());
  auto G = 0.5 * (torch::bmm(Fd.transpose(1, 2), Fd) - I);            // (m, 2, 2)
  auto trace = G.diagonal(0, 1, 2).sum(1);
  auto psi = material.mu * G.pow(2).sum({1, 2}) + 0.5 * material.lambda * trace.pow(2);
  return (cloth.face_area * psi).sum() * material.thickness;
}

torch::Tensor StretchTerm::energy(const torch::Tensor& x_next, const FrameState& state,
                                  const ClothGeometry& cloth, const BodyContact*) const {
  check_positions(x_next, cloth);
  return stretch_energy(x_next, cloth, state.material);
}

}  // namespace pb4u
