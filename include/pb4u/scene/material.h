#pragma once
// Cloth material (SPEC 2). The defaults are the evaluation material.
#include "pb4u/config/config_io.h"

namespace pb4u {

struct Material {
  double density = 0.20022;      // area density, kg/m^2
  double mu = 23600;             // Lame mu, Pa (N/m^2) in the membrane model
  double lambda = 44400;         // Lame lambda
  double bending = 3.9625778e-5; // bending coefficient k_b
  double thickness = 4.7e-4;     // h, m

  template <class V>
  void visit(V& v) {
    v("density", density, positive());
    v("mu", mu, positive());
    v("lambda", lambda, non_negative());
    v("bending", bending, non_negative());
    v("thickness", thickness, positive());
  }
};

// Training samples one material per garment from these ranges (SPEC 2).
struct MaterialRanges {
  std::vector<double> density{0.0434, 0.7};              // uniform
  std::vector<double> mu{15909, 63636};                   // log-uniform
  std::vector<double> lambda{3535.41, 93333.74};          // uniform
  std::vector<double> bending{6.370782e-8, 1.3139738e-3}; // log-uniform

  template <class V>
  void visit(V& v) {
    v("density", density);
    v("mu", mu);
    v("lambda", lambda);
    v("bending", bending);
  }
};

}  // namespace pb4u
