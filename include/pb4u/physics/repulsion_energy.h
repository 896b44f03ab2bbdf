#pragma once
// Cloth against itself: ContourCraft's repulsion term (Grigorev et al., SIGGRAPH 2024, stage 1,
// as its public code computes it), on with the `self_collision` effect. A cubic penalty keeps
// each cloth vertex on the side of a nearby cloth face that it was on at t.
//
// Pairs, found at t: a vertex v and a face f that does not hold v, with v's projection onto
// f's plane inside f and |d| < radius, d = (x_v - x_f0) . n_f (spatial/points_over_faces.h).
// Energy of x_next:
//   E = weight * sum over pairs (k max(eps - s d', 0))^3,
// d' the same distance at t + dt (the face moving too), s the side at t (+1 where d >= 0),
// k = pinned_factor where v or a vertex of f is pinned, else 1. eps and radius in m, weight
// in J/m^3. ContourCraft's sign(0) = 0 would charge a pair lying in the plane eps^3 whatever
// it does; here it is side +1.
#include <torch/torch.h>

#include "pb4u/physics/physics_config.h"
#include "pb4u/physics/physics_term.h"

namespace pb4u {

struct RepulsionPairs {
  torch::Tensor vertex, face;  // (P) int64
  torch::Tensor side;          // (P) +1 / -1: the side of the face's plane at t
  torch::Tensor factor;        // (P) k above
  int64_t size() const { return vertex.defined() ? vertex.size(0) : 0; }
};

// The pairs of positions x (n, 3) m with faces (m, 3) int64; pinned (n) bool or undefined.
// Tensors on x's device, side and factor in x's dtype.
RepulsionPairs repulsion_pairs(const torch::Tensor& x, const torch::Tensor& faces, const torch::Tensor& pinned,
                               double radius, double pinned_factor);

// E above (0-dim, x_next's dtype, differentiable in x_next).
torch::Tensor repulsion_energy(const torch::Tensor& x_next, const torch::Tensor& faces, const RepulsionPairs& pairs,
                               double eps, double weight);

class RepulsionTerm : public PhysicsTerm {
 public:
  explicit RepulsionTerm(const RepulsionConfig& config) : config_(config) {}
  std::string name() const override { return "repulsion"; }
  // Pairs from state.x (kept while state.x is the same tensor, unmodified), the energy of x_next.
  torch::Tensor energy(const torch::Tensor& x_next, const FrameState& state, const ClothGeometry& cloth,
                       const BodyContact* contact) const override;

 private:
  RepulsionConfig config_;
  struct Cache {
    torch::Tensor x, pinned;
    uint32_t x_version = 0;
    RepulsionPairs pairs;
  };
  mutable Cache cache_;
};

}  // namespace pb4u
