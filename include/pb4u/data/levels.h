#pragma once
// Resolution levels: target triangle counts per garment. The paper's Lv.1-Lv.4 are about
// 11K / 18K / 25K / 38K triangles; the CPU scale keeps the ratios (2K / 3.3K / 4.5K / 7K).
// A fifth, finer level serves the propagation-depth (K) study.
#include <vector>

#include "pb4u/config/config_io.h"

namespace pb4u {

struct LevelsConfig {
  std::vector<int> triangles = {2000, 3300, 4500, 7000, 11000};

  template <class V>
  void visit(V& v) {
    v("triangles", triangles);
  }
};

// Throws pb4u::Error naming `where` unless the counts are >= 8 and strictly increasing.
void validate_levels(const LevelsConfig& levels, const std::string& where);

}  // namespace pb4u
