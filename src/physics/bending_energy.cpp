#include "pb4u/physics/bending_energy.h"

namespace pb4u {

torch::Tensor dihedral_angles(const torch::Tensor& x, const torch::Tensor& hinges,
                              double degenerate_area) {
  auto xi = x.index_select(0, hinges.select(1, 0)), xj = x.index_select(0, hinges.select(1, 1));
  auto xk0 = x.index_select(0, hinges.select(1, 2)), xk1 = x.index_select(0, hinges.select(1, 3));
  auto e = xj - xi;
  // Face 0 is (i, j, k0); face 1 traverses the edge backwards, (j, i, k1), so with a
  // consistent orientation both normals agree on a flat sheet.
  auto n0 = torch::cross(e, xk0 - xi, 1);
  auto n1 = torch::cross(xk1 - xi, e, 1);
  auto a0 = n0.norm(2, 1, true), a1 = n1.norm(2, 1, true);
  n0 = n0 / a0.clamp_min(degenerate_area);
  n1 = n1 / a1.clamp_min(degenerate_area);
  auto len = e.norm(2, 1, true);
  auto e_hat = e / len.clamp_min(std::sqrt(degenerate_area));
  auto sin_t = (torch::cross(n0, n1, 1) * e_hat).sum(1);
  auto cos_t = (n0 * n1).sum(1);
  // For a sound hinge (sin, cos) is a unit vector; near zero only when a face or the edge
  // has collapsed, where atan2's gradient would be 0/0. Such hinges bend by 0.
  auto sound = (sin_t * sin_t + cos_t * cos_t) > 0.5;
  auto safe_sin = torch::where(sound, sin_t, torch::zeros_like(sin_t));
  auto safe_cos = torch::where(sound, cos_t, torch::ones_like(cos_t));
  return torch::atan2(safe_sin, safe_cos);
}

torch::Tensor bending_energy(const torch::Tensor& x, const ClothGeometry& cloth,
                             const Material& material, double degenerate_area) {
  auto theta = dihedral_angles(x, cloth.hinges, degenerate_area);
  auto d = theta - cloth.rest_angle;
  return 0.5 * material.bending * (cloth.hinge_weight * d * d).sum();
}

torch::Tensor BendingTerm::energy(const torch::Tensor& x_next, const FrameState& state,
                                  const ClothGeometry& cloth, const BodyContact*) const {
  check_positions(x_next, cloth);
  return bending_energy(x_next, cloth, state.material, degenerate_area_);
}

}  // namespace pb4u
