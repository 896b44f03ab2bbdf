#include "pb4u/physics/physics_term.h"

#include "pb4u/physics/bending_energy.h"
#include "pb4u/physics/collision_energy.h"
#include "pb4u/physics/friction_energy.h"
#include "pb4u/physics/gravity_energy.h"
#include "pb4u/physics/inertia_energy.h"
#include "pb4u/physics/repulsion_energy.h"
#include "pb4u/physics/stretch_energy.h"
#include "pb4u/util/error.h"

namespace pb4u {

TermList build_terms(const Effects& effects, const PhysicsConfig& config, double weight, double repulsion) {
  TermList terms;
  terms.push_back(std::make_unique<StretchTerm>());
  terms.push_back(std::make_unique<BendingTerm>(config.degenerate_area));
  if (effects.collision)
    terms.push_back(std::make_unique<CollisionTerm>(
        config.collision, weight < 0 ? config.collision.weight_end : weight));
  terms.push_back(std::make_unique<InertiaTerm>());
  if (effects.gravity) terms.push_back(std::make_unique<GravityTerm>());
  if (effects.friction) terms.push_back(std::make_unique<FrictionTerm>(config.friction));
  if (effects.self_collision) {
    RepulsionConfig r = config.repulsion;
    if (repulsion >= 0) r.weight = repulsion;
    terms.push_back(std::make_unique<RepulsionTerm>(r));
  }
  return terms;
}

std::vector<std::string> term_names(const TermList& terms) {
  std::vector<std::string> names;
  for (const auto& t : terms) names.push_back(t->name());
  return names;
}

void check_positions(const torch::Tensor& x_next, const ClothGeometry& cloth) {
  if (!x_next.defined() || x_next.dim() != 2 || x_next.size(0) != cloth.num_vertices ||
      x_next.size(1) != 3)
    throw Error("physics: positions must be (" + std::to_string(cloth.num_vertices) +
                ", 3), got " + (x_next.defined() ? c10::str(x_next.sizes()) : "undefined"));
  if (x_next.scalar_type() != cloth.dtype())
    throw Error("physics: positions are " + std::string(c10::toString(x_next.scalar_type())) +
                " but the cloth geometry is " + c10::toString(cloth.dtype()));
}

}  // namespace pb4u
