#pragma once
// The corner tetrahedron (0,0,0), e_x, e_y, e_z with outward faces, in this order: z = 0,
// y = 0, x = 0 and x + y + z = 1. Closed forms are easy on it.
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u::test {

inline TriMesh corner_tetrahedron() {
  TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(4, 3);
  m.F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

}  // namespace pb4u::test
