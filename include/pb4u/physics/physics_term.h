#pragma once
// The common shape of the six physics terms (SPEC 3). Each term is a small object in its own
// file with a free function that computes it; build_terms() assembles the terms a scene's
// effects call for, and only those.
#include <torch/torch.h>

#include <memory>
#include <string>
#include <vector>

#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/scene/frame_state.h"

namespace pb4u {

struct BodyContact;

class PhysicsTerm {
 public:
  virtual ~PhysicsTerm() = default;
  // "stretch", "bending", "collision", "inertia", "gravity", "friction" or "repulsion".
  virtual std::string name() const = 0;
  // Energy (J, 0-dim tensor of x_next's dtype, differentiable in x_next) of the predicted
  // positions x_next (n, 3) m, under state.material. contact: the step's body contact; terms
  // that need it throw pb4u::Error when it is null.
  virtual torch::Tensor energy(const torch::Tensor& x_next, const FrameState& state,
                               const ClothGeometry& cloth, const BodyContact* contact) const = 0;
  // A per-vertex isotropic curvature estimate (n, N/m) of the parts of this term that change
  // quickly with x_next (contacts), which the reference solver adds to its fixed initial
  // Hessian each iteration; undefined for terms it already covers or does not need.
  virtual torch::Tensor contact_stiffness(const torch::Tensor& x_next, const FrameState& state,
                                          const ClothGeometry& cloth,
                                          const BodyContact* contact) const {
    return {};
  }
  // The direction contact_stiffness acts in, for a solver that keeps directions
  // (coordinate_hessian.h): per vertex unit normals (n, 3); `across` false for k n n^T (a
  // normal contact), true for k (I - n n^T) (tangential friction). Undefined normals (the
  // default): isotropic, k I.
  struct ContactDirection {
    torch::Tensor normal;
    bool across = false;
  };
  virtual ContactDirection contact_direction(const FrameState& state, const BodyContact* contact) const {
    return {};
  }
};

using TermList = std::vector<std::unique_ptr<PhysicsTerm>>;

// The active terms in Table-1 order (stretch, bending, collision, inertia, gravity, friction),
// then repulsion: stretch, bending and inertia always; gravity / collision / friction /
// repulsion (effect self_collision) only if the effect is on.
// collision_weight (J/m^3): < 0 means the final weight config.collision.weight_end (evaluation);
// training passes collision_weight(config.collision, step).
// repulsion_weight likewise: < 0 means config.repulsion.weight.
TermList build_terms(const Effects& effects, const PhysicsConfig& config,
                     double collision_weight = -1.0, double repulsion_weight = -1.0);

// Names of the terms in `terms`, in order.
std::vector<std::string> term_names(const TermList& terms);

// Throws pb4u::Error unless x_next is (num_vertices, 3) floating point of the cloth's dtype.
void check_positions(const torch::Tensor& x_next, const ClothGeometry& cloth);

}  // namespace pb4u
