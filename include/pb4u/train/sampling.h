#pragma once
// Random choices made per training step: material (SPEC 2 ranges) and effect set (SPEC 6).
#include <Eigen/Core>
#include <random>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/scene/material.h"
#include "pb4u/scene/effects.h"

namespace pb4u {

// Density and lambda uniform, mu and bending log-uniform within `ranges`; thickness from `base`.
Material sample_material(const MaterialRanges& ranges, const Material& base, std::mt19937_64& rng);

// How often each optional effect is on in a training sample. The network sees scenes with and
// without gravity and body so that, e.g., a scene without gravity does not fall.
struct EffectSampling {
  double p_gravity = 0.8;
  double p_body = 0.8;      // body present -> collision on, friction with p_friction
  double p_friction = 0.5;  // given a body
  // Pinned cloth: with a body the pins follow the garment's skinned motion (a waistband held
  // on); without one they hold their start positions (a garment hanging from pins).
  double p_pins = 0.0;
  // Cloth against itself (the repulsion term, effect self_collision): drawn only when > 0, so
  // that runs without it keep their sample stream.
  double p_self_collision = 0.0;
  template <class V>
  void visit(V& v) {
    v("p_gravity", p_gravity, in_range(0, 1));
    v("p_body", p_body, in_range(0, 1));
    v("p_friction", p_friction, in_range(0, 1));
    v("p_pins", p_pins, in_range(0, 1));
    v("p_self_collision", p_self_collision, in_range(0, 1));
  }
};

Effects sample_effects(const EffectSampling& sampling, std::mt19937_64& rng);

// The vertices a pinned training sample holds, chosen on the rest shape V (n x 3, y up): half
// the time a band along the top (every vertex within 1-4 cm of the highest, as scenes'
// pins.top_band), otherwise 2-4 single points among the top 10% of the vertices by height.
// Never empty.
std::vector<int> sample_pinned_vertices(const Eigen::MatrixXd& V, std::mt19937_64& rng);

}  // namespace pb4u
