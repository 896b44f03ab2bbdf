#pragma once
// Dihedral-angle bending (SPEC 3.2).
#include "pb4u/physics/physics_term.h"

namespace pb4u {

// x: (n, 3) m; hinges: (h, 4) int64 (i, j, k0, k1) as in ClothGeometry. Signed dihedral angle
// (rad, in (-pi, pi]) theta = atan2(e.(n0 x n1), n0.n1) with e the unit edge i -> j and n0, n1
// the unit normals of faces (i, j, k0) and (j, i, k1): 0 when flat, computed with atan2 so it
// stays accurate (and NaN-free) near 180 degrees. Hinges on a face with doubled area below
// degenerate_area (m^2) get 0.
torch::Tensor dihedral_angles(const torch::Tensor& x, const torch::Tensor& hinges,
                              double degenerate_area);

// E = sum_e k_b l_e^2 / (4 (A0 + A1)) (theta - theta_rest)^2 / 2 (J), weights at rest.
torch::Tensor bending_energy(const torch::Tensor& x, const ClothGeometry& cloth,
                             const Material& material, double degenerate_area);

class BendingTerm : public PhysicsTerm {
 public:
  explicit BendingTerm(double degenerate_area) : degenerate_area_(degenerate_area) {}
  std::string name() const override { return "bending"; }
  torch::Tensor energy(const torch::Tensor& x_next, const FrameState& state,
                       const ClothGeometry& cloth, const BodyContact*) const override;
  double degenerate_area() const { return degenerate_area_; }  // m^2

 private:
  double degenerate_area_;
};

}  // namespace pb4u
