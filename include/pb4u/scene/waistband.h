#pragma once
// Garments held up at the waist. A skirt has no shoulders to hang from: worn, its closure or
// elastic grips the waist. Without that grip the reference solver lets the quick dataset's
// skirts slide off both mannequins within 10 frames (docs/robustness.md), so a rollout on a
// body would measure a skirt falling to the ground. On a body, the waistband of these garments
// is pinned to the skinned garment (the pins ride on the body, as in training); without a body
// they hang like any other garment.
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"

namespace pb4u {

struct WaistbandConfig {
  std::vector<std::string> garments{"skirt"};  // garment names held at the waist
  double band = 0.02;  // m: the waistband, the rest-shape vertices within this of the highest one

  // Whether `garment` (a template name or a garment file's stem) is held at the waist.
  bool holds(const std::string& garment) const;

  template <class V>
  void visit(V& v) {
    v("garments", garments);
    v("band", band, in_range(0.0, 0.5));
  }
};

}  // namespace pb4u
